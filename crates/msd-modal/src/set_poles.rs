//! The poles common to a set of frequency responses, refined by Gauss–Newton with each
//! member's linear parameters (modal constants, residual terms) eliminated: variable
//! projection (Golub & Pereyra 1973) in Kaufman's form.
//!
//! For fixed poles p, member o's weighted residuals are r_o = A_o x̂_o − b_o with x̂_o
//! from LSFD. With D_o = ∂(model_o)/∂p at x̂_o (weighted), the reduced Jacobian is
//! J_o = (I − P_o) D_o, P_o the projection on A_o's columns, so
//! J_oᵀJ_o = D_oᵀD_o − D_oᵀA_o(A_oᵀA_o)⁻¹A_oᵀD_o and J_oᵀr_o = D_oᵀr_o (r_o ⊥ A_o).
//! Summed over the members these are the normal equations of the 2M pole parameters,
//! and σ̂²(Σ J_oᵀJ_o)⁻¹ is the poles' block of the full covariance.
//!
//! ## The residuals against the members' own noise
//! Where every member's σ are absolute (the coherence's noise model, two or more
//! averages), the set's SSE is checked as one fit's is ([`NoiseCheck`]): the residual
//! projector of the whole fit is M = Q − J·N⁻¹·Jᵀ with Q = diag(I − P_o), J the stacked
//! J_o and N = Σ J_oᵀJ_o. With the members' errors independent of one another, each
//! correlated as its lines say (C = diag C_o),
//! E\[SSE\] = tr(MC) = Σ_o (rows_o − tr(P_oC_o)) − tr(N⁻¹G), G = Σ J_oᵀC_oJ_o, and
//! Var\[SSE\]/2 = tr(MCMC) = Σ_o tr(Q_oC_oQ_oC_o) − 2·tr(N⁻¹·Σ_o J_oᵀC_oQ_oC_oJ_o) +
//! tr((N⁻¹G)²) (Q·J = J). Members that read one force record share its noise: G and
//! tr C² then gain the cross terms of [`crate::shared_force`], with κ estimated from the
//! residuals (Σ J_oᵀC_oQ_oC_oJ_o keeps the members' own terms only; its cross terms are
//! of the order of the fit's 2M + 2 columns against each member's 2L rows).

use nalgebra::{DMatrix, DVector};

use crate::polish::lsfd_system;
use crate::shared_force::{SharedForce, cross_information, cross_squared_correlation, estimate};
use msd_modal_core::correlated::{complex_inner, sandwich};
use msd_modal_core::error::{ModalError, Result, not_identifiable};
use msd_modal_core::lines::Lines;
use msd_modal_core::modal::term_with_gradient;
use msd_modal_core::noise_check::NoiseCheck;
use msd_opt::statistics::Linearization;

/// The refined poles (ωn, ζ), their covariance (rows ωn₁, ζ₁, ωn₂, …), σ̂ and the
/// degrees of freedom, the iterations taken, and the residuals against the members'
/// own noise where their σ are absolute.
pub(crate) struct RefinedPoles {
    pub poles: Vec<(f64, f64)>,
    pub covariance: DMatrix<f64>,
    pub sigma: f64,
    pub degrees_of_freedom: usize,
    pub iterations: usize,
    pub noise_check: Option<NoiseCheck>,
    pub shared_force: Option<SharedForce>,
}

/// The sum of squares and the reduced normal equations at some poles.
pub(crate) struct Reduced {
    sse: f64,
    normal: DMatrix<f64>,
    gradient: DVector<f64>,
}

/// Levenberg–Marquardt on the poles of every member of `lines` (one axis) from `start`.
pub(crate) fn refine_poles(lines: &[Lines], start: Vec<(f64, f64)>) -> Result<RefinedPoles> {
    let mut poles = start;
    let mut at = reduce(lines, &poles)?;
    let mut lambda = 1e-3;
    let mut iterations = 0;
    while iterations < 100 && lambda < 1e12 {
        iterations += 1;
        let mut lhs = at.normal.clone();
        for i in 0..lhs.nrows() {
            lhs[(i, i)] *= 1.0 + lambda;
        }
        let Some(step) = lhs.cholesky().map(|c| c.solve(&-&at.gradient)) else {
            lambda *= 10.0;
            continue;
        };
        let trial: Vec<(f64, f64)> = poles
            .iter()
            .enumerate()
            .map(|(r, &(wn, zeta))| (wn + step[2 * r], zeta + step[2 * r + 1]))
            .collect();
        let valid = trial.iter().all(|&(wn, zeta)| wn > 0.0 && zeta > 0.0);
        match valid.then(|| reduce(lines, &trial)) {
            Some(Ok(next)) if next.sse < at.sse => {
                let gain = (at.sse - next.sse) / at.sse;
                (poles, at) = (trial, next);
                lambda = (lambda / 10.0).max(1e-12);
                if gain < 1e-12 {
                    break;
                }
            }
            _ => lambda *= 10.0,
        }
    }
    covariance_at(lines, poles, at, iterations)
}

/// The poles' covariance at `poles` (the reduced problem `at` there), with σ̂, the
/// degrees of freedom, the shared force and the noise check (see the module docs).
pub(crate) fn covariance_at(
    lines: &[Lines],
    poles: Vec<(f64, f64)>,
    at: Reduced,
    iterations: usize,
) -> Result<RefinedPoles> {
    let residuals: usize = lines.iter().map(|l| 2 * l.omega.len()).sum();
    let parameters = 2 * poles.len() + lines.len() * (2 * poles.len() + 2);
    if residuals <= parameters {
        return Err(ModalError::TooFewSamples {
            got: residuals / 2,
            needed: parameters / 2 + 1,
            why: "lines (summed over the set) for the modal parameters of every mode",
        });
    }
    let members: Vec<Member> = (lines.iter())
        .map(|l| Member::at(l, &poles))
        .collect::<Option<_>>()
        .ok_or_else(cannot_tell_apart)?;
    let weighted: Vec<&DVector<f64>> = members.iter().map(|m| &m.r).collect();
    let shared_force = estimate(lines, &weighted, at.sse / (residuals - parameters) as f64);
    let kappa = shared_force.map_or(0.0, |s| s.fraction);
    // The lines' correlated errors: the sandwich where every member's correlation is
    // known (s² over the degrees of freedom the fit leaves the correlated residuals),
    // else the first member's correlation length for all.
    let (normal, residual_dof) = error_information(lines, &members, kappa)
        .and_then(|(g, constants_taken)| {
            let (normal, poles_taken) = sandwich(&at.normal, &g)?;
            Some((normal, residuals as f64 - constants_taken - poles_taken))
        })
        .unwrap_or_else(|| {
            let normal = &at.normal / lines[0].correlated_lines;
            (normal, (residuals - parameters) as f64)
        });
    let residual_dof = residual_dof.max(1.0);
    let s2 = lines[0].residual_variance(at.sse, residual_dof);
    let degrees_of_freedom = residual_dof.floor() as usize;
    let covariance = Linearization::from_normal_matrix(&normal)
        .map(|l| l.covariance(s2))
        .map_err(|e| not_identifiable(e, "the set's lines", &[]))?;
    Ok(RefinedPoles {
        noise_check: noise_check(lines, &members, at.sse, kappa),
        shared_force,
        poles,
        covariance,
        sigma: s2.sqrt(),
        degrees_of_freedom,
        iterations,
    })
}

/// The set's SSE against its members' own noise (see the module docs); `None` where a
/// member's σ are not absolute or the moments cannot be formed.
fn noise_check(lines: &[Lines], members: &[Member], sse: f64, kappa: f64) -> Option<NoiseCheck> {
    if lines
        .iter()
        .any(|l| l.noise_model.is_none() || l.averages < 2)
    {
        return None;
    }
    let (mean, variance) = set_moments(lines, members, kappa)?;
    NoiseCheck::from_moments(sse, mean, variance)
}

/// E\[SSE\] and Var\[SSE\] of the set under its members' noise alone (the module docs),
/// their force noise common by `kappa`.
fn set_moments(lines: &[Lines], members: &[Member], kappa: f64) -> Option<(f64, f64)> {
    let m2 = members[0].d.ncols();
    let mut reduced: Vec<DMatrix<f64>> = members.iter().map(Member::projected).collect();
    // One column scaling for every member (N sums them); the traces do not depend on it.
    for j in 0..m2 {
        let norm = (reduced.iter())
            .map(|d| d.column(j).norm_squared())
            .sum::<f64>()
            .sqrt()
            .max(f64::MIN_POSITIVE);
        reduced
            .iter_mut()
            .for_each(|d| d.column_mut(j).scale_mut(1.0 / norm));
    }
    let (mut mean, mut half) = (0.0, 0.0);
    let (mut normal, mut g, mut middle) = (
        DMatrix::zeros(m2, m2),
        DMatrix::zeros(m2, m2),
        DMatrix::zeros(m2, m2),
    );
    if kappa > 0.0 {
        g += kappa * cross_information(lines, &reduced);
        half += 2.0 * kappa * kappa * cross_squared_correlation(lines);
    }
    for ((l, m), j) in lines.iter().zip(members).zip(&reduced) {
        let (mean_o, variance_o) = l.residual_moments(&m.a)?;
        mean += mean_o;
        half += variance_o / 2.0;
        normal += j.transpose() * j;
        let Some((z, cz)) = l.correlated_columns(j) else {
            // Independent lines: C_o = I, so G_o = J_oᵀJ_o and J_oᵀC_oQ_oC_oJ_o = G_o.
            g += j.transpose() * j;
            middle += j.transpose() * j;
            continue;
        };
        let (za, _) = l.correlated_columns(&m.a)?;
        g += DMatrix::from_fn(m2, m2, |a, b| complex_inner(&z[a], &cz[b]));
        // J_oᵀC_oQ_oC_oJ_o = (CJ)ᵀ(CJ) − (AᵀCJ)ᵀ(AᵀA)⁻¹(AᵀCJ).
        let h = DMatrix::from_fn(m2, m2, |a, b| complex_inner(&cz[a], &cz[b]));
        let acj = DMatrix::from_fn(za.len(), m2, |i, b| complex_inner(&za[i], &cz[b]));
        middle += h - acj.transpose() * m.gram.solve(&acj);
    }
    let normal = normal.cholesky()?;
    let (ng, nm) = (normal.solve(&g), normal.solve(&middle));
    mean -= ng.trace();
    let variance = 2.0 * (half - 2.0 * nm.trace() + (&ng * &ng).trace());
    Some((mean, variance))
}

/// The reduced problem at `poles`: Σ SSE, Σ J_oᵀJ_o and Σ J_oᵀr_o.
pub(crate) fn reduce(lines: &[Lines], poles: &[(f64, f64)]) -> Result<Reduced> {
    let m2 = 2 * poles.len();
    let mut out = Reduced {
        sse: 0.0,
        normal: DMatrix::zeros(m2, m2),
        gradient: DVector::zeros(m2),
    };
    for l in lines {
        let m = Member::at(l, poles).ok_or_else(cannot_tell_apart)?;
        let atd = m.a.transpose() * &m.d;
        out.sse += m.r.norm_squared();
        out.normal += m.d.transpose() * &m.d - atd.transpose() * m.gram.solve(&atd);
        out.gradient += m.d.transpose() * &m.r;
    }
    Ok(out)
}

/// The error of a member whose modal constants cannot be told apart.
fn cannot_tell_apart() -> ModalError {
    ModalError::NotIdentifiable {
        reason: "the modal constants cannot be told apart (two poles too close?)".into(),
    }
}

/// One member's LSFD at fixed poles: the column-scaled A with its Gram factor, the
/// residual r = A·x̂ − b and D (see the module docs).
struct Member {
    a: DMatrix<f64>,
    gram: nalgebra::Cholesky<f64, nalgebra::Dyn>,
    r: DVector<f64>,
    d: DMatrix<f64>,
}

impl Member {
    /// `None` when the modal constants cannot be told apart.
    fn at(l: &Lines, poles: &[(f64, f64)]) -> Option<Self> {
        let (mut a, b) = lsfd_system(l, poles);
        // Column scaling leaves the projection unchanged and keeps AᵀA well conditioned.
        let norms: Vec<f64> = a.column_iter().map(|c| c.norm()).collect();
        for (j, &norm) in norms.iter().enumerate() {
            a.column_mut(j).scale_mut(1.0 / norm);
        }
        let gram = (a.transpose() * &a).cholesky()?;
        let x = gram.solve(&(a.transpose() * &b));
        let r = &a * &x - &b;
        let d = derivatives(l, poles, &x, &norms);
        Some(Self { a, gram, r, d })
    }

    /// The reduced Jacobian J_o = (I − P_o)·D_o.
    fn projected(&self) -> DMatrix<f64> {
        &self.d - &self.a * self.gram.solve(&(self.a.transpose() * &self.d))
    }
}

/// Σ_o J_oᵀC_oJ_o over the members, the information their correlated lines' errors
/// carry about the poles (each member's errors correlated as its own lines say; with
/// their force noise common by `shared` > 0, the cross terms of
/// [`crate::shared_force`], a member whose correlation is not known taken with
/// independent lines when its [`Lines::correlated_lines`] is 1, as a table's), and
/// Σ_o tr(P_o·C_o), the degrees of freedom the members' modal constants take from the
/// correlated residuals (P_o the projection on member o's LSFD columns); `None` when a
/// member's correlation is not known.
fn error_information(
    lines: &[Lines],
    members: &[Member],
    shared: f64,
) -> Option<(DMatrix<f64>, f64)> {
    let cross = shared > 0.0
        && (lines.iter()).all(|l| !l.correlation.is_empty() || l.correlated_lines == 1.0);
    let m2 = members[0].d.ncols();
    let mut sum = DMatrix::zeros(m2, m2);
    let mut taken = 0.0;
    let mut reduced = Vec::with_capacity(members.len());
    for (l, member) in lines.iter().zip(members) {
        let j = member.projected();
        match l.error_information(&j) {
            Some(g) => {
                sum += g;
                taken += member.gram.solve(&l.error_information(&member.a)?).trace();
            }
            // Independent lines of equal variance: C_o = I.
            None if cross => {
                sum += j.transpose() * &j;
                taken += member.a.ncols() as f64;
            }
            None => return None,
        }
        reduced.push(j);
    }
    if cross {
        sum += shared * cross_information(lines, &reduced);
    }
    Some((sum, taken))
}

/// D = ∂(weighted model)/∂(ωn_r, ζ_r) at the scaled LSFD solution `x` (column norms
/// `norms`): 2K × 2M, real parts then imaginary parts.
fn derivatives(l: &Lines, poles: &[(f64, f64)], x: &DVector<f64>, norms: &[f64]) -> DMatrix<f64> {
    let n = l.omega.len();
    let mut d = DMatrix::zeros(2 * n, 2 * poles.len());
    for (k, (&w, &s)) in l.omega.iter().zip(&l.sigma).enumerate() {
        for (r, &(wn, zeta)) in poles.iter().enumerate() {
            let (a, b) = (x[2 * r] / norms[2 * r], x[2 * r + 1] / norms[2 * r + 1]);
            let (_, g) = term_with_gradient(&[wn, zeta, a, b], w);
            for (i, gi) in [g[0], g[1]].iter().enumerate() {
                d[(k, 2 * r + i)] = gi.re / s;
                d[(n + k, 2 * r + i)] = gi.im / s;
            }
        }
    }
    d
}
