//! Property tests: breakpoints are complete (the signal is continuous between them) and
//! consistent with `value` / `left_limit`.

use std::f64::consts::TAU;

use msd_signal::{Prbs, PrbsSpec, Signal, Sweep};
use proptest::prelude::*;

fn term() -> impl Strategy<Value = Signal> {
    prop_oneof![
        (-5.0..5.0f64, 0.0..10.0f64).prop_map(|(amplitude, time)| Signal::Step { amplitude, time }),
        (
            -3.0..3.0f64,
            0.0..3.0f64,
            -3.0..3.0f64,
            0.0..5.0f64,
            0.1..5.0f64
        )
            .prop_map(|(a, f, p, on, len)| {
                Signal::Sine {
                    amplitude: a,
                    frequency: f,
                    phase: p,
                    t_on: on,
                    t_off: Some(on + len),
                }
            }),
        (
            0.1..2.0f64,
            0.1..3.0f64,
            1.0..6.0f64,
            0.0..3.0f64,
            any::<bool>()
        )
            .prop_map(|(f0, f1, d, t0, log)| {
                let sweep = if log {
                    Sweep::Logarithmic
                } else {
                    Sweep::Linear
                };
                Signal::Chirp {
                    amplitude: 1.0,
                    f0,
                    f1,
                    duration: d,
                    phase: 0.3,
                    sweep,
                    t_start: t0,
                }
            }),
        (2u32..8, 0.05..0.5f64, 0.0..2.0f64).prop_map(|(order, tc, t0)| {
            Signal::Prbs(
                Prbs::new(PrbsSpec {
                    order,
                    clock_period: tc,
                    amplitude: 1.0,
                    t_start: t0,
                })
                .expect("valid"),
            )
        }),
    ]
}

/// A bound on |u'(t)| for the generated terms: Σ 2π·f_max·|A| (PRBS and steps are flat).
fn slope_bound(s: &Signal) -> f64 {
    match s {
        Signal::Sine {
            amplitude,
            frequency,
            ..
        } => TAU * frequency * amplitude.abs(),
        Signal::Chirp {
            amplitude, f0, f1, ..
        } => TAU * f0.max(*f1) * amplitude.abs(),
        Signal::Sum { terms } => terms.iter().map(slope_bound).sum(),
        Signal::Scaled { gain, signal } => gain.abs() * slope_bound(signal),
        _ => 0.0,
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn signal_is_continuous_between_breakpoints(terms in prop::collection::vec(term(), 1..5), gain in -2.0..2.0f64) {
        let u = Signal::Sum { terms }.scaled(gain);
        prop_assert!(u.validate().is_ok());
        let (t0, t1) = (0.0, 12.0);
        let bps = u.breakpoints(t0, t1);
        for w in bps.windows(2) {
            prop_assert!(w[0].time < w[1].time);
        }
        for b in &bps {
            prop_assert_eq!(b.right, u.value(b.time));
            prop_assert_eq!(b.left, u.left_limit(b.time));
        }
        // Between consecutive breakpoints the signal moves no faster than its slope bound.
        let h = 1e-7;
        let lipschitz = slope_bound(&u) * h + 1e-9;
        let mut edges: Vec<f64> = vec![t0];
        edges.extend(bps.iter().map(|b| b.time));
        edges.push(t1);
        for w in edges.windows(2) {
            let (a, b) = (w[0], w[1]);
            if b - a < 4.0 * h {
                continue;
            }
            for k in 1..20 {
                let t = a + h + (b - a - 3.0 * h) * k as f64 / 20.0;
                let jump = (u.value(t + h) - u.value(t)).abs();
                prop_assert!(jump <= lipschitz, "jump {} at t = {} between breakpoints {} and {}", jump, t, a, b);
            }
        }
    }
}
