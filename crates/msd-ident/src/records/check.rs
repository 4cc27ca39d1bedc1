//! The records' checks, each refusal naming the record and the channel.

use super::model::OutputKind;
use super::setup::{Record, RecordsOptions};
use crate::{
    data::MIN_SAMPLES,
    error::{IdentError, Result},
};

/// Checks every record against the options; returns each channel's output kind.
pub(crate) fn check_records(
    records: &[Record],
    options: &RecordsOptions,
) -> Result<Vec<Vec<OutputKind>>> {
    let Some(first) = records.first() else {
        return Err(IdentError::Setup {
            setup: options.drive.setup(),
            reason: "no records to fit: give at least one record".into(),
        });
    };
    let dt0 = first.excitation.dt();
    records
        .iter()
        .map(|record| {
            let fail = |channel: Option<&str>, reason: String| IdentError::InvalidRecord {
                record: record.name.clone(),
                channel: channel.map(str::to_string),
                reason,
            };
            let (dt, n) = (record.excitation.dt(), record.excitation.len());
            if (dt - dt0).abs() > 1e-9 * dt0 {
                return Err(fail(None, format!(
                    "sampled every {dt} s, but record `{}` every {dt0} s: fit records of one sampling rate together (resample one of them)",
                    first.name
                )));
            }
            if n < MIN_SAMPLES {
                return Err(fail(None, format!("{n} samples: at least {MIN_SAMPLES} are needed")));
            }
            let drive = record.excitation.samples();
            if options.drive != crate::plant::Drive::None
                && drive.iter().all(|v| *v == drive[0])
            {
                return Err(fail(None, format!(
                    "the {} is {} at every sample: nothing drives the mass, so the response carries no information on the plant's gain (a record that only rings down is a free decay: no drive, which identifies ωn and ζ)",
                    options.drive.quantity(),
                    drive[0]
                )));
            }
            if record.channels.is_empty() {
                return Err(fail(None, "no channels: give at least one measured response".into()));
            }
            for (i, channel) in record.channels.iter().enumerate() {
                if record.channels[..i].iter().any(|c| c.name == channel.name) {
                    return Err(fail(Some(&channel.name), "two channels of this name in one record: give each sensor its own name".into()));
                }
                check_samples(&channel.samples, n).map_err(|reason| fail(Some(&channel.name), reason))?;
            }
            record
                .channels
                .iter()
                .map(|c| options.output_kind(&record.name, c))
                .collect()
        })
        .collect()
}

/// The length, finiteness and variation of one channel's samples.
fn check_samples(samples: &[f64], n: usize) -> std::result::Result<(), String> {
    if samples.len() != n {
        return Err(format!(
            "{} samples, but the excitation has {n}: every channel needs one sample per excitation sample",
            samples.len()
        ));
    }
    if let Some((i, v)) = samples.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(format!("sample {i} is {v}: expected a finite number"));
    }
    if samples.iter().all(|v| *v == samples[0]) {
        return Err(format!(
            "every sample is {}: a constant channel carries no information (a disconnected sensor, or the wrong column?)",
            samples[0]
        ));
    }
    Ok(())
}
