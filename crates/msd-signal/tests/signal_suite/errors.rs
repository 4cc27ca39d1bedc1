//! Every invalid signal parameter returns a specific error; nothing panics.

use msd_signal::{
    ClippingOptions, Multisine, MultisineSpec, Prbs, PrbsSpec, Signal, SignalError, SineSegment,
    Sweep,
};

fn param_err(r: Result<(), SignalError>, name: &str) -> bool {
    matches!(r, Err(SignalError::InvalidParameter { ref parameter, .. }) if parameter == name)
}

fn sine(amplitude: f64, frequency: f64, t_on: f64, t_off: Option<f64>) -> Signal {
    Signal::Sine {
        amplitude,
        frequency,
        phase: 0.0,
        t_on,
        t_off,
    }
}

fn chirp(f0: f64, f1: f64, duration: f64, sweep: Sweep) -> Signal {
    Signal::Chirp {
        amplitude: 1.0,
        f0,
        f1,
        duration,
        phase: 0.0,
        sweep,
        t_start: 0.0,
    }
}

#[test]
fn nan_and_infinite_parameters() {
    assert!(param_err(
        Signal::Constant { value: f64::NAN }.validate(),
        "value"
    ));
    assert!(param_err(
        Signal::Step {
            amplitude: 1.0,
            time: f64::INFINITY
        }
        .validate(),
        "time"
    ));
    assert!(param_err(
        sine(f64::NAN, 1.0, 0.0, None).validate(),
        "amplitude"
    ));
    assert!(param_err(
        sine(1.0, 1.0, f64::NEG_INFINITY, None).validate(),
        "t_on"
    ));
    assert!(param_err(
        Signal::Constant { value: 1.0 }.scaled(f64::NAN).validate(),
        "gain"
    ));
    assert!(
        chirp(0.1, 1.0, 2.0, Sweep::Linear)
            .scaled(1.0)
            .validate()
            .is_ok()
    );
    assert!(param_err(
        chirp(f64::NAN, 1.0, 2.0, Sweep::Linear)
            .scaled(1.0)
            .validate(),
        "signal.f0"
    ));
}

#[test]
fn negative_frequency_or_duration() {
    let e = sine(1.0, -0.5, 0.0, None).validate();
    assert!(
        matches!(e, Err(SignalError::InvalidParameter { ref parameter, value, .. }) if parameter == "frequency" && value == -0.5)
    );
    assert!(param_err(
        chirp(-0.1, 1.0, 2.0, Sweep::Linear).validate(),
        "f0"
    ));
    assert!(param_err(
        chirp(0.1, 1.0, -2.0, Sweep::Linear).validate(),
        "duration"
    ));
    assert!(param_err(
        chirp(0.1, 1.0, 0.0, Sweep::Linear).validate(),
        "duration"
    ));
}

#[test]
fn log_chirp_needs_positive_frequencies() {
    assert!(chirp(0.0, 1.0, 2.0, Sweep::Linear).validate().is_ok());
    assert!(param_err(
        chirp(0.0, 1.0, 2.0, Sweep::Logarithmic).validate(),
        "f0"
    ));
    assert!(param_err(
        chirp(0.5, 0.0, 2.0, Sweep::Logarithmic).validate(),
        "f1"
    ));
    assert!(param_err(
        chirp(0.5, -1.0, 2.0, Sweep::Logarithmic).validate(),
        "f1"
    ));
}

#[test]
fn reversed_windows_and_overlapping_segments() {
    assert!(matches!(
        sine(1.0, 1.0, 2.0, Some(1.0)).validate(),
        Err(SignalError::ReversedWindow { t_on, t_off, .. }) if t_on == 2.0 && t_off == 1.0
    ));
    assert!(matches!(
        sine(1.0, 1.0, 2.0, Some(2.0)).validate(),
        Err(SignalError::ReversedWindow { .. })
    ));
    let seg = |t_on, t_off| SineSegment {
        frequency: 1.0,
        amplitude: 1.0,
        t_on,
        t_off,
        phase: 0.0,
    };
    let s = Signal::SteppedSine {
        segments: vec![seg(0.0, Some(2.0)), seg(1.5, Some(3.0))],
    };
    assert!(matches!(
        s.validate(),
        Err(SignalError::OverlappingSegments { index: 1, .. })
    ));
    let s = Signal::SteppedSine {
        segments: vec![seg(0.0, None), seg(5.0, Some(6.0))],
    };
    assert!(matches!(
        s.validate(),
        Err(SignalError::OverlappingSegments { index: 1, .. })
    ));
    let s = Signal::Sum {
        terms: vec![
            Signal::Constant { value: 0.0 },
            Signal::SteppedSine {
                segments: vec![seg(1.0, Some(0.5))],
            },
        ],
    };
    assert!(matches!(
        s.validate(),
        Err(SignalError::ReversedWindow { ref parameter, .. }) if parameter == "terms[1].segments[0]"
    ));
    let s = Signal::Sum {
        terms: vec![sine(1.0, f64::NAN, 0.0, None)],
    };
    assert!(param_err(s.validate(), "terms[0].frequency"));
    assert!(matches!(
        Signal::SteppedSine { segments: vec![] }.validate(),
        Err(SignalError::EmptyData { .. })
    ));
}

#[test]
fn prbs_order_and_clock_out_of_range() {
    for order in [0, 1, 25, 64] {
        let r = Prbs::new(PrbsSpec {
            order,
            ..PrbsSpec::default()
        });
        assert!(
            matches!(r, Err(SignalError::PrbsOrder { order: o, min: 2, max: 24 }) if o == order)
        );
    }
    for bad in [0.0, -0.01, f64::NAN] {
        let r = Prbs::new(PrbsSpec {
            clock_period: bad,
            ..PrbsSpec::default()
        });
        assert!(
            matches!(r, Err(SignalError::InvalidParameter { ref parameter, .. }) if parameter == "clock_period")
        );
    }
}

#[test]
fn multisine_parameters() {
    let ok = MultisineSpec::default();
    let bad = |s: MultisineSpec| Multisine::new(s).map(|_| ());
    assert!(param_err(
        bad(MultisineSpec {
            base_frequency: 0.0,
            ..ok
        }),
        "base_frequency"
    ));
    assert!(param_err(bad(MultisineSpec { f_min: -1.0, ..ok }), "f_min"));
    assert!(param_err(
        bad(MultisineSpec {
            f_max: 0.05,
            f_min: 0.1,
            ..ok
        }),
        "f_max"
    ));
    assert!(param_err(
        bad(MultisineSpec {
            rms: f64::NAN,
            ..ok
        }),
        "rms"
    ));
    assert!(matches!(
        bad(MultisineSpec {
            base_frequency: 1.0,
            f_min: 0.2,
            f_max: 0.8,
            ..ok
        }),
        Err(SignalError::NoMultisineLines { .. })
    ));
    assert!(matches!(
        bad(MultisineSpec {
            base_frequency: 1e-3,
            f_max: 1e3,
            ..ok
        }),
        Err(SignalError::TooManyLines { .. })
    ));
    let clip = Some(ClippingOptions {
        iterations: 10,
        clip_ratio: 1.5,
    });
    assert!(param_err(
        bad(MultisineSpec {
            crest_factor_reduction: clip,
            ..ok
        }),
        "crest_factor_reduction.clip_ratio"
    ));
}

#[test]
fn error_messages_name_parameter_value_and_range() {
    let e = chirp(0.0, 1.0, 2.0, Sweep::Logarithmic)
        .validate()
        .expect_err("invalid");
    assert_eq!(
        e.to_string(),
        "invalid parameter `f0` = 0: expected a finite value > 0"
    );
    let e = Prbs::new(PrbsSpec {
        order: 30,
        ..PrbsSpec::default()
    })
    .expect_err("invalid");
    assert_eq!(
        e.to_string(),
        "PRBS order 30 out of range: expected 2 ..= 24"
    );
}
