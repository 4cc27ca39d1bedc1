//! Poles by the least-squares complex-frequency estimator (LSCF; Guillaume, Verboven,
//! Vanlanduit, Van der Auweraer & Peeters, "A poly-reference implementation of the
//! least-squares complex frequency-domain estimator", IMAC 2003), for one frequency
//! response.
//!
//! ## The method
//! A common-denominator model H ≈ N(Ω)/D(Ω) with polynomials of order n in
//! Ω_k = e^{jω_kΔt}, real coefficients, Δt = 1/(2·f_max) (the band maps onto the upper
//! half of the unit circle, where the powers of Ω are well conditioned). The equation
//! error w_k·(N(Ω_k) − H_k·D(Ω_k)), w_k = 1/σ_k, is linear in the coefficients β of N
//! and α of D. Its normal matrix [[R, S], [Sᵀ, T]] is Toeplitz in each block:
//! R_ij = Σ w²·cos(ωΔt(j − i)), S_ij = −Re Σ w²·H·e^{jωΔt(j − i)},
//! T_ij = Σ w²|H|²·cos(ωΔt(j − i)), so all orders come from 3·(2n + 1) sums. Eliminating
//! β leaves M = T − SᵀR⁻¹S; with α_n = 1, α solves the first n rows of M·α = 0. Each
//! order's R and S are the leading blocks of the largest order's, and so are the Cholesky
//! factor L of R = LLᵀ and W = L⁻¹S (forward substitution does not look ahead): one
//! factorisation gives every order's M = T − WᵀW (each order's own where the largest
//! order's R is not positive definite). The roots z_r of D are the poles
//! λ_r = ln(z_r)/Δt: the eigenvalues of its companion matrix at the first order, then each
//! order's refined from the order before's by the Aberth–Ehrlich iteration (O(n²) a sweep
//! against the eigenvalues' O(n³); the companion matrix again where it fails).

use std::f64::consts::TAU;

use msd_signal::Complex64;
use nalgebra::DMatrix;

use msd_modal_core::lines::Lines;

/// The Toeplitz sums of one frequency response, up to a largest order.
pub(crate) struct Lscf {
    /// R's lags 0 … max.
    r: Vec<f64>,
    /// T's lags 0 … max.
    t: Vec<f64>,
    /// S's lags −max … max, at index lag + max.
    s: Vec<f64>,
    max_order: usize,
    dt: f64,
    /// W = L⁻¹S of the largest order, R = LLᵀ, and Wᵀ (a view with swapped strides would
    /// do, but nalgebra 0.34's small-matrix gemm overruns on a row stride ≠ 1); `None` if
    /// that R is not positive definite (then each order's R is factorised alone).
    w: Option<(DMatrix<f64>, DMatrix<f64>)>,
}

impl Lscf {
    /// The sums for orders up to `max_order` over `lines`.
    pub(crate) fn new(lines: &Lines, max_order: usize) -> Self {
        let omega_max = lines.omega[lines.omega.len() - 1];
        let dt = std::f64::consts::PI / omega_max;
        let mut r = vec![0.0; max_order + 1];
        let mut t = vec![0.0; max_order + 1];
        let mut s = vec![0.0; 2 * max_order + 1];
        for ((&w, h), &sigma) in lines.omega.iter().zip(&lines.h).zip(&lines.diagram_sigma) {
            let weight = 1.0 / (sigma * sigma);
            let step = Complex64::from_polar(1.0, w * dt);
            let mut power = Complex64::new(1.0, 0.0);
            let wh = h * weight;
            let wh2 = h.norm_sqr() * weight;
            for d in 0..=max_order {
                r[d] += weight * power.re;
                t[d] += wh2 * power.re;
                // e^{−jωΔt·d} = conj(power) for the negative lags.
                s[max_order + d] -= (wh * power).re;
                if d > 0 {
                    s[max_order - d] -= (wh * power.conj()).re;
                }
                power *= step;
            }
        }
        Self::from_sums(r, t, s, max_order, dt)
    }

    /// The estimator of the sums, with W of the largest order when its R is positive
    /// definite.
    fn from_sums(r: Vec<f64>, t: Vec<f64>, s: Vec<f64>, max_order: usize, dt: f64) -> Self {
        let mut lscf = Self {
            r,
            t,
            s,
            max_order,
            dt,
            w: None,
        };
        let (r, mut w) = lscf.r_and_s(max_order);
        if let Some(l) = r.cholesky() {
            let solved = l.l_dirty().solve_lower_triangular_mut(&mut w);
            debug_assert!(solved, "a Cholesky factor has a positive diagonal");
            let w_t = w.transpose();
            lscf.w = Some((w, w_t));
        }
        lscf
    }

    /// R and S of order `n`.
    fn r_and_s(&self, n: usize) -> (DMatrix<f64>, DMatrix<f64>) {
        let size = n + 1;
        let r = DMatrix::from_fn(size, size, |i, j| self.r[i.abs_diff(j)]);
        let s = DMatrix::from_fn(size, size, |i, j| self.s[self.max_order + j - i]);
        (r, s)
    }

    /// The roots z_r of the order-`n` denominator (n ≤ the largest order), refined from
    /// `warm` (a lower order's roots) when given (see [`roots_of`]); `None` if its normal
    /// equations are singular.
    pub(crate) fn roots(&self, n: usize, warm: Option<&[Complex64]>) -> Option<Vec<Complex64>> {
        roots_of(self.reduced(n)?, n, warm)
    }

    /// The reduced normal matrix M = T − SᵀR⁻¹S of order `n` ((n + 1) × (n + 1));
    /// `None` if R is not positive definite.
    pub(crate) fn reduced(&self, n: usize) -> Option<DMatrix<f64>> {
        debug_assert!((1..=self.max_order).contains(&n));
        let Some((w, w_t)) = &self.w else {
            return self.reduced_alone(n);
        };
        let size = n + 1;
        let (w, w_t) = (w.view((0, 0), (size, size)), w_t.view((0, 0), (size, size)));
        let mut m = DMatrix::from_fn(size, size, |i, j| self.t[i.abs_diff(j)]);
        m.gemm(-1.0, &w_t, &w, 1.0);
        Some(m)
    }

    /// M of order `n` from its own R's Cholesky factor (the reference).
    fn reduced_alone(&self, n: usize) -> Option<DMatrix<f64>> {
        let size = n + 1;
        let (r, s) = self.r_and_s(n);
        let t = DMatrix::from_fn(size, size, |i, j| self.t[i.abs_diff(j)]);
        let r_inv_s = r.cholesky()?.solve(&s);
        Some(t - s.transpose() * r_inv_s)
    }

    /// The sampling step Δt = π/ω_max of the z-domain model.
    pub(crate) fn dt(&self) -> f64 {
        self.dt
    }
}

/// The roots z_r of the order-`n` common denominator whose reduced normal matrix
/// (summed over the frequency responses that share it) is `m`; `None` if the first n rows
/// of M·α = 0 (α_n = 1) are singular. From `warm`, a lower order's roots, they are refined
/// by the Aberth–Ehrlich iteration (see [`aberth`]); without it, or when that fails, they
/// are the eigenvalues of the companion matrix.
pub(crate) fn roots_of(
    m: DMatrix<f64>,
    n: usize,
    warm: Option<&[Complex64]>,
) -> Option<Vec<Complex64>> {
    let alpha = denominator(m, n)?;
    let refined = warm.and_then(|w| aberth(&alpha, warm_start(w, n)));
    Some(refined.unwrap_or_else(|| companion_roots(&alpha)))
}

/// α_0 … α_{n−1} of the order-`n` denominator: the first n rows of M·α = 0, α_n = 1.
fn denominator(m: DMatrix<f64>, n: usize) -> Option<Vec<f64>> {
    let rhs = -m.view((0, n), (n, 1)).clone_owned();
    let alpha = m.view((0, 0), (n, n)).clone_owned().cholesky()?.solve(&rhs);
    Some(alpha.as_slice().to_vec())
}

/// The roots of z^n + α_{n−1}z^{n−1} + … + α_0: the eigenvalues of its companion matrix.
fn companion_roots(alpha: &[f64]) -> Vec<Complex64> {
    let n = alpha.len();
    let mut companion = DMatrix::<f64>::zeros(n, n);
    for j in 0..n {
        companion[(0, j)] = -alpha[n - 1 - j];
    }
    for i in 1..n {
        companion[(i, i - 1)] = 1.0;
    }
    companion.complex_eigenvalues().iter().copied().collect()
}

/// `n` starting points: the roots of a lower order, then the rest spread on the circle of
/// their mean radius, at angles (2πk + 1)/extra: distinct, and none on the real axis.
fn warm_start(warm: &[Complex64], n: usize) -> Vec<Complex64> {
    debug_assert!(!warm.is_empty() && warm.len() < n);
    let radius = warm.iter().map(|z| z.norm()).sum::<f64>() / warm.len() as f64;
    let extra = n - warm.len();
    let spread =
        (0..extra).map(|k| Complex64::from_polar(radius, (TAU * k as f64 + 1.0) / extra as f64));
    warm.iter().copied().chain(spread).collect()
}

/// Sweeps of the Aberth–Ehrlich iteration before it gives up.
const MAX_SWEEPS: usize = 60;

/// The roots of z^n + α_{n−1}z^{n−1} + … + α_0 from the `n` distinct starting points `z`
/// by the Aberth–Ehrlich iteration (cubic near simple roots; each sweep O(n²)): each
/// z_i −= 1/(p′/p(z_i) − Σ_{j≠i} 1/(z_i − z_j)), the updated z_j used at once. A root is
/// done when its step is a few ulps of it, or p(z_i) is within the rounding error of
/// Horner's rule (the best any method resolves it). `None` if a root is not finite or they
/// are not all done within [`MAX_SWEEPS`].
fn aberth(alpha: &[f64], mut z: Vec<Complex64>) -> Option<Vec<Complex64>> {
    let n = alpha.len();
    debug_assert_eq!(z.len(), n);
    let mut done = vec![false; n];
    for _ in 0..MAX_SWEEPS {
        for i in 0..n {
            if done[i] {
                continue;
            }
            let zi = z[i];
            let r = zi.norm();
            // p, p′ and Σ|α_k||z|^k (the scale of p's rounding error) by Horner's rule.
            let (mut p, mut dp, mut scale) =
                (Complex64::new(1.0, 0.0), Complex64::new(0.0, 0.0), 1.0);
            for &a in alpha.iter().rev() {
                dp = dp * zi + p;
                p = p * zi + a;
                scale = scale * r + a.abs();
            }
            if !scale.is_finite() {
                return None; // |z|^n overflows
            }
            if p.norm_sqr() <= (4.0 * f64::EPSILON * scale).powi(2) {
                done[i] = true;
                continue;
            }
            let repulsion: Complex64 = z[..i]
                .iter()
                .chain(&z[i + 1..])
                .map(|&zj| {
                    // 1/d with one division.
                    let d = zi - zj;
                    d.conj() * d.norm_sqr().recip()
                })
                .sum();
            let step = (dp / p - repulsion).inv();
            z[i] = zi - step;
            if !z[i].is_finite() {
                return None;
            }
            done[i] = step.norm_sqr() <= (4.0 * f64::EPSILON).powi(2) * z[i].norm_sqr();
        }
        if done.iter().all(|&d| d) {
            return Some(z);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use msd_modal_core::modal::term;
    use msd_modal_core::synthetic::synthetic_frequency_response;

    #[test]
    fn two_exact_modes_give_their_poles_at_order_four() {
        let modes = [[TAU * 10.0, 0.02, 1.0, 0.0], [TAU * 23.0, 0.01, -0.5, 0.0]];
        let omega: Vec<f64> = (1..=500).map(|i| TAU * 0.1 * i as f64).collect();
        let h: Vec<Complex64> = omega
            .iter()
            .map(|&w| modes.iter().map(|m| term(m, w)).sum())
            .collect();
        let lines = Lines::uniform(omega, h);
        let lscf = Lscf::new(&lines, 8);
        let poles: Vec<Complex64> = lscf
            .roots(4, None)
            .expect("regular")
            .iter()
            .map(|z| z.ln() / lscf.dt())
            .collect();
        for m in &modes {
            let lambda = Complex64::new(-m[1] * m[0], m[0] * (1.0 - m[1] * m[1]).sqrt());
            let nearest = poles
                .iter()
                .map(|p| (p - lambda).norm())
                .fold(f64::INFINITY, f64::min);
            // The discrete-time model is not the continuous one exactly: close, not equal.
            assert!(nearest < 1e-3 * lambda.norm(), "{lambda}: {poles:?}");
        }
    }

    /// Five lightly damped modes (ζ 0.1 % to 1 %) in 1000 lines with 1 % noise from
    /// `seed`; the modal constants' signs alternate with the seed.
    fn noisy_lines(seed: u64) -> Lines {
        let modes = [
            (52.0, 1e-3),
            (142.0, 2e-3),
            (279.0, 4e-3),
            (460.0, 6e-3),
            (687.0, 1e-2),
        ];
        let sign = if seed.is_multiple_of(2) { 1.0 } else { -1.0 };
        let f: Vec<f64> = (1..=1000).map(f64::from).collect();
        let frf = synthetic_frequency_response(&f, 0.01, seed, |f| {
            let mut h = Complex64::new(0.0, 0.0);
            for (r, &(fn_hz, zeta)) in modes.iter().enumerate() {
                let a = 1e4 * if r % 2 == 0 { 1.0 } else { sign };
                h += term(&[TAU * fn_hz, zeta, a, 0.0], TAU * f);
            }
            h
        })
        .expect("a valid table");
        Lines::uniform(f.iter().map(|f| TAU * f).collect(), frf.h)
    }

    #[test]
    fn every_order_from_the_largest_orders_factor_is_its_own() {
        let lscf = Lscf::new(&noisy_lines(1), 120);
        assert!(lscf.w.is_some());
        let worst = (2..=120)
            .map(|n| {
                let reference = lscf.reduced_alone(n).expect("regular");
                (lscf.reduced(n).expect("regular") - &reference).norm() / reference.norm()
            })
            .fold(0.0, f64::max);
        eprintln!("largest relative difference {worst:e}");
        assert!(worst <= 1e-10, "{worst:e}");
    }

    #[test]
    fn without_a_factor_of_the_largest_order_each_order_is_factorised_alone() {
        // R tridiagonal, lags 1 and −0.55: its eigenvalues 1 − 1.1·cos(kπ/(n + 2)) are all
        // positive up to order 5 only.
        let max = 10;
        let mut r = vec![0.0; max + 1];
        (r[0], r[1]) = (1.0, -0.55);
        let t = (0..=max).map(|d| 0.5_f64.powi(d as i32)).collect();
        let s = (0..=2 * max).map(|d| (d as f64).sin()).collect();
        let lscf = Lscf::from_sums(r, t, s, max, 1.0);
        assert!(lscf.w.is_none());
        for n in 1..=max {
            assert_eq!(lscf.reduced(n).is_some(), n <= 5, "order {n}");
        }
        // Ten lines: R has rank 20 at most, singular at order 30 but not at the lowest.
        let all = noisy_lines(1);
        let (omega, h) = all.omega.iter().zip(&all.h).step_by(100).unzip();
        let lscf = Lscf::new(&Lines::uniform(omega, h), 30);
        assert!(lscf.w.is_none());
        assert!(lscf.reduced(2).is_some() && lscf.reduced(30).is_none());
        for n in 1..=30 {
            assert_eq!(lscf.reduced(n), lscf.reduced_alone(n), "order {n}");
        }
    }

    /// Over orders 2, 4, …, `max` of the denominators `alpha_at` gives, each order's
    /// roots refined from the order before's (as the diagram does) against the
    /// companion's, both ways nearest: the largest relative difference and the orders
    /// where the refinement failed.
    fn against_companion(max: usize, alpha_at: impl Fn(usize) -> Vec<f64>) -> (f64, Vec<usize>) {
        let nearest = |z: &Complex64, to: &[Complex64]| {
            to.iter()
                .map(|w| (z - w).norm() / w.norm())
                .fold(f64::INFINITY, f64::min)
        };
        let (mut worst, mut failed, mut previous) = (0.0_f64, Vec::new(), None::<Vec<Complex64>>);
        for n in (2..=max).step_by(2) {
            let alpha = alpha_at(n);
            let reference = companion_roots(&alpha);
            let refined = previous
                .as_ref()
                .and_then(|w| aberth(&alpha, warm_start(w, n)));
            if let Some(z) = &refined {
                for (a, b) in [(z, &reference), (&reference, z)] {
                    worst = a.iter().map(|x| nearest(x, b)).fold(worst, f64::max);
                }
            } else if previous.is_some() {
                failed.push(n);
            }
            previous = Some(refined.unwrap_or(reference));
        }
        (worst, failed)
    }

    #[test]
    fn warm_started_roots_are_the_companion_roots_at_every_order() {
        let (a, b) = (
            Lscf::new(&noisy_lines(1), 120),
            Lscf::new(&noisy_lines(2), 120),
        );
        let alone = |n: usize| denominator(a.reduced(n).expect("regular"), n).expect("regular");
        let summed = |n: usize| {
            let m = a.reduced(n).expect("regular") + b.reduced(n).expect("regular");
            denominator(m, n).expect("regular")
        };
        for (what, (worst, failed)) in [
            ("one response", against_companion(120, alone)),
            ("two summed", against_companion(120, summed)),
        ] {
            assert!(
                failed.is_empty(),
                "{what}: Aberth failed at orders {failed:?}"
            );
            assert!(worst < 1e-10, "{what}: roots differ by {worst:e}");
        }
    }

    #[test]
    fn a_failed_refinement_falls_back_to_the_companion_roots() {
        // A start where |z|^n overflows fails rather than freezing a root.
        let far = [Complex64::new(1e200, 1e200), Complex64::new(0.5, 0.5)];
        assert_eq!(aberth(&[2.0, -3.0, 1.0], warm_start(&far, 3)), None);
        let lscf = Lscf::new(&noisy_lines(1), 20);
        let m = lscf.reduced(20).expect("regular");
        let reference = companion_roots(&denominator(m.clone(), 20).expect("regular"));
        // Coincident starting points: 1/(z_i − z_j) is not finite.
        let bad = vec![Complex64::new(0.5, 0.5); 18];
        assert_eq!(roots_of(m.clone(), 20, Some(&bad)), Some(reference.clone()));
        assert_eq!(roots_of(m, 20, None), Some(reference));
    }
}
