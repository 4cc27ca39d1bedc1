//! The optional `[nonlinear]` section: estimate one nonlinear model (`model`) or compare
//! candidate models by BIC (`compare`, the linear baseline always included), with
//! msd-ident's [`estimate_nonlinear`](msd_ident::nonlinear::estimate_nonlinear) and
//! [`compare_models`](msd_ident::nonlinear::compare_models). Off unless present.
//!
//! ```
//! use msd_ident::{nonlinear::{DampingLaw, ModelStructure, StiffnessLaw}};
//! use msd_experiment::config::{Candidates, NonlinearSection};
//! let section: NonlinearSection = toml::from_str(r#"
//!     compare = [{ damping = "viscous", stiffness = "cubic" }]
//!     max_evaluations = 200
//! "#).unwrap();
//! let duffing = ModelStructure { damping: DampingLaw::Viscous, stiffness: StiffnessLaw::Cubic };
//! assert_eq!(section.compare, Some(Candidates::List(vec![duffing])));
//! assert_eq!(section.candidates(), [ModelStructure::LINEAR, duffing]);
//! let all: NonlinearSection = toml::from_str(r#"compare = "all""#).unwrap();
//! assert_eq!(all.candidates().len(), 6);
//! ```

use super::{check_positive, default_true};
use msd_ident::nonlinear::{
    ModelStructure, NonlinearMethod, NonlinearSimulation, SmoothingVelocity,
};
use msd_ident::residuals::sandwich::ResidualCovariance;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// The `[nonlinear]` section.
///
/// By default (for every optional field) msd-ident's [`msd_ident::nonlinear::NonlinearOptions`]:
/// Levenberg–Marquardt with the Jacobian from the forward sensitivities, the solver
/// `auto` (RK4 on the cubic hold for measured data, ode45 RelTol 1e-8 and AbsTol 1e-12
/// for a known signal), Coulomb smoothing velocity 1e-3 × the nominal RMS velocity,
/// dissipative damping, no multistart.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NonlinearSection {
    /// Estimate this one model, e.g. `{ damping = "viscous", stiffness = "cubic" }`.
    /// Give this or `compare`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<ModelStructure>,
    /// Compare these candidates (`"all"` for all six); the linear model is always added
    /// as the baseline. Give this or `model`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compare: Option<Candidates>,
    /// `"levenberg_marquardt"` or `"nelder_mead"`. By default the former.
    #[serde(default)]
    pub method: NonlinearMethod,
    /// The solver (`"auto"`, `"rk4"` or `"ode45"`), RK4's hold (`"zero"`, `"first"`,
    /// `"cubic"`), ode45's tolerances and the Coulomb smoothing velocity,
    /// `{ solver, hold, rel_tol, abs_tol, smoothing_velocity = { relative = 1e-3 } }` (or
    /// `{ absolute = v }`). By default auto, cubic, 1e-8, 1e-12, relative 1e-3.
    #[serde(default)]
    pub simulation: NonlinearSimulation,
    /// Estimate x(t₀) and x'(t₀) with the parameters. By default as
    /// `estimation.estimate_initial_state`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub estimate_initial_state: Option<bool>,
    /// Keep F_c ≥ 0 and c₂ ≥ 0 by bounds. By default true.
    #[serde(default = "default_true")]
    pub dissipative_damping: bool,
    /// Cost evaluations of one local run. By default 20·(p + 1) for Levenberg–Marquardt
    /// and fminsearch's 200·p for Nelder–Mead.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_evaluations: Option<usize>,
    /// Local runs from a Latin hypercube around the start (off unless given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub multistart: Option<NonlinearMultistartSection>,
    /// How the intervals treat the residuals: `"auto"` (the block sandwich where the
    /// identification residuals fail the whiteness test), `"white"` or `"sandwich"`.
    /// By default auto.
    #[serde(default)]
    pub covariance: ResidualCovariance,
}

/// `[nonlinear.multistart]`: msd-ident's [`msd_ident::nonlinear::NonlinearMultistart`], its
/// threads set by the run (`--threads`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NonlinearMultistartSection {
    /// Number of starts, the nominal one included. By default 8.
    pub starts: usize,
    /// Half-width of the box for m, c, k in decades. By default 0.5.
    pub decades: f64,
    /// Half-width of the box for the nonlinear coefficients in scale units. By default 1.
    pub nonlinear_width: f64,
    /// Seed of the design. By default the experiment's seed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
}

impl Default for NonlinearMultistartSection {
    fn default() -> Self {
        let d = msd_ident::nonlinear::NonlinearMultistart::default();
        Self {
            starts: d.starts,
            decades: d.decades,
            nonlinear_width: d.nonlinear_width,
            seed: None,
        }
    }
}

/// The candidates of a comparison: `"all"` or a list of `{ damping, stiffness }`.
#[derive(Debug, Clone, PartialEq)]
pub enum Candidates {
    /// All six structures.
    All,
    /// These structures, in order.
    List(Vec<ModelStructure>),
}

impl Serialize for Candidates {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            Candidates::All => s.serialize_str("all"),
            Candidates::List(v) => v.serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for Candidates {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = Candidates;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(r#""all" or a list of { damping, stiffness }"#)
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<Candidates, E> {
                if v == "all" {
                    Ok(Candidates::All)
                } else {
                    Err(E::invalid_value(serde::de::Unexpected::Str(v), &self))
                }
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                seq: A,
            ) -> std::result::Result<Candidates, A::Error> {
                Vec::<ModelStructure>::deserialize(serde::de::value::SeqAccessDeserializer::new(
                    seq,
                ))
                .map(Candidates::List)
            }
        }
        d.deserialize_any(Visitor)
    }
}

impl NonlinearSection {
    /// The models to estimate: the one `model`, or the linear baseline followed by the
    /// `compare` candidates (each once).
    pub fn candidates(&self) -> Vec<ModelStructure> {
        if let Some(m) = self.model {
            return vec![m];
        }
        let listed = match &self.compare {
            Some(Candidates::All) | None => ModelStructure::all(),
            Some(Candidates::List(v)) => v.clone(),
        };
        let mut out = vec![ModelStructure::LINEAR];
        for s in listed {
            if !out.contains(&s) {
                out.push(s);
            }
        }
        out
    }

    /// Whether this asks for a comparison (else one model).
    pub fn is_comparison(&self) -> bool {
        self.model.is_none()
    }

    /// Checks every value; the error is the field path and the rest of the message.
    pub(super) fn validate(
        &self,
        estimation: &msd_ident::EstimationOptions,
    ) -> std::result::Result<(), (String, String)> {
        let err = |field: &str, message: String| Err((field.to_string(), message));
        match (&self.model, &self.compare) {
            (None, None) => {
                return err(
                    "nonlinear",
                    ": neither `model` nor `compare` given: expected exactly one (a model to estimate, or the candidates to compare)".into(),
                );
            }
            (Some(_), Some(_)) => {
                return err(
                    "nonlinear.compare",
                    ": both `model` and `compare` given: expected exactly one".into(),
                );
            }
            (None, Some(Candidates::List(list))) => {
                if list.is_empty() {
                    return err(
                        "nonlinear.compare",
                        " = []: expected \"all\" or at least one candidate { damping, stiffness } (the linear baseline is always added)".into(),
                    );
                }
                for (i, s) in list.iter().enumerate() {
                    if let Some(j) = list[..i].iter().position(|t| t == s) {
                        return err(
                            &format!("nonlinear.compare[{i}]"),
                            format!(
                                " = {s}: the same candidate as compare[{j}]: expected each candidate once"
                            ),
                        );
                    }
                }
            }
            _ => {}
        }
        if estimation.estimate_offset || estimation.offset != 0.0 {
            return err(
                "nonlinear",
                format!(
                    ": not available with a sensor offset (estimation.estimate_offset = {}, estimation.offset = {}): expected no offset, since the nonlinear models have none (remove the mean in data.preprocessing instead)",
                    estimation.estimate_offset, estimation.offset
                ),
            );
        }
        let sim = &self.simulation;
        check_positive("nonlinear.simulation.rel_tol", sim.rel_tol)?;
        check_positive("nonlinear.simulation.abs_tol", sim.abs_tol)?;
        let (name, v) = match sim.smoothing_velocity {
            SmoothingVelocity::Relative(v) => ("relative", v),
            SmoothingVelocity::Absolute(v) => ("absolute", v),
        };
        check_positive(
            &format!("nonlinear.simulation.smoothing_velocity.{name}"),
            v,
        )?;
        if let Err(e) = sim.validate() {
            return err("nonlinear.simulation", format!(": {e}"));
        }
        if self.max_evaluations == Some(0) {
            return err(
                "nonlinear.max_evaluations",
                " = 0: expected an integer >= 1".into(),
            );
        }
        if let Some(ms) = &self.multistart {
            if ms.starts < 2 {
                return err(
                    "nonlinear.multistart.starts",
                    format!(
                        " = {}: expected an integer >= 2 (the nominal start and at least one more)",
                        ms.starts
                    ),
                );
            }
            check_positive("nonlinear.multistart.decades", ms.decades)?;
            check_positive("nonlinear.multistart.nonlinear_width", ms.nonlinear_width)?;
        }
        Ok(())
    }
}
