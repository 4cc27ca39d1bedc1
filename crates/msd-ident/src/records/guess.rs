//! The starting point of a joint fit: candidate (ωn, ζ) from each channel, the one with
//! the smallest projected cost.
//!
//! Every channel of a linear plant shares the plant's poles, so an ARX(2, 3) fit of any
//! channel against the drive (decimated by 2, 4, … as in
//! [`arx_initial_guess`](crate::arx::arx_initial_guess), from the coarsest rate to the first
//! that resolves the resonance well) proposes ωn and ζ; a free decay's
//! candidates are its classroom estimates. With a force drive the outputs scale as 1/m
//! at fixed ωn and ζ, so the mass of each candidate is a linear least-squares gain.

use super::problem::Joint;
use super::setup::RecordsOptions;
use crate::arx::arx_poles;
use crate::plant::Drive;
use crate::{
    error::{IdentError, Result},
    free_decay::ClassroomEstimates,
    params::KnownParameter,
};
use std::f64::consts::PI;

/// θ₀ (m, c, k; m = 1 and c, k per unit mass unless the drive is a force).
pub(crate) fn initial_theta(problem: &Joint<'_>, options: &RecordsOptions) -> Result<[f64; 3]> {
    let candidates = match options.initial_guess {
        Some(g) => vec![(g.natural_frequency(), g.damping_ratio().max(1e-4))],
        None if problem.drive == Drive::None => classroom_candidates(problem)?,
        None => arx_candidates(problem),
    };
    // Scored on the first record alone: the candidates come from it, and the guess then
    // costs the same whatever the number of records.
    let first = &problem.records[0];
    let weights: Vec<(&str, f64)> = first
        .record
        .channels
        .iter()
        .map(|c| c.name.as_str())
        .zip(first.weights.iter().copied())
        .collect();
    let mut scorer = Joint::new(
        &[first.record],
        std::slice::from_ref(&first.kinds),
        options,
        [None; 3],
    );
    scorer.set_sigmas(|name| {
        weights
            .iter()
            .find(|(n, _)| *n == name)
            .map_or(1.0, |(_, w)| 1.0 / w)
    });
    let candidates = distinct(candidates);
    let best = candidates
        .iter()
        .filter_map(|&(wn, zeta)| score(&mut scorer, wn, zeta).map(|(cost, m)| (cost, wn, zeta, m)))
        .min_by(|a, b| a.0.total_cmp(&b.0));
    if problem.drive != Drive::None {
        // A reversed sensor: its data against the response of the best candidate (or of
        // each, when none scores).
        let tried: Vec<(f64, f64)> = match best {
            Some((_, wn, zeta, _)) => vec![(wn, zeta)],
            None => candidates.clone(),
        };
        if let Some(reason) = inverted(&mut scorer, &tried) {
            return Err(IdentError::Setup {
                setup: problem.drive.setup(),
                reason,
            });
        }
    }
    let (wn, zeta, gain_mass) = match (best, options.initial_guess) {
        (Some((_, wn, zeta, m)), _) => (wn, zeta, m),
        // A given guess is used as it is, even where its response does not score.
        (None, Some(g)) => (g.natural_frequency(), g.damping_ratio().max(1e-4), g.mass),
        (None, None) => {
            return Err(IdentError::Setup {
                setup: problem.drive.setup(),
                reason: "no initial guess could be formed from the records (no candidate ωn, ζ could be simulated); give `initial_guess`".into(),
            });
        }
    };
    let m = match (problem.drive, options.known, options.initial_guess) {
        (Drive::Force, KnownParameter::Mass(m), _) => m,
        (Drive::Force, KnownParameter::Stiffness(k), _) => k / (wn * wn),
        // A given guess's ωn and ζ are kept, its gain matched to the records (the mass
        // that best scales its response): a mass 100× off otherwise sends the search to
        // a wrong minimum, c to zero.
        (Drive::Force, _, _) => gain_mass,
        _ => 1.0,
    };
    Ok([m, 2.0 * zeta * wn * m, wn * wn * m])
}

/// The classroom estimates of each record's first channel; a record that does not ring
/// down is refused, naming it.
fn classroom_candidates(problem: &Joint<'_>) -> Result<Vec<(f64, f64)>> {
    let dt = problem.records[0].record.excitation.dt();
    problem
        .records
        .iter()
        .map(|rec| {
            let channel = &rec.record.channels[0];
            let c = ClassroomEstimates::from_record(dt, &channel.samples).map_err(|e| {
                IdentError::InvalidRecord {
                    record: rec.record.name.clone(),
                    channel: Some(channel.name.clone()),
                    reason: match e {
                        IdentError::NotIdentifiable { reason } => reason,
                        other => other.to_string(),
                    },
                }
            })?;
            Ok((2.0 * PI * c.natural_frequency_hz, c.damping_ratio))
        })
        .collect()
}

/// ARX poles of every channel of the first record, from the coarsest rate of the
/// cascade to finer ones until the resonance sits below 0.15 rad per sample (finer
/// rates crowd the poles at z = 1 and fit worse, and cost the most).
fn arx_candidates(problem: &Joint<'_>) -> Vec<(f64, f64)> {
    const MIN_DECIMATED: usize = 100;
    let record = problem.records[0].record;
    let cascade = |x: &[f64]| {
        let mut levels = vec![x.to_vec()];
        while let Some(last) = levels.last().filter(|x| x.len() / 2 >= MIN_DECIMATED) {
            match msd_signal::decimate(last, 2) {
                Ok(d) => levels.push(d),
                Err(_) => break,
            }
        }
        levels
    };
    let drive = cascade(record.excitation.samples());
    let mut candidates = Vec::new();
    for channel in &record.channels {
        let response = cascade(&channel.samples);
        for (j, (u, y)) in drive.iter().zip(&response).enumerate().rev() {
            let dt = record.excitation.dt() * (1u64 << j) as f64;
            if let Ok((wn, zeta)) = arx_poles(u, y, dt) {
                candidates.push((wn, zeta));
                if wn * dt < 0.15 {
                    break;
                }
            }
        }
    }
    candidates
}

/// The usable candidates (finite, ωn > 0, ζ > 0: what [`score`] can simulate) without
/// near-repeats, in their order: one within 2 % in ωn and 10 % in ζ of a kept one (on a
/// log scale, so the test is symmetric) starts Levenberg–Marquardt in the same basin, and
/// scoring it would cost a simulation of the record for nothing (the channels of one
/// record and the rates of the cascade mostly agree that closely).
fn distinct(candidates: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    let mut kept: Vec<(f64, f64)> = Vec::with_capacity(candidates.len());
    let usable =
        |&(wn, zeta): &(f64, f64)| wn.is_finite() && wn > 0.0 && zeta.is_finite() && zeta > 0.0;
    for (wn, zeta) in candidates.into_iter().filter(usable) {
        let near = |&(w, z): &(f64, f64)| (wn / w).ln().abs() < 0.02 && (zeta / z).ln().abs() < 0.1;
        if !kept.iter().any(near) {
            kept.push((wn, zeta));
        }
    }
    kept
}

/// Why a channel looks reversed: its data correlate with the response of one of the
/// `candidates` at −0.5 or below (a sound channel correlates near +1, noise near 0).
fn inverted(problem: &mut Joint<'_>, candidates: &[(f64, f64)]) -> Option<String> {
    for &(wn, zeta) in candidates {
        if !problem.prepare([1.0, 2.0 * zeta * wn, wn * wn]) {
            continue;
        }
        let correlations = problem.channel_correlations();
        if let Some((name, r)) = correlations.iter().find(|(_, r)| *r <= -0.5) {
            return Some(format!(
                "channel `{name}` appears inverted: its correlation with the response the drive predicts (fn = {:.4} Hz, ζ = {:.4}) is {r:.2}; check how the sensor is mounted and wired, and give it scale = -1 (or negate its calibration)",
                wn / (2.0 * PI),
                zeta
            ));
        }
    }
    None
}

/// The projected cost of (ωn, ζ) and, with a force drive, the best mass (the inverse
/// of the least-squares gain of the response from rest).
fn score(problem: &mut Joint<'_>, wn: f64, zeta: f64) -> Option<(f64, f64)> {
    if !(wn.is_finite() && wn > 0.0 && zeta.is_finite() && zeta > 0.0) {
        return None;
    }
    if !problem.prepare([1.0, 2.0 * zeta * wn, wn * wn]) {
        return None;
    }
    let (y, f) = problem.projected_data_and_response();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let (yy, yf, ff) = (dot(&y, &y), dot(&y, &f), dot(&f, &f));
    let gain = if problem.drive == Drive::Force {
        yf / ff
    } else {
        1.0
    };
    let cost = yy - 2.0 * gain * yf + gain * gain * ff;
    (cost.is_finite() && gain > 0.0).then_some((cost, 1.0 / gain))
}

#[cfg(test)]
mod tests {
    use super::distinct;

    #[test]
    fn near_repeats_collapse_and_an_unusable_candidate_suppresses_nothing() {
        let candidates = vec![
            (f64::NAN, 0.05),
            (6.9, -0.01),
            (6.0, 0.05),
            (6.05, 0.052), // within 1 % and 4 % of the first usable: dropped
            (6.0, 0.06),   // ζ 18 % away: kept
            (6.3, 0.05),   // ωn 5 % away: kept
            (5.95, 0.0505),
        ];
        assert_eq!(
            distinct(candidates),
            vec![(6.0, 0.05), (6.0, 0.06), (6.3, 0.05)]
        );
    }
}
