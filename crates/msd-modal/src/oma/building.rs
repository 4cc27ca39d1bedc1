//! A shear building (a chain of floors on springs, fixed at the base) under white-noise
//! forces on every floor, its accelerations sampled exactly: the truth for testing and
//! teaching output-only analysis (pyOMA2's example is five floors of 25.91 kg on 10 kN/m,
//! ζ = 2 %).

use nalgebra::{DMatrix, DVector, SymmetricEigen};
use serde::{Deserialize, Serialize};

use super::record::{OutputRecord, accelerometer};
use msd_modal_core::error::{ModalError, Result};
use msd_modal_core::mode::Dof;

/// Floors of mass `masses[j]` (kg) on storeys of stiffness `stiffnesses[j]` (N/m, storey
/// j between floor j − 1 and floor j, floor −1 the ground), every mode damped at
/// `damping_ratio`.
///
/// ```
/// use msd_modal::ShearBuilding;
/// let building = ShearBuilding { masses: vec![25.91; 5], stiffnesses: vec![10_000.0; 5], damping_ratio: 0.02 };
/// let modes = building.modes()?;
/// // fn_j = (1/π)·√(k/m)·sin((2j − 1)π/22) for five equal floors.
/// let first = (10_000.0_f64 / 25.91).sqrt() / std::f64::consts::PI * (std::f64::consts::PI / 22.0).sin();
/// assert!((modes[0].0 / first - 1.0).abs() < 1e-12);
/// # Ok::<(), msd_modal::ModalError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShearBuilding {
    /// The floors' masses, kg, from the ground up.
    pub masses: Vec<f64>,
    /// The storeys' stiffnesses, N/m, from the ground up.
    pub stiffnesses: Vec<f64>,
    /// The damping ratio of every mode.
    pub damping_ratio: f64,
}

impl ShearBuilding {
    fn check(&self) -> Result<()> {
        let n = self.masses.len();
        if n == 0 || self.stiffnesses.len() != n {
            return Err(ModalError::LengthMismatch {
                what: "stiffnesses",
                expected: n.max(1),
                got: self.stiffnesses.len(),
            });
        }
        for (name, v) in self
            .masses
            .iter()
            .map(|&m| ("masses", m))
            .chain(self.stiffnesses.iter().map(|&k| ("stiffnesses", k)))
        {
            if !(v.is_finite() && v > 0.0) {
                return Err(ModalError::InvalidParameter {
                    name,
                    value: v,
                    expected: "positive, finite values",
                });
            }
        }
        if !(self.damping_ratio > 0.0 && self.damping_ratio < 1.0) {
            return Err(ModalError::InvalidParameter {
                name: "damping_ratio",
                value: self.damping_ratio,
                expected: "a ratio in (0, 1)",
            });
        }
        Ok(())
    }

    /// The undamped modes: fn (Hz), and the shape over the floors, largest entry 1; by
    /// frequency.
    pub fn modes(&self) -> Result<Vec<(f64, Vec<f64>)>> {
        self.check()?;
        let (phi, omega2) = self.mass_normalised()?;
        Ok((0..self.masses.len())
            .map(|j| {
                let shape: Vec<f64> = (0..self.masses.len()).map(|r| phi[(r, j)]).collect();
                let largest = shape
                    .iter()
                    .copied()
                    .fold(0.0_f64, |a, v| if v.abs() > a.abs() { v } else { a });
                (
                    omega2[j].sqrt() / std::f64::consts::TAU,
                    shape.iter().map(|v| v / largest).collect(),
                )
            })
            .collect())
    }

    /// The mass-normalised shapes Φ (ΦᵀMΦ = I) and ω², by frequency.
    fn mass_normalised(&self) -> Result<(DMatrix<f64>, Vec<f64>)> {
        let n = self.masses.len();
        let k = self.stiffness_matrix();
        let s = DVector::from_iterator(n, self.masses.iter().map(|m| m.sqrt().recip()));
        let scaled = DMatrix::from_fn(n, n, |r, c| s[r] * k[(r, c)] * s[c]);
        let eig = SymmetricEigen::new(scaled);
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
        let phi = DMatrix::from_fn(n, n, |r, c| s[r] * eig.eigenvectors[(r, order[c])]);
        Ok((phi, order.iter().map(|&j| eig.eigenvalues[j]).collect()))
    }

    fn stiffness_matrix(&self) -> DMatrix<f64> {
        let n = self.masses.len();
        let kk = &self.stiffnesses;
        DMatrix::from_fn(n, n, |r, c| {
            if r == c {
                kk[r] + if r + 1 < n { kk[r + 1] } else { 0.0 }
            } else if c == r + 1 {
                -kk[c]
            } else if r == c + 1 {
                -kk[r]
            } else {
                0.0
            }
        })
    }

    /// The floors' accelerations (channels `a1` … at DOFs `j:+1`) under independent
    /// white-noise forces of unit spectral density on every floor, held over each sample
    /// and integrated exactly; each channel then gets white noise of `noise_fraction` of
    /// its rms. `normal` draws standard normal numbers.
    pub fn ambient_record(
        &self,
        sample_rate_hz: f64,
        samples: usize,
        noise_fraction: f64,
        mut normal: impl FnMut() -> f64,
    ) -> Result<OutputRecord> {
        self.check()?;
        let n = self.masses.len();
        let (phi, omega2) = self.mass_normalised()?;
        let m = DMatrix::from_diagonal(&DVector::from_vec(self.masses.clone()));
        let modal = DMatrix::from_diagonal(&DVector::from_iterator(
            n,
            omega2.iter().map(|w2| 2.0 * self.damping_ratio * w2.sqrt()),
        ));
        let c = &m * &phi * modal * phi.transpose() * &m;
        let minv = DMatrix::from_diagonal(&DVector::from_iterator(
            n,
            self.masses.iter().map(|v| v.recip()),
        ));
        let (k_over_m, c_over_m) = (-&minv * self.stiffness_matrix(), -&minv * c);
        let dt = sample_rate_hz.recip();
        // exp([[A, B], [0, 0]]·dt) gives the exact step with the force held.
        let mut big = DMatrix::zeros(3 * n, 3 * n);
        for r in 0..n {
            big[(r, n + r)] = dt;
            for col in 0..n {
                big[(n + r, col)] = k_over_m[(r, col)] * dt;
                big[(n + r, n + col)] = c_over_m[(r, col)] * dt;
                big[(n + r, 2 * n + col)] = minv[(r, col)] * dt;
            }
        }
        let step = big.exp();
        let (ad, bd) = (
            step.view((0, 0), (2 * n, 2 * n)).into_owned(),
            step.view((0, 2 * n), (2 * n, n)).into_owned(),
        );
        let scale = (sample_rate_hz).sqrt(); // unit density: variance fs per held sample
        let mut x = DVector::zeros(2 * n);
        let mut out = vec![Vec::with_capacity(samples); n];
        for _ in 0..samples {
            let f = DVector::from_fn(n, |_, _| scale * normal());
            let acc = &k_over_m * x.rows(0, n) + &c_over_m * x.rows(n, n) + &minv * &f;
            for (r, o) in out.iter_mut().enumerate() {
                o.push(acc[r]);
            }
            x = &ad * &x + &bd * &f;
        }
        let channels = out
            .into_iter()
            .enumerate()
            .map(|(r, mut v)| {
                let rms = (v.iter().map(|a| a * a).sum::<f64>() / samples.max(1) as f64).sqrt();
                for a in &mut v {
                    *a += noise_fraction * rms * normal();
                }
                let dof = Dof {
                    node: r as u32 + 1,
                    direction: 1,
                };
                accelerometer(format!("a{}", r + 1), dof, v)
            })
            .collect();
        Ok(OutputRecord::new(sample_rate_hz, channels))
    }
}
