//! Imposed motion, measured force: a damper dynamometer or servo-hydraulic test machine
//! imposes a stroke x(t) (a sine of frequency f and amplitude X per test condition),
//! measures it and the force F, and F = m·x″ + f_d(x′) + k·x (+ a load-cell offset F₀)
//! with f_d one of the [`DampingLaw`]s.
//!
//! See [`dynamometer()`] for the method.

mod condition;
mod harmonics;
mod inverse;
mod law_fit;
mod left_out;
mod predicted;
mod recording;
mod regression;
mod summary;
mod synthetic;

pub use condition::{Condition, MIN_CYCLES};
pub use inverse::{
    ForcePrediction, InverseCoefficient, InverseDynamics, InverseLaw, InverseOptions,
    inverse_dynamics,
};
pub use law_fit::LawFit;
pub use left_out::ConditionPrediction;
pub use predicted::PredictedLaw;
pub use recording::{machine_recording, stroke_and_force};
pub use summary::ConditionSummary;
pub use synthetic::{Stroke, SyntheticDynamometer, synthetic_dynamometer};

use crate::{
    error::{IdentError, Result},
    nonlinear::{DampingLaw, SmoothingVelocity, bic_evidence},
};
pub use harmonics::fundamental_share;
use harmonics::{HarmonicFit, estimate_frequency};
use regression::{Needs, Normal, Prepared};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Options of [`dynamometer()`].
///
/// ```
/// use msd_ident::dynamometer::DynamometerOptions;
/// let o = DynamometerOptions::default();
/// assert_eq!((o.harmonics, o.laws.len(), o.known_mass, o.force_offset), (5, 3, None, true));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DynamometerOptions {
    /// Harmonics H of the stroke frequency in the Fourier fits. By default 5: a
    /// hydraulic actuator's stroke distortion lives in the first few harmonics, and
    /// each further one adds noise (h·ω)²·σₓ to x̂″.
    pub harmonics: usize,
    /// The damping laws compared. By default all three.
    pub laws: Vec<DampingLaw>,
    /// The moving mass, kg, when known (weighed): then not estimated. By default
    /// estimated.
    pub known_mass: Option<f64>,
    /// Whether a constant force F₀ (load-cell zero, gas-spring preload) is estimated. By
    /// default true.
    pub force_offset: bool,
    /// The Coulomb law's smoothing velocity v_s. By default 1e-3 × the RMS of x̂′ over
    /// all conditions, as the nonlinear module's.
    pub smoothing_velocity: SmoothingVelocity,
}

impl Default for DynamometerOptions {
    fn default() -> Self {
        Self {
            harmonics: 5,
            laws: vec![
                DampingLaw::Viscous,
                DampingLaw::CoulombViscous,
                DampingLaw::QuadraticViscous,
            ],
            known_mass: None,
            force_offset: true,
            smoothing_velocity: SmoothingVelocity::default(),
        }
    }
}

impl DynamometerOptions {
    /// Checks the ranges: 1 ≤ harmonics ≤ 50, at least one law, a known mass finite ≥ 0,
    /// a smoothing velocity finite > 0.
    pub fn validate(&self) -> Result<()> {
        let invalid = |name, value: f64, expected| {
            Err(IdentError::InvalidParameter {
                name,
                value,
                expected,
            })
        };
        if !(1..=50).contains(&self.harmonics) {
            return invalid(
                "harmonics",
                self.harmonics as f64,
                "an integer from 1 to 50",
            );
        }
        if self.laws.is_empty() {
            return invalid("laws", 0.0, "at least one damping law");
        }
        if let Some(m) = self.known_mass
            && !(m.is_finite() && m >= 0.0)
        {
            return invalid("known_mass", m, "a finite number ≥ 0 kg");
        }
        let (SmoothingVelocity::Relative(v) | SmoothingVelocity::Absolute(v)) =
            self.smoothing_velocity;
        if !(v.is_finite() && v > 0.0) {
            return invalid("smoothing_velocity", v, "a finite number > 0");
        }
        Ok(())
    }
}

/// The result of [`dynamometer()`]: each condition's summary and each law's fit.
///
/// Displays as two Markdown tables (conditions; laws, ranked) and the verdict.
///
/// ```
/// use msd_ident::{dynamometer::{dynamometer, DynamometerOptions, synthetic_dynamometer, SyntheticDynamometer}, nonlinear::DampingLaw};
/// let conditions = synthetic_dynamometer(&SyntheticDynamometer::default())?;
/// let result = dynamometer(&conditions, &DynamometerOptions::default())?;
/// assert_eq!(result.laws[result.best].rank, 1);
/// assert!(result.law(DampingLaw::Viscous).unwrap().delta_bic > 10.0);
/// // The F–v plot of condition 9 (8 Hz, 25 mm): measured points about the fitted law.
/// let points = result.measured_damping_force(9, result.best);
/// assert_eq!(points.len(), result.conditions[9].velocity.len());
/// assert!(result.to_string().contains("| rank | law |"));
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Dynamometer {
    /// One summary per condition, in input order.
    pub conditions: Vec<ConditionSummary>,
    /// One fit per law, in the order of [`DynamometerOptions::laws`].
    pub laws: Vec<LawFit>,
    /// Index in `laws` of the lowest BIC.
    pub best: usize,
    /// Harmonics of the Fourier fits.
    pub harmonics: usize,
    /// Which law the evidence supports and how strongly.
    pub verdict: String,
    /// Validation on fresh data: each condition's force predicted by the best law fitted
    /// to the other conditions (three conditions or more; `None` with fewer).
    pub leave_one_out: Option<Vec<ConditionPrediction>>,
}

impl Dynamometer {
    /// The law with the lowest BIC.
    pub fn best_law(&self) -> &LawFit {
        &self.laws[self.best]
    }

    /// The law `law`, if it was fitted.
    pub fn law(&self, law: DampingLaw) -> Option<&LawFit> {
        self.laws.iter().find(|l| l.law == law)
    }

    /// The measured damping force of condition `condition` under fit `law` (indices):
    /// F − (m·x̂″ + k·x̂ + F₀), the points of the F–v plot around `law`'s curve.
    pub fn measured_damping_force(&self, condition: usize, law: usize) -> Vec<f64> {
        let (c, l) = (&self.conditions[condition], &self.laws[law]);
        let model = &l.model_force[condition];
        (0..c.force.len())
            .map(|i| c.force[i] - model[i] + l.damping_force(c.velocity[i]))
            .collect()
    }
}

impl std::fmt::Display for Dynamometer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "| condition | f Hz | X mm | E J | c_eq N·s/m | k′ N/m | η | peak F N | peak v m/s |"
        )?;
        writeln!(f, "|---|---|---|---|---|---|---|---|---|")?;
        for c in &self.conditions {
            writeln!(f, "{c}")?;
        }
        if self.conditions.iter().any(|c| c.frequency_estimated) {
            writeln!(f, "(* frequency estimated from the stroke)")?;
        }
        writeln!(f)?;
        writeln!(f, "| rank | law | p | coefficients | σ̂_F N | BIC | ΔBIC |")?;
        writeln!(f, "|---|---|---|---|---|---|---|")?;
        let mut order: Vec<&LawFit> = self.laws.iter().collect();
        order.sort_by_key(|l| l.rank);
        for l in order {
            writeln!(f, "{l}")?;
        }
        write!(f, "\n{}", self.verdict)?;
        if let Some(predictions) = &self.leave_one_out {
            write!(f, "\nthe best law fitted to the other conditions predicts:")?;
            for p in predictions {
                write!(f, "\n  {}: {}", p.condition, p.fit)?;
            }
        }
        Ok(())
    }
}

/// Identifies the damper of a test machine from its `conditions`: per condition the
/// loop's summary, across all conditions each law's coefficients with 95 % intervals,
/// and the laws ranked by BIC.
///
/// Refused with a located message: an invalid option, a condition whose fields do not
/// match, are not finite, constant, shorter than [`MIN_CYCLES`] whole cycles or with a
/// harmonic past Nyquist; m free with a single stroke frequency; collinear regressors.
///
/// ## The algorithm
/// 1. Per condition ([`Condition`]): the stroke frequency (given, or by the IEEE 1057
///    four-parameter sine fit), the samples of its whole cycles, and a least-squares
///    Fourier series of H harmonics of f fitted to the stroke and to the force.
///    Differentiated analytically, the stroke's series gives x̂′ and x̂″ with no
///    amplification of the noise beyond the H-th harmonic.
/// 2. Per condition, model-free ([`ConditionSummary`]): the energy per cycle ∮F dx, the
///    equivalent viscous damping, the storage stiffness, the loss factor, peaks.
/// 3. Across all conditions, each requested law by linear least squares on the regressors
///    x̂″, x̂′, x̂, the law's term (x̂′|x̂′| or tanh(x̂′/v_s)) and 1 ([`LawFit`]); the laws
///    ranked by BIC = N·ln(SSE/N) + p·ln N and the margin graded on Kass & Raftery's
///    scale ([`bic_evidence`]).
///
/// ## The intervals
/// The covariance of the coefficients β̂ is the least-squares one, σ̂_F²·(XᵀX)⁻¹, plus the
/// stroke noise: the noise of the measured stroke (σ̂ₓ, from the residual of its Fourier
/// fit) makes each condition's harmonic coefficients θ uncertain, Cov θ = σ̂ₓ²·(GᵀG)⁻¹,
/// and every regressor is a function of θ. To first order (the delta method for errors in
/// the variables) the force equation's error gains −∂F̂/∂θ·Δθ, hence
/// Cov β̂ = (XᵀX)⁻¹·[σ̂_F²·XᵀX + Σ_c σ̂ₓ²·S_c·(GᵀG)⁻¹·S_cᵀ]·(XᵀX)⁻¹ with
/// S_c = Xᵀ·∂F̂/∂θ_c. σ̂_F² = SSE/(N − p) also holds that stroke-noise force, a share of
/// order (2H + 1)·conditions/N of it (conservative, negligible). The intervals use
/// Student's t with N − p degrees of freedom. An estimated frequency is taken as exact
/// (its error, of order σ/(X·N^{3/2}), is far below the amplitude's).
///
/// ## Identifiability
/// A sine stroke at one frequency gives m·x″ + k·x = (k − m·ω²)·x: m and k apart need two
/// or more frequencies, or a known mass ([`DynamometerOptions::known_mass`]); the
/// analysis refuses otherwise.
///
/// ```
/// use msd_ident::{dynamometer::{dynamometer, DynamometerOptions, synthetic_dynamometer, SyntheticDynamometer}, nonlinear::DampingLaw};
/// let spec = SyntheticDynamometer::default(); // a quadratic damper, 5 frequencies × 2 strokes
/// let conditions = synthetic_dynamometer(&spec)?;
/// let result = dynamometer(&conditions, &DynamometerOptions::default())?;
/// assert_eq!(result.best_law().law, DampingLaw::QuadraticViscous);
/// let c2 = result.best_law().coefficient("quadratic_damping").unwrap();
/// assert!(c2.contains(spec.plant.quadratic_damping()));
/// println!("{result}");
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn dynamometer(conditions: &[Condition], options: &DynamometerOptions) -> Result<Dynamometer> {
    options.validate()?;
    let (summaries, laws) = fit_laws(conditions, options, None)?;
    let mut laws = laws;
    let (best, verdict) = rank(&mut laws);
    let leave_one_out = (conditions.len() >= left_out::FEWEST)
        .then(|| left_out::leave_one_condition_out(conditions, options, laws[best].law))
        .transpose()?;
    Ok(Dynamometer {
        conditions: summaries,
        laws,
        best,
        harmonics: options.harmonics,
        verdict,
        leave_one_out,
    })
}

/// The noise levels of a planned test machine.
///
/// ```
/// let noise = msd_ident::dynamometer::DynamometerNoise { force_sigma: 2.0, stroke_sigma: 1e-5 };
/// assert!(noise.stroke_sigma < noise.force_sigma);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DynamometerNoise {
    /// The load cell's white noise σ_F, N (> 0).
    pub force_sigma: f64,
    /// The stroke sensor's white noise σₓ, m (≥ 0).
    pub stroke_sigma: f64,
}

/// The prediction of [`dynamometer()`]'s intervals before the test: each law of `options`
/// fitted to the noise-free `conditions` (the planned strokes and the prior plant's
/// force), its covariance the analysis's own — σ_F²·(XᵀX)⁻¹ plus the stroke noise carried
/// through the harmonic fits — with the noise levels of `noise` in place of the
/// estimated ones. For the plant's own law the values are the plant's and the
/// covariance is exact for the force noise (linear least squares given the strokes) and
/// first order for the stroke noise.
///
/// ```
/// use msd_ident::{dynamometer::{dynamometer, DynamometerNoise, DynamometerOptions, predicted_dynamometer, synthetic_dynamometer, SyntheticDynamometer}, nonlinear::DampingLaw};
/// let mut spec = SyntheticDynamometer::default();
/// let noise = DynamometerNoise { force_sigma: spec.force_noise, stroke_sigma: 0.0 };
/// (spec.force_noise, spec.displacement_noise) = (0.0, 0.0); // the planned strokes, noise-free
/// let options = DynamometerOptions { laws: vec![DampingLaw::QuadraticViscous], ..Default::default() };
/// let planned = predicted_dynamometer(&synthetic_dynamometer(&spec)?, &noise, &options)?;
/// let c2 = planned[0].coefficient("quadratic_damping").unwrap();
/// assert!((c2.value / spec.plant.quadratic_damping() - 1.0).abs() < 1e-6);
/// assert!(c2.standard_error > 0.0);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn predicted_dynamometer(
    conditions: &[Condition],
    noise: &DynamometerNoise,
    options: &DynamometerOptions,
) -> Result<Vec<PredictedLaw>> {
    options.validate()?;
    let valid = |v: f64, low: f64| v.is_finite() && v >= low;
    if !(valid(noise.force_sigma, 0.0) && noise.force_sigma > 0.0) {
        return Err(IdentError::InvalidParameter {
            name: "force_sigma",
            value: noise.force_sigma,
            expected: "a finite noise level > 0 N",
        });
    }
    if !valid(noise.stroke_sigma, 0.0) {
        return Err(IdentError::InvalidParameter {
            name: "stroke_sigma",
            value: noise.stroke_sigma,
            expected: "a finite noise level ≥ 0 m",
        });
    }
    let (_, laws) = fit_laws(conditions, options, Some(noise))?;
    Ok(laws.into_iter().map(PredictedLaw::from).collect())
}

/// Each condition's summary and each law's fit; with `noise`, the noise levels given
/// instead of estimated.
fn fit_laws(
    conditions: &[Condition],
    options: &DynamometerOptions,
    noise: Option<&DynamometerNoise>,
) -> Result<(Vec<ConditionSummary>, Vec<LawFit>)> {
    if conditions.is_empty() {
        return Err(IdentError::TooFewSamples {
            got: 0,
            needed: 1,
            why: "a dynamometer analysis needs at least one test condition",
        });
    }
    let mut summaries = Vec::with_capacity(conditions.len());
    let mut prepared = Vec::with_capacity(conditions.len());
    for c in conditions {
        let (summary, mut ready) = prepare(c, options.harmonics)?;
        if let Some(noise) = noise {
            ready.fit.stroke_sigma = noise.stroke_sigma;
        }
        summaries.push(summary);
        prepared.push(ready);
    }
    check_frequencies(&summaries, options)?;
    let smoothing = smoothing_velocity(&prepared, options.smoothing_velocity);
    let needs = Needs {
        quadratic: options.laws.contains(&DampingLaw::QuadraticViscous),
        coulomb: options.laws.contains(&DampingLaw::CoulombViscous),
    };
    let mut normal = Normal::default();
    for (c, p) in conditions.iter().zip(&mut prepared) {
        p.accumulate(c.dt(), 1.0 / smoothing, needs, &mut normal);
    }
    let mut laws = Vec::with_capacity(options.laws.len());
    for &law in &options.laws {
        if laws.iter().all(|l: &LawFit| l.law != law) {
            let sigma = noise.map(|n| n.force_sigma);
            laws.push(law_fit::fit_law(
                law, &prepared, &normal, smoothing, options, sigma,
            )?);
        }
    }
    Ok((summaries, laws))
}

/// Validates one condition, finds its frequency and whole cycles, fits its harmonics.
fn prepare(c: &Condition, harmonics: usize) -> Result<(ConditionSummary, Prepared)> {
    c.validate(harmonics)?;
    let (f, estimated) = match c.frequency_hz {
        Some(f) => (f, false),
        None => {
            let f = estimate_frequency(c.dt(), c.displacement()).ok_or_else(|| {
                let found = "fewer than two upward zero crossings".to_string();
                c.invalid(
                    "displacement",
                    found,
                    format!("at least {MIN_CYCLES} whole cycles"),
                )
            })?;
            c.check_frequency(f, harmonics)?;
            (f, true)
        }
    };
    let (cycles, n) = c.whole_cycles(f);
    let (x, force) = (&c.displacement()[..n], &c.force()[..n]);
    let fit = HarmonicFit::new(c.dt(), 2.0 * PI * f, harmonics, x, force).ok_or_else(|| {
        c.invalid(
            "displacement",
            "a singular Fourier basis".into(),
            "whole cycles of f",
        )
    })?;
    let summary = ConditionSummary::new(c.name(), &fit, (cycles, estimated), x, force);
    let ready = Prepared {
        fit,
        force: force.to_vec(),
        projection: Vec::new(),
        quadratic_slope: Vec::new(),
        coulomb_slope: Vec::new(),
        quadratic_grams: Default::default(),
        coulomb_grams: Default::default(),
    };
    Ok((summary, ready))
}

/// m and k apart need two stroke frequencies (or a known mass).
fn check_frequencies(summaries: &[ConditionSummary], options: &DynamometerOptions) -> Result<()> {
    let first = summaries[0].frequency_hz;
    let distinct = summaries
        .iter()
        .any(|s| (s.frequency_hz / first - 1.0).abs() > 1e-6);
    if options.known_mass.is_none() && !distinct {
        return Err(IdentError::NotIdentifiable {
            reason: format!(
                "every condition strokes at {first} Hz, where m·x″ + k·x = (k − m·ω²)·x: m and \
                 k are not separately identifiable; test at two or more frequencies or fix \
                 the mass (`known_mass`)"
            ),
        });
    }
    Ok(())
}

/// v_s in m/s: absolute, or relative to the RMS of x̂′ over all conditions.
fn smoothing_velocity(prepared: &[Prepared], rule: SmoothingVelocity) -> f64 {
    match rule {
        SmoothingVelocity::Absolute(v) => v,
        SmoothingVelocity::Relative(factor) => {
            let (mut squares, mut n) = (0.0, 0usize);
            for p in prepared {
                squares += p.fit.velocity.iter().map(|v| v * v).sum::<f64>();
                n += p.fit.velocity.len();
            }
            factor * (squares / n as f64).sqrt()
        }
    }
}

/// Ranks the laws by BIC (1 = lowest) and words the verdict.
fn rank(laws: &mut [LawFit]) -> (usize, String) {
    let mut order: Vec<usize> = (0..laws.len()).collect();
    order.sort_by(|&a, &b| laws[a].bic.total_cmp(&laws[b].bic));
    let lowest = laws[order[0]].bic;
    for (r, &i) in order.iter().enumerate() {
        laws[i].rank = r + 1;
        laws[i].delta_bic = laws[i].bic - lowest;
    }
    let best = &laws[order[0]];
    let verdict = match order.get(1).map(|&i| &laws[i]) {
        None => format!("Only the {:?} law was fitted.", best.law),
        Some(runner) => format!(
            "The evidence supports the {:?} law (lowest BIC); over the runner-up {:?} \
             ΔBIC = {:.1}: {} evidence on Kass & Raftery's scale (>10 very strong, 6–10 \
             strong, 2–6 positive).",
            best.law,
            runner.law,
            runner.delta_bic,
            bic_evidence(runner.delta_bic)
        ),
    };
    (order[0], verdict)
}
