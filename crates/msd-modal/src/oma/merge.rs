//! Several setups of one structure merged into global modes (PoSER: each setup identified
//! on its own, its shapes rescaled onto the DOFs every setup shares, the references), and
//! a node's oblique channels turned into its x, y and z components.

use msd_opt::statistics::{Interval, t_975};
use msd_signal::Complex64;
use nalgebra::{Matrix3, Vector3};
use serde::Serialize;

use super::OmaFit;
use super::record::OutputRecord;
use super::record::dof;
use super::select::aligned;
use crate::shapes::mac;
use msd_modal_core::error::{ModalError, Result};
use msd_modal_core::mode::{Dof, Mode, ShapeEntry};

/// One setup: its record (the channels' DOFs and directions) and its fit.
#[derive(Debug, Clone, Copy)]
pub struct Setup<'a> {
    /// The record as analysed.
    pub record: &'a OutputRecord,
    /// Its modes.
    pub fit: &'a OmaFit,
}

/// Global modes over every setup's DOFs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MergedFit {
    /// The modes: fn and ζ the mean over the setups that found them (intervals from their
    /// scatter, Student's t on n − 1 dof; one setup's own where only one found it), the
    /// shape over every DOF.
    pub modes: Vec<Mode>,
    /// The DOFs every setup measured: the shapes are scaled onto them.
    pub reference_dofs: Vec<Dof>,
    /// Per mode and setup: the setup's mode index, where it found it.
    pub found: Vec<Vec<Option<usize>>>,
    /// Per mode and setup: the MAC of the setup's reference entries with the first
    /// finder's (how well the rescaling holds).
    pub reference_mac: Vec<Vec<Option<f64>>>,
}

/// `shape` (one entry per channel of `record`) with each node that has three or more
/// channels in independent directions given as its x, y, z components (least squares over
/// the channels' unit vectors; directions ±1…±3 are the axes, an oblique channel its
/// vector); other channels as they are. Standard errors propagate as independent.
///
/// ```
/// use msd_modal::{Channel, Dof, OutputRecord, Quantity, ShapeEntry, node_components};
/// use msd_signal::Complex64;
/// let c = |v: [f64; 3], n: &str| Channel { direction: Some(v),
///     ..Channel::new(n, Quantity::Velocity, vec![0.0, 1.0]).at(Dof { node: 5, direction: 0 }) };
/// let s = 0.5_f64.sqrt();
/// let record = OutputRecord::new(1.0, vec![c([s, s, 0.0], "a"), c([s, -s, 0.0], "b"), c([0.0, 0.0, 1.0], "c")]);
/// // The node moves along x by 1: the beams read 1/√2, 1/√2, 0.
/// let shape: Vec<ShapeEntry> = [s, s, 0.0].iter().map(|&v| ShapeEntry::new(Dof { node: 5, direction: 0 }, Complex64::new(v, 0.0))).collect();
/// let xyz = node_components(&record, &shape);
/// assert_eq!(xyz.iter().map(|e| e.direction).collect::<Vec<_>>(), [1, 2, 3]);
/// assert!((xyz[0].re - 1.0).abs() < 1e-12 && xyz[1].re.abs() < 1e-12);
/// ```
pub fn node_components(record: &OutputRecord, shape: &[ShapeEntry]) -> Vec<ShapeEntry> {
    let mut out = Vec::new();
    let mut done = vec![false; shape.len()];
    for i in 0..shape.len() {
        if done[i] {
            continue;
        }
        let node = dof(&record.channels()[i]).node;
        let same: Vec<usize> = (i..shape.len())
            .filter(|&j| dof(&record.channels()[j]).node == node)
            .collect();
        let units: Vec<Option<[f64; 3]>> = same.iter().map(|&j| unit(record, j)).collect();
        let solved = (same.len() >= 3 && units.iter().all(Option::is_some))
            .then(|| {
                solve(
                    node,
                    &same.iter().map(|&j| shape[j]).collect::<Vec<_>>(),
                    &units.iter().flatten().copied().collect::<Vec<_>>(),
                )
            })
            .flatten();
        match solved {
            Some(entries) => {
                same.iter().for_each(|&j| done[j] = true);
                out.extend(entries);
            }
            None => {
                done[i] = true;
                out.push(shape[i]);
            }
        }
    }
    out
}

/// Channel `j`'s measuring direction as a unit vector (None for a rotation).
fn unit(record: &OutputRecord, j: usize) -> Option<[f64; 3]> {
    let c = &record.channels()[j];
    c.direction.or_else(|| {
        let d = dof(c).direction;
        (1..=3).contains(&d.abs()).then(|| {
            let mut v = [0.0; 3];
            v[d.unsigned_abs() as usize - 1] = f64::from(d.signum());
            v
        })
    })
}

/// The x, y, z components at `node` from readings along `units` (None when they do not
/// span space).
fn solve(node: u32, readings: &[ShapeEntry], units: &[[f64; 3]]) -> Option<Vec<ShapeEntry>> {
    let mut normal = Matrix3::zeros();
    for u in units {
        let v = Vector3::from(*u);
        normal += v * v.transpose();
    }
    let inverse = normal
        .try_inverse()
        .filter(|_| normal.determinant().abs() > 1e-6)?;
    let gain: Vec<Vector3<f64>> = units.iter().map(|u| inverse * Vector3::from(*u)).collect();
    Some(
        (0..3)
            .map(|axis| {
                let value: Complex64 = readings
                    .iter()
                    .zip(&gain)
                    .map(|(r, g)| r.value() * g[axis])
                    .sum();
                let se = readings
                    .iter()
                    .zip(&gain)
                    .try_fold([0.0, 0.0], |acc, (r, g)| {
                        r.standard_error.map(|[a, b]| {
                            [
                                acc[0] + (g[axis] * a).powi(2),
                                acc[1] + (g[axis] * b).powi(2),
                            ]
                        })
                    });
                ShapeEntry {
                    standard_error: se.map(|[a, b]| [a.sqrt(), b.sqrt()]),
                    ..ShapeEntry::new(
                        Dof {
                            node,
                            direction: axis as i32 + 1,
                        },
                        value,
                    )
                }
            })
            .collect(),
    )
}

/// Merges `setups` (PoSER): every setup's shapes in node components; the DOFs all
/// setups share are the references; a mode of one setup is the same as another's when
/// their fn are within `tolerance` (relative; the nearest, with the higher MAC on the
/// references where two qualify); each setup's shape is scaled (complex least squares)
/// onto the first finder's reference entries and its other DOFs joined (averaged where
/// two setups measured one).
///
/// Errors: fewer than two setups, no DOF common to all of them.
pub fn merge_setups(setups: &[Setup<'_>], tolerance: f64) -> Result<MergedFit> {
    if setups.len() < 2 {
        return Err(ModalError::InvalidParameter {
            name: "setups",
            value: setups.len() as f64,
            expected: "at least two setups to merge",
        });
    }
    let shapes: Vec<Vec<Vec<ShapeEntry>>> = setups
        .iter()
        .map(|s| {
            s.fit
                .modes
                .iter()
                .map(|m| node_components(s.record, &m.shape))
                .collect()
        })
        .collect();
    let dofs_of = |s: usize| -> Vec<Dof> {
        shapes[s]
            .first()
            .map_or_else(Vec::new, |m| m.iter().map(ShapeEntry::dof).collect())
    };
    let reference_dofs: Vec<Dof> = dofs_of(0)
        .into_iter()
        .filter(|d| (1..setups.len()).all(|s| dofs_of(s).contains(d)))
        .collect();
    if reference_dofs.is_empty() {
        return Err(ModalError::NotIdentifiable { reason: "the setups share no DOF: PoSER scales each setup's shapes on the DOFs every setup measures (the reference sensors)".into() });
    }
    let groups = grouped(setups, &shapes, &reference_dofs, tolerance);
    let mut merged = MergedFit {
        modes: Vec::new(),
        reference_dofs: reference_dofs.clone(),
        found: Vec::new(),
        reference_mac: Vec::new(),
    };
    for group in groups {
        let (mode, macs) = merged_mode(setups, &shapes, &group, &reference_dofs);
        merged.modes.push(mode);
        merged.found.push(group);
        merged.reference_mac.push(macs);
    }
    merged.modes.sort_by(|a, b| {
        a.natural_frequency_hz
            .value
            .total_cmp(&b.natural_frequency_hz.value)
    });
    Ok(merged)
}

/// The entries of `shape` at `dofs`, in their order (zero where absent).
fn at(shape: &[ShapeEntry], dofs: &[Dof]) -> Vec<Complex64> {
    dofs.iter()
        .map(|d| {
            shape
                .iter()
                .find(|e| e.dof() == *d)
                .map_or(Complex64::new(0.0, 0.0), ShapeEntry::value)
        })
        .collect()
}

/// Which mode of each setup is which global mode: greedy, setup by setup, each of its
/// modes joining the nearest unclaimed group within `tolerance` or starting one.
fn grouped(
    setups: &[Setup<'_>],
    shapes: &[Vec<Vec<ShapeEntry>>],
    refs: &[Dof],
    tolerance: f64,
) -> Vec<Vec<Option<usize>>> {
    let mut groups: Vec<Vec<Option<usize>>> = Vec::new();
    let fn_of = |s: usize, m: usize| setups[s].fit.modes[m].natural_frequency_hz.value;
    let se_of = |s: usize, m: usize| setups[s].fit.modes[m].natural_frequency_hz.standard_error;
    for s in 0..setups.len() {
        let mut claimed = vec![false; groups.len()];
        for m in 0..setups[s].fit.modes.len() {
            let f = fn_of(s, m);
            let candidates = (0..groups.len())
                .filter(|&g| !claimed[g] && groups[g][s].is_none())
                .filter_map(|g| {
                    let (s0, m0) = groups[g]
                        .iter()
                        .enumerate()
                        .find_map(|(s0, m0)| m0.map(|m0| (s0, m0)))?;
                    let df = (fn_of(s0, m0) / f - 1.0).abs();
                    // The same mode: within the tolerance, or within 3 standard errors of
                    // the difference (a poorly resolved mode moves more than 1 % between
                    // setups).
                    let spread = 3.0 * se_of(s0, m0).hypot(se_of(s, m)) / f;
                    (df <= tolerance.max(spread)).then(|| {
                        (
                            g,
                            df - mac(&at(&shapes[s0][m0], refs), &at(&shapes[s][m], refs))
                                * tolerance,
                        )
                    })
                });
            match candidates.min_by(|a, b| a.1.total_cmp(&b.1)) {
                Some((g, _)) => {
                    groups[g][s] = Some(m);
                    claimed[g] = true;
                }
                None => {
                    let mut group = vec![None; setups.len()];
                    group[s] = Some(m);
                    groups.push(group);
                    claimed.push(true);
                }
            }
        }
    }
    groups
}

/// One global mode from the setups' modes in `group`.
fn merged_mode(
    setups: &[Setup<'_>],
    shapes: &[Vec<Vec<ShapeEntry>>],
    group: &[Option<usize>],
    refs: &[Dof],
) -> (Mode, Vec<Option<f64>>) {
    let members: Vec<(usize, usize)> = group
        .iter()
        .enumerate()
        .filter_map(|(s, m)| m.map(|m| (s, m)))
        .collect();
    let (s0, m0) = members[0];
    let anchor = at(&shapes[s0][m0], refs);
    let mut joined: Vec<(Dof, Complex64, Option<[f64; 2]>, f64)> = Vec::new();
    let mut macs = vec![None; setups.len()];
    for &(s, m) in &members {
        let own = at(&shapes[s][m], refs);
        macs[s] = Some(mac(&own, &anchor));
        let scaled = aligned(&own, &anchor);
        let alpha = own
            .iter()
            .zip(&scaled)
            .find(|(o, _)| o.norm() > 0.0)
            .map_or(Complex64::new(1.0, 0.0), |(o, t)| t / o);
        for e in &shapes[s][m] {
            let value = e.value() * alpha;
            let se = e
                .standard_error
                .map(|[a, b]| [a * alpha.norm(), b * alpha.norm()]);
            match joined.iter_mut().find(|j| j.0 == e.dof()) {
                Some(j) => {
                    j.1 += value;
                    j.3 += 1.0;
                }
                None => joined.push((e.dof(), value, se, 1.0)),
            }
        }
    }
    let entries: Vec<(Dof, Complex64, Option<[f64; 2]>)> = joined
        .into_iter()
        .map(|(d, v, se, n)| (d, v / n, se))
        .collect();
    let largest = entries
        .iter()
        .map(|e| e.1)
        .max_by(|a, b| a.norm().total_cmp(&b.norm()))
        .unwrap_or(Complex64::new(1.0, 0.0));
    let shape = entries
        .iter()
        .map(|(d, v, se)| ShapeEntry {
            standard_error: se.map(|[a, b]| [a / largest.norm(), b / largest.norm()]),
            ..ShapeEntry::new(*d, v / largest)
        })
        .collect();
    let modes: Vec<&Mode> = members
        .iter()
        .map(|&(s, m)| &setups[s].fit.modes[m])
        .collect();
    let mut mode = Mode::new(
        pooled(&modes, |m| &m.natural_frequency_hz, false),
        pooled(&modes, |m| &m.damping_ratio, true),
    )
    .with_shape(shape);
    mode.stable_orders = Some(members.len());
    (mode, macs)
}

/// The mean over the setups with its interval from their scatter (t on n − 1 dof), or
/// the one setup's interval.
fn pooled(modes: &[&Mode], pick: impl Fn(&Mode) -> &Interval, positive: bool) -> Interval {
    if modes.len() == 1 {
        return *pick(modes[0]);
    }
    let n = modes.len() as f64;
    let values: Vec<f64> = modes.iter().map(|m| pick(m).value).collect();
    let mean = values.iter().sum::<f64>() / n;
    let se = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
    let t = t_975(modes.len() - 1);
    if positive {
        Interval::positive(mean, se, t)
    } else {
        Interval::new(mean, se, t)
    }
}
