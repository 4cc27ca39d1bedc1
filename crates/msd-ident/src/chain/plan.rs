//! `predict_chain`: the Cramér–Rao prediction of a chain test before it is run.

use super::problem::{ChainProblem, Layout, enough_rows};
use super::setup::{ChainParameters, ChainSetup, setup_error};
use super::uncertainty::{ChainUncertainty, Point, uncertainty_at};
use super::{ChainOptions, simulate_chain};
use crate::error::{IdentError, Result};
use msd_opt::LeastSquaresProblem;
use nalgebra::DMatrix;

/// The uncertainty a fit of one record of `setup` will have if the chain is `truth`, the
/// drive `input` (every `dt` s) and each sensor's noise σ as in `noise`: the
/// Cramér–Rao bound σ²(JᵀJ)⁻¹ from the exact sensitivities at the truth (the fit's own
/// linearisation, with the true noise levels). A sensor's `delay` is its true delay; an
/// estimated one (`estimate_delay`) gets an interval too.
///
/// ```
/// use msd_ident::{chain::{ChainOptions, ChainParameters, ChainSetup, predict_chain}};
/// let paper = ChainParameters { masses: vec![2.5], dampers: vec![1.8], springs: vec![120.0], ..ChainParameters::default() };
/// let force: Vec<f64> = (0..5000).map(|i| (0.01 * i as f64).sin()).collect();
/// let plan = predict_chain(&ChainSetup::default(), &paper, &force, 2e-3, &[0.0025], &ChainOptions::default())?;
/// let k = plan.intervals.expect("identified").springs[0];
/// assert!(k.standard_error > 0.0 && k.standard_error < 1.0);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn predict_chain(
    setup: &ChainSetup,
    truth: &ChainParameters,
    input: &[f64],
    dt: f64,
    noise: &[f64],
    options: &ChainOptions,
) -> Result<ChainUncertainty> {
    let outputs = simulate_chain(setup, truth, input, dt)?;
    if noise.len() != setup.sensors.len() {
        return Err(setup_error(format!(
            "{} noise levels: expected one per sensor ({})",
            noise.len(),
            setup.sensors.len()
        )));
    }
    if let Some((i, s)) = noise
        .iter()
        .enumerate()
        .find(|(_, s)| !(s.is_finite() && **s > 0.0))
    {
        return Err(setup_error(format!(
            "sensors[{i}] noise σ = {s}: expected a finite number > 0 (a noiseless channel would predict zero uncertainty)"
        )));
    }
    let record = setup.recording("plan", dt, input.to_vec(), outputs);
    setup.check_recording(&record)?;
    super::setup::levels(&record)?;
    if let Some(&m) = options
        .known_masses
        .iter()
        .find(|&&m| !(1..=setup.masses).contains(&m))
    {
        return Err(setup_error(format!(
            "known_masses contains {m}: expected masses from 1 to {}",
            setup.masses
        )));
    }
    let layout = Layout::new(setup, &options.known_masses, truth);
    let delays: Vec<f64> = setup
        .sensors
        .iter()
        .map(|s| s.delay.unwrap_or(0.0))
        .collect();
    let mut problem = ChainProblem {
        setup,
        record: &record,
        layout: &layout,
        base: truth,
        delays: &delays,
        noise: noise.to_vec(),
    };
    let rows = problem.residual_count();
    enough_rows(rows, layout.len())?;
    let theta = layout.theta(truth, &delays);
    let mut jacobian = DMatrix::zeros(rows, layout.len());
    // Non-finite sensitivities (absurd parameter ratios) would stall the SVD below.
    if !problem.jacobian(&theta, &mut jacobian) || jacobian.iter().any(|v| !v.is_finite()) {
        return Err(IdentError::EstimationFailed {
            reason: "the chain's sensitivities cannot be computed at the planned plant".into(),
        });
    }
    let at = Point {
        setup,
        layout: &layout,
        theta: &theta,
        base: truth,
        delays: &delays,
    };
    // Weighted by the true σ: the residuals have unit variance.
    Ok(uncertainty_at(
        &at,
        &jacobian,
        1.0,
        rows - layout.len(),
        None,
    ))
}
