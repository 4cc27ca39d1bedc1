//! Multistart: finds the global minimum where one bad start does not, and gives
//! identical results on 1 and 2 threads.

use msd_opt::{
    Bounds, LevenbergMarquardtOptions, MultistartOptions, NelderMeadOptions, OptError, ResidualFn,
    Sampling, levenberg_marquardt, multistart, nelder_mead,
};

/// Rastrigin's function in 2-D: global minimum 0 at the origin, a local minimum
/// near every integer point.
fn rastrigin(x: &[f64]) -> f64 {
    x.iter()
        .map(|v| v * v - 10.0 * (2.0 * std::f64::consts::PI * v).cos() + 10.0)
        .sum::<f64>()
}

fn nm_tight() -> NelderMeadOptions {
    NelderMeadOptions {
        x_tolerance: 1e-8,
        f_tolerance: 1e-10,
        ..Default::default()
    }
}

/// Two tilted double wells, separable: four local minima near (±2, ±1); the tilt
/// makes (−2, −1) the global one. Along x, g(x) = (x² − 4)² + 0.5x has g(−2) = −1
/// and g(2) = 1 at the wells; along y, h(y) = (y² − 1)² + 0.3y has h(∓1) = ∓0.3.
fn double_wells(x: &[f64]) -> f64 {
    (x[0] * x[0] - 4.0).powi(2) + 0.5 * x[0] + (x[1] * x[1] - 1.0).powi(2) + 0.3 * x[1]
}

#[test]
fn finds_the_global_minimum_a_bad_start_misses() {
    let single = nelder_mead(double_wells, &[2.5, 1.5], &nm_tight()).unwrap();
    assert!(single.x[0] > 0.0 && single.x[1] > 0.0, "a local basin");
    let bounds = Bounds::new(vec![-3.0, -2.0], vec![3.0, 2.0]).unwrap();
    for sampling in [Sampling::LatinHypercube, Sampling::Halton] {
        let options = MultistartOptions {
            starts: 16,
            seed: 11,
            sampling,
            ..Default::default()
        };
        let ranked = multistart(&bounds, &options, |x0| {
            nelder_mead(double_wells, x0, &nm_tight())
        })
        .unwrap();
        assert_eq!(ranked.len(), 16);
        let best = &ranked[0].result;
        assert!(
            best.x[0] < -1.9 && best.x[1] < -0.9,
            "{sampling:?}: {:?}",
            best.x
        );
        // The wells differ by 2 (x) and 0.6 (y): the global value is 2.6 lower
        // than the single start's, up to the wells' small shifts (< 0.1).
        assert!(best.cost < single.cost - 2.5, "{sampling:?}");
        assert!(
            ranked
                .windows(2)
                .all(|w| w[0].result.cost <= w[1].result.cost)
        );
        assert!(ranked.iter().all(|r| bounds.contains(&r.x0)));
    }
}

#[test]
fn identical_results_for_one_and_two_threads() {
    let bounds = Bounds::new(vec![-3.5, -3.5], vec![3.5, 3.5]).unwrap();
    let run = |threads| {
        let options = MultistartOptions {
            starts: 24,
            seed: 5,
            threads,
            ..Default::default()
        };
        multistart(&bounds, &options, |x0| {
            nelder_mead(rastrigin, x0, &nm_tight())
        })
        .unwrap()
    };
    assert_eq!(run(1), run(2));

    // Levenberg–Marquardt as the local method: Rastrigin as residuals.
    let lm = |threads| {
        let options = MultistartOptions {
            starts: 12,
            seed: 9,
            threads,
            ..Default::default()
        };
        multistart(&bounds, &options, |x0| {
            let mut p = ResidualFn::new(2, |x: &[f64], r: &mut [f64]| {
                for (ri, v) in r.iter_mut().zip(x) {
                    *ri = (v * v - 10.0 * (2.0 * std::f64::consts::PI * v).cos() + 10.0).sqrt();
                }
                true
            });
            levenberg_marquardt(&mut p, x0, &LevenbergMarquardtOptions::default())
        })
        .unwrap()
    };
    assert_eq!(lm(1), lm(2));
}

#[test]
fn bad_input_is_a_specific_error() {
    let b = Bounds::new(vec![0.0], vec![1.0]).unwrap();
    let local = |x0: &[f64]| nelder_mead(|x| x[0], x0, &NelderMeadOptions::default());
    for (name, options) in [
        (
            "starts",
            MultistartOptions {
                starts: 0,
                ..Default::default()
            },
        ),
        (
            "threads",
            MultistartOptions {
                threads: 0,
                ..Default::default()
            },
        ),
    ] {
        let err = multistart(&b, &options, local).unwrap_err();
        assert!(matches!(err, OptError::InvalidOption { name: n, .. } if n == name));
    }
    let open = Bounds::new(vec![0.0], vec![f64::INFINITY]).unwrap();
    assert!(matches!(
        multistart(&open, &MultistartOptions::default(), local),
        Err(OptError::InfiniteBounds { index: 0, .. })
    ));
    let inverted = Bounds {
        lower: vec![1.0],
        upper: vec![0.0],
    };
    assert!(matches!(
        multistart(&inverted, &MultistartOptions::default(), local),
        Err(OptError::InvertedBounds { .. })
    ));
    let bad_local = |_: &[f64]| nelder_mead(|x| x[0], &[], &NelderMeadOptions::default());
    assert!(matches!(
        multistart(&b, &MultistartOptions::default(), bad_local),
        Err(OptError::LocalSolver { start: 0, .. })
    ));
}
