//! A chain of masses (M, C, K), one to eight, as a lab's two-storey rig or tuned mass
//! damper: the setup (a force on any mass or the base's acceleration; displacement,
//! velocity or acceleration sensors with delays and low-pass filters), its exact
//! simulation ([`simulate_chain`]), the fit of every m, c, k from measured records with
//! intervals and modes ([`fit_chain`]), the Cramér–Rao prediction for planning
//! ([`predict_chain`]); and [`ChainPlant`]: the receptance, modes and response of a chain
//! for the frequency-response sources that simulate one.

mod fit;
mod identifiable;
mod model;
mod modes;
mod noise;
mod plan;
mod problem;
mod setup;
mod simulate;
mod uncertainty;
mod validate;

pub use fit::{
    CUTOFF_NOT_SEPARATED, ChainFit, ChainOptions, GROUND_AT_ZERO, GROUND_NOT_IN_RECORDS, fit_chain,
};
pub use plan::predict_chain;
pub use setup::{
    ChainDrive, ChainParameters, ChainSensor, ChainSetup, LowPass, level_out_of_range,
};
pub use setup::{LEVELS, MAX_MASSES};
pub use uncertainty::{ChainIntervals, ChainUncertainty};
pub use validate::{ChainPrediction, ChainValidation, hold_out_chain};

use msd_modal_core::ModalParameters;
use msd_signal::{Complex64, FrfKind, ResponseQuantity};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// A chain of masses fixed to the ground at one end: spring and damper i join mass i to
/// mass i − 1 (the first to the ground). One mass is the single-degree-of-freedom plant.
///
/// ```
/// use msd_ident::chain::ChainPlant;
/// let plant = ChainPlant { masses: vec![2.0, 1.0], springs: vec![2e4, 1e4], dampers: vec![4.0, 2.0],
///     force_at: 2, response_at: 2 };
/// assert_eq!(plant.modes().len(), 2);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChainPlant {
    /// Masses, kg (> 0), from the ground out; 1 to 8 of them.
    pub masses: Vec<f64>,
    /// Stiffnesses, N/m (> 0), one per mass.
    pub springs: Vec<f64>,
    /// Viscous dampers, N·s/m (≥ 0), one per mass.
    pub dampers: Vec<f64>,
    /// The mass the force acts on, numbered from 1 at the ground. By default 1.
    #[serde(default = "first")]
    pub force_at: usize,
    /// The mass whose displacement is measured. By default 1.
    #[serde(default = "first")]
    pub response_at: usize,
}

fn first() -> usize {
    1
}

impl ChainPlant {
    /// One mass on a spring and a damper to the ground, force and response on it: the
    /// single-degree-of-freedom plant m·x″ + c·x′ + k·x = F.
    ///
    /// ```
    /// use msd_ident::chain::ChainPlant;
    /// let plant = ChainPlant::one_mass(2.5, 1.8, 120.0);
    /// assert_eq!((plant.len(), plant.force_at, plant.response_at), (1, 1, 1));
    /// assert_eq!(plant.springs, [120.0]);
    /// ```
    pub fn one_mass(mass: f64, damping: f64, stiffness: f64) -> Self {
        Self {
            masses: vec![mass],
            springs: vec![stiffness],
            dampers: vec![damping],
            force_at: 1,
            response_at: 1,
        }
    }

    /// The number of masses.
    pub fn len(&self) -> usize {
        self.masses.len()
    }

    /// Whether the chain has no mass (a validated plant has at least one).
    pub fn is_empty(&self) -> bool {
        self.masses.is_empty()
    }

    /// The mass, damping and stiffness matrices M, C, K: spring and damper i join mass
    /// i to mass i − 1, the first to the ground.
    pub(crate) fn matrices(&self) -> [DMatrix<f64>; 3] {
        let chain = model::chain_matrix;
        [
            DMatrix::from_diagonal(&self.masses.clone().into()),
            chain(&self.dampers),
            chain(&self.springs),
        ]
    }

    /// The dynamic stiffness Z(s) = M s² + C s + K.
    fn dynamic_stiffness(&self, s: Complex64) -> DMatrix<Complex64> {
        let [m, c, k] = self.matrices();
        DMatrix::from_fn(self.len(), self.len(), |i, j| {
            s * s * m[(i, j)] + s * c[(i, j)] + k[(i, j)]
        })
    }

    /// The receptance x_response/F_force at `frequency_hz`: the response column of
    /// Z(jω)⁻¹ at the force's row.
    ///
    /// ```
    /// use msd_ident::chain::ChainPlant;
    /// let plant = ChainPlant { masses: vec![2.5], springs: vec![120.0], dampers: vec![1.8],
    ///     force_at: 1, response_at: 1 };
    /// let w = std::f64::consts::TAU * 0.7;
    /// let direct = 1.0 / msd_signal::Complex64::new(120.0 - 2.5 * w * w, 1.8 * w);
    /// assert!((plant.receptance(0.7) - direct).norm() < 1e-15);
    /// ```
    pub fn receptance(&self, frequency_hz: f64) -> Complex64 {
        let z = self.dynamic_stiffness(Complex64::new(0.0, TAU * frequency_hz));
        let mut force = nalgebra::DVector::zeros(self.len());
        force[self.force_at - 1] = Complex64::new(1.0, 0.0);
        z.lu()
            .solve(&force)
            .map_or(Complex64::new(f64::NAN, f64::NAN), |x| {
                x[self.response_at - 1]
            })
    }

    /// The plant's modes, by frequency: each pole λ (Im λ > 0) among the eigenvalues of
    /// the state matrix, with fn = |λ|/2π, ζ = −Re λ/|λ| and the modal constant of the
    /// receptance from the residue R = adj Z(λ)[response, force] / (d det Z/ds)(λ) as
    /// A = −2·Re(R·λ̄), B = 2·ωn·Re R (see [`ModalParameters`]). Overdamped (real) poles
    /// are not modes and are left out.
    ///
    /// ```
    /// use msd_ident::chain::ChainPlant;
    /// let plant = ChainPlant { masses: vec![2.5], springs: vec![120.0], dampers: vec![1.8],
    ///     force_at: 1, response_at: 1 };
    /// let modes = plant.modes();
    /// assert_eq!(modes.len(), 1);
    /// assert!((modes[0].natural_frequency_hz - (120.0f64 / 2.5).sqrt() / std::f64::consts::TAU).abs() < 1e-12);
    /// assert!((modes[0].modal_constant - 1.0 / 2.5).abs() < 1e-12);
    /// ```
    pub fn modes(&self) -> Vec<ModalParameters> {
        self.poles().iter().map(|&l| self.mode_of(l)).collect()
    }

    /// The underdamped poles λ (Im λ > 0) of the state matrix, by |λ|.
    pub(crate) fn poles(&self) -> Vec<Complex64> {
        let [m, c, k] = self.matrices();
        underdamped_poles(&state_matrix(&m, &c, &k))
    }

    /// The mode of pole `lambda`.
    fn mode_of(&self, lambda: Complex64) -> ModalParameters {
        let z = self.dynamic_stiffness(lambda);
        let [m, c, _] = self.matrices();
        let dz = DMatrix::from_fn(self.len(), self.len(), |i, j| {
            lambda * m[(i, j)] * 2.0 + c[(i, j)]
        });
        // Jacobi: d det Z = Σ_j det(Z with column j differentiated).
        let derivative: Complex64 = (0..self.len())
            .map(|j| {
                let mut zj = z.clone();
                zj.set_column(j, &dz.column(j));
                zj.determinant()
            })
            .sum();
        let (r, f) = (self.response_at - 1, self.force_at - 1);
        let minor = z.clone().remove_row(f).remove_column(r);
        let sign = if (r + f) % 2 == 0 { 1.0 } else { -1.0 };
        let cofactor = if self.len() == 1 {
            Complex64::new(1.0, 0.0)
        } else {
            minor.determinant() * sign
        };
        let residue = cofactor / derivative;
        let wn = lambda.norm();
        ModalParameters {
            natural_frequency_hz: wn / TAU,
            damping_ratio: -lambda.re / wn,
            modal_constant: -2.0 * (residue * lambda.conj()).re,
            modal_constant_imaginary: 2.0 * wn * residue.re,
        }
    }

    /// The response to the force samples `force` (N, every `dt` s, the force linear
    /// between samples), from rest, as the quantity of `kind`: the displacement
    /// (receptance), velocity (mobility) or acceleration (accelerance) of the response
    /// mass. Exact for a force linear between samples (the state equations augmented
    /// with the force and its slope, advanced by one matrix exponential per step; the
    /// acceleration is the state equation's row, a = (A·x + B·F)[n + response]). It is [`simulate_chain`] with one
    /// ideal sensor: the chain's one simulator. Errors: those of `simulate_chain` (a
    /// non-finite force, a bad dt or plant).
    ///
    /// ```
    /// use msd_ident::chain::ChainPlant;
    /// use msd_signal::FrfKind;
    /// let plant = ChainPlant::one_mass(2.5, 1.8, 120.0);
    /// // A constant 1 N from rest: x ≈ 0, x″ = F/m at the first instant.
    /// let a = plant.sampled_response(&[1.0; 3], 1e-3, FrfKind::Accelerance)?;
    /// assert!((a[0] - 1.0 / 2.5).abs() < 1e-15);
    /// let x = plant.sampled_response(&[1.0; 3], 1e-3, FrfKind::Receptance)?;
    /// assert_eq!(x[0], 0.0);
    /// // ½·(F/m)·t², to a relative (c/m)·t/3 ≈ 2e-4 (the next term of the series).
    /// assert!((x[1] / (0.5 * 1e-6 / 2.5) - 1.0).abs() < 1e-3);
    /// # Ok::<(), msd_ident::IdentError>(())
    /// ```
    pub fn sampled_response(
        &self,
        force: &[f64],
        dt: f64,
        kind: FrfKind,
    ) -> crate::error::Result<Vec<f64>> {
        let quantity = match kind {
            FrfKind::Receptance => ResponseQuantity::Displacement,
            FrfKind::Mobility => ResponseQuantity::Velocity,
            FrfKind::Accelerance => ResponseQuantity::Acceleration,
        };
        let setup = ChainSetup {
            masses: self.len(),
            drive: ChainDrive::Force,
            force_at: self.force_at,
            sensors: vec![ChainSensor {
                at: self.response_at,
                quantity,
                ..ChainSensor::default()
            }],
        };
        let parameters = ChainParameters {
            masses: self.masses.clone(),
            dampers: self.dampers.clone(),
            springs: self.springs.clone(),
            ..ChainParameters::default()
        };
        let mut outputs = simulate_chain(&setup, &parameters, force, dt)?;
        Ok(outputs.swap_remove(0))
    }
}

/// The state matrix [[0, I], [−M⁻¹K, −M⁻¹C]] of a diagonal M (the plant's
/// [`state_space`](crate::plant::state_space)).
pub(crate) fn state_matrix(m: &DMatrix<f64>, c: &DMatrix<f64>, k: &DMatrix<f64>) -> DMatrix<f64> {
    let w: Vec<f64> = m.diagonal().iter().map(|v| 1.0 / v).collect();
    crate::plant::state_space(&w, c, k, crate::plant::Input::None).0
}

/// The poles λ with Im λ > 0 among the eigenvalues of `a`, by |λ| (overdamped, real
/// poles are not modes).
pub(crate) fn underdamped_poles(a: &DMatrix<f64>) -> Vec<Complex64> {
    let mut poles: Vec<Complex64> = a
        .complex_eigenvalues()
        .iter()
        .copied()
        .filter(|l| l.im > 1e-9 * l.norm())
        .collect();
    poles.sort_by(|x, y| x.norm().total_cmp(&y.norm()));
    poles
}

/// Every sensor's noise-free reading of `setup` with `parameters` driven by `input`
/// (force or base acceleration, every `dt` s, linear between samples, from rest),
/// delays and filters included: one series per sensor.
///
/// ```
/// use msd_ident::{chain::{ChainParameters, ChainSetup, simulate_chain}};
/// let p = ChainParameters { masses: vec![2.5], dampers: vec![1.8], springs: vec![120.0], ..ChainParameters::default() };
/// let y = simulate_chain(&ChainSetup::default(), &p, &vec![1.0; 30_000], 2e-3)?;
/// // A constant 1 N settles at 1/k (after 60 s the transient is e^(−c·t/2m) ≈ 4e-10 of it).
/// assert!((y[0][29_999] - 1.0 / 120.0).abs() < 1e-11);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn simulate_chain(
    setup: &ChainSetup,
    parameters: &ChainParameters,
    input: &[f64],
    dt: f64,
) -> crate::error::Result<Vec<Vec<f64>>> {
    setup.validate()?;
    parameters.validate(setup.masses)?;
    if !(dt.is_finite() && dt > 0.0) {
        return Err(crate::error::IdentError::InvalidParameter {
            name: "dt",
            value: dt,
            expected: "a finite number > 0",
        });
    }
    if let Some(index) = input.iter().position(|u| !u.is_finite()) {
        return Err(crate::error::IdentError::NonFiniteSample {
            field: "input",
            index,
            value: input[index],
        });
    }
    for (i, sensor) in setup.sensors.iter().enumerate() {
        if let Some(delay) = sensor.delay
            && delay >= dt * input.len() as f64
        {
            return Err(setup::setup_error(format!(
                "sensors[{i}].delay = {} s: expected less than the record ({} s)",
                setup::show(delay),
                dt * input.len() as f64
            )));
        }
    }
    if input.is_empty() {
        return Ok(vec![Vec::new(); setup.sensors.len()]);
    }
    let plant = model::system(setup, &problem::values(parameters));
    let delays: Vec<f64> = setup
        .sensors
        .iter()
        .map(|s| s.delay.unwrap_or(0.0))
        .collect();
    let sim = simulate::simulate(&plant, &[], &delays, input, dt, None)?;
    Ok(sim
        .outputs
        .chunks(input.len().max(1))
        .map(<[f64]>::to_vec)
        .collect())
}

#[cfg(test)]
mod fit_tests;

#[cfg(test)]
mod tests {
    use super::*;

    fn two_masses(force_at: usize, response_at: usize) -> ChainPlant {
        ChainPlant {
            masses: vec![2.0, 1.0],
            springs: vec![20_000.0, 10_000.0],
            dampers: vec![4.0, 2.0],
            force_at,
            response_at,
        }
    }

    #[test]
    fn the_modes_sum_to_the_receptance() {
        // Proportional damping C = 2e-4·K: ωn² = 5000 and 20000 (det(K − ω²M) = 0),
        // ζ = 1e-4·ωn.
        for (f, r) in [(2, 2), (1, 2), (2, 1)] {
            let plant = two_masses(f, r);
            let modes = plant.modes();
            assert_eq!(modes.len(), 2);
            for (mode, w2) in modes.iter().zip([5000.0f64, 20000.0]) {
                let wn = TAU * mode.natural_frequency_hz;
                assert!((wn / w2.sqrt() - 1.0).abs() < 1e-12);
                // The eigenvalues are found to about ε·‖A‖ ≈ 1e-11 (‖A‖ ≈ 3e4), and
                // Re λ = −ζωn is 0.5 or 2: ζ to about 1e-11 relative.
                assert!((mode.damping_ratio / (1e-4 * w2.sqrt()) - 1.0).abs() < 1e-10);
            }
            for hz in [1.0, 11.0, 17.0, 22.5, 60.0] {
                let sum: Complex64 = modes.iter().map(|m| m.receptance(hz)).sum();
                let direct = plant.receptance(hz);
                // The poles' rounding (ε‖A‖ ≈ 1e-11) is amplified near a resonance by
                // |λ|/|jω − λ| (≈ 50 at 11 Hz), and the residues come from the
                // cofactors of a nearly singular Z(λ): 1e-9 relative.
                assert!(
                    (sum - direct).norm() < 1e-9 * direct.norm(),
                    "{f}→{r} at {hz}: {}",
                    (sum - direct).norm() / direct.norm()
                );
            }
        }
    }

    #[test]
    fn a_step_settles_at_the_static_deflection() {
        // 1 N on mass 2 for 60 s (the slow mode decays as e^(−0.5 t)): the springs in series, 1/20000 + 1/10000 m.
        let plant = two_masses(2, 2);
        let y = plant
            .sampled_response(&vec![1.0; 60_000], 1e-3, FrfKind::Receptance)
            .unwrap();
        let end = y[y.len() - 1];
        assert!(
            (end / (1.0 / 20_000.0 + 1.0 / 10_000.0) - 1.0).abs() < 1e-6,
            "{end}"
        );
        assert_eq!(y[0], 0.0);
    }

    #[test]
    fn velocity_and_acceleration_follow_the_step_response() {
        // 1 N from rest on m, c, k: x = (1/k)·(1 − e^(−σt)(cos ωd·t + (σ/ωd)·sin ωd·t)),
        // x′ = (ωn²/(k·ωd))·e^(−σt)·sin ωd·t (σ = ζωn), and m·x″ = 1 − c·x′ − k·x.
        let plant = ChainPlant::one_mass(2.5, 1.8, 120.0);
        let (m, c, k, dt): (f64, f64, f64, f64) = (2.5, 1.8, 120.0, 1e-2);
        let force = vec![1.0; 500];
        let [x, v, a] = [FrfKind::Receptance, FrfKind::Mobility, FrfKind::Accelerance]
            .map(|kind| plant.sampled_response(&force, dt, kind).unwrap());
        let (wn2, sigma) = (k / m, c / (2.0 * m));
        let wd = (wn2 - sigma * sigma).sqrt();
        for i in (0..500).step_by(37) {
            let t = i as f64 * dt;
            let decay = (-sigma * t).exp();
            let x_exact = (1.0 - decay * ((wd * t).cos() + sigma / wd * (wd * t).sin())) / k;
            let v_exact = wn2 / (k * wd) * decay * (wd * t).sin();
            // The matrix exponential is exact to rounding (≈ 1e-16 of the state's scale,
            // 1/k = 8e-3 m and 1e-2 m/s), accumulated over at most 500 steps.
            assert!((x[i] - x_exact).abs() < 1e-13, "x at {t}");
            assert!((v[i] - v_exact).abs() < 1e-13, "v at {t}");
            assert!(
                (m * a[i] - (1.0 - c * v[i] - k * x[i])).abs() < 1e-13,
                "a at {t}"
            );
        }
    }
}
