//! Covariance-driven stochastic subspace identification with reference channels
//! (SSI-cov/ref), its stabilization diagram, the automatic selection and the intervals.

use msd_opt::statistics::t_975;
use msd_signal::Complex64;

use super::covariance::{BlockCovariances, Lags, subspace_matrix};
use super::horizon::block_rows;
use super::options::OmaOptions;
use super::record::OutputRecord;
use super::record::order;
use super::select::{
    Physical, clusters, column, flag_stability, mean_pole, selected, without_splits,
};
use super::subspace::{Pole, Subspace};
use super::uncertainty::{StandardErrors, Target, jackknife, mode_with_errors};
use super::{OmaFit, OmaMethod};
use msd_modal_core::diagram::StabilizationDiagram;
use msd_modal_core::error::{ModalError, Result};
use msd_modal_core::mode::Mode;
use msd_modal_core::phase::modal_phase_collinearity;
use nalgebra::DMatrix;

/// The modes of an output-only record by SSI-cov/ref, selected automatically (or at the
/// named frequencies), with 95 % intervals on fn, ζ and every shape entry.
///
/// ## The method
/// Each channel centred and scaled to unit variance; the covariances R_k of every channel
/// with the references at lags 1 … 2i − 1 fill the block Toeplitz matrix T (i block rows);
/// its SVD gives, for every model order n, the observability matrix, the state matrix by
/// the shift of its block rows, the poles λ = fs·ln μ and the shapes C·ψ (Peeters & De
/// Roeck, Mech. Syst. Signal Process. 13, 1999). Shapes are reported as displacement
/// shapes in the channels' units (a velocity entry divided by λ, an acceleration's by
/// λ²), largest entry 1. The selection and its thresholds: [`OmaOptions`]; a mode's
/// estimate is the mean of its cluster's poles at every fourth order of the diagram. The
/// intervals: the leave-one-block-out jackknife over `blocks` blocks of the record, each
/// replicate repeating the estimate (the subspace, the cluster's orders, the mean), with
/// Student's t on `blocks` − 1 degrees of freedom; the replicates run side by side (rayon)
/// and give the same numbers whatever the thread count.
///
/// Errors: a bad record (NaN, a constant channel, lengths, references:
/// [`OutputRecord::check`]), bad options, a record too short for the block rows and
/// blocks, orders the Toeplitz matrix cannot hold, no mode selected.
///
/// ```
/// use msd_modal::{Channel, Dof, OmaOptions, OutputRecord, Quantity, ssi_cov};
/// // Two channels of one lightly damped 4 Hz mode driven by noise (an AR(2) process).
/// let (fs, f, zeta) = (50.0_f64, 4.0_f64, 0.02_f64);
/// let w = std::f64::consts::TAU * f / fs;
/// let (a1, a2) = (2.0 * (-zeta * w).exp() * (w * (1.0 - zeta * zeta).sqrt()).cos(), -(-2.0 * zeta * w).exp());
/// let mut x = vec![0.0; 20_000];
/// let mut seed = 1_u64;
/// for t in 2..x.len() {
///     seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
///     x[t] = a1 * x[t - 1] + a2 * x[t - 2] + ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5);
/// }
/// let channel = |node: u32, gain: f64| Channel::new(format!("d{node}"), Quantity::Displacement,
///     x.iter().map(|v| gain * v).collect()).at(Dof { node, direction: 1 });
/// let record = OutputRecord::new(fs, vec![channel(1, 1.0), channel(2, -0.5)]);
/// let fit = ssi_cov(&record, &OmaOptions { orders: [2, 20], ..OmaOptions::default() })?;
/// assert_eq!(fit.modes.len(), 1);
/// let mode = &fit.modes[0];
/// assert!((mode.natural_frequency_hz.value / 4.0 - 1.0).abs() < 0.005); // 0.3 % here
/// assert!(mode.natural_frequency_hz.standard_error < 0.01);
/// assert!((mode.shape[1].re + 0.5).abs() < 0.01);
/// # Ok::<(), msd_modal::ModalError>(())
/// ```
pub fn ssi_cov(record: &OutputRecord, options: &OmaOptions) -> Result<OmaFit> {
    subspace_identification(record, options, OmaMethod::SsiCov)
}

/// The modes of an output-only record by data-driven SSI with references (SSI-dat/ref,
/// the unweighted principal component algorithm): as [`ssi_cov`] in everything but the
/// matrix whose SVD gives the observability matrix — the projection of the future
/// outputs on the past references, whose left singular vectors are those of T·L⁻ᵀ (L the
/// Cholesky factor of the past references' covariance), computed from the same block
/// covariances rather than by a QR of the data's block Hankel matrix (the same numbers up
/// to the record's end effects, at the cost of SSI-cov). Same options, selection and
/// jackknife intervals.
///
/// ```
/// use msd_modal::{OmaOptions, ShearBuilding, ssi_dat};
/// use rand::SeedableRng;
/// use rand_distr::{Distribution, StandardNormal};
/// let building = ShearBuilding { masses: vec![20.0; 2], stiffnesses: vec![8000.0; 2], damping_ratio: 0.02 };
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
/// let record = building.ambient_record(50.0, 20_000, 0.1, || StandardNormal.sample(&mut rng))?;
/// let fit = ssi_dat(&record, &OmaOptions { orders: [2, 20], ..OmaOptions::default() })?;
/// let truth = building.modes()?;
/// assert_eq!(fit.modes.len(), 2);
/// for (mode, (f, _)) in fit.modes.iter().zip(&truth) {
///     assert!((mode.natural_frequency_hz.value / f - 1.0).abs() < 0.01);
/// }
/// # Ok::<(), msd_modal::ModalError>(())
/// ```
pub fn ssi_dat(record: &OutputRecord, options: &OmaOptions) -> Result<OmaFit> {
    subspace_identification(record, options, OmaMethod::SsiDat)
}

/// SSI-cov or SSI-dat (`method`), everything else shared.
fn subspace_identification(
    record: &OutputRecord,
    options: &OmaOptions,
    method: OmaMethod,
) -> Result<OmaFit> {
    record.check()?;
    options.validate()?;
    let fs = record.sample_rate_hz();
    let references = record.reference_indices();
    let (l, r) = (record.channels().len(), references.len());
    let (scaled, scales) = record.standardised();
    let i = block_rows(options, &scaled, fs, r);
    check_sizes(record, options, i, l, r)?;
    let lags = Lags {
        first: 0,
        last: 2 * i - 1,
    };
    let covariances = BlockCovariances::with_lags(&scaled, &references, lags, options.blocks);
    let data_driven = method == OmaMethod::SsiDat;
    let matrix = |cov: &[DMatrix<f64>]| subspace_matrix(cov, i, &references, data_driven);
    let t = matrix(&covariances.covariances(None)).ok_or_else(not_converged)?;
    let subspace = Subspace::new(t, l, options.orders[1]).ok_or_else(not_converged)?;
    let orders: Vec<usize> = (options.orders[0]..=options.orders[1])
        .step_by(options.order_step)
        .collect();
    let nyquist = 0.5 * fs;
    let band = options.band_hz.unwrap_or([0.0, nyquist]);
    let physical = |order_index: usize| {
        let quantities: Vec<i32> = record
            .channels()
            .iter()
            .map(|c| order(c.quantity))
            .collect();
        let scales = scales.clone();
        move |p: &Pole| physical_pole(p, order_index, &scales, &quantities, band, options)
    };
    let mut poles: Vec<Physical> = Vec::new();
    for (k, &n) in orders.iter().enumerate() {
        poles.extend(subspace.poles(n, fs).iter().filter_map(physical(k)));
    }
    let mut diagram_orders = flag_stability(&orders, &mut poles, options);
    let found = clusters(&poles, options);
    let (chosen, splits) = without_splits(
        selected(&found, &poles, orders.len(), options)?,
        &found,
        &poles,
        options,
    );
    mark_modes(&mut diagram_orders, &chosen, &found, &poles);
    let used: Vec<Vec<usize>> = chosen
        .iter()
        .map(|&c| estimated_from(&found[c].members, &poles))
        .collect();
    let estimates: Vec<Physical> = chosen
        .iter()
        .zip(&used)
        .map(|(&c, used)| {
            let members: Vec<&Physical> = used.iter().map(|&m| &poles[m]).collect();
            mean_pole(&members, &poles[found[c].representative].shape)
        })
        .collect();
    let targets: Vec<Target<'_>> = used
        .iter()
        .zip(&estimates)
        .map(|(used, estimate)| Target {
            members: used
                .iter()
                .map(|&m| (orders[poles[m].order_index], &poles[m]))
                .collect(),
            pole: estimate,
        })
        .collect();
    let errors = jackknife(
        &covariances,
        &matrix,
        fs,
        &targets,
        options.cluster_distance,
        physical(0),
    );
    let t975 = t_975(options.blocks - 1);
    let mut modes = Vec::new();
    let mut unconfirmed: Vec<_> = splits.iter().map(|&c| column(&found[c], &poles)).collect();
    for ((&c, se), estimate) in chosen.iter().zip(&errors).zip(&estimates) {
        let cluster = &found[c];
        match se {
            Some(se) => modes.push(mode_of(
                &cluster.members,
                estimate,
                &poles,
                record,
                se,
                t975,
            )),
            None => unconfirmed.push(column(cluster, &poles)),
        }
    }
    let diagram = StabilizationDiagram {
        orders: diagram_orders,
        candidates: found.iter().map(|c| column(c, &poles)).collect(),
        modes: chosen.iter().map(|&c| column(&found[c], &poles)).collect(),
        band_hz: band,
    };
    Ok(OmaFit {
        method,
        modes,
        diagram,
        block_rows: Some(i),
        blocks: options.blocks,
        references: references
            .iter()
            .map(|&r| record.channels()[r].name.clone())
            .collect(),
        singular_values: subspace.singular_values,
        unconfirmed,
        spectrum: None,
    })
}

/// Marks in the diagram each pole that formed a chosen cluster with that mode's index.
fn mark_modes(
    diagram: &mut [msd_modal_core::diagram::DiagramOrder],
    chosen: &[usize],
    found: &[super::select::Cluster],
    poles: &[Physical],
) {
    for (m, &c) in chosen.iter().enumerate() {
        for &p in &found[c].members {
            let order = &mut diagram[poles[p].order_index];
            let at = order
                .poles
                .iter()
                .position(|d| d.natural_frequency_hz == poles[p].frequency_hz);
            if let Some(at) = at {
                order.poles[at].mode = Some(m);
            }
        }
    }
}

/// The record long enough and the orders within the Toeplitz matrix.
fn check_sizes(
    record: &OutputRecord,
    options: &OmaOptions,
    i: usize,
    l: usize,
    r: usize,
) -> Result<()> {
    let largest = (i * l).min(i * r);
    if options.orders[1] > largest {
        return Err(ModalError::InvalidParameter {
            name: "orders[1]",
            value: options.orders[1] as f64,
            expected: "at most block_rows × (the number of references): raise block_rows or name more references",
        });
    }
    let needed = options.blocks * 4 * i;
    if record.len() < needed {
        return Err(ModalError::TooFewSamples {
            got: record.len(),
            needed,
            why: "each of the blocks must hold at least four times the lags (blocks × 4 × block_rows)",
        });
    }
    record.check_band(options.band_hz)
}

/// A pole as a physical one (inside the band, 0 < ζ ≤ the largest, MPC high enough),
/// its shape in displacement and the channels' units, largest entry 1.
fn physical_pole(
    pole: &Pole,
    order_index: usize,
    scales: &[f64],
    quantities: &[i32],
    band: [f64; 2],
    options: &OmaOptions,
) -> Option<Physical> {
    let (f, zeta) = (pole.frequency_hz(), pole.damping_ratio());
    if !(f >= band[0] && f <= band[1] && zeta > 0.0 && zeta <= options.max_damping_ratio) {
        return None;
    }
    let shape: Vec<Complex64> = pole
        .shape
        .iter()
        .zip(scales.iter().zip(quantities))
        .map(|(v, (s, &q))| v * *s / pole.lambda.powi(q))
        .collect();
    let largest = shape
        .iter()
        .copied()
        .max_by(|a, b| a.norm().total_cmp(&b.norm()))?;
    if largest.norm() == 0.0 {
        return None;
    }
    let shape: Vec<Complex64> = shape.iter().map(|v| v / largest).collect();
    (modal_phase_collinearity(&shape) >= options.min_mpc).then_some(Physical {
        order_index,
        frequency_hz: f,
        damping_ratio: zeta,
        shape,
        stable: false,
    })
}

/// The mode of a cluster: its mean pole's fn, ζ and shape with the jackknife's
/// intervals, the cluster's spread and size.
fn mode_of(
    members: &[usize],
    p: &Physical,
    poles: &[Physical],
    record: &OutputRecord,
    se: &StandardErrors,
    t: f64,
) -> Mode {
    let sd = |v: Vec<f64>| {
        let n = v.len() as f64;
        let mean = v.iter().sum::<f64>() / n;
        (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt()
    };
    let mut mode = mode_with_errors(p, record, se, t);
    mode.stable_orders = Some(members.len());
    mode.cluster_spread = Some([
        sd(members.iter().map(|&m| poles[m].frequency_hz).collect()),
        sd(members.iter().map(|&m| poles[m].damping_ratio).collect()),
    ]);
    mode
}

fn not_converged() -> ModalError {
    ModalError::EstimationFailed {
        reason: "the SVD of the covariances' Toeplitz matrix did not converge".into(),
    }
}

/// The cluster's poles a mode is estimated from: those at every fourth order of the
/// diagram (the orders' estimates differ little, and each replicate of the jackknife
/// repeats only these orders: a quarter of the eigenproblems), or all of them where fewer
/// than three lie there.
fn estimated_from(members: &[usize], poles: &[Physical]) -> Vec<usize> {
    let thinned: Vec<usize> = members
        .iter()
        .copied()
        .filter(|&m| poles[m].order_index % 4 == 3)
        .collect();
    if thinned.len() >= 3 {
        thinned
    } else {
        members.to_vec()
    }
}
