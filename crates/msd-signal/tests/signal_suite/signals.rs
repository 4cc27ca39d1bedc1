//! Values at known instants, both sides of every discontinuity, breakpoints, chirps.

use std::f64::consts::{PI, TAU};

use msd_signal::{
    Breakpoint, Signal, SineSegment, Sweep, paper_identification_input, paper_validation_input,
};

/// Rounding allowance for a handful of f64 operations on values of order 10.
const EPS: f64 = 1e-12;

#[test]
fn constant_and_step_values_on_both_sides() {
    let c = Signal::Constant { value: -1.25 };
    assert_eq!(c.value(-1e9), -1.25);
    assert_eq!(c.value(3.0), -1.25);
    assert!(c.breakpoints(-10.0, 10.0).is_empty());

    let s = Signal::Step {
        amplitude: 6.0,
        time: 0.5,
    };
    assert_eq!(s.value(0.5), 6.0, "H(0) = 1: right-continuous");
    assert_eq!(s.left_limit(0.5), 0.0);
    assert_eq!(s.value(0.5 - 1e-12), 0.0);
    assert_eq!(s.value(0.5 + 1e-12), 6.0);
    assert_eq!(
        s.breakpoints(0.0, 1.0),
        vec![Breakpoint {
            time: 0.5,
            left: 0.0,
            right: 6.0
        }]
    );
    assert!(s.breakpoints(0.6, 1.0).is_empty());
}

#[test]
fn windowed_sine_is_active_on_half_open_window() {
    let (a, f, phi) = (2.0, 1.5, 0.3);
    let s = Signal::Sine {
        amplitude: a,
        frequency: f,
        phase: phi,
        t_on: 1.0,
        t_off: Some(2.2),
    };
    let sine = |t: f64| a * (TAU * f * t + phi).sin();
    assert_eq!(s.value(0.999), 0.0);
    assert!((s.value(1.0) - sine(1.0)).abs() < EPS, "on at t_on");
    assert_eq!(s.left_limit(1.0), 0.0);
    assert!((s.value(1.7) - sine(1.7)).abs() < EPS);
    assert_eq!(s.value(2.2), 0.0, "off at t_off");
    assert!((s.left_limit(2.2) - sine(2.2)).abs() < EPS);
    let bps = s.breakpoints(0.0, 5.0);
    assert_eq!(bps.len(), 2);
    assert_eq!((bps[0].time, bps[1].time), (1.0, 2.2));
    assert!((bps[0].right - sine(1.0)).abs() < EPS && bps[0].left == 0.0);
    assert!((bps[1].left - sine(2.2)).abs() < EPS && bps[1].right == 0.0);
    // A sine switching on at a zero crossing is a kink: listed with left == right.
    let k = Signal::Sine {
        amplitude: 1.0,
        frequency: 1.0,
        phase: 0.0,
        t_on: 0.0,
        t_off: None,
    };
    let bps = k.breakpoints(-1.0, 1.0);
    assert_eq!(
        bps,
        vec![Breakpoint {
            time: 0.0,
            left: 0.0,
            right: 0.0
        }]
    );
}

#[test]
fn paper_identification_input_documented_values() {
    let u = paper_identification_input();
    u.validate().expect("paper input is valid");
    let f = |t: f64| {
        let mut v = if t >= 0.5 { 6.0 } else { 0.0 };
        if (3.0..9.0).contains(&t) {
            v += 3.0 * (TAU * 0.5 * t).sin();
        }
        if (9.0..=15.0).contains(&t) {
            v += 2.5 * (TAU * 1.4 * t).sin();
        }
        v
    };
    for &t in &[
        0.0, 0.25, 0.5, 1.0, 2.999, 3.0, 3.5, 4.0, 8.75, 8.9999, 9.0, 9.1, 12.0, 14.999, 15.0,
    ] {
        assert!(
            (u.value(t) - f(t)).abs() < EPS,
            "t = {t}: {} vs {}",
            u.value(t),
            f(t)
        );
    }
    // Closed-form checks: sin(2π·0.5·3.5) = sin(3.5π) = −1; sin(2π·1.4·9) = sin(25.2π) = sin(1.2π).
    assert!((u.value(3.5) - (6.0 - 3.0)).abs() < EPS);
    assert!((u.value(9.0) - (6.0 + 2.5 * (1.2 * PI).sin())).abs() < EPS);
    // Both sides of each jump.
    let bps = u.breakpoints(0.0, 15.0);
    assert_eq!(bps.len(), 3);
    assert_eq!(
        bps[0],
        Breakpoint {
            time: 0.5,
            left: 0.0,
            right: 6.0
        }
    );
    assert_eq!(bps[1].time, 3.0);
    assert!(
        (bps[1].left - 6.0).abs() < EPS && (bps[1].right - 6.0).abs() < EPS,
        "sin(3π) = 0: a kink"
    );
    assert_eq!(bps[2].time, 9.0);
    assert!(
        (bps[2].left - 6.0).abs() < EPS,
        "3·sin(9π) = 0 from the left"
    );
    assert!((bps[2].right - (6.0 + 2.5 * (1.2 * PI).sin())).abs() < EPS);
    // Sampling uses t0 + i·dt exactly.
    let s = u.sample(0.0, 0.002, 7501);
    assert_eq!(s.len(), 7501);
    assert_eq!(s[249], 0.0);
    assert_eq!(s[250], 6.0);
    assert!((s[4500] - u.value(9.0)).abs() == 0.0);
}

#[test]
fn paper_validation_input_documented_values() {
    let u = paper_validation_input();
    u.validate().expect("paper input is valid");
    let (f0, f1, t_end) = (0.2, 3.0, 15.0);
    let f = |t: f64| {
        2.5 * (TAU * (f0 * t + (f1 - f0) / (2.0 * t_end) * t * t)).sin()
            + if t >= 1.0 { 1.0 } else { 0.0 }
    };
    for &t in &[0.0, 0.5, 0.999, 1.0, 2.0, 7.5, 10.0, 14.99] {
        assert!((u.value(t) - f(t)).abs() < EPS, "t = {t}");
    }
    // At t = 15 the chirp window has closed; the formula gives 2.5·sin(48π) = 0 too.
    assert!((u.value(15.0) - f(15.0)).abs() < 1e-12);
    let bps = u.breakpoints(0.0, 15.0);
    let times: Vec<f64> = bps.iter().map(|b| b.time).collect();
    assert_eq!(times, vec![0.0, 1.0, 15.0]);
    assert!((bps[1].jump() - 1.0).abs() < EPS);
}

/// Phase of a chirp computed independently of the crate, for the derivative check.
fn chirp_phase(sweep: Sweep, f0: f64, f1: f64, t_end: f64, tau: f64) -> f64 {
    match sweep {
        Sweep::Linear => TAU * (f0 * tau + (f1 - f0) / (2.0 * t_end) * tau * tau),
        Sweep::Logarithmic => {
            let k = (f1 / f0).ln() / t_end;
            TAU * f0 * ((k * tau).exp() - 1.0) / k
        }
    }
}

#[test]
fn chirp_instantaneous_frequency_start_middle_end() {
    let (f0, f1, t_end, t_start) = (0.5, 8.0, 4.0, 1.0);
    for sweep in [Sweep::Linear, Sweep::Logarithmic] {
        let c = Signal::Chirp {
            amplitude: 1.5,
            f0,
            f1,
            duration: t_end,
            phase: 0.2,
            sweep,
            t_start,
        };
        c.validate().expect("valid chirp");
        let mid = match sweep {
            Sweep::Linear => (f0 + f1) / 2.0,
            Sweep::Logarithmic => (f0 * f1).sqrt(), // geometric mean
        };
        let just_before_end = t_start + t_end - 1e-9;
        for (t, expected) in [
            (t_start, f0),
            (t_start + t_end / 2.0, mid),
            (just_before_end, f1),
        ] {
            let fi = c.instantaneous_frequency(t).expect("inside the sweep");
            assert!(
                (fi - expected).abs() < 1e-7 * f1,
                "{sweep:?} t = {t}: {fi} vs {expected}"
            );
            // The reported frequency is the derivative of the phase: central difference,
            // truncation error h²/6·|θ'''| ≲ 1e-6 for h = 1e-4 (θ''' ≤ 2π·f1·ln(16)²/T²).
            let tau = (t - t_start).clamp(1e-4, t_end - 1e-4);
            let h = 1e-4;
            let num = (chirp_phase(sweep, f0, f1, t_end, tau + h)
                - chirp_phase(sweep, f0, f1, t_end, tau - h))
                / (2.0 * h * TAU);
            let fi_tau = c.instantaneous_frequency(t_start + tau).expect("inside");
            assert!(
                (num - fi_tau).abs() < 1e-5,
                "{sweep:?}: numeric {num} vs {fi_tau}"
            );
        }
        // Values follow A·sin(θ(τ) + φ), and the chirp is 0 outside [t_start, t_start + T).
        for &tau in &[0.0, 0.37, 1.9, 3.3] {
            let expected = 1.5 * (chirp_phase(sweep, f0, f1, t_end, tau) + 0.2).sin();
            assert!((c.value(t_start + tau) - expected).abs() < 1e-10);
        }
        assert_eq!(c.value(t_start - 1e-9), 0.0);
        assert_eq!(c.value(t_start + t_end), 0.0);
        assert!(c.instantaneous_frequency(t_start + t_end).is_none());
        let bps = c.breakpoints(0.0, 10.0);
        assert_eq!(bps.len(), 2);
        assert_eq!(bps[0].left, 0.0);
        assert!((bps[0].right - 1.5 * 0.2f64.sin()).abs() < EPS);
        assert_eq!(bps[1].time, t_start + t_end);
        assert_eq!(bps[1].right, 0.0);
    }
}

#[test]
fn stepped_sine_segments_switch_at_their_windows() {
    let s = Signal::SteppedSine {
        segments: vec![
            SineSegment {
                frequency: 1.0,
                amplitude: 1.0,
                t_on: 0.0,
                t_off: Some(1.25),
                phase: 0.0,
            },
            SineSegment {
                frequency: 2.0,
                amplitude: 3.0,
                t_on: 1.25,
                t_off: Some(2.0),
                phase: 0.0,
            },
        ],
    };
    s.validate().expect("valid");
    // sin(2π·1.25) = 1 from the left; 3·sin(2π·2·1.25) = 3·sin(5π) = 0 from the right.
    let bps = s.breakpoints(0.0, 3.0);
    assert_eq!(bps.len(), 3);
    assert!((bps[1].left - 1.0).abs() < EPS && bps[1].right.abs() < EPS);
    assert_eq!(s.instantaneous_frequency(1.25), Some(2.0));
    assert_eq!(s.instantaneous_frequency(2.0), None);
}

#[test]
fn sums_and_scaled_copies_merge_coincident_breakpoints() {
    let a = Signal::Step {
        amplitude: 2.0,
        time: 1.0,
    };
    let b = Signal::Step {
        amplitude: -0.5,
        time: 1.0,
    };
    let c = Signal::Sine {
        amplitude: 1.0,
        frequency: 0.25,
        phase: 0.0,
        t_on: 1.0,
        t_off: Some(3.0),
    };
    let sum = (a + b + c).scaled(3.0);
    sum.validate().expect("valid");
    let bps = sum.breakpoints(0.0, 5.0);
    assert_eq!(bps.len(), 2, "the three events at t = 1 are one breakpoint");
    assert_eq!(bps[0].time, 1.0);
    assert_eq!(bps[0].left, 0.0);
    let right = 3.0 * (2.0 - 0.5 + (TAU * 0.25).sin());
    assert!((bps[0].right - right).abs() < EPS);
    // At t = 3 the sine, sin(1.5π) = −1, switches off on top of the steps.
    assert!((bps[1].left - 3.0 * (1.5 - 1.0)).abs() < EPS);
    assert!((bps[1].right - 3.0 * 1.5).abs() < EPS);
    // value() agrees with the terms at any t.
    for &t in &[0.3, 1.0, 2.1, 3.0, 4.4] {
        let direct = 3.0
            * ((if t >= 1.0 { 1.5 } else { 0.0 })
                + if (1.0..3.0).contains(&t) {
                    (TAU * 0.25 * t).sin()
                } else {
                    0.0
                });
        assert!((sum.value(t) - direct).abs() < EPS);
    }
}

#[test]
fn sample_into_matches_value() {
    let u = paper_validation_input();
    let mut out = [0.0; 64];
    u.sample_into(0.5, 0.01, &mut out);
    for (i, v) in out.iter().enumerate() {
        assert_eq!(*v, u.value(0.5 + i as f64 * 0.01));
    }
}
