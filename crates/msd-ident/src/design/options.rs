//! What a design optimises and within which limits; checked once, here.

use crate::{
    data::Excitation,
    error::{IdentError, Result},
    params::Parameters,
};
use serde::{Deserialize, Serialize};

/// The optimality criterion, on the covariance of the relative parameters
/// (m/m₀, c/c₀, k/k₀). In TOML `"d_optimal"`, `"a_optimal"` or `"minimax"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Criterion {
    /// The smallest determinant: the smallest joint confidence ellipsoid. The default.
    #[default]
    DOptimal,
    /// The smallest trace: the smallest mean relative variance.
    AOptimal,
    /// The smallest worst relative standard error of m, c and k.
    Minimax,
}

impl std::fmt::Display for Criterion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::DOptimal => "D-optimal",
            Self::AOptimal => "A-optimal",
            Self::Minimax => "minimax",
        })
    }
}

/// What the standard errors are measured against before the criterion combines them.
/// In TOML `"prior"` or `"reference"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Normalise {
    /// Relative to the prior's values: m/m₀, c/c₀, k/k₀. The default.
    #[default]
    Prior,
    /// Relative to the reference input's predicted standard errors: the minimax design
    /// then minimises the worst ratio to the reference, the A-optimal one their mean
    /// square (the D-optimal design is the same either way).
    Reference,
}

/// How the criterion is combined over the plants of the robust box. In TOML
/// `"average"` or `"worst"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Aggregate {
    /// The geometric mean of the plants' criteria. The default.
    #[default]
    Average,
    /// The worst plant's criterion (a smooth maximum while optimising).
    Worst,
}

/// The plants the stroke limit holds on. In TOML `"prior"` or `"every_plant"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StrokeOn {
    /// The prior plant only (the other plants of a robust box may exceed it: the design
    /// reports their peaks). The default.
    #[default]
    Prior,
    /// Every plant of the robust box: the rig's travel is safe whichever of them is the
    /// real plant, at the price of less force near the softest plants' resonances.
    EveryPlant,
}

/// A step in the input, for the static stiffness: its time, and the least height the
/// test needs (its amplitude is optimised with the rest).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepOption {
    /// When the step comes, s (rounded to a sample).
    pub time: f64,
    /// The least |height| of the step, N. By default 0 (free).
    #[serde(default)]
    pub min_amplitude: f64,
}

/// The limits of a designed input. The record's duration and sample rate are those of
/// the reference input's record.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DesignConstraints {
    /// Largest |force|, N. By default 9, the paper input's peak (6 N step + 3 N sine).
    pub max_force: f64,
    /// Largest RMS force, N. By default none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_rms_force: Option<f64>,
    /// Largest |displacement| (the stroke) on the prior plant, or on every plant of the
    /// box (`stroke_on`), m. By default 0.1115, the paper input's peak on the paper's
    /// plant.
    pub max_stroke: f64,
    /// The band of the excited lines, Hz. By default 0.2 … 4.2 (61 lines of a 15 s
    /// record's grid, around the paper plant's 1.10 Hz mode). Exactly two values.
    ///
    /// ```
    /// use msd_ident::design::DesignConstraints;
    /// assert!(toml::from_str::<DesignConstraints>("band_hz = [0.5, 3.0]").is_ok());
    /// let err = toml::from_str::<DesignConstraints>("band_hz = [0.5, 3.0, 9.0]").unwrap_err();
    /// assert!(err.to_string().contains("expected 2 values [low, high], got 3"), "{err}");
    /// ```
    #[serde(deserialize_with = "msd_signal::pair::exactly_two")]
    pub band_hz: [f64; 2],
    /// An optional step. By default none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step: Option<StepOption>,
    /// The plants `max_stroke` holds on. By default the prior only.
    pub stroke_on: StrokeOn,
}

impl Default for DesignConstraints {
    fn default() -> Self {
        Self {
            max_force: 9.0,
            max_rms_force: None,
            max_stroke: 0.1115,
            band_hz: [0.2, 4.2],
            step: None,
            stroke_on: StrokeOn::Prior,
        }
    }
}

/// The robust box: the design is optimised over `plants` plants, the prior and a
/// seeded Latin hypercube of m, c, k within ±`spread` of it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RobustBox {
    /// Relative half-width of the box. By default 0.3 (±30 %).
    pub spread: f64,
    /// Plants, the prior included. By default 1 (the prior only: not robust).
    pub plants: usize,
    /// How their criteria combine. By default the average.
    pub aggregate: Aggregate,
}

impl Default for RobustBox {
    fn default() -> Self {
        Self {
            spread: 0.3,
            plants: 1,
            aggregate: Aggregate::Average,
        }
    }
}

impl RobustBox {
    /// The box of a sequential design: around a pilot test's estimate of m, c and k,
    /// three of its largest relative standard errors wide (at least 1 %), instead of a
    /// guessed ±30 %.
    ///
    /// ```
    /// use msd_ident::{estimate, EstimationOptions, PaperExperiment, design::RobustBox};
    /// let pilot = estimate(&PaperExperiment::generate(3)?.identification, &EstimationOptions::fast())?;
    /// let u = &pilot.uncertainty;
    /// let robust = RobustBox::around(&[u.mass, u.damping, u.stiffness], 9);
    /// assert!(robust.spread >= 0.01 && robust.spread < 0.3);
    /// # Ok::<(), msd_ident::IdentError>(())
    /// ```
    pub fn around(pilot: &[msd_opt::statistics::Interval; 3], plants: usize) -> Self {
        let worst = pilot
            .iter()
            .map(|iv| iv.standard_error / iv.value.abs())
            .fold(0.0, f64::max);
        Self {
            spread: (3.0 * worst).clamp(0.01, 0.9),
            plants,
            aggregate: Aggregate::Average,
        }
    }
}

/// Everything a design needs besides the prior plant and the reference input. In TOML,
/// the `[design]` section of a config; every field optional.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DesignOptions {
    /// The criterion. By default D-optimal.
    pub criterion: Criterion,
    /// What the standard errors are measured against. By default the prior's values.
    pub normalise: Normalise,
    /// The limits.
    pub constraints: DesignConstraints,
    /// Lines of the multisine's frequency grid (every 1/period Hz) in the band (spread
    /// evenly over the band's lines when it has more). By default 60.
    pub lines: usize,
    /// The multisine's period, s: the record repeats it. By default the record, up to
    /// [`LONGEST_PERIOD`] samples; a longer record is split into the fewest equal
    /// periods of at most that many samples (a periodic input whose information is
    /// counted on one period and its repetitions, not along the whole record).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub period: Option<f64>,
    /// Time segments of equal length, each with its own amplitudes and phases. By
    /// default 1 (one multisine over the whole record).
    pub segments: usize,
    /// The plants the design is optimised over.
    pub robust: RobustBox,
    /// Starting points: Schroeder phases, then seeded random phases. By default 1.
    pub starts: usize,
    /// L-BFGS iterations per sharpness stage (3 stages). By default 100.
    pub iterations: usize,
    /// Seed of the random phases and of the robust box's plants. By default 0.
    pub seed: u64,
}

impl Default for DesignOptions {
    fn default() -> Self {
        Self {
            criterion: Criterion::DOptimal,
            normalise: Normalise::Prior,
            constraints: DesignConstraints::default(),
            lines: 60,
            period: None,
            segments: 1,
            robust: RobustBox::default(),
            starts: 1,
            iterations: 100,
            seed: 0,
        }
    }
}

fn invalid(key: &'static str, value: f64, expected: impl Into<String>) -> IdentError {
    IdentError::InvalidDesign {
        key,
        value,
        expected: expected.into(),
    }
}

fn positive(key: &'static str, value: f64) -> Result<()> {
    match value.is_finite() && value > 0.0 {
        true => Ok(()),
        false => Err(invalid(key, value, "a finite number > 0")),
    }
}

fn at_least_one(key: &'static str, value: usize) -> Result<()> {
    match value >= 1 {
        true => Ok(()),
        false => Err(invalid(key, value as f64, "at least 1")),
    }
}

/// The longest period, in samples, of a design's multisine by default.
pub const LONGEST_PERIOD: usize = 65_536;

impl DesignOptions {
    /// The multisine's period in samples on the record of `reference` (see
    /// [`period`](Self::period)).
    ///
    /// ```
    /// use msd_ident::{Excitation, design::DesignOptions};
    /// let short = Excitation::from_samples(0.0, 0.002, vec![0.0; 7501])?;
    /// let long = Excitation::from_samples(0.0, 0.002, vec![0.0; 1_000_000])?;
    /// let options = DesignOptions::default();
    /// assert_eq!(options.period_samples(&short), 7500); // the record
    /// assert_eq!(options.period_samples(&long), 62_500); // 16 periods of 125 s
    /// # Ok::<(), msd_ident::IdentError>(())
    /// ```
    pub fn period_samples(&self, reference: &Excitation) -> usize {
        let record = reference.len().max(2) - 1;
        match self.period {
            Some(t) => ((t / reference.dt()).round() as usize).clamp(1, record),
            None => record.div_ceil(record.div_ceil(LONGEST_PERIOD)),
        }
    }

    /// Checks every field for a design on `prior` over the record of `reference`, each
    /// error naming its key.
    ///
    /// ```
    /// use msd_ident::{Excitation, IdentError, Parameters, design::DesignOptions};
    /// let reference = Excitation::from_samples(0.0, 0.002, vec![0.0; 7501])?;
    /// let mut options = DesignOptions::default();
    /// options.constraints.band_hz = [1.0, 300.0];
    /// let err = options.validate(&Parameters::PAPER, &reference).unwrap_err();
    /// assert!(matches!(err, IdentError::InvalidDesign { key: "constraints.band_hz", .. }));
    /// assert!(err.to_string().contains("below the Nyquist frequency 250 Hz"), "{err}");
    /// # Ok::<(), IdentError>(())
    /// ```
    pub fn validate(&self, prior: &Parameters, reference: &Excitation) -> Result<()> {
        prior.validate()?;
        let c = &self.constraints;
        positive("constraints.max_force", c.max_force)?;
        positive("constraints.max_stroke", c.max_stroke)?;
        if let Some(rms) = c.max_rms_force {
            positive("constraints.max_rms_force", rms)?;
        }
        self.validate_period(reference)?;
        self.validate_band(reference)?;
        if let Some(step) = c.step {
            self.validate_step(&step, prior, reference)?;
        }
        at_least_one("lines", self.lines)?;
        at_least_one("segments", self.segments)?;
        if self.segments > reference.len() / 16 {
            let expected = "at most one segment per 16 samples of the record";
            return Err(invalid("segments", self.segments as f64, expected));
        }
        at_least_one("robust.plants", self.robust.plants)?;
        let spread = self.robust.spread;
        if !(spread.is_finite() && (0.0..1.0).contains(&spread)) {
            return Err(invalid(
                "robust.spread",
                spread,
                "a relative half-width in [0, 1)",
            ));
        }
        at_least_one("starts", self.starts)?;
        at_least_one("iterations", self.iterations)
    }

    fn validate_period(&self, reference: &Excitation) -> Result<()> {
        let Some(period) = self.period else {
            return Ok(());
        };
        let dt = reference.dt();
        let record = dt * (reference.len().max(2) - 1) as f64;
        if !(period.is_finite() && period >= 4.0 * dt && period <= record * (1.0 + 1e-12)) {
            let expected = format!(
                "a period of at least 4 samples ({} s) and at most the record, {record} s",
                4.0 * dt
            );
            return Err(invalid("period", period, expected));
        }
        Ok(())
    }

    fn validate_band(&self, reference: &Excitation) -> Result<()> {
        let [low, high] = self.constraints.band_hz;
        let nyquist = 0.5 / reference.dt();
        let spacing = 1.0 / (reference.dt() * self.period_samples(reference) as f64);
        if !(low.is_finite() && low >= 0.0) {
            return Err(invalid("constraints.band_hz", low, "a lower edge ≥ 0 Hz"));
        }
        if !(high.is_finite() && high > low) {
            let expected =
                format!("an upper edge above the lower edge {low} Hz (the band is empty)");
            return Err(invalid("constraints.band_hz", high, expected));
        }
        if high >= nyquist {
            let expected =
                format!("an upper edge below the Nyquist frequency {nyquist} Hz of the record");
            return Err(invalid("constraints.band_hz", high, expected));
        }
        if (high / spacing).floor() < (low / spacing).ceil().max(1.0) {
            let expected = format!(
                "a band holding a line of the multisine's frequency grid (every {spacing:.4} Hz, 1/period)"
            );
            return Err(invalid("constraints.band_hz", high, expected));
        }
        Ok(())
    }

    fn validate_step(
        &self,
        step: &StepOption,
        prior: &Parameters,
        reference: &Excitation,
    ) -> Result<()> {
        let end = reference.t0() + reference.dt() * (reference.len() - 1) as f64;
        if !(step.time >= reference.t0() && step.time < end) {
            let expected = format!("a time within the record, {} … {end} s", reference.t0());
            return Err(invalid("constraints.step.time", step.time, expected));
        }
        let min = step.min_amplitude;
        if !(min.is_finite() && min >= 0.0) {
            return Err(invalid(
                "constraints.step.min_amplitude",
                min,
                "a finite height ≥ 0 N",
            ));
        }
        if min > self.constraints.max_force {
            let expected = format!(
                "at most constraints.max_force = {} N",
                self.constraints.max_force
            );
            return Err(invalid("constraints.step.min_amplitude", min, expected));
        }
        let deflection = min / prior.stiffness;
        if deflection > self.constraints.max_stroke {
            let expected = format!(
                "at least the static deflection {deflection} m of the required step (step.min_amplitude / stiffness)"
            );
            return Err(invalid(
                "constraints.max_stroke",
                self.constraints.max_stroke,
                expected,
            ));
        }
        let signal = msd_signal::Signal::Step {
            amplitude: min,
            time: step.time,
        };
        let force =
            Excitation::from_signal(signal, reference.t0(), reference.dt(), reference.len())?;
        let x = crate::simulate::simulate(
            prior,
            &force,
            crate::params::InitialState::REST,
            &crate::simulate::Backend::EXACT,
        )?;
        let peak = x.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if peak > self.constraints.max_stroke {
            let expected = format!(
                "at least the peak response {peak:.6} m of the required step on the prior (its overshoot included)"
            );
            return Err(invalid(
                "constraints.max_stroke",
                self.constraints.max_stroke,
                expected,
            ));
        }
        Ok(())
    }
}
