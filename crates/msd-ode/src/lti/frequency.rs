//! The exact simulator's frequency response: what its recurrence does to each line of
//! a record's DFT.

use super::{CUBIC_CENTRED, ExactSimulator, Hold, LINEAR, STENCILS, ZERO, lagrange_monomials};
use nalgebra::{Complex, SVector};
use std::sync::LazyLock;

impl<const N: usize> ExactSimulator<N> {
    /// The sampled system's frequency response: the state's response to the input at
    /// z = e^{iω·dt}, X(z)/U(z) = (zI − Φ)⁻¹·Σ_m W_m·z^{o_m}, with W_m the weights of the
    /// hold's interior stencil and o_m its nodes' offsets from the step's start. It is
    /// the DFT of the simulated response to one unit input sample (placed where no
    /// one-sided stencil reaches it), so a record's DFT is X(z)·U(z) plus the terms its
    /// ends leave. `None` where zI − Φ is singular (z an eigenvalue of Φ).
    ///
    /// ```
    /// use msd_ode::{Complex, ExactSimulator, Hold, LtiModel, SMatrix, SVector};
    /// let (m, c, k, dt) = (2.5, 1.8, 120.0, 0.002);
    /// let model = LtiModel {
    ///     a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -k / m, -c / m),
    ///     b: SVector::<f64, 2>::new(0.0, 1.0 / m),
    /// };
    /// let sim = ExactSimulator::new(&model, dt, Hold::Cubic)?;
    /// // At 1 Hz the displacement's response is the plant's 1/(k − mω² + icω).
    /// let w = 2.0 * std::f64::consts::PI;
    /// let x = sim.frequency_response(Complex::from_polar(1.0, w * dt)).unwrap();
    /// let plant = Complex::new(k - m * w * w, c * w).inv();
    /// assert!((x[0] - plant).norm() < 1e-6 * plant.norm());
    /// # Ok::<(), msd_ode::OdeError>(())
    /// ```
    pub fn frequency_response(&self, z: Complex<f64>) -> Option<SVector<Complex<f64>, N>> {
        self.resolvent(z)?.frequency_response()
    }

    /// The DFT of a simulated record's states at a line z of its n-point DFT (zⁿ = 1),
    /// in closed form: Σ_{t<n} x_t·z⁻ᵗ = (I − Φ/z)⁻¹·(x₀ − Φ·x_{n−1} + Σⱼ Γⱼ·Mⱼ(z)),
    /// with x₀ the initial state, x_{n−1} the last (from the simulation, or any other
    /// way), Γⱼ the state's response over one step to the input sʲ and
    /// Mⱼ(z) = Σ_{t=1}^{n−1} aⱼ(t)·z⁻ᵗ the DFT of the hold's j-th coefficient on the step
    /// into sample t ([`SampledInput::hold_polynomials`](crate::SampledInput::hold_polynomials), entry t − 1). The record's
    /// ends and breakpoints are in the Mⱼ: the identity is exact, where the DFT of an
    /// input times [`frequency_response`](Self::frequency_response) leaves the
    /// transient out. The Mⱼ do not depend on the model, so a fit that moves the model
    /// transforms its input once and each state sequence costs one 2 × 2 solve per line
    /// instead of a simulation and an FFT. `None` where zI − Φ is singular.
    ///
    /// ```
    /// use msd_ode::{Complex, ExactSimulator, Hold, LtiModel, SampledInput, SMatrix, SVector};
    /// let model = LtiModel {
    ///     a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -48.0, -0.72),
    ///     b: SVector::<f64, 2>::new(0.0, 0.4),
    /// };
    /// let sim = ExactSimulator::new(&model, 0.05, Hold::Cubic)?;
    /// let u: Vec<f64> = (0..40).map(|t| (0.3 * t as f64).sin()).collect();
    /// let input = SampledInput::smooth(&u);
    /// let x0 = SVector::<f64, 2>::new(0.01, -0.2);
    /// let states = sim.simulate(&x0, &input)?;
    /// let holds = input.hold_polynomials(Hold::Cubic)?;
    /// let z = Complex::from_polar(1.0, 2.0 * std::f64::consts::PI * 3.0 / 40.0);
    /// let dft = |f: &dyn Fn(usize) -> f64, from: usize| -> Complex<f64> {
    ///     (from..40).map(|t| f(t) * z.powi(-(t as i32))).sum()
    /// };
    /// let m: [Complex<f64>; 4] = std::array::from_fn(|j| dft(&|t| holds[t - 1][j], 1));
    /// let closed = sim.state_spectrum(z, &x0, &states[39], &m).unwrap();
    /// for i in 0..2 {
    ///     let direct = dft(&|t| states[t][i], 0);
    ///     assert!((closed[i] - direct).norm() < 1e-12 * direct.norm(), "{closed} {direct}");
    /// }
    /// # Ok::<(), msd_ode::OdeError>(())
    /// ```
    pub fn state_spectrum(
        &self,
        z: Complex<f64>,
        x0: &SVector<f64, N>,
        last: &SVector<f64, N>,
        hold: &[Complex<f64>; 4],
    ) -> Option<SVector<Complex<f64>, N>> {
        self.resolvent(z)?.state_spectrum(x0, last, hold)
    }

    /// (zI − Φ) at the line z, ready to solve: one line's [`frequency_response`],
    /// [`state_spectrum`] and any other (zI − Φ)⁻¹·b from one factorisation
    /// ([`Resolvent`]). `None` where zI − Φ is singular (for N = 2; larger systems
    /// find it when they solve).
    ///
    /// [`frequency_response`]: Self::frequency_response
    /// [`state_spectrum`]: Self::state_spectrum
    ///
    /// ```
    /// use msd_ode::{Complex, ExactSimulator, Hold, LtiModel, SMatrix, SVector};
    /// let model = LtiModel {
    ///     a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -48.0, -0.72),
    ///     b: SVector::<f64, 2>::new(0.0, 0.4),
    /// };
    /// let sim = ExactSimulator::new(&model, 0.05, Hold::Cubic)?;
    /// let z = Complex::from_polar(1.0, 0.3);
    /// let line = sim.resolvent(z).unwrap();
    /// assert_eq!(line.frequency_response(), sim.frequency_response(z));
    /// // (zI − Φ)·x = b for any b.
    /// let b = [Complex::new(1.0, -2.0), Complex::new(0.5, 0.0)];
    /// let x = line.solve(b).unwrap();
    /// let back = (SMatrix::<Complex<f64>, 2, 2>::identity() * z - sim.transition().cast()) * x;
    /// assert!((back - SVector::from(b)).norm() < 1e-12);
    /// # Ok::<(), msd_ode::OdeError>(())
    /// ```
    pub fn resolvent(&self, z: Complex<f64>) -> Option<Resolvent<'_, N>> {
        let shifted: [[Complex<f64>; N]; N] = std::array::from_fn(|r| {
            std::array::from_fn(|c| {
                let diagonal = if r == c { z } else { Complex::new(0.0, 0.0) };
                diagonal - self.phi[(r, c)]
            })
        });
        let mut scale = Complex::new(0.0, 0.0);
        if N == 2 {
            // The adjugate: one division where elimination takes three.
            let det = shifted[0][0] * shifted[1][1] - shifted[0][1] * shifted[1][0];
            if det.l1_norm() == 0.0 {
                return None;
            }
            scale = det.inv();
        }
        Some(Resolvent {
            sim: self,
            z,
            shifted,
            scale,
        })
    }
}

/// zI − Φ at one line z of a sampled system ([`ExactSimulator::resolvent`]), with its
/// determinant's inverse for N = 2: each (zI − Φ)⁻¹·b at the line costs a few products.
#[derive(Debug, Clone, Copy)]
pub struct Resolvent<'a, const N: usize> {
    sim: &'a ExactSimulator<N>,
    z: Complex<f64>,
    shifted: [[Complex<f64>; N]; N],
    /// 1 / det(zI − Φ) for N = 2 (unused otherwise).
    scale: Complex<f64>,
}

impl<const N: usize> Resolvent<'_, N> {
    /// The line's point z.
    pub fn z(&self) -> Complex<f64> {
        self.z
    }

    /// (zI − Φ)⁻¹·`b`; `None` where zI − Φ is singular.
    pub fn solve(&self, b: [Complex<f64>; N]) -> Option<SVector<Complex<f64>, N>> {
        if N == 2 {
            let s = &self.shifted;
            let (a, b01, c, d) = (s[0][0], s[0][1], s[1][0], s[1][1]);
            let mut x = SVector::<Complex<f64>, N>::zeros();
            x[0] = (d * b[0] - b01 * b[1]) * self.scale;
            x[1] = (a * b[1] - c * b[0]) * self.scale;
            return Some(x);
        }
        solve(self.shifted, b).map(SVector::from)
    }

    /// [`ExactSimulator::frequency_response`] at this line.
    pub fn frequency_response(&self) -> Option<SVector<Complex<f64>, N>> {
        let (z, variant) = (self.z, interior(self.sim.hold));
        let w = &self.sim.weights[variant];
        let mut drive = [Complex::new(0.0, 0.0); N];
        for (node, power) in stencil_powers(z, variant).enumerate() {
            for (d, weight) in drive.iter_mut().zip(&w[node]) {
                *d += power * *weight;
            }
        }
        self.solve(drive)
    }

    /// (zI − Φ)⁻¹·Σⱼ Γⱼ·mⱼ: the state's response at this line to an input whose hold
    /// coefficients have the transforms `m`. With [`Hold::interior_transforms`] it is
    /// the frequency response; a fit that visits the same lines at many models takes
    /// those once.
    pub fn held_response(&self, m: &[Complex<f64>; 4]) -> Option<SVector<Complex<f64>, N>> {
        self.solve(std::array::from_fn(|r| {
            (self.sim.gamma.iter().zip(m)).map(|(g, m)| m * g[r]).sum()
        }))
    }

    /// [`ExactSimulator::state_spectrum`] at this line.
    pub fn state_spectrum(
        &self,
        x0: &SVector<f64, N>,
        last: &SVector<f64, N>,
        hold: &[Complex<f64>; 4],
    ) -> Option<SVector<Complex<f64>, N>> {
        let end = self.sim.phi * last;
        // z·(x₀ − Φ·x_{n−1} + Σⱼ Γⱼ·Mⱼ), then (zI − Φ)⁻¹ of it.
        let drive: [Complex<f64>; N] = std::array::from_fn(|r| {
            let held: Complex<f64> = (self.sim.gamma.iter().zip(hold))
                .map(|(g, m)| m * g[r])
                .sum();
            self.z * (held + (x0[r] - end[r]))
        });
        self.solve(drive)
    }
}

impl Hold {
    /// The transforms Pⱼ(z) = Σ_m ℓ_{m,j}·z^{o_m} of the interior stencil's monomial
    /// coefficients (o_m its nodes' offsets from the step's start, ℓ_{m,j} the
    /// coefficient of sʲ in node m's Lagrange polynomial): what one unit input sample
    /// contributes to each Mⱼ at the line z, whatever the model. The sampled system's
    /// drive at z is Σⱼ Γⱼ·Pⱼ(z) ([`Resolvent::held_response`]).
    ///
    /// ```
    /// use msd_ode::{Complex, Hold};
    /// // A zero-order hold holds the sample: only the constant term, at every line.
    /// let z = Complex::from_polar(1.0, 0.7);
    /// assert_eq!(Hold::Zero.interior_transforms(z)[0], Complex::new(1.0, 0.0));
    /// // A first-order hold's slope is the next sample less this one: z − 1.
    /// assert!((Hold::First.interior_transforms(z)[1] - (z - 1.0)).norm() < 1e-15);
    /// ```
    pub fn interior_transforms(self, z: Complex<f64>) -> [Complex<f64>; 4] {
        // Every variant's Lagrange basis, taken once.
        static BASES: LazyLock<[[[f64; 4]; 4]; 7]> =
            LazyLock::new(|| std::array::from_fn(|variant| lagrange_monomials(STENCILS[variant])));
        let variant = interior(self);
        let basis = &BASES[variant];
        let mut out = [Complex::new(0.0, 0.0); 4];
        for (node, power) in stencil_powers(z, variant).enumerate() {
            for (p, l) in out.iter_mut().zip(&basis[node]) {
                *p += power * *l;
            }
        }
        out
    }
}

/// The stencil variant a hold uses away from breakpoints and the record's ends.
fn interior(hold: Hold) -> usize {
    match hold {
        Hold::Zero => ZERO,
        Hold::First => LINEAR,
        Hold::Cubic => CUBIC_CENTRED,
    }
}

/// z^{o_m} for each node m of the stencil `variant`.
fn stencil_powers(z: Complex<f64>, variant: usize) -> impl Iterator<Item = Complex<f64>> {
    // The stencils' offsets run from −2 to 3; z⁻¹ only where one is negative.
    let inverse = if z.norm_sqr() > 0.0 { z.inv() } else { z };
    STENCILS[variant]
        .iter()
        .map(move |&offset| match offset as i32 {
            0 => Complex::new(1.0, 0.0),
            o if o > 0 => z.powu(o as u32),
            o => inverse.powu(o.unsigned_abs()),
        })
}

/// x with a·x = b by Gaussian elimination with partial pivoting; `None` where `a` is
/// singular.
fn solve<const N: usize>(
    mut a: [[Complex<f64>; N]; N],
    mut b: [Complex<f64>; N],
) -> Option<[Complex<f64>; N]> {
    for col in 0..N {
        // Pivots by |re| + |im|: as good a choice as the modulus, without its hypot.
        let size = |i: usize| a[i][col].l1_norm();
        let pivot = (col..N).max_by(|&i, &j| size(i).total_cmp(&size(j)))?;
        if size(pivot) == 0.0 {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        let (pivot_row, b_pivot) = (a[col], b[col]);
        for (row, b_row) in a.iter_mut().zip(b.iter_mut()).skip(col + 1) {
            let factor = row[col] / pivot_row[col];
            for (v, p) in row.iter_mut().zip(&pivot_row).skip(col) {
                *v -= factor * p;
            }
            *b_row -= factor * b_pivot;
        }
    }
    for row in (0..N).rev() {
        let tail: Complex<f64> = (row + 1..N).map(|k| a[row][k] * b[k]).sum();
        b[row] = (b[row] - tail) / a[row][row];
    }
    Some(b)
}
