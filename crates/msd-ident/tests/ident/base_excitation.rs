//! Base excitation: what it identifies, and 95 % coverage over 200 seeds.

use msd_ident::{
    Backend, BaseExcitationOptions, DataSet, Excitation, FixedParameters, InitialState, Parameters,
    base_excitation, simulate,
};
use msd_signal::{gaussian_noise, paper_identification_input};

/// The relative displacement of the paper's plant on a table whose acceleration is the
/// paper's input (m/s²), simulated as the force −m·z″ on the plant itself.
fn table() -> (Excitation, Vec<f64>) {
    let base = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501).unwrap();
    let m = Parameters::PAPER.mass;
    let force = base.samples().iter().map(|a| -m * a).collect();
    let force = Excitation::from_samples(0.0, 0.002, force).unwrap();
    let y = simulate(
        &Parameters::PAPER,
        &force,
        InitialState::REST,
        &Backend::EXACT,
    )
    .unwrap();
    let base = Excitation::from_samples(0.0, 0.002, base.samples().to_vec()).unwrap();
    (base, y)
}

/// 400 seeds with noise σ = 1 mm: the intervals of fn and ζ (mass unknown) and of c and k
/// (mass weighed) each cover the truth 95 ± 3 % of the time (binomial σ = 1.1 % with 400:
/// the issue asks for at least 200, and 200 put ζ at the 2σ edge, 92 %).
#[test]
fn intervals_cover_the_truth_over_400_seeds_with_and_without_the_mass() {
    let (base, clean) = table();
    let p = Parameters::PAPER;
    let known = BaseExcitationOptions {
        known_mass: Some(p.mass),
        ..BaseExcitationOptions::default()
    };
    let mut covered = [0usize; 4];
    let seeds = 400;
    for seed in 0..seeds {
        let noise = gaussian_noise(seed, "base", 1e-3, clean.len()).unwrap();
        let y: Vec<f64> = clean.iter().zip(&noise).map(|(c, n)| c + n).collect();
        let record = DataSet::new("table", base.clone(), y).unwrap();
        let free = base_excitation(&record, &BaseExcitationOptions::default()).unwrap();
        assert!(free.parameters.is_none());
        let weighed = base_excitation(&record, &known).unwrap();
        let physical = weighed.parameters.unwrap();
        for (q, hit) in [
            free.natural_frequency_hz.contains(p.natural_frequency_hz()),
            free.damping_ratio.contains(p.damping_ratio()),
            physical.damping.contains(p.damping),
            physical.stiffness.contains(p.stiffness),
        ]
        .into_iter()
        .enumerate()
        {
            covered[q] += usize::from(hit);
        }
    }
    for (q, c) in covered.iter().enumerate() {
        let coverage = *c as f64 / seeds as f64;
        eprintln!("quantity {q}: coverage {coverage}");
        assert!(
            (coverage - 0.95).abs() <= 0.03,
            "quantity {q}: coverage {coverage}"
        );
    }
}

#[test]
fn the_mass_alone_is_not_identifiable_and_other_fixed_values_are_refused() {
    let (base, y) = table();
    let record = DataSet::new("table", base, y).unwrap();
    let fit = base_excitation(&record, &BaseExcitationOptions::default()).unwrap();
    assert_eq!(fit.identifiable, ["natural_frequency_hz", "damping_ratio"]);
    assert!(
        fit.note
            .as_deref()
            .unwrap()
            .contains("not separately identifiable")
    );
    assert!(fit.to_string().contains("fn = "));
    // c/m and k/m are what the record fixes.
    let p = Parameters::PAPER;
    assert!((fit.stiffness_per_mass.value / (p.stiffness / p.mass) - 1.0).abs() < 1e-6);
    let mut options = BaseExcitationOptions::default();
    options.estimation.fixed = FixedParameters {
        mass: Some(2.5),
        ..FixedParameters::default()
    };
    let err = base_excitation(&record, &options).unwrap_err().to_string();
    assert!(err.contains("known_mass"), "{err}");
    let bad = BaseExcitationOptions {
        known_mass: Some(0.0),
        ..BaseExcitationOptions::default()
    };
    assert!(
        base_excitation(&record, &bad)
            .unwrap_err()
            .to_string()
            .contains("known mass = 0")
    );
}
