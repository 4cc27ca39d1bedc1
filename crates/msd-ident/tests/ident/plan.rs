//! The Cramér–Rao prediction against the estimator over 200 seeds, and its scaling.

use msd_ident::{
    EstimationOptions, Excitation, PaperExperiment, Parameters, estimate, predicted_uncertainty,
};

/// The paper's record with noise σ = 2.5 mm, estimated by Levenberg–Marquardt on the
/// exact simulation: the standard deviations of m, c, k, fn and ζ over 200 seeds match
/// the prediction to within 10 % (the relative standard error of a standard deviation
/// from 200 draws is 1/√398 = 5 %, so 10 % is 2σ).
#[test]
fn the_prediction_matches_the_spread_of_200_estimates() {
    let options = EstimationOptions::default();
    let first = PaperExperiment::generate(0).unwrap();
    let plan = predicted_uncertainty(
        &Parameters::PAPER,
        &first.identification.excitation,
        PaperExperiment::SIGMA,
        &options,
    )
    .unwrap();
    let predicted = [
        plan.mass,
        plan.damping,
        plan.stiffness,
        plan.natural_frequency_hz,
        plan.damping_ratio,
    ];
    let mut values = vec![Vec::new(); 5];
    for seed in 0..200 {
        let data = PaperExperiment::generate(seed).unwrap().identification;
        let u = estimate(&data, &options).unwrap().uncertainty;
        for (v, iv) in values.iter_mut().zip([
            u.mass,
            u.damping,
            u.stiffness,
            u.natural_frequency_hz,
            u.damping_ratio,
        ]) {
            v.push(iv.value);
        }
    }
    for (q, v) in values.iter().enumerate() {
        let n = v.len() as f64;
        let mean = v.iter().sum::<f64>() / n;
        let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        let ratio = sd / predicted[q].standard_error;
        eprintln!("quantity {q}: spread / prediction = {ratio:.3}");
        assert!(
            (ratio - 1.0).abs() <= 0.10,
            "quantity {q}: spread / prediction = {ratio}"
        );
    }
}

#[test]
fn standard_errors_scale_as_the_noise_over_the_force() {
    let paper = PaperExperiment::generate(0)
        .unwrap()
        .identification
        .excitation;
    let scaled = |a: f64| {
        let samples = paper.samples().iter().map(|f| a * f).collect();
        Excitation::from_samples(paper.t0(), paper.dt(), samples).unwrap()
    };
    let (input, doubled) = (scaled(1.0), scaled(2.0));
    let options = EstimationOptions {
        estimate_initial_state: true,
        estimate_offset: true,
        ..EstimationOptions::default()
    };
    let plan = |e: &Excitation, sigma| {
        predicted_uncertainty(&Parameters::PAPER, e, sigma, &options).unwrap()
    };
    let (base, stronger, noisier) = (plan(&input, 1e-3), plan(&doubled, 1e-3), plan(&input, 3e-3));
    for (b, s, x) in [
        (base.mass, stronger.mass, noisier.mass),
        (
            base.damping_ratio,
            stronger.damping_ratio,
            noisier.damping_ratio,
        ),
    ] {
        assert!(
            (s.standard_error / b.standard_error - 0.5).abs() < 1e-9,
            "{} {}",
            s.standard_error,
            b.standard_error
        );
        assert!((x.standard_error / b.standard_error - 3.0).abs() < 1e-9);
    }
    // No noise, nothing to predict.
    assert!(predicted_uncertainty(&Parameters::PAPER, &input, 0.0, &options).is_err());
}

/// Information adds up over samples: a periodic force in steady state adds the same
/// information every period, so the information of 60 periods follows from 10 and 15
/// (PlannedInformation::extrapolated), as `plan` uses it, to rounding.
#[test]
fn the_information_of_a_repeating_input_extrapolates_exactly() {
    use msd_ident::PlannedInformation;
    // Three sines with a common period of 10 s, sampled at 100 Hz.
    let dt = 0.01;
    let force = |n: usize| {
        let samples = (0..n)
            .map(|i| {
                let t = i as f64 * dt;
                [0.1, 0.5, 1.1]
                    .iter()
                    .map(|f| (std::f64::consts::TAU * f * t + f).sin())
                    .sum()
            })
            .collect();
        Excitation::from_samples(0.0, dt, samples).unwrap()
    };
    let options = EstimationOptions::default();
    let at = |seconds: usize| {
        PlannedInformation::new(&Parameters::PAPER, &force(seconds * 100 + 1), &options).unwrap()
    };
    // After 100 s the start's transient has decayed by e^(−ζωn·100) = e^(−36).
    let (ten, fifteen, sixty) = (at(100), at(150), at(600));
    let extrapolated = ten.extrapolated(&fifteen, sixty.samples);
    assert_eq!(extrapolated.samples, sixty.samples);
    let p = sixty.normal.nrows();
    for i in 0..p {
        for j in 0..p {
            let scale = (sixty.normal[(i, i)] * sixty.normal[(j, j)]).sqrt();
            let error = (extrapolated.normal[(i, j)] - sixty.normal[(i, j)]).abs();
            assert!(error < 1e-9 * scale, "({i}, {j}): {error:e} of {scale:e}");
        }
    }
    let (direct, analytic) = (
        sixty.uncertainty(1e-3).unwrap(),
        extrapolated.uncertainty(1e-3).unwrap(),
    );
    let relative = (analytic.damping.standard_error / direct.damping.standard_error - 1.0).abs();
    assert!(relative < 1e-8, "{relative:e}");
}
