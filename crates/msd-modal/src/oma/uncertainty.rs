//! Standard errors of the selected modes by the leave-one-block-out jackknife: the record
//! cut into B blocks, the covariances recomputed without each block (no second pass over
//! the data), the subspace and the mode's order identified again, the pole nearest the
//! mode picked, and Var θ = (B − 1)/B · Σ (θ_b − θ̄)². This is the delta method on the
//! block covariances' scatter — what Reynders, Pintelon & De Roeck (Mech. Syst. Signal
//! Process. 22, 2008) propagate analytically — taken through the whole identification
//! numerically, so it needs no sensitivity of the SVD; the intervals use Student's t with
//! B − 1 degrees of freedom.

use msd_opt::statistics::Interval;
use msd_signal::Complex64;
use rayon::prelude::*;

use super::covariance::BlockCovariances;
use super::record::OutputRecord;
use super::select::{Physical, aligned, distance, mean_pole};
use super::subspace::{Pole, Subspace};
use msd_modal_core::mode::{Mode, ShapeEntry};
use nalgebra::DMatrix;

/// The covariances (from lag 0) to the matrix whose SVD gives the observability matrix
/// (SSI-cov's or SSI-dat's: [`subspace_matrix`](super::covariance::subspace_matrix)).
pub(crate) type SubspaceMatrix<'a> = dyn Fn(&[DMatrix<f64>]) -> Option<DMatrix<f64>> + Sync + 'a;

/// The standard errors of one mode.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct StandardErrors {
    /// Of fn, Hz.
    pub frequency_hz: f64,
    /// Of ζ.
    pub damping_ratio: f64,
    /// Of each shape entry's real and imaginary parts.
    pub shape: Vec<[f64; 2]>,
}

/// One selected mode to follow through the replicates: the poles of its cluster, each with
/// its model order, and the mode's estimate (their mean).
pub(crate) struct Target<'a> {
    /// The cluster's poles and their orders.
    pub members: Vec<(usize, &'a Physical)>,
    /// The estimate.
    pub pole: &'a Physical,
}

/// The jackknife standard errors of fn, ζ and of every shape entry's real and imaginary
/// parts, for each target: each replicate repeats the estimate as the full record's was
/// made — each cluster pole's nearest pole at its order, then their mean — so that the
/// average over orders is in the variance (`None` where a replicate matched
/// fewer than half the cluster's poles within the clustering distance).
pub(crate) fn jackknife(
    covariances: &BlockCovariances,
    matrix: &SubspaceMatrix<'_>,
    sample_rate_hz: f64,
    targets: &[Target<'_>],
    cut: f64,
    physical: impl Fn(&Pole) -> Option<Physical> + Sync,
) -> Vec<Option<StandardErrors>> {
    let n_max = targets
        .iter()
        .flat_map(|t| t.members.iter().map(|m| m.0))
        .max()
        .unwrap_or(0);
    let b = covariances.blocks();
    // The replicates are independent: computed side by side, gathered in block order.
    let estimates: Vec<Option<Vec<Option<Physical>>>> = (0..b)
        .into_par_iter()
        .map(|left_out| {
            let cov = covariances.covariances(Some(left_out));
            let subspace = Subspace::new(matrix(&cov)?, cov[0].nrows(), n_max)?;
            Some(replicate(
                &subspace,
                sample_rate_hz,
                targets,
                cut,
                &physical,
            ))
        })
        .collect();
    let mut replicates: Vec<Vec<Option<Physical>>> = vec![Vec::with_capacity(b); targets.len()];
    for estimate in estimates {
        let Some(estimate) = estimate else {
            return vec![None; targets.len()];
        };
        for (k, e) in estimate.into_iter().enumerate() {
            replicates[k].push(e);
        }
    }
    targets
        .iter()
        .zip(replicates)
        .map(|(target, reps)| {
            let reps: Option<Vec<Physical>> = reps.into_iter().collect();
            reps.map(|reps| standard_errors(target.pole, &reps))
        })
        .collect()
}

/// Each target's estimate from one replicate's subspace: each cluster pole's nearest pole
/// at its order (within `cut`), then their mean (`None` where fewer than half matched).
fn replicate(
    subspace: &Subspace,
    sample_rate_hz: f64,
    targets: &[Target<'_>],
    cut: f64,
    physical: &(impl Fn(&Pole) -> Option<Physical> + Sync),
) -> Vec<Option<Physical>> {
    let mut at_order: std::collections::BTreeMap<usize, Vec<Physical>> = Default::default();
    let mut out = Vec::with_capacity(targets.len());
    for target in targets {
        let mut matched: Vec<Physical> = Vec::new();
        for &(order, member) in &target.members {
            let poles = at_order.entry(order).or_insert_with(|| {
                subspace
                    .poles(order, sample_rate_hz)
                    .iter()
                    .filter_map(physical)
                    .collect()
            });
            let d = |q: &Physical| {
                distance(member.frequency_hz, &member.shape, q.frequency_hz, &q.shape)
            };
            if let Some(q) = poles
                .iter()
                .filter(|q| d(q) <= cut)
                .min_by(|a, c| d(a).total_cmp(&d(c)))
            {
                matched.push(q.clone());
            }
        }
        let enough = 2 * matched.len() >= target.members.len() && !matched.is_empty();
        let refs: Vec<&Physical> = matched.iter().collect();
        out.push(enough.then(|| mean_pole(&refs, &target.pole.shape)));
    }
    out
}

/// The jackknife standard errors from the replicates, shapes aligned in scale and phase to
/// the full record's.
pub(crate) fn standard_errors(full: &Physical, reps: &[Physical]) -> StandardErrors {
    let b = reps.len() as f64;
    let se = |values: &[f64]| {
        let mean = values.iter().sum::<f64>() / b;
        ((b - 1.0) / b * values.iter().map(|v| (v - mean).powi(2)).sum::<f64>()).sqrt()
    };
    let f: Vec<f64> = reps.iter().map(|r| r.frequency_hz).collect();
    let z: Vec<f64> = reps.iter().map(|r| r.damping_ratio).collect();
    let aligned: Vec<Vec<Complex64>> = reps
        .iter()
        .map(|r| aligned(&r.shape, &full.shape))
        .collect();
    let shape = (0..full.shape.len())
        .map(|c| {
            let re: Vec<f64> = aligned.iter().map(|s| s[c].re).collect();
            let im: Vec<f64> = aligned.iter().map(|s| s[c].im).collect();
            [se(&re), se(&im)]
        })
        .collect();
    StandardErrors {
        frequency_hz: se(&f),
        damping_ratio: se(&z),
        shape,
    }
}

/// A mode from its estimate and standard errors: fn, ζ (kept positive) and every shape
/// entry (on the record's DOFs) with 95 % intervals by Student's `t`.
pub(crate) fn mode_with_errors(
    p: &Physical,
    record: &OutputRecord,
    se: &StandardErrors,
    t: f64,
) -> Mode {
    let shape = record
        .channels()
        .iter()
        .enumerate()
        .map(|(c, ch)| ShapeEntry {
            standard_error: se.shape.get(c).copied(),
            ..ShapeEntry::new(super::record::dof(ch), p.shape[c])
        })
        .collect();
    Mode::new(
        Interval::new(p.frequency_hz, se.frequency_hz, t),
        Interval::positive(p.damping_ratio, se.damping_ratio, t),
    )
    .with_shape(shape)
}
