//! The superposition against the exact simulation, and the gradient against differences.

use super::basis::PlantBasis;
use super::objective::{Limits, Objective};
use super::{Aggregate, Criterion, DesignOptions, StepOption, signal};
use crate::{
    data::Excitation,
    params::{InitialState, Parameters},
    sensitivity::sensitivities,
};
use msd_ode::Hold;

/// Two segments and a step on a short record of the paper plant.
fn setup() -> (super::basis::Layout, Vec<f64>, Excitation) {
    let reference = Excitation::from_samples(0.0, 0.01, vec![0.0; 801]).unwrap();
    let mut options = DesignOptions {
        lines: 7,
        segments: 2,
        ..DesignOptions::default()
    };
    options.constraints.band_hz = [0.3, 2.5];
    options.constraints.step = Some(StepOption {
        time: 0.5,
        min_amplitude: 0.0,
    });
    let layout = signal::layout(&options, &reference);
    let noise = msd_signal::gaussian_noise(4, "test", 1.0, layout.variables()).unwrap();
    (layout, noise, reference)
}

/// The displacement and relative sensitivities by superposition equal those of the
/// 8-state simulation of the sampled force, to the hold's error (cubic: O((ω·dt)⁴)).
#[test]
fn superposition_matches_the_exact_simulation() {
    let (layout, w, reference) = setup();
    let plant = Parameters::PAPER;
    let bases = [PlantBasis::new(&plant, &layout).unwrap()];
    let limits = Limits {
        force: 1.0,
        stroke: 1.0,
        rms_force: None,
        min_step: 0.0,
        stroke_plants: 1,
    };
    let mut objective = Objective::new(
        &layout,
        &bases,
        limits,
        Criterion::DOptimal,
        Aggregate::Average,
    );
    let x = objective.signals(&w).1.to_vec();
    let force = super::signal::to_signal_for_tests(&layout, &w, reference.t0());
    let excitation = Excitation::from_signal(force, 0.0, layout.dt, layout.samples).unwrap();
    let mut exact = vec![[0.0; 4]; layout.samples];
    sensitivities(
        &plant,
        &excitation,
        InitialState::REST,
        Hold::Cubic,
        |i, s| {
            let p = s.parameters;
            exact[i] = [
                s.displacement,
                plant.mass * p[0],
                plant.damping * p[1],
                plant.stiffness * p[2],
            ];
        },
    )
    .unwrap();
    let scale = exact.iter().fold(0.0f64, |m, e| m.max(e[0].abs()));
    for n in 0..layout.samples {
        assert!(
            (x[n] - exact[n][0]).abs() < 1e-6 * scale,
            "x at {n}: {} vs {}",
            x[n],
            exact[n][0]
        );
    }
    let fim = objective.information(&w, 0);
    let mut expected = nalgebra::Matrix3::zeros();
    for e in &exact {
        let j = nalgebra::Vector3::new(e[1], e[2], e[3]);
        expected += j * j.transpose();
    }
    assert!(
        (fim - expected).norm() < 1e-6 * expected.norm(),
        "{fim} vs {expected}"
    );
}

/// Each criterion's gradient equals central differences (step 1e-6 relative: the
/// difference error is O(h²) ≈ 1e-12, rounding ≈ 1e-16/1e-6 = 1e-10, relative).
#[test]
fn the_gradient_equals_central_differences() {
    let (layout, w, _) = setup();
    let plants = [
        Parameters::PAPER,
        Parameters {
            mass: 2.0,
            damping: 2.2,
            stiffness: 140.0,
        },
    ];
    let bases: Vec<_> = plants
        .iter()
        .map(|p| PlantBasis::new(p, &layout).unwrap())
        .collect();
    // The stroke on the prior only, and on both plants.
    for (criterion, aggregate, stroke_plants) in [
        (Criterion::DOptimal, Aggregate::Average, 1),
        (Criterion::AOptimal, Aggregate::Worst, 1),
        (Criterion::Minimax, Aggregate::Average, 1),
        (Criterion::DOptimal, Aggregate::Worst, 2),
        (Criterion::Minimax, Aggregate::Average, 2),
    ] {
        let limits = Limits {
            force: 9.0,
            stroke: 0.1,
            rms_force: Some(5.0),
            min_step: 50.0,
            stroke_plants,
        };
        let mut objective = Objective::new(&layout, &bases, limits, criterion, aggregate);
        objective.sharpness = 8.0;
        let mut grad = vec![0.0; w.len()];
        let mut scratch = vec![0.0; w.len()];
        objective.evaluate(&w, &mut grad);
        let norm = grad.iter().map(|g| g * g).sum::<f64>().sqrt();
        for i in 0..w.len() {
            let h = 1e-6 * w[i].abs().max(1e-3);
            let (mut up, mut down) = (w.clone(), w.clone());
            up[i] += h;
            down[i] -= h;
            let diff = (objective.evaluate(&up, &mut scratch)
                - objective.evaluate(&down, &mut scratch))
                / (2.0 * h);
            assert!(
                (diff - grad[i]).abs() < 1e-5 * norm,
                "{criterion}, stroke on {stroke_plants}, variable {i}: {diff} vs {}",
                grad[i]
            );
        }
    }
}

/// A step below its least height after scaling is raised to it, and the multisine's
/// gain bisected to the limits: the step is exactly the least height and the largest
/// peak ratio is within (1 − 1e-6, 1].
#[test]
fn a_step_below_its_least_height_is_raised_to_it() {
    let (layout, mut w, reference) = setup();
    let last = w.len() - 1;
    w[last] = -1e-3; // a step far below the others
    let constraints = super::DesignConstraints {
        step: Some(StepOption {
            time: 0.5,
            min_amplitude: 3.0,
        }),
        ..super::DesignConstraints::default()
    };
    let plants = [Parameters::PAPER];
    let scaled = signal::scaled(&layout, &w, &plants, &reference, &constraints).unwrap();
    assert_eq!(scaled.step_amplitude, -3.0);
    let ratio = (scaled.peak_force / 9.0).max(scaled.peak_strokes[0] / 0.1115);
    assert!(ratio <= 1.0 && ratio > 1.0 - 1e-6, "{ratio}");
}

/// A record of eight periods on a well-damped plant: the kept samples (the settling after
/// each edge and one period) stand for the record. The cost and its gradient equal those
/// summed over every sample, to the rounding of the sums (the free responses cut at 1e-16
/// of their peak change nothing above it), and the gradient equals central differences.
#[test]
fn a_repeated_period_counts_as_the_whole_record() {
    let reference = Excitation::from_samples(0.0, 0.01, vec![0.0; 2001]).unwrap();
    let mut options = DesignOptions {
        lines: 5,
        segments: 2,
        period: Some(2.5),
        ..DesignOptions::default()
    };
    options.constraints.band_hz = [0.3, 3.0];
    options.constraints.step = Some(StepOption {
        time: 3.0,
        min_amplitude: 0.0,
    });
    let every = signal::layout(&options, &reference);
    assert_eq!(every.period, 250);
    let plants = [Parameters {
        mass: 1.0,
        damping: 40.0,
        stiffness: 400.0,
    }];
    let bases = [PlantBasis::new(&plants[0], &every).unwrap()];
    let settle = bases[0].free.len();
    assert!(settle < 400, "settles in {settle} samples");
    let mut kept = every.clone();
    kept.keep(settle);
    assert!(kept.kept.len() < 1400, "{} kept", kept.kept.len());
    assert_eq!(kept.weights.iter().sum::<f64>(), 2001.0);
    let w = msd_signal::gaussian_noise(5, "test", 1.0, every.variables()).unwrap();
    let limits = Limits {
        force: 9.0,
        stroke: 0.01,
        rms_force: Some(5.0),
        min_step: 1.0,
        stroke_plants: 1,
    };
    let evaluate = |layout: &super::basis::Layout, w: &[f64]| {
        let mut objective = Objective::new(
            layout,
            &bases,
            limits,
            Criterion::DOptimal,
            Aggregate::Average,
        );
        let mut grad = vec![0.0; w.len()];
        let cost = objective.evaluate(w, &mut grad);
        (cost, grad, objective.information(w, 0))
    };
    let (cost, grad, fim) = evaluate(&every, &w);
    let (kept_cost, kept_grad, kept_fim) = evaluate(&kept, &w);
    let norm = grad.iter().map(|g| g * g).sum::<f64>().sqrt();
    assert!(
        (cost - kept_cost).abs() < 1e-12 * cost.abs().max(1.0),
        "{cost} vs {kept_cost}"
    );
    assert!(
        (fim - kept_fim).norm() < 1e-12 * fim.norm(),
        "{fim} vs {kept_fim}"
    );
    for (i, (g, k)) in grad.iter().zip(&kept_grad).enumerate() {
        assert!((g - k).abs() < 1e-11 * norm, "variable {i}: {g} vs {k}");
        let h = 1e-6 * w[i].abs().max(1e-3);
        let (mut up, mut down) = (w.clone(), w.clone());
        up[i] += h;
        down[i] -= h;
        let diff = (evaluate(&kept, &up).0 - evaluate(&kept, &down).0) / (2.0 * h);
        assert!(
            (diff - k).abs() < 1e-5 * norm,
            "variable {i}: {diff} vs {k}"
        );
    }
}
