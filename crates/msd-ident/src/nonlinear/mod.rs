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
//! `quadratic_viscous`, `linear`, `cubic`), not a code path per model.
//!
//! ## Simulation
//! [`NonlinearSimulation`] picks the solver ([`NonlinearSolver`]); by default
//! - on measured data (a force known only by its samples) classical RK4 sample interval
//!   by sample interval on the hold polynomial of the force (cubic by default, as the
//!   linear model's exact backend), with as many sub-steps as the model's fastest
//!   eigenvalue needs (ρ·h ≤ 0.1): an adaptive solver stepping across the kink at every
//!   sample keeps rejecting steps, a fixed step restarted at each sample never does.
//!   The estimate reports the output's error by step doubling ([`SimulationUsed`]);
//! - on a known signal (synthetic data, the paper's way) msd-ode's ode45 (Dormand–Prince
//!   5(4)) with the force evaluated continuously, RelTol 1e-8 and AbsTol 1e-12.
//!
//! Under either, the estimator's Jacobian comes from the forward sensitivity equations
//! of each damping and stiffness law ([`nonlinear_sensitivities`]) integrated beside the
//! state by the same RK4, one augmented simulation a Jacobian: the exact derivative of
//! the RK4 output, and of ode45's to within the two solvers' agreement.
//!
//! ## Coulomb friction: regularised, not event-located
//! sign(x') is replaced by tanh(x'/v_s) with the smoothing velocity v_s by default
//! 1e-3 × the RMS velocity of the nominal (linear-part) response
//! ([`SmoothingVelocity`]). Why: the solvers step smoothly through every velocity
//! reversal (with event location they would stop and restart at each one, and handle
//! sticking with a separate mode); and for estimation a smooth model keeps the output
//! differentiable in F_c (slope F_c/v_s·(1 − tanh²) in x'), so the sensitivities and
//! the Gauss–Newton covariance stay meaningful. The price is a slight viscous-like
//! behaviour for |x'| ≲ v_s, negligible at 0.1 % of the typical speed, and a stiff
//! slope F_c/(m·v_s) there, which RK4 resolves with more sub-steps.
//!
//! ## The estimator
//! [`estimate_nonlinear`]: output error Σ(ŷ − y)² with each ŷ one simulation.
//! Start: the linear estimate ([`estimate`](crate::estimate::estimate()), fast method) with zero
//! nonlinear coefficients. Parameters are scaled: ln m, ln c, ln k (positive), and
//! F_c/s, c₂/s, k₃/s (which may be 0, and k₃ negative) with s making the nonlinear force
//! comparable to the linear one at the output's RMS amplitude (s = c·v_rms for F_c,
//! c/v_rms for c₂, k/x_rms² for k₃, v_rms = x_rms·ωₙ). Levenberg–Marquardt with the
//! exact Jacobian (default; F_c ≥ 0 and c₂ ≥ 0 kept by bounds, see
//! [`NonlinearOptions::dissipative_damping`]) or Nelder–Mead, optionally multistart. The
//! covariance is σ̂²·D(JᵀJ)⁻¹D from the sensitivities at the optimum (D: the chain rule
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
//! use msd_ident::{Excitation, nonlinear::{DampingLaw, estimate_nonlinear, ModelStructure, NonlinearOptions, NonlinearParameters, NonlinearSimulation, StiffnessLaw, synthetic_nonlinear_data}, SyntheticOptions};
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
mod problem;
mod rk4;
mod simulate;

pub use crate::law::DampingLaw;
pub use compare::{
    CandidateFailure, Comparison, ComparisonOptions, ComparisonRow, FixedModel, ValidationStart,
    assess_estimate, bic_evidence, compare_models, fit_initial_state,
};
pub use estimate::{
    NonlinearEstimate, NonlinearMethod, NonlinearMultistart, NonlinearOptions, estimate_nonlinear,
    synthetic_nonlinear_data,
};
pub use model::{ModelStructure, NonlinearParameters, StiffnessLaw};
pub use simulate::{
    NonlinearSensitivities, NonlinearSimulation, NonlinearSolver, SimulationUsed,
    SmoothingVelocity, nonlinear_sensitivities, simulate_nonlinear,
};
