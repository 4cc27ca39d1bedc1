//! Several modes: three modes (fn 10, 23, 41 Hz; ζ 1 %, 2 %, 0.5 %) in 2000 lines with
//! 1 % noise; the stabilization diagram, the polished parameters and their intervals.

use msd_modal::ModalError;
use msd_modal::{
    FrfWeighting, ModalOptions, ModalParameters, fit_modes, stabilization_diagram,
    synthetic_frequency_response,
};
use msd_signal::{Complex64, FrequencyResponseEstimate};

/// The three modes (real modal constants, in 1/kg).
pub fn three_modes() -> [ModalParameters; 3] {
    [(10.0, 0.01, 1.0), (23.0, 0.02, -0.6), (41.0, 0.005, 0.4)].map(|(f, z, a)| ModalParameters {
        natural_frequency_hz: f,
        damping_ratio: z,
        modal_constant: a,
        modal_constant_imaginary: 0.0,
    })
}

/// 2000 lines, 0.025 … 50 Hz.
pub fn lines() -> Vec<f64> {
    (1..=2000).map(|i| 0.025 * i as f64).collect()
}

fn exact(f: &[f64], modes: &[ModalParameters]) -> Vec<Complex64> {
    f.iter()
        .map(|&f| modes.iter().map(|m| m.receptance(f)).sum())
        .collect()
}

/// The three-mode response with 1 % complex noise from `seed`.
pub fn noisy(seed: u64) -> FrequencyResponseEstimate {
    let modes = three_modes();
    synthetic_frequency_response(&lines(), 0.01, seed, |f| {
        modes.iter().map(|m| m.receptance(f)).sum()
    })
    .expect("valid")
}

const OPTIONS: ModalOptions = ModalOptions {
    band_hz: None,
    weighting: FrfWeighting::Relative,
    orders: [2, 40],
    order_step: 2,
    frequency_tolerance: 0.01,
    damping_tolerance: 0.05,
    max_damping_ratio: 0.5,
    min_stable_share: 0.4,
    mode_count: None,
};

#[test]
fn three_modes_in_noise_are_found_and_fitted_within_their_intervals() {
    let frf = noisy(1);
    let fit = fit_modes(&frf, &OPTIONS).expect("fit");
    println!("{fit}\n{}", fit.diagram);
    assert_eq!(fit.diagram.modes.len(), 3, "{}", fit.diagram);
    assert_eq!(fit.modes.len(), 3);
    for (r, (mode, truth)) in fit.modes.iter().zip(&three_modes()).enumerate() {
        let [a, b] = fit.modal_constant(r).expect("a modal constant");
        let (f, z) = (mode.natural_frequency_hz, mode.damping_ratio);
        assert!(
            (f.value / truth.natural_frequency_hz - 1.0).abs() < 1e-3,
            "fn {f}"
        );
        assert!((z.value / truth.damping_ratio - 1.0).abs() < 0.03, "ζ {z}");
        assert!(
            f.contains(truth.natural_frequency_hz),
            "fn {f} vs {truth:?}"
        );
        assert!(z.contains(truth.damping_ratio), "ζ {z} vs {truth:?}");
        // The other quantities within three standard errors: of the twelve 95 %
        // intervals of one seed, one or two miss by chance (here mode 1's A, by 0.1 SE;
        // the coverage over seeds is the next test's).
        for (name, i, truth) in [("A", a, truth.modal_constant), ("B", b, 0.0)] {
            assert!(
                (i.value - truth).abs() < 3.0 * i.standard_error,
                "{name} {i}"
            );
        }
        assert!(mode.window_correction.is_none());
    }
    // No residual terms in the truth.
    for r in [fit.lower_residual, fit.upper_residual] {
        assert!(r.value.abs() < 3.0 * r.standard_error, "{fit}");
    }
    // 1 % noise: what is left is the noise (σ̂ ≈ 0.01 with relative weights).
    assert!((fit.sigma / 0.01 - 1.0).abs() < 0.1, "σ̂ = {}", fit.sigma);
    assert_eq!((fit.lines, fit.degrees_of_freedom), (2000, 4000 - 14));
    // The model as fitted reproduces the data to the noise.
    let f = lines();
    let worst = f
        .iter()
        .zip(exact(&f, &three_modes()))
        .map(|(&f, h)| ((fit.response(f) - h) / h).norm())
        .fold(0.0f64, f64::max);
    assert!(
        worst < 0.01,
        "worst relative error of the fitted model {worst}"
    );
}

/// Every order has its flags; each true mode is stable at half the orders or more.
#[test]
fn the_diagram_flags_stable_poles_and_counts_orders() {
    let diagram = stabilization_diagram(&noisy(2), &OPTIONS).expect("diagram");
    assert_eq!(diagram.orders.len(), 20); // 2, 4, …, 40
    assert_eq!(diagram.orders[0].order, 2);
    for p in diagram.orders.iter().flat_map(|o| &o.poles) {
        assert_eq!(p.stable, p.stable_frequency && p.stable_damping);
    }
    for (mode, truth) in diagram.modes.iter().zip(&three_modes()) {
        assert!((mode.natural_frequency_hz / truth.natural_frequency_hz - 1.0).abs() < 1e-3);
        assert!(mode.stable_orders >= 10, "{diagram}");
    }
    // By count: the two stable at the most orders.
    let two = ModalOptions {
        mode_count: Some(2),
        ..OPTIONS
    };
    assert_eq!(
        stabilization_diagram(&noisy(2), &two)
            .expect("diagram")
            .modes
            .len(),
        2
    );
    let four = ModalOptions {
        mode_count: Some(40),
        ..OPTIONS
    };
    let err = stabilization_diagram(&noisy(2), &four).expect_err("not so many");
    let ModalError::TooFewModes { diagram, reason } = &err else {
        panic!("{err}")
    };
    assert!(reason.contains("40 were asked for"), "{reason}");
    // The diagram is kept for a plot: every order, its columns, the modes it did select.
    assert_eq!(
        diagram.orders.len(),
        (OPTIONS.orders[1] - OPTIONS.orders[0]) / OPTIONS.order_step + 1
    );
    assert!(diagram.modes.len() >= 2 && diagram.modes.len() < 40);
}

/// Over 40 noise seeds the 95 % intervals of fn, ζ and A of the three modes cover the
/// truth in 95 ± 4 % of the 360 cases (binomial σ ≈ 1.1 %, the cases of one seed share
/// its noise).
#[test]
fn the_modal_intervals_cover_the_truth() {
    let truth = three_modes();
    let (mut covered, mut cases) = (0, 0);
    for seed in 100..140 {
        let fit = fit_modes(&noisy(seed), &OPTIONS).expect("fit");
        assert_eq!(fit.modes.len(), 3, "seed {seed}: {}", fit.diagram);
        for (r, (m, t)) in fit.modes.iter().zip(&truth).enumerate() {
            let [a, _] = fit.modal_constant(r).expect("a modal constant");
            covered += usize::from(m.natural_frequency_hz.contains(t.natural_frequency_hz));
            covered += usize::from(m.damping_ratio.contains(t.damping_ratio));
            covered += usize::from(a.contains(t.modal_constant));
            cases += 3;
        }
    }
    let share = 100.0 * covered as f64 / cases as f64;
    println!("modal coverage {share:.1} % of {cases}");
    assert!((share - 95.0).abs() <= 4.0, "{share} %");
}

#[test]
fn bad_modal_options_are_refused_by_name() {
    let frf = noisy(1);
    let cases = [
        (
            ModalOptions {
                orders: [0, 10],
                ..OPTIONS
            },
            "orders[0]",
        ),
        (
            ModalOptions {
                order_step: 0,
                ..OPTIONS
            },
            "order_step",
        ),
        (
            ModalOptions {
                frequency_tolerance: 0.0,
                ..OPTIONS
            },
            "frequency_tolerance",
        ),
        (
            ModalOptions {
                min_stable_share: 1.5,
                ..OPTIONS
            },
            "min_stable_share",
        ),
        (
            ModalOptions {
                mode_count: Some(0),
                ..OPTIONS
            },
            "mode_count",
        ),
        (
            ModalOptions {
                band_hz: Some([5.0, f64::NAN]),
                ..OPTIONS
            },
            "band_hz[1]",
        ),
    ];
    for (options, name) in cases {
        let err = fit_modes(&frf, &options).expect_err(name);
        assert!(
            matches!(err, ModalError::InvalidParameter { name: n, .. } if n == name),
            "{err}"
        );
    }
    // Order 40 needs 41 lines; 9.6 … 10.5 Hz holds 37.
    let narrow = ModalOptions {
        band_hz: Some([9.6, 10.5]),
        ..OPTIONS
    };
    assert!(matches!(
        fit_modes(&frf, &narrow),
        Err(ModalError::TooFewSamples {
            got: 37,
            needed: 41,
            ..
        })
    ));
    let toml: ModalOptions = toml::from_str("orders = [4, 30]\nmode_count = 3").expect("valid");
    assert_eq!(
        (toml.orders, toml.mode_count, toml.order_step),
        ([4, 30], Some(3), 2)
    );
    assert!(toml::from_str::<ModalOptions>("orders = [4, 30, 50]").is_err());
}
