//! The physical parameters and the quantities derived from them.

use crate::error::{IdentError, Result};
use crate::plant::{Drive, Plant};
use msd_ode::{LtiModel, SVector};
use serde::{Deserialize, Serialize};

/// Mass m, damping c and stiffness k of m·x'' + c·x' + k·x = F(t), in consistent units
/// (SI: kg, N·s/m, N/m).
///
/// ```
/// use msd_ident::Parameters;
/// let plant = Parameters::new(2.5, 1.8, 120.0)?;
/// assert!((plant.natural_frequency() - 6.9282).abs() < 1e-4);      // rad/s
/// assert!((plant.natural_frequency_hz() - 1.1027).abs() < 1e-4);
/// assert!((plant.damping_ratio() - 0.051962).abs() < 1e-6);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Parameters {
    /// Mass m (> 0).
    pub mass: f64,
    /// Viscous damping coefficient c (≥ 0).
    pub damping: f64,
    /// Stiffness k (> 0).
    pub stiffness: f64,
}

impl Parameters {
    /// Names of the three parameters, in the order used by vectors and matrices.
    ///
    /// ```
    /// assert_eq!(msd_ident::Parameters::NAMES[1], "damping");
    /// ```
    pub const NAMES: [&str; 3] = ["mass", "damping", "stiffness"];

    /// Checked constructor.
    pub fn new(mass: f64, damping: f64, stiffness: f64) -> Result<Self> {
        let p = Self {
            mass,
            damping,
            stiffness,
        };
        p.validate()?;
        Ok(p)
    }

    /// The paper's plant: m = 2.5 kg, c = 1.8 N·s/m, k = 120 N/m.
    pub const PAPER: Parameters = Parameters {
        mass: 2.5,
        damping: 1.8,
        stiffness: 120.0,
    };

    /// Finite, mass and stiffness > 0, damping ≥ 0.
    ///
    /// ```
    /// use msd_ident::{IdentError, Parameters};
    /// let p = Parameters { mass: 1.0, damping: f64::NAN, stiffness: 1.0 };
    /// assert!(matches!(p.validate(), Err(IdentError::InvalidParameter { name: "damping", .. })));
    /// ```
    pub fn validate(&self) -> Result<()> {
        let checks = [
            ("mass", self.mass, self.mass > 0.0, "a finite number > 0"),
            (
                "damping",
                self.damping,
                self.damping >= 0.0,
                "a finite number >= 0",
            ),
            (
                "stiffness",
                self.stiffness,
                self.stiffness > 0.0,
                "a finite number > 0",
            ),
        ];
        for (name, value, ok, expected) in checks {
            if !(value.is_finite() && ok) {
                return Err(IdentError::InvalidParameter {
                    name,
                    value,
                    expected,
                });
            }
        }
        Ok(())
    }

    /// As an array (m, c, k).
    pub fn to_array(&self) -> [f64; 3] {
        [self.mass, self.damping, self.stiffness]
    }

    /// From an array (m, c, k), unchecked.
    pub fn from_array(v: [f64; 3]) -> Self {
        Self {
            mass: v[0],
            damping: v[1],
            stiffness: v[2],
        }
    }

    /// Undamped natural frequency ωn = √(k/m), rad/s.
    pub fn natural_frequency(&self) -> f64 {
        (self.stiffness / self.mass).sqrt()
    }

    /// Natural frequency fn = ωn/2π, Hz.
    pub fn natural_frequency_hz(&self) -> f64 {
        self.natural_frequency() / (2.0 * std::f64::consts::PI)
    }

    /// Damping ratio ζ = c / (2√(mk)).
    pub fn damping_ratio(&self) -> f64 {
        self.damping / (2.0 * (self.mass * self.stiffness).sqrt())
    }

    /// Damped natural frequency ωd = ωn√(1 − ζ²), rad/s; `None` when ζ ≥ 1 (no
    /// oscillation).
    pub fn damped_natural_frequency(&self) -> Option<f64> {
        let z = self.damping_ratio();
        (z < 1.0).then(|| self.natural_frequency() * (1.0 - z * z).sqrt())
    }

    /// Quality factor Q = 1/(2ζ) (infinite without damping).
    pub fn quality_factor(&self) -> f64 {
        1.0 / (2.0 * self.damping_ratio())
    }

    /// Static compliance 1/k: displacement per unit static force.
    pub fn static_compliance(&self) -> f64 {
        1.0 / self.stiffness
    }

    /// State-space form with state (x, x'): A = [[0, 1], [−k/m, −c/m]], b = [0, 1/m].
    pub fn state_space(&self) -> LtiModel<2> {
        self.plant().model()
    }

    /// The plant driven by a force on the mass.
    pub(crate) fn plant(&self) -> Plant {
        Plant {
            theta: self.to_array(),
            drive: Drive::Force,
        }
    }
}

impl std::fmt::Display for Parameters {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "m = {:.6}, c = {:.6}, k = {:.6}",
            self.mass, self.damping, self.stiffness
        )
    }
}

/// Initial state of the mass: displacement x(t₀) and velocity x'(t₀).
///
/// By default at rest (0, 0).
///
/// ```
/// use msd_ident::InitialState;
/// let x0 = InitialState { displacement: 0.01, velocity: -0.5 };
/// assert_eq!(x0.to_string(), "x(t₀) = 1.0000e-2, x'(t₀) = -5.0000e-1");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialState {
    /// x(t₀).
    pub displacement: f64,
    /// x'(t₀).
    pub velocity: f64,
}

impl InitialState {
    /// At rest.
    pub const REST: InitialState = InitialState {
        displacement: 0.0,
        velocity: 0.0,
    };

    pub(crate) fn vector(&self) -> SVector<f64, 2> {
        SVector::<f64, 2>::new(self.displacement, self.velocity)
    }

    /// Its two values, named as the options that hold them name them.
    pub(crate) fn named(&self) -> [(&'static str, f64); 2] {
        [
            ("initial_state.displacement", self.displacement),
            ("initial_state.velocity", self.velocity),
        ]
    }
}

/// The first of the named `values` that is NaN or infinite, as
/// [`IdentError::InvalidParameter`] expecting "a finite number".
pub(crate) fn require_finite(values: impl IntoIterator<Item = (&'static str, f64)>) -> Result<()> {
    match values.into_iter().find(|(_, value)| !value.is_finite()) {
        Some((name, value)) => Err(IdentError::InvalidParameter {
            name,
            value,
            expected: "a finite number",
        }),
        None => Ok(()),
    }
}

impl std::fmt::Display for InitialState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "x(t₀) = {:.4e}, x'(t₀) = {:.4e}",
            self.displacement, self.velocity
        )
    }
}

/// What else is known about the plant: a free decay alone gives ωn and ζ only.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum KnownParameter {
    /// Nothing: ωn and ζ only.
    #[default]
    None,
    /// The mass m, kg (weighed): gives c and k.
    Mass(f64),
    /// The static stiffness k, N/m (from a static load test): gives m and c.
    Stiffness(f64),
}

impl KnownParameter {
    /// Checks that a known mass or stiffness is finite and > 0.
    ///
    /// ```
    /// use msd_ident::KnownParameter;
    /// assert!(KnownParameter::Mass(2.5).validate().is_ok());
    /// assert!(KnownParameter::Stiffness(-1.0).validate().is_err());
    /// ```
    pub fn validate(&self) -> Result<()> {
        let (name, value) = match *self {
            KnownParameter::Mass(v) => ("known mass", v),
            KnownParameter::Stiffness(v) => ("known stiffness", v),
            KnownParameter::None => return Ok(()),
        };
        if value.is_finite() && value > 0.0 {
            return Ok(());
        }
        Err(IdentError::InvalidParameter {
            name,
            value,
            expected: "a finite number > 0",
        })
    }
}
