//! Excitation signals: the [`Signal`] enum, its evaluation, sampling and breakpoints.
//!
//! A signal is a plain value that describes itself in TOML (serde, tagged by `kind`).
//! It can be
//!
//! * evaluated at any time with [`Signal::value`] (no allocation, for adaptive ODE solvers),
//! * sampled onto a uniform grid with [`Signal::sample`] / [`Signal::sample_into`],
//! * asked where it is not smooth with [`Signal::breakpoints`], so that an exact
//!   (piecewise) simulator never interpolates across a jump or a kink.
//!
//! ## Conventions
//! Signals are **right-continuous**: a step at time T has its new value at t = T
//! (H(0) = 1), and an active window `[t_on, t_off)` is on at `t_on` and off at `t_off`.
//! Sines use absolute time, `A·sin(2π·f·t + φ)`, so a windowed sine is a slice of one
//! continuous sinusoid (as in the paper's input); chirps, multisines and PRBS count
//! their time from their own `t_start`.
//!
//! Deserialised signals are not checked: call [`Signal::validate`] before use (multisine
//! and PRBS are the exception, they are checked when built or deserialised).
//!
//! ```
//! use msd_signal::{Breakpoint, Signal};
//!
//! let u = Signal::Sum { terms: vec![
//!     Signal::Step { amplitude: 6.0, time: 0.5 },
//!     Signal::Sine { amplitude: 3.0, frequency: 0.5, phase: 0.0, t_on: 3.0, t_off: Some(9.0) },
//! ]};
//! u.validate()?;
//! assert_eq!(u.value(0.5), 6.0);
//! assert_eq!(u.value(0.4999), 0.0);
//! let bps = u.breakpoints(0.0, 15.0);
//! assert_eq!(bps.len(), 3);
//! assert_eq!(bps[0], Breakpoint { time: 0.5, left: 0.0, right: 6.0 });
//! # Ok::<(), msd_signal::SignalError>(())
//! ```

pub(crate) mod chirp;
pub(crate) mod multisine;
pub(crate) mod prbs;
mod prepared;

use std::f64::consts::TAU;

use serde::{Deserialize, Serialize};

use crate::error::{Result, SignalError, finite, non_negative, positive};
pub use chirp::Sweep;
pub use multisine::{ClippingOptions, LineSelection, Multisine, MultisineSpec, PhaseScheme};
pub use prbs::{Prbs, PrbsSpec};
pub use prepared::PreparedSignal;

/// An excitation signal u(t). See the [module docs](self) for the conventions.
///
/// In TOML every variant is a table with `kind = "<snake_case name>"`; unknown fields are
/// rejected. Optional fields are marked below with their default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Signal {
    /// u(t) = `value` for all t.
    Constant {
        /// The constant level.
        value: f64,
    },
    /// u(t) = `amplitude`·H(t − `time`), with H(0) = 1.
    Step {
        /// Height of the step.
        amplitude: f64,
        /// Time of the jump.
        time: f64,
    },
    /// u(t) = `amplitude`·sin(2π·`frequency`·t + `phase`) for t in `[t_on, t_off)`, else 0.
    Sine {
        /// Peak amplitude.
        amplitude: f64,
        /// Frequency in Hz (≥ 0).
        frequency: f64,
        /// Phase in radians at t = 0 (absolute time). Default 0.
        #[serde(default)]
        phase: f64,
        /// Start of the active window. Default 0.
        #[serde(default)]
        t_on: f64,
        /// End of the active window (excluded); `None` = forever. Default `None`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        t_off: Option<f64>,
    },
    /// The paper's multi-level stepped sinusoid: a time-ordered list of non-overlapping
    /// windowed sines, each with its own frequency and amplitude.
    SteppedSine {
        /// The segments, in time order, windows not overlapping.
        segments: Vec<SineSegment>,
    },
    /// A swept sine on `[t_start, t_start + duration)`, zero outside
    /// (formulas in the `chirp` section of [`Sweep`]'s module).
    ///
    /// u = `amplitude`·sin(θ(τ) + `phase`), τ = t − `t_start`, with θ the linear
    /// (2π·(f0·τ + (f1 − f0)/(2T)·τ²)) or logarithmic (2π·f0·T/ln(f1/f0)·((f1/f0)^(τ/T) − 1))
    /// sweep phase.
    Chirp {
        /// Peak amplitude.
        amplitude: f64,
        /// Start frequency in Hz (≥ 0; > 0 for a logarithmic sweep).
        f0: f64,
        /// End frequency in Hz (≥ 0; > 0 for a logarithmic sweep).
        f1: f64,
        /// Sweep duration T in seconds (> 0).
        duration: f64,
        /// Phase offset in radians. Default 0.
        #[serde(default)]
        phase: f64,
        /// Linear or logarithmic sweep. Default linear.
        #[serde(default)]
        sweep: Sweep,
        /// Start of the sweep. Default 0.
        #[serde(default)]
        t_start: f64,
    },
    /// A periodic multisine (checked and prepared when built or deserialised).
    Multisine(Multisine),
    /// A maximum-length pseudo-random binary sequence (checked and prepared when built).
    Prbs(Prbs),
    /// The sum of the terms (an empty sum is 0).
    Sum {
        /// The terms.
        terms: Vec<Signal>,
    },
    /// `gain` times another signal.
    Scaled {
        /// The factor.
        gain: f64,
        /// The scaled signal.
        signal: Box<Signal>,
    },
}

/// One segment of a [`Signal::SteppedSine`]:
/// `amplitude`·sin(2π·`frequency`·t + `phase`) on `[t_on, t_off)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SineSegment {
    /// Frequency in Hz (≥ 0).
    pub frequency: f64,
    /// Peak amplitude.
    pub amplitude: f64,
    /// Start of the window (included).
    pub t_on: f64,
    /// End of the window (excluded); `None` = forever. Default `None`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t_off: Option<f64>,
    /// Phase in radians at t = 0 (absolute time). Default 0.
    #[serde(default)]
    pub phase: f64,
}

/// A time where a signal is not smooth: a jump (`left != right`) or a kink
/// (`left == right`, a discontinuous derivative).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Breakpoint {
    /// The time.
    pub time: f64,
    /// The limit from the left, u(time⁻).
    pub left: f64,
    /// The value at and just after, u(time) = u(time⁺).
    pub right: f64,
}

impl Breakpoint {
    /// The size of the jump, `right − left` (0 for a kink).
    pub fn jump(&self) -> f64 {
        self.right - self.left
    }
}

/// Is t inside `[t_on, t_off)` (right side) or `(t_on, t_off]` (left limit)?
#[inline]
fn in_window(t: f64, t_on: f64, t_off: Option<f64>, left: bool) -> bool {
    if left {
        t > t_on && t_off.is_none_or(|off| t <= off)
    } else {
        t >= t_on && t_off.is_none_or(|off| t < off)
    }
}

/// Pushes `t` if it lies in `[t0, t1]`.
#[inline]
fn push_in(out: &mut Vec<f64>, t: f64, t0: f64, t1: f64) {
    if t >= t0 && t <= t1 {
        out.push(t);
    }
}

fn window_check(
    path: &str,
    amplitude: f64,
    frequency: f64,
    phase: f64,
    t_on: f64,
    t_off: Option<f64>,
) -> Result<()> {
    finite(|| format!("{path}amplitude"), amplitude)?;
    non_negative(|| format!("{path}frequency"), frequency)?;
    at_most_max_frequency(|| format!("{path}frequency"), frequency)?;
    finite(|| format!("{path}phase"), phase)?;
    finite(|| format!("{path}t_on"), t_on)?;
    if let Some(off) = t_off {
        finite(|| format!("{path}t_off"), off)?;
        if off <= t_on {
            // The window's path (e.g. `segments[0]`), or `t_off` for a top-level sine.
            let window = path.trim_end_matches('.');
            return Err(SignalError::ReversedWindow {
                parameter: if window.is_empty() {
                    "t_off".to_string()
                } else {
                    window.to_string()
                },
                t_on,
                t_off: off,
            });
        }
    }
    Ok(())
}

/// `InvalidParameter` unless `frequency` ≤ [`Signal::MAX_FREQUENCY`].
fn at_most_max_frequency(parameter: impl Fn() -> String, frequency: f64) -> Result<()> {
    if frequency <= Signal::MAX_FREQUENCY {
        Ok(())
    } else {
        Err(SignalError::InvalidParameter {
            parameter: parameter(),
            value: frequency,
            expected: "a frequency of at most 1e12 Hz",
        })
    }
}

impl Signal {
    /// Highest frequency accepted, Hz: far above any mechanical or electrical test
    /// signal, and low enough that every phase 2π·f·t stays finite for |t| ≤ 1e280 s.
    pub const MAX_FREQUENCY: f64 = 1e12;

    /// Checks every parameter (recursively), naming the first bad one by its path,
    /// e.g. `terms[1].segments[0].t_off`.
    ///
    /// Rejects NaN and infinite values, negative frequencies and frequencies above
    /// [`Signal::MAX_FREQUENCY`], non-positive durations, `f0` or `f1` ≤ 0 for a
    /// logarithmic chirp, a sweep whose phase would overflow, reversed windows,
    /// overlapping stepped-sine segments, and sums or gains whose peak amplitude would
    /// overflow. A signal that passes is finite at every |t| ≤ 1e280 s.
    ///
    /// ```
    /// use msd_signal::{Signal, SignalError, Sweep};
    /// let chirp = Signal::Chirp { amplitude: 1.0, f0: 0.0, f1: 3.0, duration: 15.0,
    ///     phase: 0.0, sweep: Sweep::Logarithmic, t_start: 0.0 };
    /// assert!(matches!(chirp.validate(), Err(SignalError::InvalidParameter { ref parameter, .. }) if parameter == "f0"));
    /// ```
    pub fn validate(&self) -> Result<()> {
        self.validate_at("")
    }

    fn validate_at(&self, path: &str) -> Result<()> {
        match self {
            Signal::Constant { value } => finite(|| format!("{path}value"), *value),
            Signal::Step { amplitude, time } => {
                finite(|| format!("{path}amplitude"), *amplitude)?;
                finite(|| format!("{path}time"), *time)
            }
            Signal::Sine {
                amplitude,
                frequency,
                phase,
                t_on,
                t_off,
            } => window_check(path, *amplitude, *frequency, *phase, *t_on, *t_off),
            Signal::SteppedSine { segments } => {
                if segments.is_empty() {
                    return Err(SignalError::EmptyData { name: "segments" });
                }
                let mut previous_end = f64::NEG_INFINITY;
                for (i, s) in segments.iter().enumerate() {
                    let p = format!("{path}segments[{i}].");
                    window_check(&p, s.amplitude, s.frequency, s.phase, s.t_on, s.t_off)?;
                    if s.t_on < previous_end {
                        return Err(SignalError::OverlappingSegments {
                            parameter: format!("{path}segments"),
                            index: i,
                            t_on: s.t_on,
                            previous_end,
                        });
                    }
                    previous_end = s.t_off.unwrap_or(f64::INFINITY);
                }
                Ok(())
            }
            Signal::Chirp {
                amplitude,
                f0,
                f1,
                duration,
                phase,
                sweep,
                t_start,
            } => {
                finite(|| format!("{path}amplitude"), *amplitude)?;
                match sweep {
                    Sweep::Linear => {
                        non_negative(|| format!("{path}f0"), *f0)?;
                        non_negative(|| format!("{path}f1"), *f1)?;
                    }
                    Sweep::Logarithmic => {
                        positive(|| format!("{path}f0"), *f0)?;
                        positive(|| format!("{path}f1"), *f1)?;
                        // ln(f1/f0) must exist: the ratio may not underflow to 0 or
                        // overflow (e.g. f1 = 5e-324 Hz against f0 = 200 Hz).
                        let ratio = f1 / f0;
                        if !(ratio.is_normal() && ratio.is_finite()) {
                            return Err(SignalError::InvalidParameter {
                                parameter: format!("{path}f1"),
                                value: *f1,
                                expected: "a logarithmic sweep whose ratio f1/f0 is a normal, finite number",
                            });
                        }
                    }
                }
                at_most_max_frequency(|| format!("{path}f0"), *f0)?;
                at_most_max_frequency(|| format!("{path}f1"), *f1)?;
                positive(|| format!("{path}duration"), *duration)?;
                finite(|| format!("{path}phase"), *phase)?;
                finite(|| format!("{path}t_start"), *t_start)?;
                finite(|| format!("{path}t_start + duration"), t_start + duration)?;
                // The phase grows monotonically over the sweep: finite at its end, finite
                // throughout.
                let end = chirp::phase(*sweep, *f0, *f1, *duration, *duration);
                if !end.is_finite() {
                    return Err(SignalError::InvalidParameter {
                        parameter: format!("{path}duration"),
                        value: *duration,
                        expected: "a sweep whose phase stays finite (fewer than ~1e300 cycles, f1/f0 finite)",
                    });
                }
                Ok(())
            }
            // Checked when built (their constructors and deserialisers validate).
            Signal::Multisine(_) | Signal::Prbs(_) => Ok(()),
            Signal::Sum { terms } => {
                for (i, term) in terms.iter().enumerate() {
                    term.validate_at(&format!("{path}terms[{i}]."))?;
                }
                let peak = self.peak();
                if !peak.is_finite() {
                    return Err(SignalError::InvalidParameter {
                        parameter: format!("{path}terms"),
                        value: peak,
                        expected: "terms whose peak amplitudes add up to a finite value",
                    });
                }
                Ok(())
            }
            Signal::Scaled { gain, signal } => {
                finite(|| format!("{path}gain"), *gain)?;
                signal.validate_at(&format!("{path}signal."))?;
                if !self.peak().is_finite() {
                    return Err(SignalError::InvalidParameter {
                        parameter: format!("{path}gain"),
                        value: *gain,
                        expected: "a gain that keeps the peak amplitude finite",
                    });
                }
                Ok(())
            }
        }
    }

    /// An upper bound of |u(t)| over all t (for checking that sums stay finite).
    fn peak(&self) -> f64 {
        match self {
            Signal::Constant { value } => value.abs(),
            Signal::Step { amplitude, .. }
            | Signal::Sine { amplitude, .. }
            | Signal::Chirp { amplitude, .. } => amplitude.abs(),
            Signal::SteppedSine { segments } => {
                segments.iter().fold(0.0, |m, s| m.max(s.amplitude.abs()))
            }
            Signal::Multisine(m) => m.line_amplitude() * m.harmonics().len() as f64,
            Signal::Prbs(p) => p.spec().amplitude.abs(),
            Signal::Sum { terms } => terms.iter().map(Signal::peak).sum(),
            Signal::Scaled { gain, signal } => gain.abs() * signal.peak(),
        }
    }

    /// u(t), the value at and just after `t` (right-continuous).
    ///
    /// Cheap and allocation-free; meant to be called inside ODE right-hand sides.
    /// For a validated signal and finite `t` the result is finite.
    ///
    /// ```
    /// use msd_signal::paper_identification_input;
    /// let u = paper_identification_input();
    /// assert_eq!(u.value(0.0), 0.0);
    /// assert_eq!(u.value(0.5), 6.0);
    /// ```
    #[inline]
    pub fn value(&self, t: f64) -> f64 {
        self.eval(t, false)
    }

    /// u(t⁻), the limit from the left.
    #[inline]
    pub fn left_limit(&self, t: f64) -> f64 {
        self.eval(t, true)
    }

    fn eval(&self, t: f64, left: bool) -> f64 {
        match self {
            Signal::Constant { value } => *value,
            Signal::Step { amplitude, time } => {
                let on = if left { t > *time } else { t >= *time };
                if on { *amplitude } else { 0.0 }
            }
            Signal::Sine {
                amplitude,
                frequency,
                phase,
                t_on,
                t_off,
            } => {
                if in_window(t, *t_on, *t_off, left) {
                    amplitude * (TAU * frequency * t + phase).sin()
                } else {
                    0.0
                }
            }
            Signal::SteppedSine { segments } => segments
                .iter()
                .filter(|s| in_window(t, s.t_on, s.t_off, left))
                .map(|s| s.amplitude * (TAU * s.frequency * t + s.phase).sin())
                .sum(),
            Signal::Chirp {
                amplitude,
                f0,
                f1,
                duration,
                phase,
                sweep,
                t_start,
            } => {
                if in_window(t, *t_start, Some(t_start + duration), left) {
                    amplitude
                        * (chirp::phase(*sweep, *f0, *f1, *duration, t - t_start) + phase).sin()
                } else {
                    0.0
                }
            }
            Signal::Multisine(m) => m.eval(t, left),
            Signal::Prbs(p) => p.eval(t, left),
            Signal::Sum { terms } => terms.iter().map(|s| s.eval(t, left)).sum(),
            Signal::Scaled { gain, signal } => gain * signal.eval(t, left),
        }
    }

    /// The instantaneous frequency in Hz at `t` of a sine, stepped sine or chirp
    /// (the derivative of its phase over 2π), `None` for other kinds or outside the
    /// active window.
    ///
    /// ```
    /// use msd_signal::paper_validation_input;
    /// let Some(msd_signal::Signal::Sum { terms }) = Some(paper_validation_input()) else { unreachable!() };
    /// assert!((terms[0].instantaneous_frequency(7.5).unwrap() - 1.6).abs() < 1e-12);
    /// ```
    pub fn instantaneous_frequency(&self, t: f64) -> Option<f64> {
        match self {
            Signal::Sine {
                frequency,
                t_on,
                t_off,
                ..
            } if in_window(t, *t_on, *t_off, false) => Some(*frequency),
            Signal::SteppedSine { segments } => segments
                .iter()
                .find(|s| in_window(t, s.t_on, s.t_off, false))
                .map(|s| s.frequency),
            Signal::Chirp {
                f0,
                f1,
                duration,
                sweep,
                t_start,
                ..
            } if in_window(t, *t_start, Some(t_start + duration), false) => {
                Some(chirp::frequency(*sweep, *f0, *f1, *duration, t - t_start))
            }
            _ => None,
        }
    }

    /// Samples u at `t0 + i·dt`, i = 0 … n−1 (each time computed directly, not accumulated).
    ///
    /// ```
    /// use msd_signal::paper_identification_input;
    /// let u = paper_identification_input().sample(0.0, 0.002, 7501);
    /// assert_eq!(u.len(), 7501);
    /// assert_eq!(u[250], 6.0); // t = 0.5 s: the step is on
    /// ```
    pub fn sample(&self, t0: f64, dt: f64, n: usize) -> Vec<f64> {
        let mut out = vec![0.0; n];
        self.sample_into(t0, dt, &mut out);
        out
    }

    /// Fills `out[i] = u(t0 + i·dt)`.
    pub fn sample_into(&self, t0: f64, dt: f64, out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.value(t0 + i as f64 * dt);
        }
    }

    /// Every time in `[t0, t1]` where the signal is not smooth: jumps and kinks, sorted,
    /// coincident times merged, with the left limit and the right value of the whole
    /// signal (so the terms of a sum are added and a scaled signal is scaled).
    ///
    /// Listed: steps; both ends of every sine, segment and chirp window and the start of a
    /// multisine or PRBS (even where the value does not jump, as the slope does); every
    /// PRBS chip edge where the level changes. The list is complete; a listed point
    /// with `left == right` is a kink. It can be long (a fast PRBS over a long span):
    /// [`Signal::max_breakpoints`] bounds its length without listing.
    ///
    /// ```
    /// use msd_signal::paper_identification_input;
    /// let bps = paper_identification_input().breakpoints(0.0, 15.0);
    /// let times: Vec<f64> = bps.iter().map(|b| b.time).collect();
    /// assert_eq!(times, vec![0.5, 3.0, 9.0]);
    /// assert_eq!(bps[0].jump(), 6.0);
    /// ```
    pub fn breakpoints(&self, t0: f64, t1: f64) -> Vec<Breakpoint> {
        let mut times = Vec::new();
        self.collect_times(t0, t1, &mut times);
        times.sort_by(f64::total_cmp);
        times.dedup();
        debug_assert!(
            times.windows(2).all(|w| w[0] < w[1]),
            "sorted, merged breakpoint times"
        );
        times
            .into_iter()
            .map(|time| Breakpoint {
                time,
                left: self.left_limit(time),
                right: self.value(time),
            })
            .collect()
    }

    fn collect_times(&self, t0: f64, t1: f64, out: &mut Vec<f64>) {
        match self {
            Signal::Constant { .. } => {}
            Signal::Step { time, .. } => push_in(out, *time, t0, t1),
            Signal::Sine { t_on, t_off, .. } => {
                push_in(out, *t_on, t0, t1);
                if let Some(off) = t_off {
                    push_in(out, *off, t0, t1);
                }
            }
            Signal::SteppedSine { segments } => {
                for s in segments {
                    push_in(out, s.t_on, t0, t1);
                    if let Some(off) = s.t_off {
                        push_in(out, off, t0, t1);
                    }
                }
            }
            Signal::Chirp {
                duration, t_start, ..
            } => {
                push_in(out, *t_start, t0, t1);
                push_in(out, t_start + duration, t0, t1);
            }
            Signal::Multisine(m) => push_in(out, m.spec().t_start, t0, t1),
            Signal::Prbs(p) => p.collect_times(t0, t1, out),
            Signal::Sum { terms } => terms.iter().for_each(|s| s.collect_times(t0, t1, out)),
            Signal::Scaled { signal, .. } => signal.collect_times(t0, t1, out),
        }
    }

    /// An upper bound on the number of breakpoints in `[t0, t1]`, that is on the length
    /// of [`Signal::breakpoints`]`(t0, t1)`, computed without listing them.
    ///
    /// It is small for every signal but a PRBS, whose chip edges grow with the span over
    /// the clock period (a 1 ns clock over 15 s has 1.5e10 of them): callers that sample
    /// a signal on a grid can refuse one that would list far more breakpoints than the
    /// grid has samples, instead of listing them.
    ///
    /// ```
    /// use msd_signal::{Prbs, PrbsSpec, Signal};
    /// let fast = Signal::Prbs(Prbs::new(PrbsSpec { clock_period: 1e-9, ..PrbsSpec::default() })?);
    /// assert!(fast.max_breakpoints(0.0, 15.0) > 1e10);
    /// assert!(msd_signal::paper_identification_input().max_breakpoints(0.0, 15.0) <= 5.0);
    /// # Ok::<(), msd_signal::SignalError>(())
    /// ```
    pub fn max_breakpoints(&self, t0: f64, t1: f64) -> f64 {
        match self {
            Signal::Constant { .. } => 0.0,
            Signal::Step { .. } | Signal::Multisine(_) => 1.0,
            Signal::Sine { .. } | Signal::Chirp { .. } => 2.0,
            Signal::SteppedSine { segments } => 2.0 * segments.len() as f64,
            Signal::Prbs(p) => p.max_times(t0, t1),
            Signal::Sum { terms } => terms.iter().map(|s| s.max_breakpoints(t0, t1)).sum(),
            Signal::Scaled { signal, .. } => signal.max_breakpoints(t0, t1),
        }
    }

    /// `gain · self`, a convenience for [`Signal::Scaled`].
    pub fn scaled(self, gain: f64) -> Signal {
        Signal::Scaled {
            gain,
            signal: Box::new(self),
        }
    }
}

impl std::ops::Add for Signal {
    type Output = Signal;

    /// `a + b` as a [`Signal::Sum`] (flattening a left-hand sum).
    fn add(self, rhs: Signal) -> Signal {
        match self {
            Signal::Sum { mut terms } => {
                terms.push(rhs);
                Signal::Sum { terms }
            }
            lhs => Signal::Sum {
                terms: vec![lhs, rhs],
            },
        }
    }
}
