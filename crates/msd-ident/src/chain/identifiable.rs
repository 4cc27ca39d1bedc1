//! What a chain's layout cannot fix, found before the fit: the combinations of m, c, k
//! (and cut-offs, delays) that leave every record unchanged.
//!
//! Two come from the layout itself: a spring (or damper) to the ground on mass 1 beside
//! spring 1 — both join mass 1 to the ground, so only their sum shows — and the scale of
//! a base-driven chain with no known mass. Any other is found from the linearisation: the
//! weighted sensitivities at a generic point near the guess (the guess moved by a few per
//! cent, so that a symmetric guess does not fake a loss) whose column-scaled singular
//! values fall below the double-precision floor. Each lost direction holds one parameter
//! at its guess — a mass first, as a weighed mass would — so the solver does not wander
//! along it; the fit then reports the modes, which are identified, and not m, c, k.

use super::model::Family;
use super::problem::{ChainProblem, Layout};
use super::setup::{ChainParameters, ChainSetup, rms};
use super::uncertainty::lost_in_words;
use msd_opt::LeastSquaresProblem;
use msd_opt::statistics::SINGULAR_CONDITION;
use msd_signal::Recording;
use nalgebra::DMatrix;

/// The samples the linearisation looks at: enough for any lost direction to show, few
/// enough to cost about one solver step on a long record.
const SAMPLES: usize = 16_384;

/// Holds in `layout` what the records cannot fix, and says what is lost in words
/// (empty when everything can be identified).
pub(super) fn hold_lost(
    setup: &ChainSetup,
    record: &Recording,
    guess: &ChainParameters,
    delays: &[f64],
    layout: &mut Layout,
) -> Vec<String> {
    let mut words = side_by_side(layout);
    let prefix = record.prefix(SAMPLES);
    let mut problem = ChainProblem {
        setup,
        record: &prefix,
        layout,
        base: guess,
        delays,
        noise: record.responses().map(rms).collect(),
    };
    let Some((scaled, norms)) = scaled_sensitivities(&mut problem) else {
        return words;
    };
    let null = null_space(&scaled);
    if null.is_empty() {
        return words;
    }
    words.extend(lost_in_words(null, &norms, layout));
    let mut kept: Vec<usize> = (0..layout.len()).collect();
    let mut held = Vec::new();
    while let Some(v) = null_space(&scaled.select_columns(&kept)).first() {
        let j = column_to_hold(v.as_slice(), &kept, layout);
        held.push(kept.remove(j));
    }
    held.sort_unstable_by(|a, b| b.cmp(a));
    for j in held {
        layout.hold(j);
    }
    words
}

/// A spring (damper) to the ground on mass 1 beside spring (damper) 1: held, said.
fn side_by_side(layout: &mut Layout) -> Vec<String> {
    let pairs = [
        (Family::Spring, Family::GroundSpring, "k1", "kg1", "springs"),
        (Family::Damper, Family::GroundDamper, "c1", "cg1", "dampers"),
    ];
    let mut words = Vec::new();
    for (series, ground, a, b, what) in pairs {
        if let (Some(_), Some(j)) = (layout.column(series, 0), layout.column(ground, 0)) {
            layout.hold(j);
            words.push(format!(
                "{a} and {b} both join mass 1 to the ground, side by side: the records fix only their sum {a} + {b} (two {what} there act as one)"
            ));
        }
    }
    words
}

/// The weighted sensitivities at a generic point near the guess, each column scaled to
/// unit norm, and the norms; `None` where the chain cannot be simulated there.
fn scaled_sensitivities(problem: &mut ChainProblem<'_>) -> Option<(DMatrix<f64>, Vec<f64>)> {
    let layout = problem.layout;
    let mut theta = layout.theta(problem.base, problem.delays);
    // A few per cent off the guess, in no pattern: a point where only structural losses
    // remain (a guess with equal ratios c/k, say, loses directions the truth keeps).
    for (j, t) in theta.iter_mut().take(layout.simulated()).enumerate() {
        *t += 0.05 * (1.7 * (j + 1) as f64).sin();
    }
    let mut jacobian = DMatrix::zeros(problem.residual_count(), layout.len());
    if !problem.jacobian(&theta, &mut jacobian) || jacobian.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let norms: Vec<f64> = (0..layout.len())
        .map(|j| jacobian.column(j).norm().max(f64::MIN_POSITIVE))
        .collect();
    for (j, n) in norms.iter().enumerate() {
        jacobian.column_mut(j).unscale_mut(*n);
    }
    Some((jacobian, norms))
}

/// The right singular vectors whose singular values fall below the largest over
/// √[`SINGULAR_CONDITION`] (a scaled JᵀJ that double precision cannot invert).
fn null_space(scaled: &DMatrix<f64>) -> Vec<nalgebra::DVector<f64>> {
    let svd = scaled.clone().svd(false, true);
    let Some(v_t) = svd.v_t else {
        return Vec::new();
    };
    let floor = svd.singular_values.max() / SINGULAR_CONDITION.sqrt();
    (0..svd.singular_values.len())
        .filter(|&i| svd.singular_values[i] <= floor)
        .map(|i| v_t.row(i).transpose())
        .collect()
}

/// Which of the `kept` columns a lost direction `v` holds: among those that move most
/// along it, a mass first (as a weighed one would be), else the one that moves most.
fn column_to_hold(v: &[f64], kept: &[usize], layout: &Layout) -> usize {
    let top = v.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let largest = (0..v.len())
        .max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs()))
        .unwrap_or(0);
    (0..v.len())
        .filter(|&j| v[j].abs() >= 0.5 * top)
        .find(|&j| matches!(layout.free.get(kept[j]), Some((Family::Mass, _))))
        .unwrap_or(largest)
}
