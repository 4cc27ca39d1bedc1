//! The harmonic content of a periodic record: the Fourier basis by recurrence, its Gram
//! matrix in closed form, the least-squares Fourier fit of a stroke and its force over
//! whole cycles, and the stroke frequency by the IEEE 1057 four-parameter sine fit.

use nalgebra::{DMatrix, DVector};

/// The basis row g = [1, cos θ, sin θ, cos 2θ, sin 2θ, …, cos Hθ, sin Hθ] at
/// θᵢ = ω·dt·i for i = 0, 1, 2, …: each harmonic's (cos hθ, sin hθ) rotated by h·ω·dt
/// from one sample to the next (independent rotations, so they vectorise), re-anchored
/// on `sin_cos` every 1024 samples so the rounding never grows past ~1e-13.
pub(crate) struct Basis {
    omega_dt: f64,
    /// (cos h·ω·dt, sin h·ω·dt), interleaved as the row.
    step: Vec<f64>,
    index: usize,
    values: Vec<f64>,
}

impl Basis {
    pub fn new(omega_dt: f64, harmonics: usize) -> Self {
        let mut step = vec![0.0; 2 * harmonics + 1];
        anchor(&mut step, omega_dt);
        Self {
            omega_dt,
            step,
            index: 0,
            values: vec![0.0; 2 * harmonics + 1],
        }
    }

    /// The row of the next sample (the first call gives sample 0).
    #[inline]
    pub fn next_row(&mut self) -> &[f64] {
        let i = self.index;
        self.index += 1;
        if i.is_multiple_of(1024) {
            anchor(&mut self.values, self.omega_dt * i as f64);
        } else {
            let pairs = self.values[1..].chunks_exact_mut(2);
            for (v, d) in pairs.zip(self.step[1..].chunks_exact(2)) {
                let (c, s) = (v[0], v[1]);
                v[0] = c * d[0] - s * d[1];
                v[1] = s * d[0] + c * d[1];
            }
        }
        &self.values
    }
}

/// row = [1, cos θ, sin θ, cos 2θ, sin 2θ, …] by `sin_cos`.
fn anchor(row: &mut [f64], theta: f64) {
    row[0] = 1.0;
    for (h, pair) in row[1..].chunks_exact_mut(2).enumerate() {
        let (s, c) = ((h + 1) as f64 * theta).sin_cos();
        pair[0] = c;
        pair[1] = s;
    }
}

/// GᵀG of the basis over samples 0..n at ω·dt = `phi`, from the Dirichlet sums
/// Σᵢ e^{i·q·φ·i} = e^{i·q·φ·(n−1)/2}·sin(n·q·φ/2)/sin(q·φ/2) (see [`from_sums`]):
/// O(H²) instead of O(n·H²). Needs q·φ/2 ∈ (0, π) for q = 1..2H, i.e. the H-th
/// harmonic below the Nyquist frequency.
pub(crate) fn gram(n: usize, phi: f64, harmonics: usize) -> DMatrix<f64> {
    let nf = n as f64;
    let mut sums = vec![nf; 4 * harmonics + 1];
    for q in 1..=2 * harmonics {
        let half = q as f64 * phi / 2.0;
        debug_assert!(half > 0.0 && half < std::f64::consts::PI, "q·φ/2 = {half}");
        let kernel = (nf * half).sin() / half.sin();
        let (s, c) = (half * (nf - 1.0)).sin_cos();
        sums[2 * q - 1] = c * kernel;
        sums[2 * q] = s * kernel;
    }
    from_sums(&sums, harmonics)
}

/// Σᵢ wᵢ·gᵢ·gᵢᵀ of the H-harmonic basis from the sums Σᵢ wᵢ·rᵢ of the 2H-harmonic rows r
/// (interleaved: Σw, Σw·cos qθ, Σw·sin qθ for q = 1..2H), by the product-to-sum
/// formulas cos a·cos b = ½(cos(a−b) + cos(a+b)), sin a·sin b = ½(cos(a−b) − cos(a+b)),
/// cos a·sin b = ½(sin(b+a) + sin(b−a)).
pub(crate) fn from_sums(sums: &[f64], harmonics: usize) -> DMatrix<f64> {
    debug_assert_eq!(sums.len(), 4 * harmonics + 1);
    // Signed lookups: cos is even, sin odd.
    let dq = |q: i64| match q.unsigned_abs() as usize {
        0 => sums[0],
        a => sums[2 * a - 1],
    };
    let eq = |q: i64| match q.unsigned_abs() as usize {
        0 => 0.0,
        a => q.signum() as f64 * sums[2 * a],
    };
    let width = 2 * harmonics + 1;
    DMatrix::from_fn(width, width, |r, col| {
        let (h, hc) = (r.div_ceil(2) as i64, col.div_ceil(2) as i64);
        let (rc, cc) = (r % 2 == 1, col % 2 == 1); // true: a cosine column
        match (r, col) {
            (0, 0) => sums[0],
            (0, _) => {
                if cc {
                    dq(hc)
                } else {
                    eq(hc)
                }
            }
            (_, 0) => {
                if rc {
                    dq(h)
                } else {
                    eq(h)
                }
            }
            _ => match (rc, cc) {
                (true, true) => 0.5 * (dq(h - hc) + dq(h + hc)),
                (false, false) => 0.5 * (dq(h - hc) - dq(h + hc)),
                (true, false) => 0.5 * (eq(hc + h) + eq(hc - h)),
                (false, true) => 0.5 * (eq(h + hc) + eq(h - hc)),
            },
        }
    })
}

/// The derivative in coefficient space: the coefficients of x′ are Q·θ for those θ of
/// x (harmonic h: a·cos + b·sin ↦ h·ω·b·cos − h·ω·a·sin); those of x″ are Q²·θ.
pub(crate) fn derivative(omega: f64, harmonics: usize) -> DMatrix<f64> {
    let width = 2 * harmonics + 1;
    let mut q = DMatrix::zeros(width, width);
    for h in 1..=harmonics {
        let w = h as f64 * omega;
        q[(2 * h - 1, 2 * h)] = w;
        q[(2 * h, 2 * h - 1)] = -w;
    }
    q
}

/// The Fourier fit of one condition's stroke and force over its whole cycles.
#[derive(Debug, Clone)]
pub(crate) struct HarmonicFit {
    /// ω, rad/s.
    pub omega: f64,
    /// (GᵀG)⁻¹: the coefficients' covariance per unit noise variance.
    pub gram_inverse: DMatrix<f64>,
    /// GᵀG.
    pub gram: DMatrix<f64>,
    /// θ of the stroke.
    pub stroke: DVector<f64>,
    /// θ of the force.
    pub force: DVector<f64>,
    /// σ̂ of the stroke about its fit, √(SSE/(n − 2H − 1)).
    pub stroke_sigma: f64,
    /// x̂, x̂′, x̂″ at every sample.
    pub displacement: Vec<f64>,
    pub velocity: Vec<f64>,
    pub acceleration: Vec<f64>,
}

impl HarmonicFit {
    /// Fits H harmonics of ω to `x` and `force` (equal lengths, whole cycles, H·ω·dt < π);
    /// `None` when GᵀG is singular.
    pub fn new(dt: f64, omega: f64, harmonics: usize, x: &[f64], force: &[f64]) -> Option<Self> {
        debug_assert_eq!(x.len(), force.len());
        let n = x.len();
        let width = 2 * harmonics + 1;
        let gram = gram(n, omega * dt, harmonics);
        let gram_inverse = gram.clone().cholesky()?.inverse();
        let (mut gx, mut gf) = (vec![0.0; width], vec![0.0; width]);
        let mut basis = Basis::new(omega * dt, harmonics);
        for (&xi, &fi) in x.iter().zip(force) {
            let g = basis.next_row();
            for ((gx, gf), &gj) in gx.iter_mut().zip(&mut gf).zip(g) {
                *gx += gj * xi;
                *gf += gj * fi;
            }
        }
        let stroke = &gram_inverse * DVector::from_vec(gx);
        let force = &gram_inverse * DVector::from_vec(gf);
        let q = derivative(omega, harmonics);
        let (dv, da) = (&q * &stroke, &q * &q * &stroke);
        let mut fit = Self {
            omega,
            gram_inverse,
            gram,
            stroke,
            force,
            stroke_sigma: 0.0,
            displacement: vec![0.0; n],
            velocity: vec![0.0; n],
            acceleration: vec![0.0; n],
        };
        let mut basis = Basis::new(omega * dt, harmonics);
        let mut sse = 0.0;
        let theta = fit.stroke.as_slice();
        let (dv, da) = (dv.as_slice(), da.as_slice());
        for (i, &xi) in x.iter().enumerate() {
            let g = basis.next_row();
            let (mut p, mut v, mut a) = (0.0, 0.0, 0.0);
            for (((g, t), dv), da) in g.iter().zip(theta).zip(dv).zip(da) {
                p += g * t;
                v += g * dv;
                a += g * da;
            }
            (fit.displacement[i], fit.velocity[i], fit.acceleration[i]) = (p, v, a);
            sse += (xi - p) * (xi - p);
        }
        fit.stroke_sigma = (sse / (n - width).max(1) as f64).sqrt();
        Some(fit)
    }

    /// The (cos, sin) coefficients of harmonic h ≥ 1 of the stroke and of the force.
    pub fn harmonic(&self, h: usize) -> ([f64; 2], [f64; 2]) {
        let (c, s) = (2 * h - 1, 2 * h);
        (
            [self.stroke[c], self.stroke[s]],
            [self.force[c], self.force[s]],
        )
    }
}

/// The stroke's frequency in Hz: a start from the upward zero crossings (with a
/// hysteresis of half the RMS, so noise near zero adds none), refined by the IEEE Std
/// 1057 four-parameter sine fit (Gauss–Newton in A, B, C and ω). `None` without two
/// upward crossings.
pub(crate) fn estimate_frequency(dt: f64, x: &[f64]) -> Option<f64> {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let rms = (x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n).sqrt();
    let band = 0.5 * rms;
    let (mut armed, mut pending, mut crossings) = (false, None, Vec::new());
    for (i, w) in x.windows(2).enumerate() {
        let (a, b) = (w[0] - mean, w[1] - mean);
        if b < -band {
            armed = true;
            pending = None;
        } else if armed && a < 0.0 && b >= 0.0 && pending.is_none() {
            pending = Some((i as f64 + a / (a - b)) * dt);
        } else if armed && b > band {
            crossings.extend(pending.take());
            armed = false;
        }
    }
    if crossings.len() < 2 {
        return None;
    }
    let (first, last) = (crossings[0], crossings[crossings.len() - 1]);
    let start = 2.0 * std::f64::consts::PI * (crossings.len() - 1) as f64 / (last - first);
    Some(four_parameter_fit(dt, x, start) / (2.0 * std::f64::consts::PI))
}

/// The share of a stroke's acceleration power in its fundamental, from five harmonics
/// fitted at its estimated frequency (harmonic h weighs h⁴ in acceleration; what the
/// five leave unexplained counts as a sixth): about 1 for a test machine's sine stroke
/// (a few per cent of distortion in the second harmonic, 2⁴ times more in acceleration,
/// still under 5 %), far less for a positioning move whose acceleration comes in pulses
/// or a stroke of several tones. `None` when the stroke has no frequency (fewer than two
/// upward crossings).
///
/// ```
/// let dt = 1e-3;
/// let sine: Vec<f64> = (0..5000).map(|i| 0.02 * (2.0 * std::f64::consts::PI * 3.0 * i as f64 * dt).sin()).collect();
/// assert!(msd_ident::dynamometer::fundamental_share(dt, &sine).unwrap() > 0.999);
/// ```
pub fn fundamental_share(dt: f64, x: &[f64]) -> Option<f64> {
    let f = estimate_frequency(dt, x)?;
    let omega = 2.0 * std::f64::consts::PI * f;
    let harmonics = (1..=5)
        .rev()
        .find(|&h| h as f64 * omega * dt < std::f64::consts::PI)?;
    let fit = HarmonicFit::new(dt, omega, harmonics, x, x)?;
    let power: Vec<f64> = (1..=harmonics)
        .map(|h| {
            let ([c, s], _) = fit.harmonic(h);
            (h as f64).powi(4) * (c * c + s * s)
        })
        .collect();
    // The unexplained part as an amplitude² (2·SSE/n), at the weight of a sixth harmonic.
    let n = x.len();
    let sse = fit.stroke_sigma.powi(2) * n.saturating_sub(2 * harmonics + 1) as f64;
    let rest = 6f64.powi(4) * 2.0 * sse / n as f64;
    let total: f64 = power.iter().sum::<f64>() + rest;
    (total > 0.0).then(|| power[0] / total)
}

/// IEEE 1057's four-parameter sine fit x ≈ A·cos ωt + B·sin ωt + C from ω₀: ω.
fn four_parameter_fit(dt: f64, x: &[f64], omega0: f64) -> f64 {
    let mut omega = omega0;
    for _ in 0..30 {
        // Linear A, B, C at this ω, then one Gauss–Newton step in all four.
        let mut basis = Basis::new(omega * dt, 1);
        let mut fit = [0.0; 3];
        let mut normal = nalgebra::Matrix3::zeros();
        let mut rhs = nalgebra::Vector3::zeros();
        for &xi in x {
            let g = basis.next_row();
            let row = nalgebra::Vector3::new(g[1], g[2], 1.0);
            normal += row * row.transpose();
            rhs += row * xi;
        }
        if let Some(sol) = normal.cholesky().map(|c| c.solve(&rhs)) {
            fit = [sol[0], sol[1], sol[2]];
        }
        let mut basis = Basis::new(omega * dt, 1);
        let mut normal = nalgebra::Matrix4::zeros();
        let mut rhs = nalgebra::Vector4::zeros();
        for (i, &xi) in x.iter().enumerate() {
            let g = basis.next_row();
            let t = i as f64 * dt;
            let dw = t * (-fit[0] * g[2] + fit[1] * g[1]);
            let row = nalgebra::Vector4::new(g[1], g[2], 1.0, dw);
            normal += row * row.transpose();
            rhs += row * (xi - fit[0] * g[1] - fit[1] * g[2] - fit[2]);
        }
        let Some(step) = normal.cholesky().map(|c| c.solve(&rhs)) else {
            break;
        };
        omega += step[3];
        if step[3].abs() <= 1e-13 * omega {
            break;
        }
    }
    omega
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_closed_form_gram_matrix_is_the_sum_over_the_basis_rows() {
        let (n, phi, h) = (1234, 0.0371, 5);
        let closed = gram(n, phi, h);
        let mut summed = DMatrix::zeros(2 * h + 1, 2 * h + 1);
        let mut basis = Basis::new(phi, h);
        for i in 0..n {
            let g = DVector::from_column_slice(basis.next_row());
            let exact: Vec<f64> = (0..=2 * h)
                .map(|j| {
                    let k = j.div_ceil(2) as f64 * phi * i as f64;
                    match j {
                        0 => 1.0,
                        _ if j % 2 == 1 => k.cos(),
                        _ => k.sin(),
                    }
                })
                .collect();
            for (a, b) in g.iter().zip(&exact) {
                assert!((a - b).abs() < 1e-12, "sample {i}: {a} vs {b}");
            }
            summed += &g * g.transpose();
        }
        let err = (&closed - &summed).abs().max();
        assert!(err < 1e-9, "{err}");
    }

    #[test]
    fn weighted_sums_of_the_doubled_basis_give_the_weighted_gram_matrix() {
        let (n, phi, h) = (777, 0.05, 4);
        let (mut sums, mut direct) = (vec![0.0; 4 * h + 1], DMatrix::zeros(2 * h + 1, 2 * h + 1));
        let mut basis = Basis::new(phi, 2 * h);
        for i in 0..n {
            let r = basis.next_row();
            let w = (0.3 * i as f64).sin().abs() + 0.1;
            sums.iter_mut().zip(r).for_each(|(s, r)| *s += w * r);
            let g = DVector::from_column_slice(&r[..2 * h + 1]);
            direct += &g * g.transpose() * w;
        }
        let err = (from_sums(&sums, h) - direct).abs().max();
        assert!(err < 1e-10, "{err}");
    }

    #[test]
    fn the_four_parameter_fit_finds_the_frequency_of_a_clean_sine() {
        let (dt, f) = (1e-3, 3.21);
        let x: Vec<f64> = (0..2000)
            .map(|i| 0.3 + 0.02 * (2.0 * std::f64::consts::PI * f * i as f64 * dt + 0.4).sin())
            .collect();
        let estimate = estimate_frequency(dt, &x).unwrap();
        assert!((estimate / f - 1.0).abs() < 1e-10, "{estimate}");
    }
}
