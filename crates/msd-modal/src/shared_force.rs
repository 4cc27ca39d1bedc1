//! Members of a set that read one force record: how much of their force noise they
//! share, and what that does to the poles' covariance and to the set's noise check.
//!
//! ## The model
//! Member o's weighted complex error at line k is r_o,k·η_o,k + F_o,k·ξ_o,k, the
//! response's part and the force's (F = f·φ, the force's share of the line's variance
//! and H's phase, [`Lines::shares`]; E|η|² = E|ξ|² = 2). A force channel read at once
//! with every response — a roving-accelerometer or shaker test on one front end —
//! multiplies every member's H1 by the same error at each line: ξ_o,k = ξ_k, the
//! members' force parts correlated with κ = 1. Members measured one after another (a
//! roving hammer, one accelerometer moved from point to point) have κ = 0. The files do
//! not say which, so κ is estimated from the residuals e at the fitted poles by the
//! method of moments over every pair of members and every line both have:
//!
//! κ̂ = Σ_{o<p} Σ_k Re(e_o,k·ē_p,k·c̄_op,k) / (2s²·Σ_{o<p} Σ_k |c_op,k|²),
//! c_op,k = F_o,k·F̄_p,k, s² the set's SSE over its degrees of freedom,
//!
//! whose standard error where κ = 0 is 1/√(2·Σ|c|²) (the terms independent, each of
//! variance 2|c|²), clamped to [0, 1]. Where the force's share comes from the residuals'
//! own noise model ([`FrfWeighting::Residuals`](msd_modal_core::FrfWeighting::Residuals):
//! no coherence), F is the part of the errors in proportion to H, whatever its cause.
//! A misfit the members share — a resonance that moved between two measurements of a
//! roving-hammer test, a mode missed — leaves residuals alike across them too: κ̂ then
//! takes it in, and the poles' intervals widen by what the members do not tell apart.
//!
//! With κ > 0 the members' errors are no longer independent: the poles' information
//! G = Σ_o J_oᵀC_oJ_o gains κ·Σ_{o≠p} J_oᵀC_opJ_p with
//! (J_oᵀC_opJ_p)_ab = Re Σ_kl z̄_o,ka·F_o,k·ρ_force(d)·F̄_p,l·z_p,lb, that is
//! Q(Σ_o u_o) − Σ_o Q(u_o) with u_o = z_o·F̄_o and Q(u)_ab = Re Σ_kl ū_a,k·ρ(d)·u_b,l;
//! and the set's tr C² gains 2κ²·Σ_{o≠p} Σ_kl |F_o,k|²·|F_p,l|²·|ρ_force(d)|². Where
//! the force's noise dominates the resonances, N members that share it know the poles
//! little better than one does: the intervals assuming independent members were
//! √N too narrow there (six members, 100 sets: 59 % coverage of fn and ζ).

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use msd_modal_core::correlated::complex_inner;
use msd_modal_core::lines::Lines;
use msd_signal::{Complex64, LineCorrelation};

/// How much of the members' force noise is common to them, estimated from the set's
/// residuals (see [`ModeSetFit::shared_force`](crate::ModeSetFit::shared_force)).
///
/// ```
/// use msd_modal::SharedForce;
/// let shared = SharedForce { fraction: 0.97, standard_error: 0.02 };
/// assert!(shared.to_string().starts_with("the members' errors in proportion to H are 97 ± 2 % common"));
/// assert!(shared.is_evident());
/// assert!(!SharedForce { fraction: 0.03, standard_error: 0.02 }.is_evident());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SharedForce {
    /// κ̂ in [0, 1]: 1 where one force record was read with every response, 0 where
    /// each member had its own.
    pub fraction: f64,
    /// Its standard error where the members' force noise is independent.
    pub standard_error: f64,
}

impl SharedForce {
    /// Whether the members' force noise is shown common: κ̂ more than two of its
    /// standard errors above 0 (where they share nothing, κ̂ exceeds that 2.3 % of the
    /// time). Summaries say it then; κ̂ is used in the intervals either way.
    pub fn is_evident(&self) -> bool {
        self.fraction > 2.0 * self.standard_error
    }
}

impl std::fmt::Display for SharedForce {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the members' errors in proportion to H are {:.0} ± {:.0} % common to them (one force record read with every response, or a misfit they share: a resonance that moved between measurements), estimated from the residuals: taken into the poles' intervals and the noise check",
            100.0 * self.fraction,
            100.0 * self.standard_error
        )
    }
}

/// One member's lines on the set's common grid of line positions, with F = f·φ.
struct OnGrid {
    slot: Vec<usize>,
    force: Vec<Complex64>,
}

/// Every member's lines placed on the union of their positions, and that grid's length.
fn on_grid(lines: &[Lines]) -> (Vec<OnGrid>, usize) {
    let mut grid: Vec<usize> = lines.iter().flat_map(|l| l.index.clone()).collect();
    grid.sort_unstable();
    grid.dedup();
    let members = (lines.iter())
        .map(|l| OnGrid {
            slot: (l.index.iter())
                .map(|i| grid.binary_search(i).unwrap_or_default())
                .collect(),
            force: l.shares().1,
        })
        .collect();
    (members, grid.len())
}

/// κ̂ from the weighted residuals `residuals[o]` (real parts, then imaginary parts) of
/// every member at the fitted poles, of variance `s2` per part (the set's SSE over its
/// degrees of freedom: κ̂ a correlation, whatever the weights' scale); `None` where fewer
/// than two members carry a force's share (no coherence noise model).
pub(crate) fn estimate(
    lines: &[Lines],
    residuals: &[&DVector<f64>],
    s2: f64,
) -> Option<SharedForce> {
    let (members, slots) = on_grid(lines);
    let on_slots = |o: usize, values: &dyn Fn(usize) -> Complex64| {
        let mut v = vec![Complex64::default(); slots];
        for (k, &s) in members[o].slot.iter().enumerate() {
            v[s] = values(k);
        }
        v
    };
    let (errors, forces): (Vec<_>, Vec<_>) = (0..lines.len())
        .map(|o| {
            let n = lines[o].omega.len();
            let r = residuals[o];
            let e = on_slots(o, &|k| Complex64::new(r[k], r[n + k]));
            (e, on_slots(o, &|k| members[o].force[k]))
        })
        .unzip();
    let (mut moment, mut weight) = (0.0, 0.0);
    for o in 0..lines.len() {
        for p in o + 1..lines.len() {
            for s in 0..slots {
                let c = forces[o][s] * forces[p][s].conj();
                moment += (errors[o][s] * errors[p][s].conj() * c.conj()).re;
                weight += c.norm_sqr();
            }
        }
    }
    (weight > 0.0 && s2 > 0.0).then(|| SharedForce {
        fraction: (moment / (2.0 * weight * s2)).clamp(0.0, 1.0),
        standard_error: (2.0 * weight).sqrt().recip(),
    })
}

/// Σ_{o≠p} J_oᵀC_opJ_p for unit κ (see the module docs): the reduced Jacobians
/// `jacobians[o]` (2L_o × P), the force's correlation kernel that of the first member.
pub(crate) fn cross_information(lines: &[Lines], jacobians: &[DMatrix<f64>]) -> DMatrix<f64> {
    let (members, slots) = on_grid(lines);
    let p = jacobians[0].ncols();
    let kernel = &lines[0].correlation.force;
    let mut total = vec![vec![Complex64::default(); slots]; p];
    let mut own = DMatrix::zeros(p, p);
    for ((member, j), l) in members.iter().zip(jacobians).zip(lines) {
        let n = l.omega.len();
        let u: Vec<Vec<Complex64>> = (0..p)
            .map(|b| {
                let mut u = vec![Complex64::default(); slots];
                for (k, &s) in member.slot.iter().enumerate() {
                    u[s] = Complex64::new(j[(k, b)], j[(n + k, b)]) * member.force[k].conj();
                }
                u
            })
            .collect();
        own += quadratic(&u, kernel);
        for (t, u) in total.iter_mut().zip(&u) {
            t.iter_mut().zip(u).for_each(|(t, u)| *t += u);
        }
    }
    quadratic(&total, kernel) - own
}

/// Q(u)_ab = Re Σ_kl ū_a,k·ρ(k − l)·u_b,l over the grid's slots.
fn quadratic(u: &[Vec<Complex64>], kernel: &[Complex64]) -> DMatrix<f64> {
    let reach = kernel.len().max(1) as i64 - 1;
    let correlated: Vec<Vec<Complex64>> = (u.iter())
        .map(|u| {
            (0..u.len() as i64)
                .map(|k| {
                    let lags = (k - reach).max(0)..=(k + reach).min(u.len() as i64 - 1);
                    lags.map(|l| LineCorrelation::at(kernel, k - l) * u[l as usize])
                        .sum()
                })
                .collect()
        })
        .collect();
    DMatrix::from_fn(u.len(), u.len(), |a, b| {
        complex_inner(&u[a], &correlated[b])
    })
}

/// Σ_{o≠p} Σ_kl |F_o,k|²·|F_p,l|²·|ρ_force(k − l)|², the cross-member part of
/// tr C²/(2κ²) (see the module docs).
pub(crate) fn cross_squared_correlation(lines: &[Lines]) -> f64 {
    let (members, slots) = on_grid(lines);
    let kernel = &lines[0].correlation.force;
    let power = |m: &OnGrid| {
        let mut v = vec![0.0; slots];
        for (k, &s) in m.slot.iter().enumerate() {
            v[s] = m.force[k].norm_sqr();
        }
        v
    };
    let powers: Vec<Vec<f64>> = members.iter().map(power).collect();
    let total: Vec<f64> = (0..slots)
        .map(|s| powers.iter().map(|v| v[s]).sum())
        .collect();
    let lagged = |a: &[f64], b: &[f64]| -> f64 {
        let reach = kernel.len().max(1) as i64 - 1;
        (0..slots as i64)
            .map(|k| {
                let lags = (k - reach).max(0)..=(k + reach).min(slots as i64 - 1);
                lags.map(|l| {
                    a[k as usize] * b[l as usize] * LineCorrelation::at(kernel, k - l).norm_sqr()
                })
                .sum::<f64>()
            })
            .sum()
    };
    lagged(&total, &total) - powers.iter().map(|v| lagged(v, v)).sum::<f64>()
}
