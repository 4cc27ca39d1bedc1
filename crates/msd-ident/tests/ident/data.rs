//! Data sets, excitations, derived quantities and the simulators.

use msd_ident::sensitivity::sensitivities;
use msd_ident::{
    Backend, DataSet, Excitation, IdentError, InitialState, PaperExperiment, Parameters, simulate,
};
use msd_ode::Hold;
use msd_signal::{paper_identification_input, paper_validation_input};

#[test]
fn derived_quantities_of_the_paper_plant() {
    let p = Parameters::PAPER;
    assert!((p.natural_frequency() - (120.0f64 / 2.5).sqrt()).abs() < 1e-12);
    assert!((p.natural_frequency() - 6.9282).abs() < 1e-4);
    assert!((p.natural_frequency_hz() - 1.1027).abs() < 1e-4);
    assert!((p.damping_ratio() - 0.051962).abs() < 1e-6);
    let wd = p.damped_natural_frequency().expect("underdamped");
    assert!((wd - p.natural_frequency() * (1.0 - p.damping_ratio().powi(2)).sqrt()).abs() < 1e-12);
    assert!((p.quality_factor() - 1.0 / (2.0 * p.damping_ratio())).abs() < 1e-12);
    assert_eq!(p.static_compliance(), 1.0 / 120.0);
    assert!(
        Parameters {
            damping: 200.0,
            ..p
        }
        .damped_natural_frequency()
        .is_none()
    );
}

#[test]
fn backends_agree_within_the_ode_tolerance() {
    for signal in [paper_identification_input(), paper_validation_input()] {
        let e = Excitation::from_signal(signal, 0.0, 0.002, 7501).expect("input");
        let exact =
            simulate(&Parameters::PAPER, &e, InitialState::REST, &Backend::EXACT).expect("exact");
        let ode =
            simulate(&Parameters::PAPER, &e, InitialState::REST, &Backend::PAPER).expect("ode45");
        let peak = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let worst = exact
            .iter()
            .zip(&ode)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        // RelTol 1e-6 on a state of size `peak`; a few hundred steps of accumulation.
        assert!(
            worst <= 1e-6 * peak * 100.0,
            "worst {worst:e} vs peak {peak}"
        );
        assert!(worst > 0.0);
    }
}

#[test]
fn sensitivities_match_central_differences() {
    let e = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 2001).expect("input");
    let p = Parameters::PAPER;
    let start = InitialState {
        displacement: 0.01,
        velocity: 0.05,
    };
    let mut exact = vec![[0.0; 5]; e.len()];
    sensitivities(&p, &e, start, Hold::Cubic, |i, s| {
        exact[i] = [
            s.parameters[0],
            s.parameters[1],
            s.parameters[2],
            s.initial_state[0],
            s.initial_state[1],
        ];
    })
    .expect("sensitivities");
    let sim = |p: Parameters, s: InitialState| simulate(&p, &e, s, &Backend::EXACT).expect("sim");
    let mut v = p.to_array();
    for j in 0..5 {
        let h = if j < 3 { 1e-5 * v[j] } else { 1e-6 };
        let (plus, minus) = if j < 3 {
            v[j] += h;
            let a = sim(Parameters::from_array(v), start);
            v[j] -= 2.0 * h;
            let b = sim(Parameters::from_array(v), start);
            v[j] += h;
            (a, b)
        } else {
            let mut s1 = start;
            let mut s2 = start;
            if j == 3 {
                s1.displacement += h;
                s2.displacement -= h;
            } else {
                s1.velocity += h;
                s2.velocity -= h;
            }
            (sim(p, s1), sim(p, s2))
        };
        let scale = exact.iter().map(|r| r[j].abs()).fold(0.0, f64::max);
        for i in 0..e.len() {
            let fd = (plus[i] - minus[i]) / (2.0 * h);
            // Central differences err by O(h²) relative plus rounding ε·|x|/h.
            assert!(
                (fd - exact[i][j]).abs() <= 1e-6 * scale,
                "column {j}, sample {i}: {fd} vs {}",
                exact[i][j]
            );
        }
    }
}

#[test]
fn excitation_places_breakpoints_on_the_grid() {
    let e = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501).expect("input");
    let indices: Vec<usize> = e.breakpoints().iter().map(|b| b.index).collect();
    assert_eq!(indices, vec![250, 1500, 4500]);
    assert_eq!(
        (e.breakpoints()[0].left, e.breakpoints()[0].right),
        (0.0, 6.0)
    );
    // Off-grid: a step at 0.501 s marks both neighbours.
    let off = msd_signal::Signal::Step {
        amplitude: 1.0,
        time: 0.501,
    };
    let e = Excitation::from_signal(off, 0.0, 0.002, 1000).expect("input");
    let indices: Vec<usize> = e.breakpoints().iter().map(|b| b.index).collect();
    assert_eq!(indices, vec![250, 251]);
}

#[test]
fn paper_experiment_is_reproducible_and_streams_are_independent() {
    let a = PaperExperiment::generate(11).expect("a");
    let b = PaperExperiment::generate(11).expect("b");
    assert_eq!(a.identification.output, b.identification.output);
    assert_eq!(a.validation.output, b.validation.output);
    let c = PaperExperiment::generate(12).expect("c");
    assert_ne!(a.identification.output, c.identification.output);
    // Identification and validation noise are uncorrelated: |ρ| < 4/√N.
    let ea: Vec<f64> = a
        .identification
        .output
        .iter()
        .zip(&a.identification_truth)
        .map(|(y, x)| y - x)
        .collect();
    let eb: Vec<f64> = a
        .validation
        .output
        .iter()
        .zip(&a.validation_truth)
        .map(|(y, x)| y - x)
        .collect();
    let rho = msd_ident::correlation::cross_correlation(&ea, &eb, 0)[0];
    assert!(rho.abs() < 4.0 / (7501f64).sqrt(), "{rho}");
    let sd = (ea.iter().map(|v| v * v).sum::<f64>() / ea.len() as f64).sqrt();
    // Sample std within 4 standard errors (σ/√(2N)) of 2.5 mm.
    assert!(
        (sd - 0.0025).abs() <= 4.0 * 0.0025 / (2.0 * 7501f64).sqrt(),
        "{sd}"
    );
}

#[test]
fn data_set_errors_name_the_problem() {
    let e = || Excitation::from_samples(0.0, 0.01, vec![0.0; 20]).expect("input");
    assert!(matches!(
        DataSet::new("x", e(), vec![0.0; 19]),
        Err(IdentError::LengthMismatch {
            expected: 20,
            got: 19,
            ..
        })
    ));
    let mut y = vec![0.0; 20];
    y[7] = f64::NAN;
    assert!(matches!(
        DataSet::new("x", e(), y),
        Err(IdentError::NonFiniteSample {
            field: "output",
            index: 7,
            ..
        })
    ));
    let short = Excitation::from_samples(0.0, 0.01, vec![0.0; 5]).expect("input");
    assert!(matches!(
        DataSet::new("x", short, vec![0.0; 5]),
        Err(IdentError::TooFewSamples { got: 5, .. })
    ));
    assert!(matches!(
        Excitation::from_samples(0.0, 0.0, vec![0.0; 5]),
        Err(IdentError::InvalidParameter { name: "dt", .. })
    ));
    let mut t: Vec<f64> = (0..20).map(|i| i as f64 * 0.01).collect();
    t[10] = 0.1 + 0.004;
    let err = DataSet::from_columns("x", &t, vec![0.0; 20], vec![0.0; 20]).unwrap_err();
    assert!(
        matches!(err, IdentError::NonUniformTime { index: 10, .. }),
        "{err}"
    );
    let t: Vec<f64> = (0..20).map(|i| i as f64 * 0.01).collect();
    assert!(DataSet::from_columns("x", &t, vec![0.0; 20], vec![0.0; 20]).is_ok());
    let d = DataSet::from_columns("x", &t, vec![0.0; 20], vec![0.0; 20]).expect("ok");
    assert!(matches!(
        d.slice(5, 30),
        Err(IdentError::RangeOutOfBounds {
            end: 30,
            len: 20,
            ..
        })
    ));
}
