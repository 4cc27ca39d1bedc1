//! Beyond linear: Coulomb and quadratic damping, cubic stiffness, and automatic model
//! selection.
//!
//! ## The models
//! m·x'' + f_d(x') + f_s(x) = F(t), a [`ModelStructure`] choosing
//! - the damping law f_d ([`DampingLaw`]): viscous c·x'; Coulomb + viscous
//!   F_c·sign(x') + c·x'; quadratic + viscous c₂·x'|x'| + c·x';
//! - the stiffness law f_s ([`StiffnessLaw`]): linear k·x; cubic k·x + k₃·x³ (Duffing,
//!   as in the Silverbox).
//!
//! The six structures share one simulator and one estimator: a candidate set is data
//! (e.g. a list in a config, serde names `viscous`, `coulomb_viscous`,
//! `quadratic_viscous`, `linear`, `cubic`), not a code path per model. Every model is
//! simulated by msd-ode's ode45 (Dormand–Prince 5(4)), the force evaluated continuously
//! (the exact simulator applies only to the linear model), by default with RelTol 1e-8
//! and AbsTol 1e-12 so that finite differences see the model, not the solver's error.
//!
//! ## Coulomb friction: regularised, not event-located
//! sign(x') is replaced by tanh(x'/v_s) with the smoothing velocity v_s by default
//! 1e-3 × the RMS velocity of the nominal (linear-part) response
//! ([`SmoothingVelocity`]). Why: the adaptive solver steps smoothly through every
//! velocity reversal (with event location it would stop and restart at each one, and
//! handle sticking with a separate mode); and for estimation a smooth model keeps the
//! output differentiable in F_c, so finite-difference Jacobians and the Gauss–Newton
//! covariance stay meaningful. The price is a slight viscous-like behaviour for
//! |x'| ≲ v_s, negligible at 0.1 % of the typical speed.
//!
//! ## The estimator
//! [`estimate_nonlinear`]: output error Σ(ŷ − y)² with each ŷ an ode45 simulation.
//! Start: the linear estimate ([`estimate`](crate::estimate), fast method) with zero
//! nonlinear coefficients. Parameters are scaled: ln m, ln c, ln k (positive), and
//! F_c/s, c₂/s, k₃/s (which may be 0, and k₃ negative) with s making the nonlinear force
//! comparable to the linear one at the output's RMS amplitude (s = c·v_rms for F_c,
//! c/v_rms for c₂, k/x_rms² for k₃, v_rms = x_rms·ωₙ). Levenberg–Marquardt with central
//! differences (default; F_c ≥ 0 and c₂ ≥ 0 kept by bounds, see
//! [`NonlinearOptions::dissipative_damping`]) or Nelder–Mead, optionally multistart. The covariance is
//! σ̂²·D(JᵀJ)⁻¹D from the central-difference Jacobian at the optimum (D: the chain rule
//! from the scaled to the physical parameters), with Student-t 95 % intervals.
//!
//! ## Selection
//! [`compare_models`] estimates each candidate (the linear model always included as the
//! baseline), predicts the validation data, and ranks by BIC = N·ln(SSE/N) + p·ln N (AIC
//! = N·ln(SSE/N) + 2p is reported too), with validation RMS/fit, Ljung–Box whiteness and
//! residual–input cross-correlation; the verdict grades the BIC margin on Kass &
//! Raftery's scale (> 10 very strong, 6–10 strong, 2–6 positive).
//!
//! ## For a driver (the xtask)
//! A config can name one model (a [`ModelStructure`], e.g.
//! `{ damping = "quadratic_viscous", stiffness = "cubic" }`) for [`estimate_nonlinear`]
//! (scored on validation data like a comparison's row by [`assess_estimate`]),
//! or a list of them for [`compare_models`]; [`NonlinearOptions`] and
//! [`ComparisonOptions`] deserialize with defaults for every field. A [`Comparison`]
//! prints as a Markdown table plus the verdict (`Display`), serializes for a
//! results file, and each [`ComparisonRow`] carries the validation output and residuals
//! (scored from `scored_from`) for a figure comparing the candidates' residuals.
//! Candidates that fail (e.g. with `dissipative_damping = false`, a negative c₂ estimate
//! whose prediction diverges) are listed in [`Comparison::failures`] instead of
//! aborting the comparison.
//!
//! ```
//! use msd_ident::{estimate_nonlinear, synthetic_nonlinear_data, DampingLaw, Excitation,
//!     ModelStructure, NonlinearOptions, NonlinearParameters, NonlinearSimulation,
//!     StiffnessLaw, SyntheticOptions};
//! use msd_signal::paper_identification_input;
//! let duffing = ModelStructure { damping: DampingLaw::Viscous, stiffness: StiffnessLaw::Cubic };
//! let plant = NonlinearParameters::new(duffing, vec![2.5, 1.8, 120.0, 3000.0])?;
//! let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.004, 2001)?;
//! let noise = SyntheticOptions { seed: 5, ..SyntheticOptions::named("id") };
//! let (data, _) = synthetic_nonlinear_data(&plant, input, &NonlinearSimulation::default(), &noise)?;
//! let e = estimate_nonlinear(&data, duffing, &NonlinearOptions::default())?;
//! let k3 = e.intervals[3];
//! assert!((k3.value - 3000.0).abs() < 4.0 * k3.standard_error);
//! # Ok::<(), msd_ident::IdentError>(())
//! ```

mod compare;
mod estimate;
mod model;
mod simulate;

pub use compare::{
    CandidateFailure, Comparison, ComparisonOptions, ComparisonRow, FixedModel, ValidationStart,
    assess_estimate, bic_evidence, compare_models, fit_initial_state,
};
pub use estimate::{
    NonlinearEstimate, NonlinearMethod, NonlinearMultistart, NonlinearOptions, estimate_nonlinear,
    synthetic_nonlinear_data,
};
pub use model::{DampingLaw, ModelStructure, NonlinearParameters, StiffnessLaw};
pub use simulate::{NonlinearSimulation, SmoothingVelocity, simulate_nonlinear};
