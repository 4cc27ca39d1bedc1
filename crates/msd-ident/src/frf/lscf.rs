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
//! β leaves M = T − SᵀR⁻¹S; with α_n = 1, α solves the first n rows of M·α = 0. The
//! roots z_r of D (eigenvalues of its companion matrix) are the poles λ_r = ln(z_r)/Δt.

use msd_signal::Complex64;
use nalgebra::{DMatrix, DVector};

use super::lines::Lines;

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
        Self {
            r,
            t,
            s,
            max_order,
            dt,
        }
    }

    /// The continuous-time poles of the order-`n` denominator (n ≤ the largest order);
    /// `None` if its normal equations are singular.
    pub(crate) fn poles(&self, n: usize) -> Option<Vec<Complex64>> {
        poles_of(self.reduced(n)?, n, self.dt)
    }

    /// The reduced normal matrix M = T − SᵀR⁻¹S of order `n` ((n + 1) × (n + 1));
    /// `None` if R is singular.
    pub(crate) fn reduced(&self, n: usize) -> Option<DMatrix<f64>> {
        debug_assert!((1..=self.max_order).contains(&n));
        let size = n + 1;
        let lag = |i: usize, j: usize| i.abs_diff(j);
        let r = DMatrix::from_fn(size, size, |i, j| self.r[lag(i, j)]);
        let t = DMatrix::from_fn(size, size, |i, j| self.t[lag(i, j)]);
        let s = DMatrix::from_fn(size, size, |i, j| self.s[self.max_order + j - i]);
        let r_inv_s = r.cholesky()?.solve(&s);
        Some(t - s.transpose() * r_inv_s)
    }

    /// The sampling step Δt = π/ω_max of the z-domain model.
    pub(crate) fn dt(&self) -> f64 {
        self.dt
    }
}

/// The poles of the order-`n` common denominator whose reduced normal matrix (summed
/// over the frequency responses that share it) is `m`: with α_n = 1, α solves the first
/// n rows of M·α = 0; `None` if they are singular.
pub(crate) fn poles_of(m: DMatrix<f64>, n: usize, dt: f64) -> Option<Vec<Complex64>> {
    let rhs = -m.view((0, n), (n, 1)).clone_owned();
    let alpha: DVector<f64> = m
        .view((0, 0), (n, n))
        .clone_owned()
        .cholesky()?
        .solve(&rhs)
        .column(0)
        .into_owned();
    // Companion matrix of z^n + α_{n−1}z^{n−1} + … + α_0.
    let mut companion = DMatrix::<f64>::zeros(n, n);
    for j in 0..n {
        companion[(0, j)] = -alpha[n - 1 - j];
    }
    for i in 1..n {
        companion[(i, i - 1)] = 1.0;
    }
    let roots = companion.complex_eigenvalues();
    Some(roots.iter().map(|z| z.ln() / dt).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frf::modal::term;
    use std::f64::consts::TAU;

    #[test]
    fn two_exact_modes_give_their_poles_at_order_four() {
        let modes = [[TAU * 10.0, 0.02, 1.0, 0.0], [TAU * 23.0, 0.01, -0.5, 0.0]];
        let omega: Vec<f64> = (1..=500).map(|i| TAU * 0.1 * i as f64).collect();
        let h: Vec<Complex64> = omega
            .iter()
            .map(|&w| modes.iter().map(|m| term(m, w)).sum())
            .collect();
        let lines = Lines::for_tests(omega, h);
        let lscf = Lscf::new(&lines, 8);
        let poles = lscf.poles(4).expect("regular");
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
}
