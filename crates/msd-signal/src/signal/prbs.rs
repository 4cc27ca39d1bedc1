//! Maximum-length pseudo-random binary sequences (m-sequences).
//!
//! ## The algorithm
//! A Fibonacci linear-feedback shift register of `order` n bits, started from all ones;
//! each clock the new bit is the XOR of the tapped positions and the output chip is the
//! bit leaving position n. The taps are the maximum-length table of Xilinx application
//! note XAPP052 (Alfke, 1996), so the chip sequence has period 2ⁿ − 1, contains
//! 2ⁿ⁻¹ ones (level +amplitude) and 2ⁿ⁻¹ − 1 zeros (level −amplitude), and every
//! non-zero n-bit pattern once per period.
//!
//! Chip i covers `[t_start + i·Tc, t_start + (i+1)·Tc)`; before `t_start` the signal is 0.
//!
//! ```
//! use msd_signal::{Prbs, PrbsSpec, Signal};
//! let prbs = Prbs::new(PrbsSpec { order: 5, clock_period: 0.01, amplitude: 2.0, t_start: 0.0 })?;
//! assert_eq!(prbs.period_chips(), 31);
//! let u = Signal::Prbs(prbs);
//! assert_eq!(u.value(0.0).abs(), 2.0);
//! # Ok::<(), msd_signal::SignalError>(())
//! ```

use serde::{Deserialize, Serialize};

use crate::error::{Result, SignalError, finite, positive};

/// Smallest supported PRBS order.
pub const PRBS_MIN_ORDER: u32 = 2;
/// Largest supported PRBS order (a period of 16 777 215 chips, 2 MiB of table).
pub const PRBS_MAX_ORDER: u32 = 24;

/// Feedback taps (1-based register positions) for orders 2 ..= 24, XAPP052 table.
const TAPS: [&[u32]; 23] = [
    &[2, 1],
    &[3, 2],
    &[4, 3],
    &[5, 3],
    &[6, 5],
    &[7, 6],
    &[8, 6, 5, 4],
    &[9, 5],
    &[10, 7],
    &[11, 9],
    &[12, 6, 4, 1],
    &[13, 4, 3, 1],
    &[14, 5, 3, 1],
    &[15, 14],
    &[16, 15, 13, 4],
    &[17, 14],
    &[18, 11],
    &[19, 6, 2, 1],
    &[20, 17],
    &[21, 19],
    &[22, 21],
    &[23, 18],
    &[24, 23, 22, 17],
];

/// The parameters of a PRBS, as written in a config.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrbsSpec {
    /// Register length n, 2 ..= 24; the period is 2ⁿ − 1 chips.
    pub order: u32,
    /// Chip duration Tc in seconds (> 0).
    pub clock_period: f64,
    /// The two levels are ±`amplitude`.
    pub amplitude: f64,
    /// Start of chip 0. Default 0.
    #[serde(default)]
    pub t_start: f64,
}

impl Default for PrbsSpec {
    /// Order 10 (1023 chips), clock period 0.01 s, amplitude 1, start 0: a 10.23 s period
    /// at a 100 Hz clock, flat to about 45 Hz (0.45·fc, the usual rule of thumb).
    fn default() -> Self {
        PrbsSpec {
            order: 10,
            clock_period: 0.01,
            amplitude: 1.0,
            t_start: 0.0,
        }
    }
}

impl PrbsSpec {
    /// Checks the order range and that the times and amplitude are finite
    /// (`clock_period > 0`).
    pub fn validate(&self) -> Result<()> {
        if !(PRBS_MIN_ORDER..=PRBS_MAX_ORDER).contains(&self.order) {
            return Err(SignalError::PrbsOrder {
                order: self.order,
                min: PRBS_MIN_ORDER,
                max: PRBS_MAX_ORDER,
            });
        }
        positive(|| "clock_period".into(), self.clock_period)?;
        finite(|| "amplitude".into(), self.amplitude)?;
        finite(|| "t_start".into(), self.t_start)
    }
}

/// A prepared PRBS: the spec plus its chip table (so evaluation never allocates).
/// Serialises as its [`PrbsSpec`].
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(try_from = "PrbsSpec", into = "PrbsSpec")]
pub struct Prbs {
    spec: PrbsSpec,
    /// One period of chips, bit-packed (bit i of word i/64).
    chips: Vec<u64>,
    period: usize,
}

impl PartialEq for Prbs {
    fn eq(&self, other: &Self) -> bool {
        self.spec == other.spec
    }
}

impl TryFrom<PrbsSpec> for Prbs {
    type Error = SignalError;
    fn try_from(spec: PrbsSpec) -> Result<Self> {
        Prbs::new(spec)
    }
}

impl From<Prbs> for PrbsSpec {
    fn from(p: Prbs) -> Self {
        p.spec
    }
}

impl Prbs {
    /// Validates the spec and generates one period of chips.
    pub fn new(spec: PrbsSpec) -> Result<Self> {
        spec.validate()?;
        let n = spec.order;
        let taps = TAPS[(n - PRBS_MIN_ORDER) as usize];
        let period = (1usize << n) - 1;
        let mask: u32 = (1u32 << n) - 1;
        let mut state: u32 = mask;
        let mut chips = vec![0u64; period.div_ceil(64)];
        for i in 0..period {
            let out = (state >> (n - 1)) & 1;
            if out == 1 {
                chips[i / 64] |= 1u64 << (i % 64);
            }
            let fb = taps
                .iter()
                .fold(0u32, |acc, &tap| acc ^ ((state >> (tap - 1)) & 1));
            state = ((state << 1) | fb) & mask;
        }
        debug_assert_eq!(
            state, mask,
            "an m-sequence returns to its start state after 2^n - 1 clocks"
        );
        Ok(Prbs {
            spec,
            chips,
            period,
        })
    }

    /// The parameters.
    pub fn spec(&self) -> &PrbsSpec {
        &self.spec
    }

    /// The period in chips, 2ⁿ − 1.
    pub fn period_chips(&self) -> usize {
        self.period
    }

    /// Chip `i` (taken modulo the period): `true` is the high level.
    pub fn chip(&self, i: usize) -> bool {
        let i = i % self.period;
        (self.chips[i / 64] >> (i % 64)) & 1 == 1
    }

    /// Start time of chip `i` (the one formula used everywhere, so edges are exact).
    #[inline]
    fn edge(&self, i: f64) -> f64 {
        self.spec.t_start + i * self.spec.clock_period
    }

    /// Index of the chip active at t (right side) or just before t (left limit), or
    /// `None` before the start.
    #[inline]
    fn chip_index(&self, t: f64, left: bool) -> Option<f64> {
        let start = self.spec.t_start;
        if !(t > start || (!left && t == start)) {
            return None;
        }
        let mut i = ((t - start) / self.spec.clock_period).floor().max(0.0);
        // Make rounding agree with `edge`: edge(i) <= t < edge(i+1) on the right side,
        // edge(i) < t <= edge(i+1) for the left limit.
        if left {
            if self.edge(i + 1.0) < t {
                i += 1.0;
            } else if i > 0.0 && self.edge(i) >= t {
                i -= 1.0;
            }
        } else if self.edge(i + 1.0) <= t {
            i += 1.0;
        } else if i > 0.0 && self.edge(i) > t {
            i -= 1.0;
        }
        Some(i)
    }

    #[inline]
    fn level(&self, i: f64) -> f64 {
        let k = i.rem_euclid(self.period as f64) as usize;
        if self.chip(k) {
            self.spec.amplitude
        } else {
            -self.spec.amplitude
        }
    }

    pub(crate) fn eval(&self, t: f64, left: bool) -> f64 {
        self.chip_index(t, left).map_or(0.0, |i| self.level(i))
    }

    pub(crate) fn collect_times(&self, t0: f64, t1: f64, out: &mut Vec<f64>) {
        let start = self.spec.t_start;
        if start >= t0 && start <= t1 {
            out.push(start);
        }
        let from = ((t0.max(start) - start) / self.spec.clock_period)
            .floor()
            .max(1.0);
        // Up to the chip of t1 (edge times stop advancing where the clock period is below
        // the resolution of t, so the times alone do not end the loop); an unbounded
        // interval lists one period of edges rather than looping forever.
        let last = if t1.is_finite() {
            ((t1 - start) / self.spec.clock_period).ceil() + 1.0
        } else {
            from + self.period as f64
        };
        let mut i = from;
        loop {
            let t = self.edge(i);
            if t > t1 || t.is_nan() || i > last {
                break;
            }
            if t >= t0 && self.level(i) != self.level(i - 1.0) {
                out.push(t);
            }
            // Beyond 2⁵³ chips from the start, chip indices (and their edge times) are
            // no longer distinct doubles: nothing further can be listed.
            if i + 1.0 == i {
                break;
            }
            i += 1.0;
        }
    }

    /// Chip edges in `[t0, t1]`, plus the start: an upper bound on what
    /// `collect_times` lists, without listing.
    pub(crate) fn max_times(&self, t0: f64, t1: f64) -> f64 {
        let start = self.spec.t_start;
        if t1 < start || t1 < t0 {
            return 0.0;
        }
        let span = t1 - t0.max(start);
        let chips = if t1.is_finite() {
            (span / self.spec.clock_period).ceil()
        } else {
            self.period as f64
        };
        chips.min(2f64.powi(53)) + 2.0
    }
}
