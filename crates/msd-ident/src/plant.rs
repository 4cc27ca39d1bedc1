//! The one-mass plant m·x″ + c·x′ + k·x under its drive, in state-space form: the one
//! place its matrices A and b, and their derivatives with respect to m, c and k, are
//! built. Every one-mass engine simulates through it (the paper's estimate and its
//! sensitivities, the joint fit of records, the synthetic records, the design).

use crate::error::Result;
use msd_ode::{ExactSimulator, Hold, LtiModel, SMatrix, SVector};
use serde::{Deserialize, Serialize};

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
    pub(crate) fn a(&self) -> [[f64; 2]; 2] {
        let [m, c, k] = self.theta;
        [[0.0, 1.0], [-k / m, -c / m]]
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
        let [m, c, k] = self.theta;
        match self.drive {
            Drive::Force => [0.0, 1.0 / m],
            Drive::BaseAcceleration => [0.0, -1.0],
            Drive::BaseDisplacement => [c / m, k / m - (c / m).powi(2)],
            Drive::None => [0.0, 0.0],
        }
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
