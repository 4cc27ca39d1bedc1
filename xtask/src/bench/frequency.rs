//! The frequency-domain rows: a three-mode fit (issue 21's speed target, ≤ 20 ms) and
//! sets of FRFs (issue 30: 2 FRFs × 1000 lines at orders 2–120 ≤ 30 ms, 30 DOFs × 2000
//! lines ≤ 300 ms).

use super::harness::{Budget, measure};
use super::report::{Row, Target};
use super::rows::fail;
use crate::Result;
use msd_experiment::config::{Config, Spec};
use msd_experiment::frf;
use msd_modal::{
    Dof, FrfWeighting, ModalOptions, ModalParameters, SetMember, fit_mode_set, fit_modes,
    synthetic_frequency_response,
};

/// Three modes (fn 10, 23, 41 Hz; ζ 1 %, 2 %, 0.5 %) in 2000 lines with 1 % noise:
/// the stabilization diagram over orders 2–40 and the polish of every modal parameter
/// (msd-ident's criterion bench `frf` measures the same).
pub fn frequency_domain(budget: &Budget) -> Result<Vec<Row>> {
    let modes = [(10.0, 0.01, 1.0), (23.0, 0.02, -0.6), (41.0, 0.005, 0.4)].map(|(f, z, a)| {
        ModalParameters {
            natural_frequency_hz: f,
            damping_ratio: z,
            modal_constant: a,
            modal_constant_imaginary: 0.0,
        }
    });
    let f: Vec<f64> = (1..=2000).map(|i| 0.025 * i as f64).collect();
    let frf =
        synthetic_frequency_response(&f, 0.01, 1, |f| modes.iter().map(|m| m.receptance(f)).sum())
            .map_err(fail("bench: frequency response"))?;
    let options = ModalOptions {
        weighting: FrfWeighting::Relative,
        ..ModalOptions::default()
    };
    let fit = fit_modes(&frf, &options).map_err(fail("bench: modal fit"))?;
    let samples = measure(budget, || fit_modes(&frf, &options).ok());
    Ok(vec![
        impact_row(budget)?,
        Row::new(
            "frequency domain",
            "three modes, 2000 lines: stabilization diagram orders 2–40 + polish",
            samples,
        )
        .target(Target::Seconds(20e-3))
        .note(format!(
            "{} modes found, {} iterations",
            fit.modes.len(),
            fit.iterations
        )),
        set_row(
            budget,
            2,
            (1..=1000).map(f64::from).collect(),
            &[
                (52.0, 5e-4),
                (142.0, 3.5e-4),
                (279.0, 1.9e-4),
                (460.0, 1.9e-4),
                (687.0, 1.5e-4),
                (959.0, 1.3e-4),
            ],
            [2, 120],
            30e-3,
            None,
        )?,
        large_set(budget, None)?,
        large_set(budget, Some(20))?,
    ])
}

/// configs/hammer-2dof.toml without figures: five hits simulated (16× finer than
/// sampled), H1 with the impact windows and the lines' correlation, the stabilization
/// diagram and the polish with the sandwich covariance, the truth compared.
fn impact_row(budget: &Budget) -> Result<Row> {
    let path = crate::project_root().join("configs/hammer-2dof.toml");
    let config = Config::load(&path)?;
    let options = crate::RunOptions::default();
    let run = || frf::run(Spec::new(config.clone())?, &options);
    let outcome = run()?;
    let samples = measure(budget, || run().ok());
    let timing = |stage: &str| {
        (outcome.timings.iter())
            .find(|(name, _)| *name == stage)
            .map_or(0.0, |(_, t)| 1e3 * t.as_secs_f64())
    };
    Ok(Row::new(
        "frequency domain",
        "impact test, configs/hammer-2dof.toml without figures: simulation, H1, diagram, polish",
        samples,
    )
    .note(format!(
        "{} modes; of one run: {:.1} ms data, {:.1} ms fit",
        outcome.fit.poles().len(),
        timing("data"),
        timing("fit")
    )))
}

/// The 30 × 2000-line set, its members with the coherence of `averages` or without.
fn large_set(budget: &Budget, averages: Option<usize>) -> Result<Row> {
    let f = (1..=2000).map(|i| 0.5 * f64::from(i)).collect();
    let modes = [(40.0, 0.01), (160.0, 0.005), (360.0, 0.003), (640.0, 0.002)];
    set_row(budget, 30, f, &modes, [2, 40], 300e-3, averages)
}

/// A roving-hammer set on a simply supported beam: `points` hammer points (shapes
/// sin(rπx/L) at x = (i + 0.7)L/(points + 1), off the modes' nodes), the response at the
/// first, `modes` (fn, ζ), 1 % noise; fitted at `orders`. With `averages` K, each member
/// carries the coherence its noise gives over K averages: the members weighted by their
/// noise models and the set's residual checked against them.
fn set_row(
    budget: &Budget,
    points: usize,
    f: Vec<f64>,
    modes: &[(f64, f64)],
    orders: [usize; 2],
    target: f64,
    averages: Option<usize>,
) -> Result<Row> {
    let shape = |r: usize, i: usize| {
        ((r + 1) as f64 * std::f64::consts::PI * (i as f64 + 0.7) / (points + 1) as f64).sin()
    };
    let members = (0..points)
        .map(|j| {
            let terms: Vec<ModalParameters> = modes
                .iter()
                .enumerate()
                .map(|(r, &(fn_hz, zeta))| ModalParameters {
                    natural_frequency_hz: fn_hz,
                    damping_ratio: zeta,
                    modal_constant: 2.0 * shape(r, 0) * shape(r, j),
                    modal_constant_imaginary: 0.0,
                })
                .collect();
            let mut frf = synthetic_frequency_response(&f, 0.01, j as u64 + 1, |f| {
                terms.iter().map(|m| m.receptance(f)).sum()
            })?;
            if let Some(k) = averages {
                // (1 − γ²)/(K·γ²) = (K − 1)/K·1e-4, the relative variance of 1 % noise.
                frf.coherence = vec![1.0 / (1.0 + (k as f64 - 1.0) * 1e-4); f.len()];
                frf.averages = k;
            }
            let dof = |node: usize| Dof {
                node: node as u32 + 1,
                direction: 3,
            };
            Ok(SetMember {
                frf,
                response: dof(0),
                reference: dof(j),
            })
        })
        .collect::<std::result::Result<Vec<_>, msd_ident::IdentError>>()
        .map_err(fail("bench: a set of FRFs"))?;
    let options = ModalOptions {
        orders,
        ..ModalOptions::default()
    };
    let fit = fit_mode_set(&members, &options).map_err(fail("bench: set fit"))?;
    let samples = measure(budget, || fit_mode_set(&members, &options).ok());
    let coherence = averages.map_or(String::new(), |k| {
        format!(" with coherence ({k} averages): noise models and the residual check")
    });
    let check = fit.noise_check.map_or(String::new(), |c| {
        format!(", SSE/E[SSE] {:.3}", c.variance_ratio)
    });
    Ok(Row::new(
        "frequency domain",
        format!(
            "set of {points} FRFs × {} lines{coherence}: diagram orders {}–{}, selection, common poles, residues",
            f.len(),
            orders[0],
            orders[1]
        ),
        samples,
    )
    .target(Target::Seconds(target))
    .note(format!(
        "{} of {} modes found, {} pole iterations{check}",
        fit.modes.len(),
        modes.len(),
        fit.iterations
    )))
}
