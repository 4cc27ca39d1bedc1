//! The two inputs of the paper experiment (`docs/paper-experiment.md`), exactly.
//!
//! Identification: F_id(t) = 6·H(t − 0.5) + 3·sin(2π·0.5·t) for 3 ≤ t < 9
//! + 2.5·sin(2π·1.4·t) for 9 ≤ t (the grid ends at 15 s).
//!
//! Validation: F_val(t) = 2.5·sin(2π·(f0·t + (f1 − f0)/(2T)·t²)) + 1·H(t − 1) with
//! f0 = 0.2 Hz, f1 = 3 Hz, T = 15 s: a linear chirp on [0, 15) s. (At t = 15 the chirp
//! window has closed; the formula's value there is 2.5·sin(48π) = 0, so both agree.)
//!
//! In TOML (the form an experiment config uses):
//!
//! ```toml
//! # identification input
//! kind = "sum"
//!
//! [[terms]]
//! kind = "step"
//! amplitude = 6.0
//! time = 0.5
//!
//! [[terms]]
//! kind = "stepped_sine"
//!
//! [[terms.segments]]
//! frequency = 0.5
//! amplitude = 3.0
//! t_on = 3.0
//! t_off = 9.0
//!
//! [[terms.segments]]
//! frequency = 1.4
//! amplitude = 2.5
//! t_on = 9.0
//! ```
//!
//! ```toml
//! # validation input
//! kind = "sum"
//!
//! [[terms]]
//! kind = "chirp"
//! amplitude = 2.5
//! f0 = 0.2
//! f1 = 3.0
//! duration = 15.0
//! sweep = "linear"
//!
//! [[terms]]
//! kind = "step"
//! amplitude = 1.0
//! time = 1.0
//! ```

use crate::signal::{Signal, SineSegment, Sweep};

/// The paper's identification input: step + two-level stepped sinusoid.
///
/// ```
/// let u = msd_signal::paper_identification_input();
/// let t: f64 = 4.0;
/// let expected = 6.0 + 3.0 * (std::f64::consts::TAU * 0.5 * t).sin();
/// assert!((u.value(t) - expected).abs() < 1e-12);
/// ```
pub fn paper_identification_input() -> Signal {
    Signal::Sum {
        terms: vec![
            Signal::Step {
                amplitude: 6.0,
                time: 0.5,
            },
            Signal::SteppedSine {
                segments: vec![
                    SineSegment {
                        frequency: 0.5,
                        amplitude: 3.0,
                        t_on: 3.0,
                        t_off: Some(9.0),
                        phase: 0.0,
                    },
                    SineSegment {
                        frequency: 1.4,
                        amplitude: 2.5,
                        t_on: 9.0,
                        t_off: None,
                        phase: 0.0,
                    },
                ],
            },
        ],
    }
}

/// The paper's validation input: linear chirp 0.2 → 3 Hz over 15 s plus a 1 N step at 1 s.
///
/// ```
/// let u = msd_signal::paper_validation_input();
/// assert_eq!(u.value(0.0), 0.0);
/// assert_eq!(u.value(1.0) - u.left_limit(1.0), 1.0);
/// ```
pub fn paper_validation_input() -> Signal {
    Signal::Sum {
        terms: vec![
            Signal::Chirp {
                amplitude: 2.5,
                f0: 0.2,
                f1: 3.0,
                duration: 15.0,
                phase: 0.0,
                sweep: Sweep::Linear,
                t_start: 0.0,
            },
            Signal::Step {
                amplitude: 1.0,
                time: 1.0,
            },
        ],
    }
}
