//! A UFF file's dataset 58 as a frequency response.

use msd_signal::{Complex64, FrequencyResponseEstimate, FrfKind};
use msd_uff::{Function58, FunctionType, Ordinate, UffFile};

/// The dataset 58 to read: number `function` (from 1) of the file's, else the first
/// frequency response function; with its 0-based index. Errors say what the file holds.
pub(crate) fn pick(
    file: &UffFile,
    function: Option<usize>,
) -> Result<(usize, &Function58), String> {
    let holds = || {
        let skipped: Vec<String> = file
            .skipped
            .iter()
            .map(|s| format!("{} at byte {}", s.number, s.offset))
            .collect();
        let mut parts = vec![format!("{} datasets 58", file.functions.len())];
        if file.header.is_some() {
            parts.push("a header (151)".into());
        }
        if file.units.is_some() {
            parts.push("units (164)".into());
        }
        if !skipped.is_empty() {
            parts.push(format!("datasets passed over: {}", skipped.join(", ")));
        }
        parts.join(", ")
    };
    match function {
        Some(number) => file
            .functions
            .get(number - 1)
            .map(|f| (number - 1, f))
            .ok_or_else(|| {
                format!(
                    "frequency_response.uff.function = {number}: the file holds {}",
                    holds()
                )
            }),
        None => file
            .functions
            .iter()
            .enumerate()
            .find(|(_, f)| f.function_type == FunctionType::FrequencyResponse)
            .ok_or_else(|| {
                format!(
                    "no frequency response function (dataset 58 of function type 4): the file holds {}",
                    holds()
                )
            }),
    }
}

/// The frequency response of `function`: complex ordinate values at its abscissa (Hz),
/// measuring `kind`, else what the ordinate axis says (SDRC data types 8 displacement,
/// 11 velocity, 12 acceleration), else receptance.
pub(crate) fn to_estimate(
    function: &Function58,
    kind: Option<FrfKind>,
) -> Result<FrequencyResponseEstimate, String> {
    if function.function_type != FunctionType::FrequencyResponse {
        return Err(format!(
            "a {} (function type {}): expected a frequency response function (type 4)",
            function.function_type,
            function.function_type.code()
        ));
    }
    let Ordinate::Complex(values) = &function.ordinate else {
        return Err("real ordinate values: expected complex ones (data type 5 or 6)".into());
    };
    let h = values
        .iter()
        .map(|&(re, im)| Complex64::new(re, im))
        .collect();
    let mut frf =
        FrequencyResponseEstimate::new(function.abscissa_values(), h).map_err(|e| e.to_string())?;
    frf.kind = kind.unwrap_or(match function.ordinate_axis.data_type {
        11 => FrfKind::Mobility,
        12 => FrfKind::Accelerance,
        _ => FrfKind::Receptance,
    });
    Ok(frf)
}
