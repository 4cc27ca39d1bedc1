//! Mode shapes compared: the modal assurance criterion (MAC), shapes normalised and
//! matched by DOF (a shape's complexity, MPC and MPD, is msd-modal-core's `phase`).

use msd_modal_core::error::{ModalError, Result};
use msd_modal_core::mode::{Dof, ShapeEntry};
use msd_signal::Complex64;

/// The modal assurance criterion of two shapes over the same DOFs:
/// MAC = |aᴴb|² / ((aᴴa)(bᴴb)), 1 for shapes that differ only by a complex factor, 0 for
/// orthogonal ones (Allemang & Brown, IMAC 1982). 0 when either shape is zero.
///
/// ```
/// use msd_modal::mac;
/// use msd_signal::Complex64;
/// let a = [1.0, 2.0, -1.0].map(|x| Complex64::new(x, 0.0));
/// let b = a.map(|x| x * Complex64::new(0.0, -3.0)); // the same shape, scaled and rotated
/// assert!((mac(&a, &b) - 1.0).abs() < 1e-15);
/// let c = [1.0, 0.0, 1.0].map(|x| Complex64::new(x, 0.0)); // orthogonal to a
/// assert_eq!(mac(&a, &c), 0.0);
/// // Any scale: shapes of 1e300 (whose products overflow) give the same MAC.
/// let huge = a.map(|x| x * 1e300);
/// assert!((mac(&huge, &b) - 1.0).abs() < 1e-15);
/// ```
pub fn mac(a: &[Complex64], b: &[Complex64]) -> f64 {
    debug_assert_eq!(a.len(), b.len());
    // Each shape divided by its largest entry first: MAC does not depend on the scale,
    // and shapes of 1e300 (or 1e-300) would overflow (underflow) the products.
    let (a, b) = (unit_peak(a), unit_peak(b));
    let cross: Complex64 = a.iter().zip(&b).map(|(x, y)| x.conj() * y).sum();
    let (aa, bb) = (norm_sqr(&a), norm_sqr(&b));
    if !(aa > 0.0 && bb > 0.0) {
        return 0.0;
    }
    cross.norm_sqr() / (aa * bb)
}

/// `shape` divided by its largest magnitude (unchanged when that is zero or not finite).
fn unit_peak(shape: &[Complex64]) -> Vec<Complex64> {
    let peak = shape
        .iter()
        .map(|z| z.re.abs().max(z.im.abs()))
        .fold(0.0, f64::max);
    if peak > 0.0 && peak.is_finite() {
        shape.iter().map(|z| z / peak).collect()
    } else {
        shape.to_vec()
    }
}

/// The MAC of every shape of `a` with every shape of `b`: `matrix[i][j]` = MAC(aᵢ, bⱼ)
/// (the auto-MAC with `b = a`).
///
/// ```
/// use msd_modal::mac_matrix;
/// use msd_signal::Complex64;
/// let shapes = vec![
///     [1.0, 1.0].map(|x| Complex64::new(x, 0.0)).to_vec(),
///     [1.0, -1.0].map(|x| Complex64::new(x, 0.0)).to_vec(),
/// ];
/// assert_eq!(mac_matrix(&shapes, &shapes), vec![vec![1.0, 0.0], vec![0.0, 1.0]]);
/// ```
pub fn mac_matrix(a: &[Vec<Complex64>], b: &[Vec<Complex64>]) -> Vec<Vec<f64>> {
    a.iter()
        .map(|x| b.iter().map(|y| mac(x, y)).collect())
        .collect()
}

/// `shape` scaled so that its largest entry is 1 (real and positive). Entries whose
/// magnitudes tie with the largest to 1e-9 (a symmetric shape: [1, −0.5, −1]) count as
/// equal, and the first of them is the reference: the sign does not hang on rounding.
///
/// ```
/// use msd_modal::unit_normalised;
/// use msd_signal::Complex64;
/// let shape = [Complex64::new(0.0, 2.0), Complex64::new(0.0, -1.0)];
/// assert_eq!(unit_normalised(&shape), vec![Complex64::new(1.0, 0.0), Complex64::new(-0.5, 0.0)]);
/// let tie = [1.0, -0.5, -1.0 - 1e-15].map(|x| Complex64::new(x, 0.0));
/// assert_eq!(unit_normalised(&tie)[0], Complex64::new(1.0, 0.0));
/// ```
pub fn unit_normalised(shape: &[Complex64]) -> Vec<Complex64> {
    let top = shape.iter().map(|x| x.norm()).fold(0.0, f64::max);
    let Some(&largest) = shape.iter().find(|x| x.norm() >= top * (1.0 - 1e-9)) else {
        return shape.to_vec();
    };
    if top == 0.0 {
        return shape.to_vec();
    }
    shape.iter().map(|x| x / largest).collect()
}

fn norm_sqr(shape: &[Complex64]) -> f64 {
    shape.iter().map(Complex64::norm_sqr).sum()
}

/// Two sets of mode shapes compared on the DOFs they share (see [`compare_shapes`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ShapeComparison {
    /// The DOFs both sets give (direction made positive), in the first set's order.
    pub shared: Vec<Dof>,
    /// DOFs of the first set that the second does not give.
    pub only_first: Vec<Dof>,
    /// DOFs of the second set that the first does not give.
    pub only_second: Vec<Dof>,
    /// `mac[i][j]` = MAC(first's mode i, second's mode j) on the shared DOFs.
    pub mac: Vec<Vec<f64>>,
}

impl ShapeComparison {
    /// For each mode of the first set, the mode of the second with the largest MAC and
    /// that MAC (`None` when the second set is empty).
    pub fn best_matches(&self) -> Vec<Option<(usize, f64)>> {
        self.mac
            .iter()
            .map(|row| {
                row.iter()
                    .copied()
                    .enumerate()
                    .max_by(|a, b| a.1.total_cmp(&b.1))
            })
            .collect()
    }
}

/// The MAC between two sets of shapes given over DOFs — two tests, or a test and a
/// model — on the DOFs both give. A DOF measured in the opposite sense (direction −3
/// against +3) is the same DOF with its value negated; DOFs only one set gives are
/// listed and left out.
///
/// Errors: a shape that gives a DOF twice, or fewer than two shared DOFs (the MAC of
/// one DOF is 1 for any pair of shapes).
///
/// ```
/// use msd_modal::{Dof, ShapeEntry, compare_shapes};
/// use msd_signal::Complex64;
/// let shape = |values: &[(u32, i32, f64)]| -> Vec<ShapeEntry> {
///     values.iter().map(|&(node, direction, re)| ShapeEntry::new(Dof { node, direction }, Complex64::new(re, 0.0))).collect()
/// };
/// let test = vec![shape(&[(1, 3, 1.0), (2, 3, 0.5), (3, 3, -0.4)])];
/// // The model: node 2 in the opposite sense, node 3 not given, node 9 not measured.
/// let model = vec![shape(&[(2, -3, -1.0), (1, 3, 2.0), (9, 3, 7.0)])];
/// let c = compare_shapes(&test, &model)?;
/// assert_eq!(c.shared.len(), 2);
/// assert!((c.mac[0][0] - 1.0).abs() < 1e-15);
/// assert_eq!(c.only_first[0].node, 3);
/// assert_eq!(c.only_second[0].node, 9);
/// # Ok::<(), msd_modal::ModalError>(())
/// ```
pub fn compare_shapes(
    first: &[Vec<ShapeEntry>],
    second: &[Vec<ShapeEntry>],
) -> Result<ShapeComparison> {
    let keyed = |set: &[Vec<ShapeEntry>], name: &str| -> Result<Vec<Vec<(Dof, Complex64)>>> {
        set.iter()
            .enumerate()
            .map(|(i, shape)| {
                let mut out: Vec<(Dof, Complex64)> = Vec::with_capacity(shape.len());
                for e in shape {
                    let sign = if e.direction < 0 { -1.0 } else { 1.0 };
                    let dof = Dof {
                        node: e.node,
                        direction: e.direction.abs(),
                    };
                    if out.iter().any(|(d, _)| *d == dof) {
                        return Err(ModalError::NotIdentifiable {
                            reason: format!(
                                "the {name} set's mode {} gives DOF {dof} twice",
                                i + 1
                            ),
                        });
                    }
                    out.push((dof, Complex64::new(sign * e.re, sign * e.im)));
                }
                Ok(out)
            })
            .collect()
    };
    let (a, b) = (keyed(first, "first")?, keyed(second, "second")?);
    let dofs = |set: &[Vec<(Dof, Complex64)>]| -> Vec<Dof> {
        let mut all: Vec<Dof> = Vec::new();
        for (d, _) in set.iter().flatten() {
            if !all.contains(d) {
                all.push(*d);
            }
        }
        all
    };
    let (in_a, in_b) = (dofs(&a), dofs(&b));
    let given_by_all = |set: &[Vec<(Dof, Complex64)>], d: &Dof| {
        set.iter().all(|shape| shape.iter().any(|(x, _)| x == d))
    };
    let shared: Vec<Dof> = in_a
        .iter()
        .copied()
        .filter(|d| given_by_all(&a, d) && given_by_all(&b, d))
        .collect();
    if shared.len() < 2 {
        return Err(ModalError::NotIdentifiable {
            reason: format!(
                "the two sets of shapes share {} DOF(s) that every shape gives: the MAC needs at least two",
                shared.len()
            ),
        });
    }
    let on_shared = |set: &[Vec<(Dof, Complex64)>]| -> Vec<Vec<Complex64>> {
        set.iter()
            .map(|shape| {
                shared
                    .iter()
                    .map(|d| {
                        shape
                            .iter()
                            .find(|(x, _)| x == d)
                            .map_or(Complex64::new(0.0, 0.0), |e| e.1)
                    })
                    .collect()
            })
            .collect()
    };
    let only = |from: &[Dof]| {
        from.iter()
            .copied()
            .filter(|d| !shared.contains(d))
            .collect()
    };
    Ok(ShapeComparison {
        mac: mac_matrix(&on_shared(&a), &on_shared(&b)),
        only_first: only(&in_a),
        only_second: only(&in_b),
        shared,
    })
}
