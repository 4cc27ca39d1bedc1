//! The model structures (damping law × stiffness law) and their parameter vectors.

use crate::error::{IdentError, Result};
use crate::law::{DampingForce, DampingLaw};
use crate::params::Parameters;
use serde::{Deserialize, Serialize};

/// The spring force f_s(x).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StiffnessLaw {
    /// k·x.
    Linear,
    /// k·x + k₃·x³ (Duffing).
    Cubic,
}

/// One candidate model m·x'' + f_d(x') + f_s(x) = F(t): a damping law and a stiffness
/// law. A set of candidates is data (e.g. a list in a config), not code.
///
/// ```
/// use msd_ident::{nonlinear::{DampingLaw, ModelStructure, StiffnessLaw}};
/// let s = ModelStructure { damping: DampingLaw::CoulombViscous, stiffness: StiffnessLaw::Cubic };
/// assert_eq!(s.parameter_names(), ["mass", "damping", "stiffness", "coulomb_force", "cubic_stiffness"]);
/// assert_eq!(s.name(), "coulomb_viscous+cubic");
/// assert_eq!(ModelStructure::all().len(), 6);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelStructure {
    /// The damping law.
    pub damping: DampingLaw,
    /// The stiffness law.
    pub stiffness: StiffnessLaw,
}

impl Default for ModelStructure {
    /// The linear model.
    fn default() -> Self {
        Self::LINEAR
    }
}

impl std::fmt::Display for ModelStructure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.name())
    }
}

impl ModelStructure {
    /// The linear model m·x'' + c·x' + k·x = F: the baseline of every comparison.
    pub const LINEAR: ModelStructure = ModelStructure {
        damping: DampingLaw::Viscous,
        stiffness: StiffnessLaw::Linear,
    };

    /// All six combinations, linear first.
    pub fn all() -> Vec<ModelStructure> {
        let mut v = Vec::with_capacity(6);
        for stiffness in [StiffnessLaw::Linear, StiffnessLaw::Cubic] {
            for damping in DampingLaw::ALL {
                v.push(ModelStructure { damping, stiffness });
            }
        }
        v
    }

    /// A short name, `damping+stiffness` in snake case (e.g. `viscous+linear`).
    pub fn name(&self) -> String {
        let d = self.damping.name();
        let s = match self.stiffness {
            StiffnessLaw::Linear => "linear",
            StiffnessLaw::Cubic => "cubic",
        };
        format!("{d}+{s}")
    }

    /// Whether this is the linear model.
    pub fn is_linear(&self) -> bool {
        *self == Self::LINEAR
    }

    /// Names of the parameters in vector order: mass, damping, stiffness, then
    /// `coulomb_force` or `quadratic_damping`, then `cubic_stiffness`.
    pub fn parameter_names(&self) -> Vec<&'static str> {
        let mut names = vec!["mass", "damping", "stiffness"];
        names.extend(self.damping.coefficient());
        if self.stiffness == StiffnessLaw::Cubic {
            names.push("cubic_stiffness");
        }
        names
    }

    /// Number of parameters (3 to 5).
    pub fn parameter_count(&self) -> usize {
        3 + usize::from(self.damping != DampingLaw::Viscous)
            + usize::from(self.stiffness == StiffnessLaw::Cubic)
    }
}

/// The parameters of one [`ModelStructure`]: a small vector in the order of
/// [`ModelStructure::parameter_names`].
///
/// ```
/// use msd_ident::{nonlinear::{DampingLaw, ModelStructure, NonlinearParameters, StiffnessLaw}, Parameters};
/// let duffing = ModelStructure { damping: DampingLaw::Viscous, stiffness: StiffnessLaw::Cubic };
/// let p = NonlinearParameters::new(duffing, vec![2.5, 1.8, 120.0, 4000.0])?;
/// assert_eq!(p.cubic_stiffness(), 4000.0);
/// assert_eq!(p.coulomb_force(), 0.0); // absent terms are zero
/// assert_eq!(p.linear_part(), Parameters::PAPER);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NonlinearParameters {
    /// The model structure.
    pub structure: ModelStructure,
    /// The values, in the order of [`ModelStructure::parameter_names`].
    pub values: Vec<f64>,
}

impl NonlinearParameters {
    /// Checked constructor: the right number of values, m > 0, c ≥ 0, k > 0, and finite
    /// nonlinear coefficients of either sign. A softening spring has k₃ < 0; F_c < 0 or
    /// c₂ < 0 would feed energy in and is not physical, but is allowed so that an
    /// estimator can step across 0 when the true coefficient is 0 (the comparison then
    /// judges the term by its interval and by BIC).
    pub fn new(structure: ModelStructure, values: Vec<f64>) -> Result<Self> {
        let p = Self { structure, values };
        p.validate()?;
        Ok(p)
    }

    /// The linear parameters with zero nonlinear coefficients.
    pub fn from_linear(structure: ModelStructure, linear: &Parameters) -> Self {
        let mut values = vec![0.0; structure.parameter_count()];
        values[..3].copy_from_slice(&linear.to_array());
        Self { structure, values }
    }

    /// Checks the count and ranges (see [`NonlinearParameters::new`]).
    pub fn validate(&self) -> Result<()> {
        let expected = self.structure.parameter_count();
        if self.values.len() != expected {
            return Err(IdentError::LengthMismatch {
                what: "nonlinear parameter vector",
                expected,
                got: self.values.len(),
            });
        }
        self.linear_part().validate()?;
        let names = self.names().into_iter().zip(self.values.iter().copied());
        crate::params::require_finite(names.skip(3))
    }

    /// The parameter names.
    pub fn names(&self) -> Vec<&'static str> {
        self.structure.parameter_names()
    }

    /// The value named `name`, if the structure has it.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.names()
            .iter()
            .position(|n| *n == name)
            .map(|i| self.values[i])
    }

    /// Mass m.
    pub fn mass(&self) -> f64 {
        self.values[0]
    }

    /// Viscous damping c.
    pub fn damping(&self) -> f64 {
        self.values[1]
    }

    /// Linear stiffness k.
    pub fn stiffness(&self) -> f64 {
        self.values[2]
    }

    /// Coulomb friction force F_c (0 when the structure has none).
    pub fn coulomb_force(&self) -> f64 {
        self.get("coulomb_force").unwrap_or(0.0)
    }

    /// Quadratic damping c₂ (0 when the structure has none).
    pub fn quadratic_damping(&self) -> f64 {
        self.get("quadratic_damping").unwrap_or(0.0)
    }

    /// Cubic stiffness k₃ (0 when the structure has none).
    pub fn cubic_stiffness(&self) -> f64 {
        self.get("cubic_stiffness").unwrap_or(0.0)
    }

    /// m, c, k as linear [`Parameters`].
    pub fn linear_part(&self) -> Parameters {
        Parameters {
            mass: self.values[0],
            damping: self.values[1],
            stiffness: self.values[2],
        }
    }
}

impl std::fmt::Display for NonlinearParameters {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let parts: Vec<String> = self
            .names()
            .iter()
            .zip(&self.values)
            .map(|(n, v)| format!("{n} = {v:.6e}"))
            .collect();
        write!(f, "{}: {}", self.structure, parts.join(", "))
    }
}

/// The forces of one parameter vector, unpacked for the right-hand side and its
/// linearisation (the sensitivity equations).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Forces {
    /// The damping law with its coefficients; its `inverse_smoothing` is 1/v_s for a
    /// structure with a Coulomb term (also at F_c = 0, where ∂/∂F_c is not 0), else 0.
    pub law: DampingForce,
    pub stiffness: f64,
    pub cubic: f64,
    /// 1/m.
    pub inverse_mass: f64,
    /// For each entry of the parameter vector, its index in [`Linearised::partials`].
    pub order: [usize; 5],
}

/// The acceleration at one point and its derivatives, for the sensitivity equations
/// ξ' = η, η' = −K·ξ − C·η + ∂a/∂θ.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Linearised {
    /// a = x''.
    pub acceleration: f64,
    /// K = −∂a/∂x = f_s'(x)/m.
    pub stiffness: f64,
    /// C = −∂a/∂x' = f_d'(x')/m.
    pub damping: f64,
    /// ∂a/∂θ for θ = m, c, k, F_c, c₂, k₃.
    pub partials: [f64; 6],
}

impl Forces {
    /// The forces of `p`, with the Coulomb smoothing velocity v_s (used only when the
    /// structure has a Coulomb term and v_s is a finite number > 0).
    pub fn new(p: &NonlinearParameters, smoothing_velocity: f64) -> Self {
        let coulomb_law = p.structure.damping == DampingLaw::CoulombViscous;
        let valid = smoothing_velocity.is_finite() && smoothing_velocity > 0.0;
        // The vector's order: m, c, k, then F_c or c₂, then k₃ (see parameter_names).
        let mut order = [0, 1, 2, 0, 0];
        let mut next = 3;
        let nonlinear = [
            (coulomb_law, 3),
            (p.structure.damping == DampingLaw::QuadraticViscous, 4),
            (p.structure.stiffness == StiffnessLaw::Cubic, 5),
        ];
        for (present, index) in nonlinear {
            if present {
                order[next] = index;
                next += 1;
            }
        }
        debug_assert_eq!(next, p.structure.parameter_count());
        Self {
            law: DampingForce {
                viscous: p.damping(),
                quadratic: p.quadratic_damping(),
                coulomb: p.coulomb_force(),
                inverse_smoothing: if coulomb_law && valid {
                    1.0 / smoothing_velocity
                } else {
                    0.0
                },
            },
            stiffness: p.stiffness(),
            cubic: p.cubic_stiffness(),
            inverse_mass: 1.0 / p.mass(),
            order,
        }
    }

    /// x'' = (F − f_d(v) − f_s(x))/m.
    #[inline]
    pub fn acceleration(&self, force: f64, x: f64, v: f64) -> f64 {
        let damping = self.law.force(v);
        let spring = self.stiffness * x + self.cubic * x * x * x;
        (force - damping - spring) * self.inverse_mass
    }

    /// The acceleration and its derivatives by x, x' and the parameters. The smoothed
    /// Coulomb term F_c·tanh(x'/v_s) has the slope F_c/v_s·(1 − tanh²), the quadratic
    /// c₂·x'|x'| the slope 2c₂|x'| (continuous at 0).
    #[inline(always)]
    pub fn linearised(&self, force: f64, x: f64, v: f64) -> Linearised {
        let (damping, slope, tanh) = self.law.force_and_slope(v);
        let (x2, speed) = (x * x, v.abs());
        let spring = self.stiffness * x + self.cubic * x2 * x;
        let inverse_mass = self.inverse_mass;
        let acceleration = (force - damping - spring) * inverse_mass;
        Linearised {
            acceleration,
            stiffness: (self.stiffness + 3.0 * self.cubic * x2) * inverse_mass,
            damping: slope * inverse_mass,
            partials: [
                -acceleration * inverse_mass,
                -v * inverse_mass,
                -x * inverse_mass,
                -tanh * inverse_mass,
                -v * speed * inverse_mass,
                -x2 * x * inverse_mass,
            ],
        }
    }

    /// A bound on the magnitude of the eigenvalues of the linearised dynamics
    /// [[0, 1], [−K, −C]] at (x, v): |λ| ≤ √|K| + |C|.
    #[inline]
    pub fn rate(&self, x: f64, v: f64) -> f64 {
        let l = self.linearised(0.0, x, v);
        l.stiffness.abs().sqrt() + l.damping.abs()
    }
}
