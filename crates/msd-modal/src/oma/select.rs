//! Automatic selection from a stabilization diagram of poles with shapes: hard criteria
//! (band, damping, MPC), soft stability against the order before (fn and MAC), then the
//! stable poles clustered by average linkage on |Δf|/f + (1 − MAC) (Magalhães, Cunha &
//! Caetano, Mech. Syst. Signal Process. 23, 2009), a cluster with poles at enough orders
//! being a mode.

use msd_signal::Complex64;

use super::options::OmaOptions;
use crate::shapes::mac;
use msd_modal_core::diagram::{DiagramOrder, DiagramPole, StableColumn};
use msd_modal_core::error::{ModalError, Result};

/// A pole that passed the hard criteria, with its displacement shape.
#[derive(Debug, Clone)]
pub(crate) struct Physical {
    /// Index of its order in the diagram.
    pub order_index: usize,
    /// fn, Hz.
    pub frequency_hz: f64,
    /// ζ.
    pub damping_ratio: f64,
    /// The displacement shape, largest entry 1.
    pub shape: Vec<Complex64>,
    /// Stable in fn and MAC against the order before.
    pub stable: bool,
}

/// The poles of one cluster, one per order, and its representative (the median fn).
#[derive(Debug, Clone)]
pub(crate) struct Cluster {
    /// Indices into the physical poles, by frequency.
    pub members: Vec<usize>,
    /// The member with the median fn.
    pub representative: usize,
}

/// |Δf|/f + (1 − MAC): the distance of the clustering and of matching a pole.
pub(crate) fn distance(a_hz: f64, a: &[Complex64], b_hz: f64, b: &[Complex64]) -> f64 {
    (a_hz - b_hz).abs() / a_hz.max(b_hz) + (1.0 - mac(a, b))
}

/// Flags each pole stable against the nearest pole (in [`distance`]) of the order
/// before, and returns the diagram's orders.
pub(crate) fn flag_stability(
    orders: &[usize],
    poles: &mut [Physical],
    options: &OmaOptions,
) -> Vec<DiagramOrder> {
    let mut diagram: Vec<DiagramOrder> = orders
        .iter()
        .map(|&order| DiagramOrder {
            order,
            poles: Vec::new(),
        })
        .collect();
    // Poles come order by order: where each order's start.
    let mut starts = vec![poles.len(); orders.len() + 1];
    for (i, p) in poles.iter().enumerate().rev() {
        starts[p.order_index] = i;
    }
    for o in (0..orders.len()).rev() {
        starts[o] = starts[o].min(starts[o + 1]);
    }
    for i in 0..poles.len() {
        let p = &poles[i];
        let before = match p.order_index {
            0 => &poles[0..0],
            o => &poles[starts[o - 1]..starts[o]],
        };
        let previous = before.iter().min_by(|a, b| {
            let d = |q: &Physical| distance(p.frequency_hz, &p.shape, q.frequency_hz, &q.shape);
            d(a).total_cmp(&d(b))
        });
        let (sf, sz, sm) = previous.map_or((false, false, false), |q| {
            (
                (p.frequency_hz - q.frequency_hz).abs()
                    <= options.frequency_tolerance * p.frequency_hz,
                (p.damping_ratio - q.damping_ratio).abs()
                    <= options.damping_tolerance * p.damping_ratio,
                1.0 - mac(&p.shape, &q.shape) <= options.mac_tolerance,
            )
        });
        let index = p.order_index;
        poles[i].stable = sf && sm;
        diagram[index].poles.push(DiagramPole {
            natural_frequency_hz: poles[i].frequency_hz,
            damping_ratio: poles[i].damping_ratio,
            stable_frequency: sf,
            stable_damping: sz,
            stable: sf && sz && sm,
            mode: None,
        });
    }
    diagram
}

/// The stable poles clustered: groups split at frequency gaps wider than the cluster
/// distance, average linkage inside each group; every cluster thinned to one pole per
/// order (the nearest its median fn). By frequency.
pub(crate) fn clusters(poles: &[Physical], options: &OmaOptions) -> Vec<Cluster> {
    let mut stable: Vec<usize> = (0..poles.len()).filter(|&i| poles[i].stable).collect();
    stable.sort_by(|&a, &b| poles[a].frequency_hz.total_cmp(&poles[b].frequency_hz));
    let mut out = Vec::new();
    let mut start = 0;
    for end in 1..=stable.len() {
        let split = end == stable.len() || {
            let (a, b) = (
                poles[stable[end - 1]].frequency_hz,
                poles[stable[end]].frequency_hz,
            );
            (b - a) / b > options.cluster_distance
        };
        if split {
            for group in average_linkage(&stable[start..end], poles, options.cluster_distance) {
                out.push(thinned(group, poles));
            }
            start = end;
        }
    }
    out.sort_by(|a, b| {
        poles[a.representative]
            .frequency_hz
            .total_cmp(&poles[b.representative].frequency_hz)
    });
    out
}

/// Average-linkage clusters of `members` with distances up to `cut`.
fn average_linkage(members: &[usize], poles: &[Physical], cut: f64) -> Vec<Vec<usize>> {
    let n = members.len();
    let mut groups: Vec<Vec<usize>> = members.iter().map(|&m| vec![m]).collect();
    let mut d: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    let (a, b) = (&poles[members[i]], &poles[members[j]]);
                    distance(a.frequency_hz, &a.shape, b.frequency_hz, &b.shape)
                })
                .collect()
        })
        .collect();
    let mut alive: Vec<bool> = vec![true; n];
    loop {
        let mut best: Option<(usize, usize, f64)> = None;
        for i in (0..n).filter(|&i| alive[i]) {
            for j in (i + 1..n).filter(|&j| alive[j]) {
                if d[i][j] <= cut && best.is_none_or(|(_, _, b)| d[i][j] < b) {
                    best = Some((i, j, d[i][j]));
                }
            }
        }
        let Some((i, j, _)) = best else { break };
        let (ni, nj) = (groups[i].len() as f64, groups[j].len() as f64);
        for k in (0..n).filter(|&k| alive[k] && k != i && k != j) {
            let merged = (ni * d[i][k] + nj * d[j][k]) / (ni + nj);
            d[i][k] = merged;
            d[k][i] = merged;
        }
        let moved = std::mem::take(&mut groups[j]);
        groups[i].extend(moved);
        alive[j] = false;
    }
    groups.into_iter().filter(|g| !g.is_empty()).collect()
}

/// One pole per order (the nearest the group's median fn), and the median member.
fn thinned(group: Vec<usize>, poles: &[Physical]) -> Cluster {
    let median_of = |ids: &[usize]| {
        let mut f: Vec<f64> = ids.iter().map(|&i| poles[i].frequency_hz).collect();
        f.sort_by(f64::total_cmp);
        f[(f.len() - 1) / 2]
    };
    let centre = median_of(&group);
    let mut members: Vec<usize> = Vec::new();
    for &i in &group {
        let same = members
            .iter()
            .position(|&m| poles[m].order_index == poles[i].order_index);
        match same {
            Some(k)
                if (poles[i].frequency_hz - centre).abs()
                    < (poles[members[k]].frequency_hz - centre).abs() =>
            {
                members[k] = i;
            }
            Some(_) => {}
            None => members.push(i),
        }
    }
    members.sort_by(|&a, &b| poles[a].frequency_hz.total_cmp(&poles[b].frequency_hz));
    let representative = members[(members.len() - 1) / 2];
    Cluster {
        members,
        representative,
    }
}

/// The clusters that are modes: automatically those with poles at `min_stable_share`
/// of `order_count` orders, or the nearest cluster to each named frequency.
pub(crate) fn selected(
    clusters: &[Cluster],
    poles: &[Physical],
    order_count: usize,
    options: &OmaOptions,
) -> Result<Vec<usize>> {
    if options.frequencies_hz.is_empty() {
        let needed = (options.min_stable_share * order_count as f64).ceil() as usize;
        return Ok((0..clusters.len())
            .filter(|&c| clusters[c].members.len() >= needed.max(2))
            .collect());
    }
    let mut chosen = Vec::new();
    for &f in &options.frequencies_hz {
        let nearest = (0..clusters.len()).min_by(|&a, &b| {
            let d = |c: usize| (poles[clusters[c].representative].frequency_hz - f).abs();
            d(a).total_cmp(&d(b))
        });
        match nearest {
            Some(c) if (poles[clusters[c].representative].frequency_hz / f - 1.0).abs() <= 0.05 => {
                if !chosen.contains(&c) {
                    chosen.push(c);
                }
            }
            _ => {
                return Err(ModalError::NotIdentifiable {
                    reason: format!(
                        "no stable pole within 5 % of the named frequency {f} Hz (frequencies_hz): the diagram has none there"
                    ),
                });
            }
        }
    }
    chosen.sort_by(|&a, &b| {
        poles[clusters[a].representative]
            .frequency_hz
            .total_cmp(&poles[clusters[b].representative].frequency_hz)
    });
    Ok(chosen)
}

/// The mean of a cluster's poles: fn, ζ, and the shapes each brought to `reference`'s
/// scale and phase (least squares) averaged, largest entry 1. The mode's estimate: a
/// smooth function of the data (a median over orders is not, and its jackknife variance
/// would not hold).
pub(crate) fn mean_pole(members: &[&Physical], reference: &[Complex64]) -> Physical {
    let n = members.len() as f64;
    let mut shape = vec![Complex64::new(0.0, 0.0); reference.len()];
    for m in members {
        for (s, v) in shape.iter_mut().zip(aligned(&m.shape, reference)) {
            *s += v / n;
        }
    }
    let largest = shape
        .iter()
        .copied()
        .max_by(|a, b| a.norm().total_cmp(&b.norm()))
        .filter(|v| v.norm() > 0.0)
        .unwrap_or(Complex64::new(1.0, 0.0));
    Physical {
        order_index: members[0].order_index,
        frequency_hz: members.iter().map(|m| m.frequency_hz).sum::<f64>() / n,
        damping_ratio: members.iter().map(|m| m.damping_ratio).sum::<f64>() / n,
        shape: shape.iter().map(|v| v / largest).collect(),
        stable: true,
    }
}

/// `shape` times the complex factor α that brings it nearest `target` (least squares).
pub(crate) fn aligned(shape: &[Complex64], target: &[Complex64]) -> Vec<Complex64> {
    let cross: Complex64 = shape.iter().zip(target).map(|(s, t)| s.conj() * t).sum();
    let norm: f64 = shape.iter().map(|s| s.norm_sqr()).sum();
    let alpha = if norm > 0.0 {
        cross / norm
    } else {
        Complex64::new(0.0, 0.0)
    };
    shape.iter().map(|s| s * alpha).collect()
}

/// A cluster as a column of the diagram: median fn and ζ, its orders.
pub(crate) fn column(cluster: &Cluster, poles: &[Physical]) -> StableColumn {
    let p = &poles[cluster.representative];
    let mut z: Vec<f64> = cluster
        .members
        .iter()
        .map(|&i| poles[i].damping_ratio)
        .collect();
    z.sort_by(f64::total_cmp);
    StableColumn {
        natural_frequency_hz: p.frequency_hz,
        damping_ratio: z[(z.len() - 1) / 2],
        stable_orders: cluster.members.len(),
        at_peak: true,
    }
}

/// The automatic selection less the splits of a mode: a chosen cluster within
/// `frequency_tolerance` (relative) of a larger chosen one, with MAC ≥ 0.9 between their
/// representatives, is the same mode identified twice at high orders (one physical mode
/// has one pole per order; its split copies share orders with it). Returns the kept
/// clusters and the splits.
pub(crate) fn without_splits(
    chosen: Vec<usize>,
    clusters: &[Cluster],
    poles: &[Physical],
    options: &OmaOptions,
) -> (Vec<usize>, Vec<usize>) {
    if !options.frequencies_hz.is_empty() {
        return (chosen, Vec::new());
    }
    let rep = |c: usize| &poles[clusters[c].representative];
    let split = |c: usize| {
        chosen.iter().any(|&d| {
            let (a, b) = (rep(c), rep(d));
            d != c
                && clusters[d].members.len() > clusters[c].members.len()
                && (a.frequency_hz / b.frequency_hz - 1.0).abs() <= options.frequency_tolerance
                && mac(&a.shape, &b.shape) >= 0.9
        })
    };
    chosen.iter().copied().partition(|&c| !split(c))
}
