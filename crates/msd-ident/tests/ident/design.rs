//! Excitation design: the reference's Cramér–Rao bound, the limits on the simulated
//! response, the criterion against the reference, and the refused constraints.

use msd_ident::{
    Backend, Excitation, IdentError, InitialState, Parameters,
    design::{
        Criterion, DesignOptions, InputComparison, Normalise, RobustBox, StepOption, StrokeOn,
        design_input,
    },
    simulate,
};
use msd_signal::{Signal, paper_identification_input};

fn paper() -> Excitation {
    Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501).unwrap()
}

/// The paper input's Cramér–Rao standard deviations are the (m 0.00145 kg,
/// c 0.00524 N·s/m, k 0.0645 N/m) within 1 % (they are given to three digits).
#[test]
fn the_paper_inputs_bound_is_the_published_one() {
    let p = paper();
    let c = InputComparison::new(&Parameters::PAPER, &p, &p, 2.5e-3).unwrap();
    for (se, expected) in c.reference.iter().zip([0.00145, 0.00524, 0.0645]) {
        assert!((se / expected - 1.0).abs() < 0.01, "{se} vs {expected}");
    }
    assert!((c.determinant_ratio - 1.0).abs() < 1e-12);
}

/// A D-optimal design with a step: the sampled force, the RMS force and the exact
/// simulated displacement on the prior stay within their limits and reach the binding
/// one (to 1e-6), every line lies in the band, the step is at least its minimum (a
/// hard limit: the step is raised to it and the multisine scaled down if needed), and
/// the design beats the reference on its criterion.
#[test]
fn a_design_keeps_its_limits_on_the_simulated_response() {
    let reference = paper();
    let mut options = DesignOptions {
        lines: 30,
        iterations: 40,
        ..DesignOptions::default()
    };
    let c = &mut options.constraints;
    c.band_hz = [0.4, 3.0];
    c.max_rms_force = Some(5.0);
    c.step = Some(StepOption {
        time: 0.5,
        min_amplitude: 4.0,
    });
    let design = design_input(&Parameters::PAPER, &reference, 2.5e-3, &options).unwrap();
    let x = simulate(
        &Parameters::PAPER,
        &design.excitation,
        InitialState::REST,
        &Backend::EXACT,
    )
    .unwrap();
    let u = design.excitation.samples();
    let peak = |v: &[f64]| v.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let rms = (u.iter().map(|u| u * u).sum::<f64>() / u.len() as f64).sqrt();
    let ratios = [peak(u) / 9.0, peak(&x) / 0.1115, rms / 5.0];
    assert!(ratios.iter().all(|r| *r <= 1.0), "{ratios:?}");
    assert!(
        ratios.iter().any(|r| *r > 1.0 - 1e-6),
        "no limit reached: {ratios:?}"
    );
    assert!((design.peak_stroke - peak(&x)).abs() <= 1e-12, "{design}");
    let Signal::Sum { terms } = &design.signal else {
        panic!("a sum")
    };
    for t in terms {
        match t {
            Signal::Sine { frequency, .. } => {
                assert!((0.4..=3.0).contains(frequency), "{frequency}")
            }
            Signal::Step { amplitude, time } => {
                assert_eq!(*time, 0.5);
                assert!(amplitude.abs() >= 4.0, "step {amplitude}");
            }
            other => panic!("unexpected term {other:?}"),
        }
    }
    assert!(design.comparison.determinant_ratio < 1.0, "{design}");
}

/// A robust design (4 plants in ±30 %) keeps the stroke on every plant's simulated
/// response with `stroke_on = every_plant` (the largest at the limit, to 1e-6), and
/// reports each plant's peak as simulated; on the prior only, the softer plants of the
/// box go past the limit (and the design says so).
#[test]
fn a_robust_design_keeps_the_stroke_on_every_plant_when_asked() {
    let reference = paper();
    let mut options = DesignOptions {
        lines: 20,
        iterations: 20,
        robust: RobustBox {
            plants: 4,
            ..RobustBox::default()
        },
        ..DesignOptions::default()
    };
    let peak = |p: &Parameters, e: &Excitation| {
        let x = simulate(p, e, InitialState::REST, &Backend::EXACT).unwrap();
        x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
    };
    let prior_only = design_input(&Parameters::PAPER, &reference, 2.5e-3, &options).unwrap();
    options.constraints.stroke_on = StrokeOn::EveryPlant;
    let every = design_input(&Parameters::PAPER, &reference, 2.5e-3, &options).unwrap();
    for design in [&prior_only, &every] {
        for (p, reported) in design.plants.iter().zip(&design.plant_strokes) {
            assert!(
                (peak(p, &design.excitation) - reported).abs() <= 1e-12,
                "{design}"
            );
        }
    }
    let top = |d: &msd_ident::design::Design| d.plant_strokes.iter().fold(0.0f64, |m, x| m.max(*x));
    assert!(top(&prior_only) > 0.1115, "{prior_only}");
    assert!(
        prior_only.to_string().contains("holds on the prior only"),
        "{prior_only}"
    );
    let (top, force) = (top(&every), every.peak_force);
    assert!(
        top <= 0.1115 && (top > 0.1115 * (1.0 - 1e-6) || force > 9.0 * (1.0 - 1e-6)),
        "{every}"
    );
    assert!(
        every.to_string().contains("holds on every plant"),
        "{every}"
    );
}

/// Each criterion's design (default settings: 60 lines, 3 × 100 iterations) is at least
/// as good as the other two on its own measure: the D design on det(cov), the A design
/// on the trace, the minimax design (relative to the reference's standard errors) on
/// the worst ratio; the optimiser is local, hence a 2 % allowance.
#[test]
fn each_criterion_wins_on_its_own_measure() {
    let reference = paper();
    let run = |criterion, normalise| {
        let options = DesignOptions {
            criterion,
            normalise,
            ..DesignOptions::default()
        };
        design_input(&Parameters::PAPER, &reference, 2.5e-3, &options)
            .unwrap()
            .comparison
    };
    let d = run(Criterion::DOptimal, Normalise::Prior);
    let a = run(Criterion::AOptimal, Normalise::Prior);
    let minimax = run(Criterion::Minimax, Normalise::Reference);
    let all = format!("{d}\n{a}\n{minimax}");
    assert!(
        d.determinant_ratio <= 1.02 * a.determinant_ratio.min(minimax.determinant_ratio),
        "{all}"
    );
    assert!(
        a.trace_ratio <= 1.02 * d.trace_ratio.min(minimax.trace_ratio),
        "{all}"
    );
    assert!(
        minimax.worst_ratio <= 1.02 * d.worst_ratio.min(a.worst_ratio),
        "{all}"
    );
}

fn refused(edit: impl Fn(&mut DesignOptions)) -> IdentError {
    let mut options = DesignOptions::default();
    edit(&mut options);
    design_input(&Parameters::PAPER, &paper(), 2.5e-3, &options).unwrap_err()
}

#[test]
fn bad_constraints_are_refused_by_their_key() {
    // A 20 N step deflects the 120 N/m prior by 1/6 m, more than the 0.1115 m stroke.
    let err = refused(|o| {
        o.constraints.max_force = 30.0;
        o.constraints.step = Some(StepOption {
            time: 0.5,
            min_amplitude: 20.0,
        });
    });
    assert!(
        matches!(
            err,
            IdentError::InvalidDesign {
                key: "constraints.max_stroke",
                ..
            }
        ),
        "{err}"
    );
    assert!(
        err.to_string().contains("static deflection 0.16666"),
        "{err}"
    );
    // An 8 N step deflects the prior by 1/15 m statically, but overshoots to 0.123 m
    // (1 + e^{−πζ/√(1−ζ²)} = 1.85 times, ζ = 0.052).
    let err = refused(|o| {
        o.constraints.step = Some(StepOption {
            time: 0.5,
            min_amplitude: 8.0,
        });
    });
    assert!(
        err.to_string().starts_with("invalid design.constraints.max_stroke = 0.1115: expected at least the peak response 0.123"),
        "{err}"
    );
    // A 6 N step from 0.5 s to 15 s has an RMS of 6·√(14.5/15) = 5.90 N on its own: an
    // RMS limit of 3 N cannot hold, and the error names that limit with its value.
    let err = refused(|o| {
        o.iterations = 2;
        o.constraints.max_rms_force = Some(3.0);
        o.constraints.step = Some(StepOption {
            time: 0.5,
            min_amplitude: 6.0,
        });
    });
    assert!(
        matches!(
            err,
            IdentError::InvalidDesign {
                key: "constraints.max_rms_force",
                value: 3.0,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("RMS force 5.8"), "{err}");
    let err = refused(|o| o.constraints.band_hz = [2.0, 2.0]);
    assert!(
        matches!(
            err,
            IdentError::InvalidDesign {
                key: "constraints.band_hz",
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("the band is empty"), "{err}");
    let err = refused(|o| o.constraints.band_hz = [1.0, 260.0]);
    assert_eq!(
        err.to_string(),
        "invalid design.constraints.band_hz = 260: expected an upper edge below the Nyquist frequency 250 Hz of the record"
    );
    let err = refused(|o| o.constraints.band_hz = [0.01, 0.05]);
    assert!(
        err.to_string()
            .contains("a line of the multisine's frequency grid"),
        "{err}"
    );
    for period in [0.0, 0.005, 16.0, f64::NAN] {
        let err = refused(|o| o.period = Some(period));
        assert!(
            matches!(err, IdentError::InvalidDesign { key: "period", .. }),
            "{err}"
        );
    }
    let err = refused(|o| o.robust.spread = 1.5);
    assert!(
        matches!(
            err,
            IdentError::InvalidDesign {
                key: "robust.spread",
                ..
            }
        ),
        "{err}"
    );
}
