//! The exact simulator's frequency response: what its recurrence does to each line of
//! a record's DFT.

use super::{CUBIC_CENTRED, ExactSimulator, Hold, LINEAR, STENCILS, ZERO};
use nalgebra::{Complex, SVector};

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
        let variant = match self.hold {
            Hold::Zero => ZERO,
            Hold::First => LINEAR,
            Hold::Cubic => CUBIC_CENTRED,
        };
        let w = &self.weights[variant];
        let mut drive = [Complex::new(0.0, 0.0); N];
        // The stencils' offsets run from −2 to 3; z⁻¹ only where one is negative.
        let inverse = if z.norm_sqr() > 0.0 { z.inv() } else { z };
        for (node, &offset) in STENCILS[variant].iter().enumerate() {
            let power = match offset as i32 {
                0 => Complex::new(1.0, 0.0),
                o if o > 0 => z.powu(o as u32),
                o => inverse.powu(o.unsigned_abs()),
            };
            for (d, weight) in drive.iter_mut().zip(&w[node]) {
                *d += power * *weight;
            }
        }
        let shifted: [[Complex<f64>; N]; N] = std::array::from_fn(|r| {
            std::array::from_fn(|c| {
                let diagonal = if r == c { z } else { Complex::new(0.0, 0.0) };
                diagonal - self.phi[(r, c)]
            })
        });
        if N == 2 {
            // The adjugate: one division where elimination takes three.
            let (a, b, c, d) = (shifted[0][0], shifted[0][1], shifted[1][0], shifted[1][1]);
            let det = a * d - b * c;
            if det.l1_norm() == 0.0 {
                return None;
            }
            let scale = det.inv();
            let mut x = SVector::<Complex<f64>, N>::zeros();
            x[0] = (d * drive[0] - b * drive[1]) * scale;
            x[1] = (a * drive[1] - c * drive[0]) * scale;
            return Some(x);
        }
        solve(shifted, drive).map(SVector::from)
    }
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
