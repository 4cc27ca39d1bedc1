//! Sobol indices: the Ishigami function, thread independence, the MSD quantities.

use msd_ident::{Backend, Parameters};
use msd_mc::{Distribution, MsdSobolOptions, SobolOptions, SobolResult, msd_sobol, sobol_indices};
use std::f64::consts::PI;

fn ishigami(threads: usize, samples: usize) -> SobolResult {
    let (a, b) = (7.0, 0.1);
    let model =
        |x: &[f64]| vec![x[0].sin() + a * x[1].sin().powi(2) + b * x[2].powi(4) * x[0].sin()];
    let inputs = [Distribution::Uniform { low: -PI, high: PI }; 3];
    let options = SobolOptions {
        samples,
        bootstrap: 300,
        seed: 3,
        threads,
        ..SobolOptions::default()
    };
    sobol_indices(model, &inputs, &["ishigami"], &options).unwrap()
}

/// Analytic indices of Ishigami (a = 7, b = 0.1): S = (0.3139, 0.4424, 0), ST = (0.5576,
/// 0.4424, 0.2437). With N = 2000 each estimate must lie within 4 bootstrap standard
/// errors of its value, and those errors must shrink like 1/√N (below 3/√N).
#[test]
fn ishigami_indices_within_their_standard_errors() {
    let n = 2000;
    let result = ishigami(2, n);
    let q = &result.quantities[0];
    assert_eq!(result.evaluations, 5 * n);
    // V = a²/8 + bπ⁴/5 + b²π⁸/18 + 1/2 = 13.8446.
    let v = 49.0 / 8.0 + 0.1 * PI.powi(4) / 5.0 + 0.01 * PI.powi(8) / 18.0 + 0.5;
    assert!((q.variance / v - 1.0).abs() < 5.0 * (2.0 / n as f64).sqrt());
    let first = [0.3139, 0.4424, 0.0];
    let total = [0.5576, 0.4424, 0.2437];
    for i in 0..3 {
        for (index, exact) in [(&q.first_order[i], first[i]), (&q.total[i], total[i])] {
            assert!(
                index.std_error < 3.0 / (n as f64).sqrt(),
                "input {i}: {index:?}"
            );
            let tolerance = 4.0 * index.std_error + 1e-4; // + rounding of the exact values
            assert!(
                (index.estimate - exact).abs() < tolerance,
                "input {i}: {index:?} vs {exact}"
            );
            assert!(index.ci[0] <= index.estimate && index.estimate <= index.ci[1]);
        }
    }
}

#[test]
fn sobol_is_identical_for_1_2_and_8_threads() {
    let reference = ishigami(1, 300);
    for threads in [2, 8] {
        let other = ishigami(threads, 300);
        assert_eq!(reference.quantities, other.quantities);
    }
}

/// fn = √(k/m)/2π depends on m and k only, additively in log: S_c = ST_c = 0 exactly, and
/// ζ depends on all three. Peak and RMS of a step response are dominated by k (static
/// deflection 1/k).
#[test]
fn msd_quantities_point_at_the_right_parameters() {
    let step = msd_ident::Excitation::from_samples(0.0, 0.01, vec![1.0; 300]).unwrap();
    let options = MsdSobolOptions {
        backend: Backend::EXACT,
        sobol: SobolOptions {
            samples: 500,
            bootstrap: 100,
            ..SobolOptions::default()
        },
        ..MsdSobolOptions::default()
    };
    let result = msd_sobol(&Parameters::PAPER, &step, &options).unwrap();
    assert_eq!(result.quantities.len(), 5);
    let fnat = &result.quantities[2];
    assert_eq!(fnat.total[1].estimate, 0.0);
    assert!(fnat.first_order[0].estimate > 0.3 && fnat.first_order[2].estimate > 0.3);
    let rms = &result.quantities[1];
    let k = rms.total[2].estimate;
    assert!(
        k > rms.total[0].estimate && k > rms.total[1].estimate,
        "{rms:?}"
    );
    assert!(
        result
            .to_string()
            .starts_with("Sobol indices (Saltelli 2010 / Jansen): N = 500")
    );
}
