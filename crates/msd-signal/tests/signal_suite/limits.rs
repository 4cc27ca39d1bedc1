//! The limits that keep a validated signal finite, each found by the property tests
//! (tests/tests/properties): a frequency, sweep or amplitude sum whose values would
//! overflow is refused by name; noise levels too large for their draws are refused; a
//! PRBS lists its breakpoints in bounded time, and says beforehand how many there are.

use msd_signal::{
    MultisineSpec, NoiseStream, Prbs, PrbsSpec, Signal, SignalError, Sweep, gaussian_noise,
};

fn refused(s: &Signal, parameter: &str) {
    match s.validate() {
        Err(SignalError::InvalidParameter { parameter: p, .. }) => assert_eq!(p, parameter),
        other => panic!("expected InvalidParameter `{parameter}`, got {other:?}"),
    }
}

fn sine(amplitude: f64, frequency: f64) -> Signal {
    Signal::Sine {
        amplitude,
        frequency,
        phase: 0.0,
        t_on: 0.0,
        t_off: None,
    }
}

/// f = f64::MAX made 2π·f·t infinite and the value NaN.
#[test]
fn frequencies_above_a_terahertz_are_refused() {
    refused(&sine(1.0, f64::MAX), "frequency");
    refused(&sine(1.0, 1.1e12), "frequency");
    let ok = sine(1.0, Signal::MAX_FREQUENCY);
    ok.validate().unwrap();
    for t in [1.0, 1e100, 1e280, -1e280] {
        assert!(ok.value(t).is_finite(), "u({t})");
    }
}

/// A chirp's phase at the end of the sweep must be finite: a huge duration at a high
/// frequency, or a logarithmic sweep whose f1/f0 overflows, is refused.
#[test]
fn sweeps_whose_phase_overflows_are_refused() {
    let chirp = |f0: f64, f1: f64, duration: f64, sweep| Signal::Chirp {
        amplitude: 1.0,
        f0,
        f1,
        duration,
        phase: 0.0,
        sweep,
        t_start: 0.0,
    };
    refused(&chirp(1e12, 1e12, 1e300, Sweep::Linear), "duration");
    // f1/f0 overflows (1e312) or underflows to 0: ln(f1/f0) does not exist.
    refused(&chirp(1e-300, 1e12, 10.0, Sweep::Logarithmic), "f1");
    refused(&chirp(219.5, 5e-324, 69.7, Sweep::Logarithmic), "f1");
    let ok = chirp(1e-3, 1e12, 10.0, Sweep::Logarithmic);
    ok.validate().unwrap();
    for i in 0..=1000 {
        assert!(ok.value(i as f64 * 0.01).is_finite());
    }
}

/// Two terms of 1e308 add up to infinity; so does a gain of 1e300 on 1e300.
#[test]
fn sums_and_gains_that_overflow_are_refused() {
    let step = |amplitude| Signal::Step {
        amplitude,
        time: 0.0,
    };
    refused(
        &Signal::Sum {
            terms: vec![step(1e308), step(-1e308)],
        },
        "terms",
    );
    refused(&step(1e300).scaled(1e300), "gain");
    let nested = Signal::Sum {
        terms: vec![step(1.0), step(1e300).scaled(1e10)],
    };
    refused(&nested, "terms[1].gain");
    let ok = Signal::Sum {
        terms: vec![step(f64::MAX / 2.0), sine(f64::MAX / 2.0, 1.0)],
    };
    ok.validate().unwrap();
    assert!(ok.value(0.25).is_finite());
}

/// A sine's reversed window at the top level names `t_off` (it used to name nothing).
#[test]
fn a_reversed_top_level_window_names_t_off() {
    let s = Signal::Sine {
        amplitude: 1.0,
        frequency: 1.0,
        phase: 0.0,
        t_on: 2.0,
        t_off: Some(2.0),
    };
    match s.validate().unwrap_err() {
        e @ SignalError::ReversedWindow { .. } => {
            assert_eq!(
                e.to_string(),
                "reversed window `t_off`: t_on = 2 must be < t_off = 2"
            )
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn multisine_rms_and_band_are_bounded() {
    let spec = |rms, f_max| MultisineSpec {
        rms,
        f_max,
        ..MultisineSpec::default()
    };
    for (s, name) in [(spec(1e308, 5.0), "rms"), (spec(1.0, 2e12), "f_max")] {
        match msd_signal::Multisine::new(s) {
            Err(SignalError::InvalidParameter { parameter, .. }) => assert_eq!(parameter, name),
            other => panic!("{name}: {other:?}"),
        }
    }
}

/// σ = f64::MAX gave ±inf noise; σ up to 1e300 stays finite.
#[test]
fn noise_levels_beyond_1e300_are_refused() {
    let err = gaussian_noise(1, "x", f64::MAX, 4).unwrap_err();
    assert!(
        matches!(err, SignalError::InvalidParameter { ref parameter, .. } if parameter == "sigma"),
        "{err:?}"
    );
    let e = gaussian_noise(1, "x", NoiseStream::MAX_SIGMA, 100_000).unwrap();
    assert!(e.iter().all(|v| v.is_finite()));
}

/// A PRBS whose clock period is below the resolution of t near its start used to list
/// chip edges forever (the edge time stopped advancing); now the listing ends, and
/// `max_breakpoints` bounds it beforehand.
#[test]
fn prbs_breakpoints_end_and_are_bounded() {
    let prbs = |clock_period, t_start| {
        Signal::Prbs(
            Prbs::new(PrbsSpec {
                order: 7,
                clock_period,
                amplitude: 1.0,
                t_start,
            })
            .unwrap(),
        )
    };
    // t + 20 == t at 1e300: the span holds no chip at all.
    let far = prbs(1.0, 1e300);
    let bps = far.breakpoints(1e300 - 1.0, 1e300 + 20.0);
    assert!(bps.len() as f64 <= far.max_breakpoints(1e300 - 1.0, 1e300 + 20.0));
    assert!(bps.len() <= 2, "{bps:?}");
    // A 1 ps clock over 15 s: 1.5e13 edges, said before listing.
    assert!(prbs(1e-12, 0.0).max_breakpoints(0.0, 15.0) > 1e13);
    // An ordinary one: the bound holds the list.
    let ok = prbs(0.01, 0.0);
    let n = ok.breakpoints(0.0, 15.0).len();
    assert!(n > 100 && n as f64 <= ok.max_breakpoints(0.0, 15.0));
}
