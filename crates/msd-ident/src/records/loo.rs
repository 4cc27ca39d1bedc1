//! Leave-one-record-out validation: each record predicted by the plant fitted to the
//! others.

use super::model::OutputKind;
use super::problem::Joint;
use super::setup::{Record, RecordsOptions};
use super::{LeftOut, channel_fits, fixed_parameters};
use msd_opt::levenberg_marquardt;

/// Each record predicted by the plant fitted to the others, from the joint estimate
/// `x` with the joint noise levels held.
pub(super) fn leave_one_out(
    records: &[Record],
    kinds: &[Vec<OutputKind>],
    options: &RecordsOptions,
    x: &[f64],
    sigma: impl Fn(&str) -> f64 + Copy,
    notes: &mut Vec<String>,
) -> Vec<LeftOut> {
    let fixed = fixed_parameters(options);
    let mut out = Vec::with_capacity(records.len());
    for (r, left) in records.iter().enumerate() {
        let others: Vec<&Record> = records
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != r)
            .map(|(_, rec)| rec)
            .collect();
        let other_kinds: Vec<Vec<OutputKind>> = kinds
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != r)
            .map(|(_, k)| k.clone())
            .collect();
        let mut rest = Joint::new(&others, &other_kinds, options, fixed);
        rest.set_sigmas(sigma);
        let theta = match levenberg_marquardt(&mut rest, x, &options.levenberg_marquardt) {
            Ok(lm) => rest.theta(&lm.x),
            Err(e) => {
                notes.push(format!(
                    "leave-one-out: the fit without record `{}` failed: {e}",
                    left.name
                ));
                continue;
            }
        };
        let mut one = Joint::new(&[left], std::slice::from_ref(&kinds[r]), options, fixed);
        one.set_sigmas(sigma);
        if !one.prepare(theta) {
            notes.push(format!(
                "leave-one-out: record `{}` cannot be predicted by the others' plant",
                left.name
            ));
            continue;
        }
        one.solve_linear();
        let [m, c, k] = theta;
        out.push(LeftOut {
            record: left.name.clone(),
            natural_frequency_hz: (k / m).sqrt() / (2.0 * std::f64::consts::PI),
            damping_ratio: c / (2.0 * (k * m).sqrt()),
            channels: channel_fits(&one, &one.records[0]),
        });
    }
    out
}
