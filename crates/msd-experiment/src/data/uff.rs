//! The time records of a Universal File Format file (datasets 58 and 58b of function
//! type 1, "time response", as test systems export a run) as named channels for the
//! `[data]` and `[setup]` readers.
//!
//! Each time response is a channel named after its DOF, `node:direction` as `msd inspect`
//! lists the file (`1:+Z`, `12:-RX`); when two share a DOF, each gets ` #k`, k its
//! number in `msd inspect`'s listing plus one (as `function = k` counts them). Its unit is
//! the ordinate axis's units label (else, in an SI file, the unit its data type says),
//! its sampling rate the abscissa's step. Every channel
//! must share one grid: the same start, step and length.

use crate::data::text::rate_of_step;
use msd_files::Channel;
use msd_uff::{Abscissa, Function58, FunctionType, Ordinate, UffFile, direction_name};

/// The time responses of `file` as channels on one grid, `Ok(None)` when it holds none;
/// an `Err` says which function's grid or values cannot be read, and why.
pub(crate) fn time_channels(file: &UffFile) -> Result<Option<Vec<Channel>>, String> {
    let records: Vec<(usize, &Function58)> = (file.functions.iter().enumerate())
        .filter(|(_, f)| f.function_type == FunctionType::TimeResponse)
        .collect();
    let Some(&(first_index, first)) = records.first() else {
        return Ok(None);
    };
    let (start, step) = grid(first_index, first)?;
    let mut channels = Vec::with_capacity(records.len());
    for &(index, f) in &records {
        let (s, h) = grid(index, f)?;
        let same = (s - start).abs() <= 1e-9 * step && (h / step - 1.0).abs() <= 1e-9;
        if !same || f.len() != first.len() {
            return Err(format!(
                "time response {index} ({}) has {} points from {s} s every {h} s, time response {first_index} {} from {start} s every {step} s: expected one grid for every channel",
                dof(f),
                f.len(),
                first.len()
            ));
        }
        let Ordinate::Real(values) = &f.ordinate else {
            return Err(format!(
                "time response {index} ({}) holds complex values: expected real samples",
                dof(f)
            ));
        };
        let shared = records.iter().filter(|(_, g)| dof(g) == dof(f)).count() > 1;
        let name = match shared {
            true => format!("{} #{}", dof(f), index + 1),
            false => dof(f),
        };
        channels.push(Channel {
            name,
            unit: unit(file, f),
            sample_rate_hz: Some(rate_of_step(step, 1.0)),
            values: values.clone(),
        });
    }
    Ok(Some(channels))
}

/// A function's unit: its ordinate axis's units label, else the SI unit its data type
/// says (13 excitation force N, 8 displacement m, 11 velocity m/s, 12 acceleration
/// m/s²) in a file in SI (dataset 164 code 1, or none).
fn unit(file: &UffFile, f: &Function58) -> Option<String> {
    let label = f.ordinate_axis.units.trim();
    if !label.is_empty() && label != "NONE" {
        return Some(label.to_string());
    }
    if file.units.as_ref().is_some_and(|u| u.code != 1) {
        return None;
    }
    let si = match f.ordinate_axis.data_type {
        13 => "N",
        8 => "m",
        11 => "m/s",
        12 => "m/s^2",
        _ => return None,
    };
    Some(si.into())
}

/// A function's response DOF as the file's listing writes it (`1:+Z`).
fn dof(f: &Function58) -> String {
    format!(
        "{}:{}",
        f.response_node,
        direction_name(f.response_direction)
    )
}

/// The start and step, s, of function `index`'s abscissa: even, or uneven but uniform
/// within 1e-6 of its step.
fn grid(index: usize, f: &Function58) -> Result<(f64, f64), String> {
    let (start, step) = match &f.abscissa {
        Abscissa::Even { start, step } => (*start, *step),
        Abscissa::Uneven(t) if t.len() >= 2 => {
            let step = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
            let uneven = (t.windows(2)).position(|w| ((w[1] - w[0]) / step - 1.0).abs() > 1e-6);
            if let Some(k) = uneven {
                return Err(format!(
                    "time response {index} ({}): its abscissa steps from {} s to {} s at point {k}, the mean step being {step} s: expected uniform sampling",
                    dof(f),
                    t[k],
                    t[k + 1]
                ));
            }
            (t[0], step)
        }
        Abscissa::Uneven(_) => (0.0, f64::NAN),
    };
    if !(step.is_finite() && step > 0.0 && start.is_finite()) {
        return Err(format!(
            "time response {index} ({}): abscissa start {start} s, step {step} s: expected a finite start and a step > 0",
            dof(f)
        ));
    }
    Ok((start, step))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(node: i64, direction: i32, step: f64, values: Vec<f64>) -> Function58 {
        let mut f = Function58::new(
            FunctionType::TimeResponse,
            Abscissa::Even { start: 0.0, step },
            Ordinate::Real(values),
        );
        (f.response_node, f.response_direction) = (node, direction);
        f.ordinate_axis.units = "N".into();
        f
    }

    #[test]
    fn time_responses_are_channels_named_by_their_dof() {
        let mut file = UffFile::default();
        file.functions.push(record(1, 3, 1e-3, vec![1.0, 2.0, 3.0]));
        let frf = Function58::new(
            FunctionType::FrequencyResponse,
            Abscissa::Even {
                start: 0.0,
                step: 1.0,
            },
            Ordinate::Complex(vec![(1.0, 0.0)]),
        );
        file.functions.push(frf);
        file.functions
            .push(record(2, -1, 1e-3, vec![4.0, 5.0, 6.0]));
        file.functions
            .push(record(2, -1, 1e-3, vec![7.0, 8.0, 9.0]));
        file.functions[3].ordinate_axis.units = "NONE".into();
        file.functions[3].ordinate_axis.data_type = 12;
        let channels = time_channels(&file).unwrap().unwrap();
        let names: Vec<&str> = channels.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["1:+Z", "2:-X #3", "2:-X #4"]);
        assert_eq!(channels[1].values, [4.0, 5.0, 6.0]);
        assert_eq!(channels[0].sample_rate_hz, Some(1000.0));
        assert_eq!(channels[0].unit.as_deref(), Some("N"));
        assert_eq!(channels[2].unit.as_deref(), Some("m/s^2"));
    }

    #[test]
    fn records_on_different_grids_or_without_one_are_refused_by_number() {
        let mut file = UffFile::default();
        assert_eq!(time_channels(&file), Ok(None));
        file.functions.push(record(1, 3, 1e-3, vec![1.0, 2.0, 3.0]));
        file.functions.push(record(2, 3, 2e-3, vec![4.0, 5.0, 6.0]));
        let e = time_channels(&file).unwrap_err();
        assert!(e.starts_with("time response 1 (2:+Z) has 3 points from 0 s every 0.002 s"));
        file.functions[1].abscissa = Abscissa::Uneven(vec![0.0, 1e-3, 3e-3]);
        let e = time_channels(&file).unwrap_err();
        assert!(e.contains("steps from 0 s to 0.001 s at point 0"), "{e}");
        file.functions[1].abscissa = Abscissa::Even {
            start: 0.0,
            step: 0.0,
        };
        let e = time_channels(&file).unwrap_err();
        assert!(e.contains("expected a finite start and a step > 0"), "{e}");
    }
}
