//! Validation on fresh data for a test machine: each condition's force predicted by the
//! best law fitted to the other conditions (leave one condition out), as the joint fit
//! of records predicts each record by the others.

use super::law_fit::fitted_force;
use super::regression::{Needs, Normal};
use super::{Condition, DynamometerOptions, prepare, smoothing_velocity};
use crate::error::Result;
use crate::metrics::FitMetrics;
use crate::nonlinear::DampingLaw;
use serde::Serialize;

/// One condition's force predicted by the law fitted to the others.
///
/// ```
/// use msd_ident::{FitMetrics, dynamometer::ConditionPrediction};
/// let p = ConditionPrediction { condition: "2 Hz".into(), fit: FitMetrics::new(&[0.0, 1.0, 2.0], &[0.0, 1.1, 1.9]) };
/// assert_eq!(serde_json::to_value(&p)?["condition"], "2 Hz");
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConditionPrediction {
    /// The condition left out.
    pub condition: String,
    /// R², fit % and RMS error (N) of its force over its analysed cycles.
    pub fit: FitMetrics,
}

/// The fewest conditions for a prediction by the others: two left to fit a law's
/// frequency-dependent terms apart.
pub(super) const FEWEST: usize = 3;

/// Each condition predicted by `law` fitted to the others (its smoothing velocity that
/// of every condition); a condition whose others cannot separate the law's terms is
/// left out of the list.
pub(super) fn leave_one_condition_out(
    conditions: &[Condition],
    options: &DynamometerOptions,
    law: DampingLaw,
) -> Result<Vec<ConditionPrediction>> {
    let mut prepared = Vec::with_capacity(conditions.len());
    for c in conditions {
        prepared.push(prepare(c, options.harmonics)?.1);
    }
    let smoothing = smoothing_velocity(&prepared, options.smoothing_velocity);
    let needs = Needs {
        quadratic: law == DampingLaw::QuadraticViscous,
        coulomb: law == DampingLaw::CoulombViscous,
    };
    let mut out = Vec::with_capacity(conditions.len());
    for (i, left) in conditions.iter().enumerate() {
        let mut normal = Normal::default();
        for (j, (c, p)) in conditions.iter().zip(&mut prepared).enumerate() {
            if j != i {
                p.accumulate(c.dt(), 1.0 / smoothing, needs, &mut normal);
            }
        }
        if let Some(model) = fitted_force(law, &normal, &prepared[i], smoothing, options) {
            out.push(ConditionPrediction {
                condition: left.name().to_string(),
                fit: FitMetrics::new(&prepared[i].force, &model),
            });
        }
    }
    Ok(out)
}
