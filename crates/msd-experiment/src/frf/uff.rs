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
/// measuring `kind`, else what the file says (see [`measured_kind`]).
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
    frf.kind = match kind {
        Some(kind) => kind,
        None => measured_kind(function)?,
    };
    Ok(frf)
}

/// The coherence function of `function` (dataset 58 #`index + 1`) in `file`: the dataset
/// 58 of function type 6 with its response and reference DOFs, with its index; `None`
/// when the file holds none. Errors: two such, other lines than the FRF's, a value that
/// is not a real number in [0, 1] — each naming the datasets.
pub(crate) fn coherence_of(
    file: &UffFile,
    function: &Function58,
    index: usize,
) -> Result<Option<(usize, Vec<f64>)>, String> {
    let dofs = |f: &Function58| {
        (
            f.response_node,
            f.response_direction,
            f.reference_node,
            f.reference_direction,
        )
    };
    let found: Vec<(usize, &Function58)> = (file.functions.iter().enumerate())
        .filter(|(_, f)| f.function_type == FunctionType::Coherence && dofs(f) == dofs(function))
        .collect();
    let (j, coherence) = match found.as_slice() {
        [] => return Ok(None),
        [one] => *one,
        [a, b, ..] => {
            return Err(format!(
                "datasets 58 #{} and #{} are both coherences of the FRF #{}: expected one",
                a.0 + 1,
                b.0 + 1,
                index + 1
            ));
        }
    };
    let said = |what: String| {
        format!(
            "dataset 58 #{} (the coherence of #{}): {what}",
            j + 1,
            index + 1
        )
    };
    if coherence.abscissa_values() != function.abscissa_values() {
        return Err(said(format!(
            "{} lines from {} Hz, the FRF {} from {} Hz: expected the FRF's lines",
            coherence.len(),
            coherence
                .abscissa_values()
                .first()
                .copied()
                .unwrap_or(f64::NAN),
            function.len(),
            function
                .abscissa_values()
                .first()
                .copied()
                .unwrap_or(f64::NAN)
        )));
    }
    let values: Vec<f64> = match &coherence.ordinate {
        Ordinate::Real(v) => v.clone(),
        Ordinate::Complex(v) => v.iter().map(|&(re, _)| re).collect(),
    };
    let imaginary = match &coherence.ordinate {
        Ordinate::Complex(v) => v.iter().position(|&(_, im)| im != 0.0),
        Ordinate::Real(_) => None,
    };
    let bad = (values.iter()).position(|g| !(0.0..=1.0).contains(g));
    match (imaginary, bad) {
        (Some(k), _) => Err(said(format!(
            "value {}: an imaginary part: expected a real coherence",
            k + 1
        ))),
        (None, Some(k)) => Err(said(format!(
            "value {} ({} Hz) is {}: expected a coherence in [0, 1]",
            k + 1,
            function.abscissa_values()[k],
            values[k]
        ))),
        (None, None) => Ok(Some((j, values))),
    }
}

/// What a frequency response function measures, from the file: the ordinate axis's
/// data type (SDRC 8 displacement, 11 velocity, 12 acceleration) and its units and label
/// (`m/N`, `(m/s)/N`, `(1/N)*(m/s2)`, `g/N`, "accelerance", …), which decide when the type
/// is 0 (unknown) or 1 (general). A type and units that disagree, or neither saying, is
/// an error that names what the file holds and the key that settles it.
fn measured_kind(function: &Function58) -> Result<FrfKind, String> {
    let axis = &function.ordinate_axis;
    let by_type = match axis.data_type {
        8 => Some(FrfKind::Receptance),
        11 => Some(FrfKind::Mobility),
        12 => Some(FrfKind::Accelerance),
        _ => None,
    };
    let by_units = kind_from_units(&axis.units).or_else(|| kind_from_units(&axis.label));
    let says = format!(
        "the ordinate axis has data type {} with units `{}` and label `{}`",
        axis.data_type,
        axis.units.trim(),
        axis.label.trim()
    );
    match (by_type, by_units) {
        (Some(t), Some(u)) if t != u => Err(format!(
            "{says}: the type says {t}, the units {u}; set frequency_response.uff.kind to the one measured"
        )),
        (Some(kind), _) | (None, Some(kind)) => Ok(kind),
        (None, None) => Err(format!(
            "{says}: neither tells receptance, mobility or accelerance; set frequency_response.uff.kind"
        )),
    }
}

/// The quantity a units string or label names, if it names one: acceleration per force
/// (`m/s2`, `m/s^2`, `m/s**2`, `m/s²`, `g`), velocity per force (`m/s`), displacement per
/// force (`m`, `mm`, `µm`, `in`), or the FRF's name itself.
fn kind_from_units(text: &str) -> Option<FrfKind> {
    let t: String = text
        .to_lowercase()
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect();
    if t.is_empty() || t == "none" {
        return None;
    }
    for (names, kind) in [
        (
            ["accelerance", "inertance", "acceleration"],
            FrfKind::Accelerance,
        ),
        (["mobility", "velocity", "admittance"], FrfKind::Mobility),
        (
            ["receptance", "compliance", "displacement"],
            FrfKind::Receptance,
        ),
    ] {
        if names.iter().any(|n| t.contains(n)) {
            return Some(kind);
        }
    }
    let per_s2 = [
        "/s2", "/s^2", "/s**2", "/s²", "/(s2)", "/(s^2)", "s^-2", "s-2",
    ];
    if per_s2.iter().any(|p| t.contains(p)) {
        return Some(FrfKind::Accelerance);
    }
    // `g` (standard gravity) as a unit of its own: `g/n`, `(1/n)*g`, `g`.
    let units: Vec<&str> = t
        .split(|c: char| !c.is_alphanumeric() && c != 'µ')
        .filter(|u| !u.is_empty())
        .collect();
    if units.contains(&"g") {
        return Some(FrfKind::Accelerance);
    }
    if t.contains("/s") || t.contains("s^-1") || t.contains("s-1") {
        return Some(FrfKind::Mobility);
    }
    let lengths = ["m", "mm", "µm", "um", "in", "mil"];
    units
        .iter()
        .any(|u| lengths.contains(u))
        .then_some(FrfKind::Receptance)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_name_the_quantity() {
        let cases = [
            ("(1/N)*(m/s2)", Some(FrfKind::Accelerance)),
            ("m/s^2/N", Some(FrfKind::Accelerance)),
            ("(m/s**2)/N", Some(FrfKind::Accelerance)),
            ("g/N", Some(FrfKind::Accelerance)),
            ("Accelerance", Some(FrfKind::Accelerance)),
            ("(m/s)/N", Some(FrfKind::Mobility)),
            ("m/N", Some(FrfKind::Receptance)),
            ("mm/N", Some(FrfKind::Receptance)),
            ("NONE", None),
            ("", None),
            ("N/N", None),
        ];
        for (units, kind) in cases {
            assert_eq!(kind_from_units(units), kind, "{units}");
        }
    }

    fn function(data_type: i32, units: &str) -> Function58 {
        let mut f = Function58::new(
            FunctionType::FrequencyResponse,
            msd_uff::Abscissa::Even {
                start: 0.0,
                step: 1.0,
            },
            Ordinate::Complex(vec![(1.0, 0.0); 4]),
        );
        f.ordinate_axis.data_type = data_type;
        f.ordinate_axis.units = units.into();
        f
    }

    #[test]
    fn a_general_ordinate_takes_its_units_and_a_conflict_is_refused() {
        assert_eq!(
            measured_kind(&function(1, "(1/N)*(m/s2)")),
            Ok(FrfKind::Accelerance)
        );
        assert_eq!(measured_kind(&function(8, "m")), Ok(FrfKind::Receptance));
        assert_eq!(
            measured_kind(&function(12, "NONE")),
            Ok(FrfKind::Accelerance)
        );
        let conflict = measured_kind(&function(8, "(1/N)*(m/s2)")).expect_err("conflict");
        assert!(
            conflict.contains("frequency_response.uff.kind"),
            "{conflict}"
        );
        let unknown = measured_kind(&function(1, "NONE")).expect_err("unknown");
        assert!(unknown.contains("data type 1"), "{unknown}");
    }
}
