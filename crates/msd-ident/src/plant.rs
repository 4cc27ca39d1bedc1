//! The plant in state-space form, the one place its matrices are built: masses joined in
//! a chain ([`state_space`]: the chains' systems and modes), of which one mass
//! m·x″ + c·x′ + k·x under its drive is the paper's case ([`Plant`], with the derivatives
//! of A and b with respect to m, c and k in closed form beside it). Every one-mass engine
//! simulates through [`Plant`] (the paper's estimate and its sensitivities, the joint fit
//! of records, the synthetic records, the design), every chain through [`state_space`].

use crate::error::Result;
use msd_ode::{ExactSimulator, Hold, LtiModel, SMatrix, SVector};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// How the drive u enters the state equation of [`state_space`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Input {
    /// A force on mass `at` (0-based).
    Force { at: usize },
    /// A base acceleration under every mass (the state relative to the base).
    BaseAcceleration,
    /// A base displacement z moving the ground end of spring k₁ and damper c₁ (those of
    /// mass 1), with the state (q, q′ − W·c₁·e₁·z) so that z′ is never needed.
    BaseDisplacement { damper: f64, spring: f64 },
    /// Nothing (a free decay): b = 0.
    None,
}

/// x′ = A·x + b·u of masses joined in a chain with inverse masses `w` (W = diag w) and
/// damping and stiffness matrices C, K, state (q, q′): A = [[0, I], [−W·K, −W·C]]; b is
/// W·e_f for a force on mass f, −1 in every velocity row under a base acceleration, and
/// (W·c₁·e₁, W·k₁·e₁ − W·C·W·c₁·e₁) under a base displacement. Every entry is affine in
/// each of w, C and K when the others are held (the chains' derivatives rest on it).
pub(crate) fn state_space(
    w: &[f64],
    damping: &DMatrix<f64>,
    stiffness: &DMatrix<f64>,
    input: Input,
) -> (DMatrix<f64>, DVector<f64>) {
    let n = w.len();
    let mut a = DMatrix::zeros(2 * n, 2 * n);
    let mut b = DVector::zeros(2 * n);
    for i in 0..n {
        a[(i, n + i)] = 1.0;
        for j in 0..n {
            a[(n + i, j)] = -w[i] * stiffness[(i, j)];
            a[(n + i, n + j)] = -w[i] * damping[(i, j)];
        }
    }
    match input {
        Input::Force { at } => b[n + at] = w[at],
        Input::BaseAcceleration => b.rows_mut(n, n).fill(-1.0),
        Input::BaseDisplacement { damper, spring } => {
            let lead = w[0] * damper;
            b[0] = lead;
            for i in 0..n {
                b[n + i] = -w[i] * damping[(i, 0)] * lead;
            }
            b[n] += w[0] * spring;
        }
        Input::None => {}
    }
    (a, b)
}

/// What drives the plant.
///
/// By default [`Drive::Force`].
///
/// ```
/// use msd_ident::Drive;
/// assert_eq!(serde_json::to_value(Drive::BaseAcceleration)?, "base_acceleration");
/// assert_eq!(Drive::None.to_string(), "free decay");
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Drive {
    /// A measured force F on the mass: m·x″ + c·x′ + k·x = F (N). Identifies m, c and k.
    #[default]
    Force,
    /// A measured base acceleration z″ (m/s²): the relative motion y = x − z obeys
    /// y″ + 2ζωn·y′ + ωn²·y = −z″. Identifies ωn and ζ (m, c, k with a known mass or
    /// stiffness).
    BaseAcceleration,
    /// A measured base displacement z (m): m·x″ + c·x′ + k·x = c·z′ + k·z, simulated with
    /// the state w = x′ − (c/m)·z so that z′ is never needed. Identifies ωn and ζ.
    BaseDisplacement,
    /// Nothing: the mass rings down from its initial state (a free decay). The records'
    /// excitation samples are ignored. Identifies ωn and ζ.
    None,
}

impl std::fmt::Display for Drive {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.setup())
    }
}

impl Drive {
    /// The setup in words, for messages.
    pub(crate) fn setup(self) -> &'static str {
        match self {
            Drive::Force => "force drive",
            Drive::BaseAcceleration => "base acceleration",
            Drive::BaseDisplacement => "base displacement",
            Drive::None => "free decay",
        }
    }

    /// The measured quantity that drives the plant, in words ("force", …).
    pub(crate) fn quantity(self) -> &'static str {
        match self {
            Drive::Force => "force",
            Drive::BaseAcceleration => "base acceleration",
            Drive::BaseDisplacement => "base displacement",
            Drive::None => "excitation",
        }
    }

    /// Whether the mass is estimated (only a force on the mass fixes it).
    pub(crate) fn estimates_mass(self) -> bool {
        self == Drive::Force
    }
}

/// The plant under one drive at θ = (m, c, k).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Plant {
    pub theta: [f64; 3],
    pub drive: Drive,
}

impl Plant {
    /// A and b from [`state_space`] (one mass).
    fn matrices(&self) -> (DMatrix<f64>, DVector<f64>) {
        let [m, c, k] = self.theta;
        let input = match self.drive {
            Drive::Force => Input::Force { at: 0 },
            Drive::BaseAcceleration => Input::BaseAcceleration,
            Drive::BaseDisplacement => Input::BaseDisplacement {
                damper: c,
                spring: k,
            },
            Drive::None => Input::None,
        };
        let one = |v: f64| DMatrix::from_element(1, 1, v);
        state_space(&[1.0 / m], &one(c), &one(k), input)
    }

    pub(crate) fn a(&self) -> [[f64; 2]; 2] {
        let (a, _) = self.matrices();
        [[a[(0, 0)], a[(0, 1)]], [a[(1, 0)], a[(1, 1)]]]
    }

    /// ∂A/∂m, ∂A/∂c, ∂A/∂k.
    pub(crate) fn da(&self) -> [[[f64; 2]; 2]; 3] {
        let [m, c, k] = self.theta;
        let m2 = m * m;
        [
            [[0.0, 0.0], [k / m2, c / m2]],
            [[0.0, 0.0], [0.0, -1.0 / m]],
            [[0.0, 0.0], [-1.0 / m, 0.0]],
        ]
    }

    pub(crate) fn b(&self) -> [f64; 2] {
        let (_, b) = self.matrices();
        [b[0], b[1]]
    }

    /// ∂b/∂m, ∂b/∂c, ∂b/∂k.
    pub(crate) fn db(&self) -> [[f64; 2]; 3] {
        let [m, c, k] = self.theta;
        let m2 = m * m;
        match self.drive {
            Drive::Force => [[0.0, -1.0 / m2], [0.0; 2], [0.0; 2]],
            Drive::BaseDisplacement => [
                [-c / m2, -k / m2 + 2.0 * c * c / (m2 * m)],
                [1.0 / m, -2.0 * c / m2],
                [0.0, 1.0 / m],
            ],
            Drive::BaseAcceleration | Drive::None => [[0.0; 2]; 3],
        }
    }

    /// The state-space form of the response, state (x, x′) (for a base displacement
    /// (x, x′ − (c/m)·z)).
    pub(crate) fn model(&self) -> LtiModel<2> {
        let (a, b) = (self.a(), self.b());
        LtiModel {
            a: SMatrix::<f64, 2, 2>::new(a[0][0], a[0][1], a[1][0], a[1][1]),
            b: SVector::<f64, 2>::new(b[0], b[1]),
        }
    }

    /// The response alone (2 states).
    pub(crate) fn response(&self, dt: f64, hold: Hold) -> Result<ExactSimulator<2>> {
        Ok(ExactSimulator::new(&self.model(), dt, hold)?)
    }

    /// The response and its sensitivities to m, c, k (8 states: s, s_m, s_c, s_k).
    pub(crate) fn sensitivities(&self, dt: f64, hold: Hold) -> Result<ExactSimulator<8>> {
        Ok(ExactSimulator::new(&self.sensitivity_model(), dt, hold)?)
    }

    /// The 8-state system of the response and its sensitivities to m, c, k: each
    /// (s_j, s_j′) block has the plant's dynamics, coupled to the response through ∂A/∂θⱼ
    /// and driven through ∂b/∂θⱼ.
    pub(crate) fn sensitivity_model(&self) -> LtiModel<8> {
        let (a, da, b, db) = (self.a(), self.da(), self.b(), self.db());
        let mut a8 = SMatrix::<f64, 8, 8>::zeros();
        let mut b8 = SVector::<f64, 8>::zeros();
        for block in 0..4 {
            for r in 0..2 {
                for c in 0..2 {
                    a8[(2 * block + r, 2 * block + c)] = a[r][c];
                    if block > 0 {
                        a8[(2 * block + r, c)] = da[block - 1][r][c];
                    }
                }
                b8[2 * block + r] = if block == 0 { b[r] } else { db[block - 1][r] };
            }
        }
        LtiModel { a: a8, b: b8 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The matrix of three elements in a chain, element i joining mass i to i − 1.
    fn chain_matrix(v: [f64; 3]) -> DMatrix<f64> {
        DMatrix::from_row_slice(
            3,
            3,
            &[
                v[0] + v[1],
                -v[1],
                0.0,
                -v[1],
                v[1] + v[2],
                -v[2],
                0.0,
                -v[2],
                v[2],
            ],
        )
    }

    /// One mass under each drive: the closed forms, to rounding.
    #[test]
    fn one_mass_is_the_closed_form() {
        let [m, c, k]: [f64; 3] = [2.5, 1.8, 120.0];
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-15 * y.abs().max(1.0);
        for (drive, b) in [
            (Drive::Force, [0.0, 1.0 / m]),
            (Drive::BaseAcceleration, [0.0, -1.0]),
            (Drive::BaseDisplacement, [c / m, k / m - (c / m).powi(2)]),
            (Drive::None, [0.0, 0.0]),
        ] {
            let plant = Plant {
                theta: [m, c, k],
                drive,
            };
            let a = plant.a();
            assert!(close(a[1][0], -k / m) && close(a[1][1], -c / m) && a[0] == [0.0, 1.0]);
            let got = plant.b();
            assert!(
                close(got[0], b[0]) && close(got[1], b[1]),
                "{drive}: {got:?}"
            );
        }
    }

    /// A chain of three under a constant base displacement z settles where every mass has
    /// moved by z (the ground's spring and damper are the only ones to the ground):
    /// −A⁻¹·b = (1, 1, 1, −w₁c₁, 0, 0) in the state (q, q′ − W·c₁·e₁·z).
    #[test]
    fn a_chain_under_a_base_displacement_settles_on_the_base() {
        let w = [0.5, 0.25, 1.0 / 3.0];
        let (c, k) = ([0.4, 0.3, 0.2], [100.0, 80.0, 60.0]);
        let input = Input::BaseDisplacement {
            damper: c[0],
            spring: k[0],
        };
        let (a, b) = state_space(&w, &chain_matrix(c), &chain_matrix(k), input);
        let x = a.lu().solve(&(-b)).expect("A invertible");
        let expected = [1.0, 1.0, 1.0, -w[0] * c[0], 0.0, 0.0];
        for (got, want) in x.iter().zip(expected) {
            assert!((got - want).abs() < 1e-12, "{x}");
        }
    }
}
