//! A signal prepared for evaluation at many times: [`PreparedSignal`].
//!
//! An adaptive ODE solver evaluates the force at every stage of every step, thousands of
//! times a simulation. [`Signal::value`] recomputes each term's constants every time (a
//! chirp's sweep rate is a division, a sine's angular frequency a product);
//! a prepared signal computes them once. It computes every value with exactly the
//! floating-point operations of [`Signal::value`], in the same order, so the two agree
//! bit for bit at every time (a property test checks it on arbitrary signals).

use std::f64::consts::TAU;

use super::{Multisine, Prbs, Signal, Sweep, chirp, in_window};

/// A [`Signal`] with its constants computed once, for fast repeated evaluation;
/// [`value`](Self::value) and [`left_limit`](Self::left_limit) equal the signal's bit
/// for bit.
///
/// ```
/// use msd_signal::paper_validation_input;
/// let signal = paper_validation_input();
/// let prepared = signal.prepare();
/// for t in [0.0, 0.999, 1.0, 7.3, 15.0] {
///     assert_eq!(prepared.value(t).to_bits(), signal.value(t).to_bits());
///     assert_eq!(prepared.left_limit(t).to_bits(), signal.left_limit(t).to_bits());
/// }
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedSignal {
    root: Node,
}

/// A sine term: `amplitude`·sin(`omega`·t + `phase`) on its window.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Sine {
    amplitude: f64,
    /// 2π·frequency, as `Signal::value` computes it first.
    omega: f64,
    phase: f64,
    t_on: f64,
    t_off: Option<f64>,
}

impl Sine {
    #[inline]
    fn value(&self, t: f64) -> f64 {
        self.amplitude * (self.omega * t + self.phase).sin()
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Node {
    Constant(f64),
    Step { amplitude: f64, time: f64 },
    Sine(Sine),
    SteppedSine(Vec<Sine>),
    Chirp(Chirp),
    Multisine(Multisine),
    Prbs(Prbs),
    Sum(Vec<Node>),
    Scaled { gain: f64, node: Box<Node> },
}

/// A chirp term: `amplitude`·sin(θ(t − `t_start`) + `phase`) on [t_start, t_end).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Chirp {
    amplitude: f64,
    phase: f64,
    t_start: f64,
    /// t_start + duration.
    t_end: f64,
    sweep: Phase,
}

impl Chirp {
    #[inline(always)]
    fn value(&self, t: f64, left: bool) -> f64 {
        if in_window(t, self.t_start, Some(self.t_end), left) {
            self.amplitude * (self.sweep.phase(t - self.t_start) + self.phase).sin()
        } else {
            0.0
        }
    }
}

/// A step term: `amplitude`·H(t − `time`).
#[inline(always)]
fn step(amplitude: f64, time: f64, t: f64, left: bool) -> f64 {
    let on = if left { t > time } else { t >= time };
    if on { amplitude } else { 0.0 }
}

/// `out[l] = value(t[l])` for the lanes with `active[l]`.
#[inline(always)]
fn each<const B: usize>(
    t: &[f64; B],
    active: &[bool; B],
    out: &mut [f64; B],
    value: impl Fn(f64) -> f64,
) {
    for ((out, &t), &on) in out.iter_mut().zip(t).zip(active) {
        if on {
            *out = value(t);
        }
    }
}

/// A chirp's phase θ(τ) with its constants computed once, as `chirp::phase` computes it.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    /// TAU·(f0·τ + rate·τ·τ), rate = (f1 − f0)/(2T).
    Linear { f0: f64, rate: f64 },
    /// (2π·f0)·τ: a logarithmic sweep with f1 ≈ f0.
    Flat { omega: f64 },
    /// scale·expm1(τ/T·ln r), scale = 2π·f0·T/ln r.
    Logarithmic {
        scale: f64,
        duration: f64,
        ln_r: f64,
    },
}

impl Phase {
    fn new(sweep: Sweep, f0: f64, f1: f64, duration: f64) -> Self {
        match sweep {
            Sweep::Linear => Phase::Linear {
                f0,
                rate: (f1 - f0) / (2.0 * duration),
            },
            Sweep::Logarithmic => {
                let ln_r = (f1 / f0).ln();
                if ln_r.abs() < chirp::FLAT_LOG_RATIO {
                    Phase::Flat { omega: TAU * f0 }
                } else {
                    Phase::Logarithmic {
                        scale: TAU * f0 * duration / ln_r,
                        duration,
                        ln_r,
                    }
                }
            }
        }
    }

    #[inline]
    fn phase(&self, tau: f64) -> f64 {
        match *self {
            Phase::Linear { f0, rate } => TAU * (f0 * tau + rate * tau * tau),
            Phase::Flat { omega } => omega * tau,
            Phase::Logarithmic {
                scale,
                duration,
                ln_r,
            } => scale * (tau / duration * ln_r).exp_m1(),
        }
    }
}

impl Signal {
    /// This signal prepared for repeated evaluation ([`PreparedSignal`]).
    pub fn prepare(&self) -> PreparedSignal {
        PreparedSignal {
            root: Node::new(self),
        }
    }
}

impl Node {
    fn new(signal: &Signal) -> Self {
        let sine = |amplitude: f64, frequency: f64, phase, t_on, t_off| Sine {
            amplitude,
            omega: TAU * frequency,
            phase,
            t_on,
            t_off,
        };
        match signal {
            Signal::Constant { value } => Node::Constant(*value),
            Signal::Step { amplitude, time } => Node::Step {
                amplitude: *amplitude,
                time: *time,
            },
            Signal::Sine {
                amplitude,
                frequency,
                phase,
                t_on,
                t_off,
            } => Node::Sine(sine(*amplitude, *frequency, *phase, *t_on, *t_off)),
            Signal::SteppedSine { segments } => Node::SteppedSine(
                segments
                    .iter()
                    .map(|s| sine(s.amplitude, s.frequency, s.phase, s.t_on, s.t_off))
                    .collect(),
            ),
            Signal::Chirp {
                amplitude,
                f0,
                f1,
                duration,
                phase,
                sweep,
                t_start,
            } => Node::Chirp(Chirp {
                amplitude: *amplitude,
                phase: *phase,
                t_start: *t_start,
                t_end: t_start + duration,
                sweep: Phase::new(*sweep, *f0, *f1, *duration),
            }),
            Signal::Multisine(m) => Node::Multisine(m.clone()),
            Signal::Prbs(p) => Node::Prbs(p.clone()),
            Signal::Sum { terms } => Node::Sum(terms.iter().map(Node::new).collect()),
            Signal::Scaled { gain, signal } => Node::Scaled {
                gain: *gain,
                node: Box::new(Node::new(signal)),
            },
        }
    }

    /// As `Signal::eval`, operation for operation. Sums evaluate their leaf terms
    /// inline (no call per term) and recurse only into nested sums and scaled signals.
    fn eval(&self, t: f64, left: bool) -> f64 {
        match self {
            Node::Sum(terms) => terms.iter().map(|s| s.leaf(t, left)).sum(),
            Node::Scaled { gain, node } => gain * node.eval(t, left),
            leaf => leaf.leaf(t, left),
        }
    }

    #[inline(always)]
    fn leaf(&self, t: f64, left: bool) -> f64 {
        match self {
            Node::Constant(value) => *value,
            Node::Step { amplitude, time } => step(*amplitude, *time, t, left),
            Node::Sine(s) => {
                if in_window(t, s.t_on, s.t_off, left) {
                    s.value(t)
                } else {
                    0.0
                }
            }
            Node::SteppedSine(segments) => segments
                .iter()
                .filter(|s| in_window(t, s.t_on, s.t_off, left))
                .map(|s| s.value(t))
                .sum(),
            Node::Chirp(c) => c.value(t, left),
            Node::Multisine(m) => m.eval(t, left),
            Node::Prbs(p) => p.eval(t, left),
            Node::Sum(_) | Node::Scaled { .. } => self.eval(t, left),
        }
    }
}

impl Node {
    /// `eval` at several times at once, for the lanes with `active[l]` (the others'
    /// entries of `out` are left as they are): each value with `eval`'s operations, in
    /// its order, but each term visited once for all lanes.
    fn eval_lanes<const B: usize>(
        &self,
        t: &[f64; B],
        active: &[bool; B],
        left: bool,
        out: &mut [f64; B],
    ) {
        let lanes = || (0..B).filter(|&l| active[l]);
        match self {
            Node::Sum(terms) => {
                // `Iterator::sum`'s own starting value, whatever it is.
                let zero: f64 = std::iter::empty::<f64>().sum();
                let mut sum = [zero; B];
                let mut term = [0.0; B];
                for node in terms {
                    node.eval_lanes(t, active, left, &mut term);
                    // Every lane (inactive ones add what they hold): vectorises.
                    for (sum, term) in sum.iter_mut().zip(&term) {
                        *sum += term;
                    }
                }
                for l in lanes() {
                    out[l] = sum[l];
                }
            }
            Node::Scaled { gain, node } => {
                node.eval_lanes(t, active, left, out);
                for l in lanes() {
                    out[l] *= gain; // commutative: gain·u bit for bit
                }
            }
            Node::SteppedSine(segments) => {
                let zero: f64 = std::iter::empty::<f64>().sum();
                for l in lanes() {
                    let mut sum = zero;
                    for s in segments
                        .iter()
                        .filter(|s| in_window(t[l], s.t_on, s.t_off, left))
                    {
                        sum += s.value(t[l]);
                    }
                    out[l] = sum;
                }
            }
            // The common leaves matched once for all lanes.
            Node::Chirp(c) => each(t, active, out, |t| c.value(t, left)),
            Node::Step { amplitude, time } => {
                each(t, active, out, |t| step(*amplitude, *time, t, left))
            }
            leaf => each(t, active, out, |t| leaf.leaf(t, left)),
        }
    }
}

impl PreparedSignal {
    /// `u(t[l])` for each lane l with `active[l]` into `out[l]` (the others are left as
    /// they are), each bit for bit [`value`](Self::value): one pass over the signal's
    /// terms for all the times, which is faster than one [`value`](Self::value) each.
    ///
    /// ```
    /// let signal = msd_signal::paper_validation_input();
    /// let prepared = signal.prepare();
    /// let t = [0.3, 1.0, 7.7, 20.0];
    /// let mut out = [f64::NAN; 4];
    /// prepared.values(&t, &[true, true, false, true], &mut out);
    /// assert_eq!(out[1].to_bits(), signal.value(1.0).to_bits());
    /// assert!(out[2].is_nan());
    /// ```
    pub fn values<const B: usize>(&self, t: &[f64; B], active: &[bool; B], out: &mut [f64; B]) {
        self.root.eval_lanes(t, active, false, out);
    }

    /// u(t), bit for bit [`Signal::value`].
    #[inline]
    pub fn value(&self, t: f64) -> f64 {
        self.root.eval(t, false)
    }

    /// u(t⁻), bit for bit [`Signal::left_limit`].
    #[inline]
    pub fn left_limit(&self, t: f64) -> f64 {
        self.root.eval(t, true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{
        paper::paper_identification_input,
        signal::{MultisineSpec, PrbsSpec, SineSegment},
    };

    /// Every kind of term, nested, at times around their edges and far away.
    #[test]
    fn every_kind_equals_the_signal_bit_for_bit() {
        let chirp = |sweep, f0: f64, f1: f64| Signal::Chirp {
            amplitude: 1.3,
            f0,
            f1,
            duration: 7.0,
            phase: 0.4,
            sweep,
            t_start: 0.7,
        };
        let signal = Signal::Sum {
            terms: vec![
                paper_identification_input(),
                chirp(Sweep::Linear, 0.2, 3.0),
                chirp(Sweep::Logarithmic, 0.2, 3.0),
                chirp(Sweep::Logarithmic, 2.0, 2.0),
                Signal::Multisine(Multisine::new(MultisineSpec::default()).unwrap()),
                Signal::Prbs(Prbs::new(PrbsSpec::default()).unwrap()).scaled(-0.5),
                Signal::SteppedSine {
                    segments: vec![SineSegment {
                        frequency: 1.1,
                        amplitude: 2.0,
                        t_on: 1.0,
                        t_off: None,
                        phase: 0.3,
                    }],
                },
                Signal::Constant { value: 0.25 },
                Signal::Sum { terms: vec![] },
            ],
        };
        signal.validate().unwrap();
        let prepared = signal.prepare();
        let mut lanes = [0.0; 4];
        for i in 0..=40_000 {
            let ts: [f64; 4] = std::array::from_fn(|l| -1.0 + (i + 10_000 * l) as f64 * 5e-4);
            prepared.values(&ts, &[true; 4], &mut lanes);
            for (l, t) in ts.into_iter().enumerate() {
                assert_eq!(
                    lanes[l].to_bits(),
                    signal.value(t).to_bits(),
                    "u({t}), lane {l}"
                );
            }
            let t = -1.0 + i as f64 * 5e-4;
            let (a, b) = (prepared.value(t), signal.value(t));
            assert_eq!(a.to_bits(), b.to_bits(), "u({t})");
            let (a, b) = (prepared.left_limit(t), signal.left_limit(t));
            assert_eq!(a.to_bits(), b.to_bits(), "u({t}⁻)");
        }
    }

    /// Sums of signed zeros keep `Iterator::sum`'s sign, one time or several.
    #[test]
    fn signed_zeros_sum_as_the_signal_sums_them() {
        let zero = |value: f64| Signal::Constant { value };
        for terms in [
            vec![],
            vec![zero(-0.0)],
            vec![zero(-0.0), zero(0.0)],
            vec![zero(0.0)],
        ] {
            let signal = Signal::Sum { terms };
            let prepared = signal.prepare();
            let mut out = [1.0; 2];
            prepared.values(&[0.0, 1.0], &[true; 2], &mut out);
            for v in [prepared.value(0.0), out[0], out[1]] {
                assert_eq!(v.to_bits(), signal.value(0.0).to_bits());
            }
        }
    }
}
