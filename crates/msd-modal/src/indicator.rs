//! Mode indicator functions of a set of frequency responses: where the modes are, before
//! any model is fitted.

use crate::set::SetMember;
use msd_modal_core::error::{ModalError, Result};
use msd_modal_core::mode::Dof;
use msd_signal::{Complex64, FrfKind};
use nalgebra::DMatrix;
use serde::Serialize;

/// The mode indicator functions of a set of FRFs, line by line.
///
/// - **CMIF** (complex mode indicator function, Shih et al., 1988): the singular values of
///   the FRF matrix H(ω) (responses × references) at each line, largest first. Each
///   peak of the first is a mode; a second curve peaking at the same line is a repeated
///   (or very close) mode, which only several references can separate. With one
///   reference or one response, the first singular value is the root sum of squares of
///   the set's magnitudes.
/// - **MIF** (the real-mode indicator function, Williams, Crowley and Vold, 1985):
///   Σ|Re Hᵢ|·|Hᵢ| / Σ|Hᵢ|² over every FRF of the set, on the receptance (an accelerance
///   or mobility is turned back by its power of jω, a common factor at each line). It
///   lies in [0, 1] and dips towards 0 at a lightly damped normal mode, where every
///   response is in quadrature with the force.
///
/// ```
/// use msd_modal::{Dof, ModalParameters, SetMember, mode_indicator};
/// use msd_signal::FrequencyResponseEstimate;
/// let mode = ModalParameters { natural_frequency_hz: 10.0, damping_ratio: 0.01,
///     modal_constant: 1.0, modal_constant_imaginary: 0.0 };
/// let f: Vec<f64> = (1..=400).map(|i| 0.05 * i as f64).collect();
/// let h = f.iter().map(|&f| mode.receptance(f)).collect();
/// let point = Dof { node: 1, direction: 3 };
/// let set = [SetMember { frf: FrequencyResponseEstimate::new(f, h)?, response: point, reference: point }];
/// let indicator = mode_indicator(&set)?;
/// let k = 199; // the line at 10 Hz
/// assert_eq!(indicator.frequency_hz[k], 10.0);
/// assert!(indicator.mif[k] < 1e-9); // in quadrature at the natural frequency
/// let peak = (0..400).max_by(|&a, &b| indicator.cmif[a][0].total_cmp(&indicator.cmif[b][0]));
/// assert_eq!(peak, Some(k));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModeIndicator {
    /// The lines, Hz.
    pub frequency_hz: Vec<f64>,
    /// The singular values of H at each line, largest first (as many as the smaller of
    /// the numbers of responses and references).
    pub cmif: Vec<Vec<f64>>,
    /// The real-mode indicator at each line, in [0, 1] (0 where H is 0).
    pub mif: Vec<f64>,
    /// The responses: the rows of H.
    pub responses: Vec<Dof>,
    /// The references: the columns of H.
    pub references: Vec<Dof>,
}

/// The mode indicator functions of `members` (see [`ModeIndicator`]).
///
/// Errors: no member, members on other lines or of another quantity than the first, a
/// pair of DOFs given twice, or pairs that do not fill the matrix of responses ×
/// references (the CMIF needs every pair; a roving test of one reference or one
/// response always fills it).
pub fn mode_indicator(members: &[SetMember]) -> Result<ModeIndicator> {
    let refuse = |reason: String| Err(ModalError::NotIdentifiable { reason });
    let Some(first) = members.first() else {
        return refuse("a mode indicator needs at least one frequency response".into());
    };
    let mut responses: Vec<Dof> = Vec::new();
    let mut references: Vec<Dof> = Vec::new();
    for m in members {
        if m.frf.frequency != first.frf.frequency || m.frf.kind != first.frf.kind {
            return refuse(format!(
                "{} / {} has other frequency lines or another quantity than {} / {}",
                m.response, m.reference, first.response, first.reference
            ));
        }
        if !responses.contains(&m.response) {
            responses.push(m.response);
        }
        if !references.contains(&m.reference) {
            references.push(m.reference);
        }
    }
    let mut slot = vec![None; responses.len() * references.len()];
    for (i, m) in members.iter().enumerate() {
        let r = responses.iter().position(|&d| d == m.response).unwrap_or(0);
        let q = references
            .iter()
            .position(|&d| d == m.reference)
            .unwrap_or(0);
        if slot[r * references.len() + q].replace(i).is_some() {
            return refuse(format!(
                "response {} / reference {} is given twice",
                m.response, m.reference
            ));
        }
    }
    if let Some(missing) = slot.iter().position(Option::is_none) {
        return refuse(format!(
            "no FRF of response {} / reference {}: the CMIF needs every pair of the {} responses × {} references",
            responses[missing / references.len()],
            references[missing % references.len()],
            responses.len(),
            references.len()
        ));
    }
    let slot: Vec<usize> = slot.into_iter().flatten().collect();
    let rotate = receptance_turn(first.frf.kind);
    let lines = first.frf.frequency.len();
    let mut cmif = Vec::with_capacity(lines);
    let mut mif = Vec::with_capacity(lines);
    for k in 0..lines {
        let h = DMatrix::from_fn(responses.len(), references.len(), |r, q| {
            members[slot[r * references.len() + q]].frf.h[k]
        });
        cmif.push(h.singular_values().iter().copied().collect());
        let (mut num, mut den) = (0.0, 0.0);
        for m in members {
            let x: Complex64 = m.frf.h[k] * rotate;
            num += x.re.abs() * x.norm();
            den += x.norm_sqr();
        }
        mif.push(if den > 0.0 { num / den } else { 0.0 });
    }
    Ok(ModeIndicator {
        frequency_hz: first.frf.frequency.clone(),
        cmif,
        mif,
        responses,
        references,
    })
}

/// The unit factor (−j)^p that turns a quantity (jω)^p × receptance back into the phase
/// of the receptance (the factor ω^p does not change the MIF).
fn receptance_turn(kind: FrfKind) -> Complex64 {
    match kind {
        FrfKind::Receptance => Complex64::new(1.0, 0.0),
        FrfKind::Mobility => Complex64::new(0.0, -1.0),
        FrfKind::Accelerance => Complex64::new(-1.0, 0.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use msd_modal_core::modal::ModalParameters;
    use msd_signal::FrequencyResponseEstimate;

    fn member(response: u32, reference: u32, h: Vec<Complex64>, f: &[f64]) -> SetMember {
        SetMember {
            frf: FrequencyResponseEstimate::new(f.to_vec(), h).expect("valid"),
            response: Dof {
                node: response,
                direction: 3,
            },
            reference: Dof {
                node: reference,
                direction: 3,
            },
        }
    }

    /// Two modes at one frequency (a repeated root, as a symmetric structure has), seen
    /// from two references: the CMIF's second singular value peaks there too, and at the
    /// natural frequency both equal |A|/(2ζωn²) for unit orthogonal shapes.
    #[test]
    fn a_repeated_mode_shows_in_the_second_singular_value() {
        let f: Vec<f64> = (1..=400).map(|i| 0.05 * i as f64).collect();
        let shapes = [[1.0, 0.0], [0.0, 1.0]];
        let zeta = 0.02;
        let h = |r: usize, q: usize, f: f64| -> Complex64 {
            (0..2)
                .map(|m| {
                    ModalParameters {
                        natural_frequency_hz: 10.0,
                        damping_ratio: zeta,
                        modal_constant: shapes[m][r] * shapes[m][q],
                        modal_constant_imaginary: 0.0,
                    }
                    .receptance(f)
                })
                .sum()
        };
        let members: Vec<SetMember> = (0..2)
            .flat_map(|r| (0..2).map(move |q| (r, q)))
            .map(|(r, q)| {
                let values = f.iter().map(|&f| h(r, q, f)).collect();
                member(r as u32 + 1, q as u32 + 1, values, &f)
            })
            .collect();
        let indicator = mode_indicator(&members).expect("a full 2 × 2 matrix");
        let k = 199;
        let wn = std::f64::consts::TAU * 10.0;
        let peak = 1.0 / (2.0 * zeta * wn * wn);
        for s in &indicator.cmif[k] {
            assert!((s / peak - 1.0).abs() < 1e-12, "{s} against {peak}");
        }
        let one_mode = mode_indicator(&members[..1]).expect("one FRF");
        assert_eq!(one_mode.cmif[k].len(), 1);
    }

    /// MIF is the same for a receptance and its accelerance, and is 1 for a real
    /// (in-phase) response.
    #[test]
    fn the_mif_reads_every_quantity_as_a_receptance() {
        let f: Vec<f64> = (1..=100).map(|i| 0.2 * i as f64).collect();
        let mode = ModalParameters {
            natural_frequency_hz: 7.0,
            damping_ratio: 0.05,
            modal_constant: 2.0,
            modal_constant_imaginary: 0.0,
        };
        let receptance: Vec<Complex64> = f.iter().map(|&f| mode.receptance(f)).collect();
        let a = mode_indicator(&[member(1, 1, receptance.clone(), &f)]).expect("valid");
        let mut accelerance = member(1, 1, receptance, &f);
        for (h, &f) in accelerance.frf.h.iter_mut().zip(&f) {
            *h *= -(std::f64::consts::TAU * f).powi(2);
        }
        accelerance.frf.kind = FrfKind::Accelerance;
        let b = mode_indicator(&[accelerance]).expect("valid");
        for (x, y) in a.mif.iter().zip(&b.mif) {
            assert!((x - y).abs() < 1e-12, "{x} against {y}");
        }
        let real = vec![Complex64::new(3.0, 0.0); f.len()];
        let c = mode_indicator(&[member(1, 1, real, &f)]).expect("valid");
        assert!(c.mif.iter().all(|&m| (m - 1.0).abs() < 1e-15));
    }

    #[test]
    fn a_matrix_with_a_missing_pair_is_refused() {
        let f = [1.0, 2.0, 3.0];
        let h = vec![Complex64::new(1.0, 1.0); 3];
        let members = [
            member(1, 1, h.clone(), &f),
            member(2, 1, h.clone(), &f),
            member(1, 2, h, &f),
        ];
        let err = mode_indicator(&members).expect_err("2:+3 / 2:+3 missing");
        assert!(
            err.to_string().contains("response 2:+3 / reference 2:+3"),
            "{err}"
        );
    }
}
