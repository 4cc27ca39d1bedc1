//! What a set's fit writes as UFF, for the modal tools of a lab: the mode shapes as
//! datasets 55 (`modes.uff`) and every FRF as the model synthesises it, as datasets 58 on
//! the data's lines (`synthesized.uff`).

use super::FrfOutcome;
use crate::error::{ExperimentError, Result};
use msd_modal::{Mode, ModeSetFit};
use msd_signal::FrfKind;
use msd_uff::{Abscissa, Analysis55, Data55, Function58, FunctionType, Ordinate, UffFile};
use std::f64::consts::TAU;
use std::path::Path;

/// Writes `modes.uff` and `synthesized.uff` into `dir`; returns their names.
pub(crate) fn write_all(o: &FrfOutcome, m: &ModeSetFit, dir: &Path) -> Result<Vec<&'static str>> {
    let fail = |name: &str| {
        let path = dir.join(name);
        move |e: msd_uff::UffError| ExperimentError::data(&path, e.to_string())
    };
    let modes = UffFile {
        data_at_nodes: m
            .modes
            .iter()
            .enumerate()
            .map(|(r, mode)| shape_dataset(&o.config.name, r, mode))
            .collect(),
        ..UffFile::default()
    };
    msd_uff::write(dir.join("modes.uff"), &modes, &Default::default())
        .map_err(fail("modes.uff"))?;
    let synthesized = UffFile {
        functions: (0..m.members.len()).map(|i| synthesized(o, m, i)).collect(),
        ..UffFile::default()
    };
    msd_uff::write(
        dir.join("synthesized.uff"),
        &synthesized,
        &Default::default(),
    )
    .map_err(fail("synthesized.uff"))?;
    Ok(vec!["modes.uff", "synthesized.uff"])
}

/// Mode `r` as a dataset 55: a complex eigenvalue (first order) with the unit-normalised
/// shape, each DOF's value in its direction's column (X, Y, Z), signed by the direction.
pub(crate) fn shape_dataset(name: &str, r: usize, mode: &Mode) -> Data55 {
    let (wn, zeta) = (
        TAU * mode.natural_frequency_hz.value,
        mode.damping_ratio.value,
    );
    let mut data = Data55 {
        ids: [
            name.to_string(),
            format!(
                "mode {}: {:.6} Hz, damping ratio {:.6e}",
                r + 1,
                wn / TAU,
                zeta
            ),
            "unit-normalised shape (largest entry 1), written by msd-experiment".into(),
            "NONE".into(),
            "NONE".into(),
        ],
        analysis: Analysis55::ComplexEigenvalue {
            second_order: false,
            load_case: 1,
            mode: r as i64 + 1,
            eigenvalue: (-zeta * wn, wn * (1.0 - zeta * zeta).max(0.0).sqrt()),
            modal_a: (0.0, 0.0),
            modal_b: (0.0, 0.0),
        },
        complex: true,
        ..Data55::default()
    };
    for entry in &mode.shape {
        let column = entry.direction.unsigned_abs() as usize;
        if !(1..=3).contains(&column) {
            continue; // rotations: a 3-value dataset has no column for them
        }
        let sign = f64::from(entry.direction.signum());
        let node = i64::from(entry.node);
        let k = match data.nodes.iter().position(|&n| n == node) {
            Some(k) => k,
            None => {
                data.nodes.push(node);
                data.values.push(vec![(0.0, 0.0); 3]);
                data.nodes.len() - 1
            }
        };
        data.values[k][column - 1] = (sign * entry.re, sign * entry.im);
    }
    data
}

/// Member `i`'s FRF as the model gives it on the data's lines, in the data's quantity.
fn synthesized(o: &FrfOutcome, m: &ModeSetFit, i: usize) -> Function58 {
    let member = &o.members[i];
    let f = &member.frf.frequency;
    let p = member.frf.kind.power();
    let values = f
        .iter()
        .map(|&f| {
            let jw = msd_signal::Complex64::new(0.0, TAU * f);
            let h = m.response(i, f) * jw.powi(p);
            if h.is_finite() {
                (h.re, h.im)
            } else {
                (0.0, 0.0)
            }
        })
        .collect();
    let step = if f.len() > 1 { f[1] - f[0] } else { 1.0 };
    let even = f
        .windows(2)
        .all(|w| ((w[1] - w[0]) / step - 1.0).abs() < 1e-9);
    let abscissa = if even {
        Abscissa::Even { start: f[0], step }
    } else {
        Abscissa::Uneven(f.clone())
    };
    let mut function = Function58::new(
        FunctionType::FrequencyResponse,
        abscissa,
        Ordinate::Complex(values),
    );
    function.ids[0] = format!("{}: the fitted model of FRF {}", o.config.name, i + 1);
    function.ids[1] = "synthesized from the modes, written by msd-experiment".into();
    (function.response_node, function.response_direction) =
        (i64::from(member.response.node), member.response.direction);
    (function.reference_node, function.reference_direction) =
        (i64::from(member.reference.node), member.reference.direction);
    function.abscissa_axis.data_type = 18;
    function.abscissa_axis.units = "Hz".into();
    (
        function.ordinate_axis.data_type,
        function.ordinate_axis.units,
    ) = match member.frf.kind {
        FrfKind::Receptance => (8, "m".into()),
        FrfKind::Mobility => (11, "m/s".into()),
        FrfKind::Accelerance => (12, "m/s2".into()),
    };
    function.denominator_axis.data_type = 13;
    function.denominator_axis.units = "N".into();
    function
}
