//! Options of the estimators.

use crate::{
    error::{IdentError, Result},
    params::{InitialState, Parameters},
    simulate::Backend,
};
use msd_opt::{LevenbergMarquardtOptions, NelderMeadOptions};
use serde::{Deserialize, Serialize};

/// The optimiser.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Nelder–Mead with fminsearch's defaults on J(θ) = Σ(y − x̂(θ))², in the raw
    /// parameters: the paper's method.
    NelderMead,
    /// Levenberg–Marquardt on the residual vector with the exact Jacobian from the
    /// sensitivity equations, in log-parameters (so m, c, k stay positive): the fast
    /// method.
    #[default]
    LevenbergMarquardt,
}

impl std::fmt::Display for Method {
    /// "Nelder–Mead" or "Levenberg–Marquardt" ([`Method::name`] is the config's word).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::NelderMead => "Nelder–Mead",
            Method::LevenbergMarquardt => "Levenberg–Marquardt",
        })
    }
}

impl Method {
    /// A short name for reports.
    pub fn name(&self) -> &'static str {
        match self {
            Method::NelderMead => "nelder_mead",
            Method::LevenbergMarquardt => "levenberg_marquardt",
        }
    }
}

/// Parameters known beforehand (e.g. a weighed mass), held at their values.
///
/// By default none.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FixedParameters {
    /// Known mass.
    pub mass: Option<f64>,
    /// Known damping.
    pub damping: Option<f64>,
    /// Known stiffness.
    pub stiffness: Option<f64>,
}

impl FixedParameters {
    pub(crate) fn as_array(&self) -> [Option<f64>; 3] {
        [self.mass, self.damping, self.stiffness]
    }
}

/// Bounds [low, high] on the physical parameters (both > 0).
///
/// By default none.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParameterBounds {
    /// Bounds on the mass.
    #[serde(default, deserialize_with = "msd_signal::pair::optional")]
    pub mass: Option<[f64; 2]>,
    /// Bounds on the damping.
    #[serde(default, deserialize_with = "msd_signal::pair::optional")]
    pub damping: Option<[f64; 2]>,
    /// Bounds on the stiffness.
    #[serde(default, deserialize_with = "msd_signal::pair::optional")]
    pub stiffness: Option<[f64; 2]>,
}

impl ParameterBounds {
    pub(crate) fn as_array(&self) -> [Option<[f64; 2]>; 3] {
        [self.mass, self.damping, self.stiffness]
    }
}

/// Multistart for a poor initial guess: seeded starting points spread over the bounds
/// (or over `decades` decades either side of the initial guess), each refined by the
/// chosen method, the best kept.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MultistartSettings {
    /// Number of starting points. By default 16.
    pub starts: usize,
    /// Half-width of the search box in decades around the initial guess, where no
    /// bounds are given. By default 2 (a factor 100 either way).
    pub decades: f64,
    /// Seed of the starting points. By default 0.
    pub seed: u64,
    /// Worker threads. By default 2.
    pub threads: usize,
}

impl Default for MultistartSettings {
    fn default() -> Self {
        Self {
            starts: 16,
            decades: 2.0,
            seed: 0,
            threads: 2,
        }
    }
}

/// Everything an estimation needs besides the data.
///
/// By default the fast method (Levenberg–Marquardt on the exact simulator) with an
/// automatic initial guess, the system at rest, no offset. [`EstimationOptions::paper`]
/// gives the paper's method.
///
/// ```
/// use msd_ident::{EstimationOptions, Method, Parameters};
/// let paper = EstimationOptions::paper();
/// assert_eq!(paper.method, Method::NelderMead);
/// assert_eq!(paper.initial_guess, Some(Parameters { mass: 2.0, damping: 1.0, stiffness: 100.0 }));
/// assert!(EstimationOptions::default().validate().is_ok());
/// ```
///
/// In TOML (as the `[estimation]` section of an experiment config) every field is
/// optional, unknown keys are refused, and `initial_guess` is `"auto"` or a table:
///
/// ```
/// use msd_ident::{EstimationOptions, Method};
/// let o: EstimationOptions = toml::from_str(
///     "method = \"nelder_mead\"\ninitial_guess = { mass = 2.0, damping = 1.0, stiffness = 100.0 }",
/// ).unwrap();
/// assert_eq!(o.method, Method::NelderMead);
/// assert_eq!(o.initial_guess.unwrap().stiffness, 100.0);
/// let auto: EstimationOptions = toml::from_str("initial_guess = \"auto\"").unwrap();
/// assert_eq!(auto, EstimationOptions::default());
/// assert!(toml::from_str::<EstimationOptions>("metod = \"nelder_mead\"").is_err());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct EstimationOptions {
    /// The optimiser. By default Levenberg–Marquardt.
    pub method: Method,
    /// The simulator inside the cost. By default exact with a cubic hold.
    pub backend: Backend,
    /// θ₀; `None` (in TOML `"auto"`) for the automatic ARX guess. By default `None`.
    #[serde(with = "auto_or_given")]
    pub initial_guess: Option<Parameters>,
    /// Known parameters. By default none.
    pub fixed: FixedParameters,
    /// Bounds on the parameters. By default none.
    pub bounds: ParameterBounds,
    /// The initial state (the starting value when it is estimated). By default at rest.
    pub initial_state: InitialState,
    /// Estimate x(t₀) and x'(t₀) too. By default false.
    pub estimate_initial_state: bool,
    /// A constant sensor offset added to the model output (the starting value when it is
    /// estimated). By default 0.
    pub offset: f64,
    /// Estimate the offset too. By default false.
    pub estimate_offset: bool,
    /// Nelder–Mead settings. By default fminsearch's.
    pub nelder_mead: NelderMeadOptions,
    /// Levenberg–Marquardt settings. By default MINPACK-like.
    pub levenberg_marquardt: LevenbergMarquardtOptions,
    /// Multistart, off by default.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub multistart: Option<MultistartSettings>,
}

/// `initial_guess` in TOML: `"auto"` for `None`, or a table `{ mass, damping, stiffness }`.
mod auto_or_given {
    use crate::params::Parameters;
    use serde::{Deserialize, Deserializer, Serialize, Serializer, de};

    pub fn serialize<S: Serializer>(guess: &Option<Parameters>, s: S) -> Result<S::Ok, S::Error> {
        match guess {
            None => s.serialize_str("auto"),
            Some(p) => p.serialize(s),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Parameters>, D::Error> {
        struct Visitor;
        impl<'de> de::Visitor<'de> for Visitor {
            type Value = Option<Parameters>;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(r#""auto" or a table { mass, damping, stiffness }"#)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
                match v {
                    "auto" => Ok(None),
                    _ => Err(E::invalid_value(de::Unexpected::Str(v), &self)),
                }
            }
            fn visit_map<A: de::MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
                Parameters::deserialize(de::value::MapAccessDeserializer::new(map)).map(Some)
            }
        }
        d.deserialize_any(Visitor)
    }
}

impl Default for EstimationOptions {
    fn default() -> Self {
        Self {
            method: Method::LevenbergMarquardt,
            backend: Backend::EXACT,
            initial_guess: None,
            fixed: FixedParameters::default(),
            bounds: ParameterBounds::default(),
            initial_state: InitialState::REST,
            estimate_initial_state: false,
            offset: 0.0,
            estimate_offset: false,
            nelder_mead: NelderMeadOptions::default(),
            levenberg_marquardt: LevenbergMarquardtOptions::default(),
            multistart: None,
        }
    }
}

impl EstimationOptions {
    /// The paper's method: Nelder–Mead with fminsearch defaults on ode45 (RelTol 1e-6,
    /// AbsTol 1e-9) from θ₀ = (2.0, 1.0, 100.0).
    pub fn paper() -> Self {
        Self {
            method: Method::NelderMead,
            backend: Backend::PAPER,
            initial_guess: Some(Parameters {
                mass: 2.0,
                damping: 1.0,
                stiffness: 100.0,
            }),
            ..Self::default()
        }
    }

    /// The fast method from the paper's θ₀: Levenberg–Marquardt on the exact simulator.
    pub fn fast() -> Self {
        Self {
            initial_guess: Self::paper().initial_guess,
            ..Self::default()
        }
    }

    /// Checks every option, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        self.backend.validate()?;
        if let Some(guess) = &self.initial_guess {
            guess.validate().map_err(|e| match e {
                IdentError::InvalidParameter {
                    name,
                    value,
                    expected,
                } => IdentError::InvalidParameter {
                    name: match name {
                        "mass" => "initial_guess.mass",
                        "damping" => "initial_guess.damping",
                        _ => "initial_guess.stiffness",
                    },
                    value,
                    expected,
                },
                other => other,
            })?;
        }
        const NAMES: [&str; 3] = ["fixed.mass", "fixed.damping", "fixed.stiffness"];
        for (name, value) in NAMES.iter().zip(self.fixed.as_array()) {
            if let Some(v) = value
                && !(v.is_finite() && v > 0.0)
            {
                return Err(IdentError::InvalidParameter {
                    name,
                    value: v,
                    expected: "a finite number > 0",
                });
            }
        }
        const BOUNDS: [&str; 3] = ["bounds.mass", "bounds.damping", "bounds.stiffness"];
        for (name, value) in BOUNDS.iter().zip(self.bounds.as_array()) {
            if let Some([lo, hi]) = value {
                if !(lo.is_finite() && lo > 0.0) {
                    return Err(IdentError::InvalidParameter {
                        name,
                        value: lo,
                        expected: "a lower bound that is finite and > 0",
                    });
                }
                if !(hi.is_finite() && hi > lo) {
                    return Err(IdentError::InvalidParameter {
                        name,
                        value: hi,
                        expected: "an upper bound that is finite and above the lower bound",
                    });
                }
            }
        }
        let state = self.initial_state.named();
        crate::params::require_finite(state.into_iter().chain([("offset", self.offset)]))?;
        if self.fixed.as_array().iter().all(Option::is_some)
            && !self.estimate_initial_state
            && !self.estimate_offset
        {
            return Err(IdentError::InvalidParameter {
                name: "fixed",
                value: 3.0,
                expected: "at least one quantity left to estimate",
            });
        }
        if let Some(ms) = &self.multistart {
            if ms.starts == 0 {
                return Err(IdentError::InvalidParameter {
                    name: "multistart.starts",
                    value: 0.0,
                    expected: "an integer >= 1",
                });
            }
            if ms.threads == 0 {
                return Err(IdentError::InvalidParameter {
                    name: "multistart.threads",
                    value: 0.0,
                    expected: "an integer >= 1",
                });
            }
            if !(ms.decades.is_finite() && ms.decades > 0.0) {
                return Err(IdentError::InvalidParameter {
                    name: "multistart.decades",
                    value: ms.decades,
                    expected: "a finite number > 0",
                });
            }
        }
        self.nelder_mead.validate()?;
        self.levenberg_marquardt.validate()?;
        Ok(())
    }
}
