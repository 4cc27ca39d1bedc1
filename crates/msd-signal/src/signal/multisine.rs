//! Periodic multisines: equal-amplitude harmonics of a base frequency over a band.
//!
//! u(t) = Σₖ a·sin(2π·k·f₀·τ + φₖ) for τ = t − t_start ≥ 0 (zero before), over the
//! harmonics k with f_min ≤ k·f₀ ≤ f_max (all, odd only, or "random-odd"), each line of
//! amplitude a = rms·√(2/K) for K lines, so the signal has the requested RMS.
//!
//! ## The algorithm
//! * Schroeder phases (Schroeder 1970): φⱼ = −π·j·(j − 1)/K for the j-th line,
//!   j = 1 … K, a low crest factor for a flat amplitude spectrum.
//! * Random phases: independent, uniform on [0, 2π), from the ChaCha stream
//!   `"multisine.phases"` of `seed` (see [`crate::noise`]).
//! * Random-odd lines (Pintelon & Schoukens): the odd harmonics, in consecutive groups
//!   of three, one line of each full group left out at random (stream `"multisine.lines"`),
//!   so that non-linear distortion shows at the missing lines.
//! * Crest-factor reduction by iterative clipping (Van der Ouderaa, Schoukens & Renneboog
//!   1988): synthesise one period on a dense grid, clip it at `clip_ratio` × its peak,
//!   take the phases of the clipped signal's spectrum at the excited lines, keep the
//!   amplitudes, repeat; the phases with the lowest crest factor seen are kept. The
//!   spectrum stays exactly on the requested lines.
//!
//! The crest factor reported is max|u|/rms over one period sampled at N ≥ 16·k_max points.
//!
//! ```
//! use msd_signal::{Multisine, MultisineSpec, PhaseScheme};
//! let spec = MultisineSpec { base_frequency: 0.1, f_min: 0.1, f_max: 5.0, rms: 1.0,
//!     phases: PhaseScheme::Schroeder, ..MultisineSpec::default() };
//! let ms = Multisine::new(spec)?;
//! assert_eq!(ms.harmonics().len(), 50);
//! assert!(ms.crest_factor() < 2.0);
//! # Ok::<(), msd_signal::SignalError>(())
//! ```

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use rand::Rng;
use rustfft::FftPlannerScalar;
use rustfft::num_complex::Complex64;
use serde::{Deserialize, Serialize};

use crate::error::{Result, SignalError, finite, non_negative, positive};
use crate::noise::stream_rng;

/// Largest harmonic index a multisine may use.
pub const MULTISINE_MAX_HARMONIC: u64 = 1 << 16;

/// How the phases of a multisine's lines are chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PhaseScheme {
    /// Schroeder's closed-form phases. The default.
    #[default]
    Schroeder,
    /// Uniform random phases drawn from the spec's `seed`.
    Random,
}

/// Which harmonics in the band are excited.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LineSelection {
    /// Every harmonic in the band. The default.
    #[default]
    All,
    /// Odd harmonics only.
    Odd,
    /// Odd harmonics, one of each group of three left out at random (seeded).
    RandomOdd,
}

/// Options of the iterative-clipping crest-factor reduction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClippingOptions {
    /// Number of clip-and-project iterations. Default 100.
    #[serde(default = "default_iterations")]
    pub iterations: usize,
    /// Clip level as a fraction of the current peak, in (0, 1). Default 0.9.
    #[serde(default = "default_clip_ratio")]
    pub clip_ratio: f64,
}

fn default_iterations() -> usize {
    100
}

fn default_clip_ratio() -> f64 {
    0.9
}

impl Default for ClippingOptions {
    /// 100 iterations at a clip level of 0.9 × peak: enough to take a random-phase
    /// multisine of tens of lines to a crest factor near Schroeder's.
    fn default() -> Self {
        ClippingOptions {
            iterations: default_iterations(),
            clip_ratio: default_clip_ratio(),
        }
    }
}

/// The parameters of a multisine, as written in a config.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MultisineSpec {
    /// Base frequency f₀ in Hz (> 0); the period is 1/f₀ and the lines are its harmonics.
    pub base_frequency: f64,
    /// Lower band edge in Hz (≥ 0).
    pub f_min: f64,
    /// Upper band edge in Hz (≥ f_min).
    pub f_max: f64,
    /// RMS value of the whole signal (≥ 0).
    pub rms: f64,
    /// Phase scheme. Default Schroeder.
    #[serde(default)]
    pub phases: PhaseScheme,
    /// Line selection. Default all.
    #[serde(default)]
    pub lines: LineSelection,
    /// Seed for random phases and random-odd lines. Default 0.
    #[serde(default)]
    pub seed: u64,
    /// Optional crest-factor reduction. Default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crest_factor_reduction: Option<ClippingOptions>,
    /// Start time; the signal is 0 before. Default 0.
    #[serde(default)]
    pub t_start: f64,
}

impl Default for MultisineSpec {
    /// 0.1 Hz base (a 10 s period), band 0.1 … 5 Hz (around the paper's 1.1 Hz mode),
    /// RMS 1, Schroeder phases, all lines, seed 0, no clipping, start 0.
    fn default() -> Self {
        MultisineSpec {
            base_frequency: 0.1,
            f_min: 0.1,
            f_max: 5.0,
            rms: 1.0,
            phases: PhaseScheme::Schroeder,
            lines: LineSelection::All,
            seed: 0,
            crest_factor_reduction: None,
            t_start: 0.0,
        }
    }
}

impl MultisineSpec {
    /// Checks every field (finite, in range; the band must contain a line).
    pub fn validate(&self) -> Result<()> {
        positive(|| "base_frequency".into(), self.base_frequency)?;
        non_negative(|| "f_min".into(), self.f_min)?;
        non_negative(|| "f_max".into(), self.f_max)?;
        if self.f_max < self.f_min {
            return Err(SignalError::InvalidParameter {
                parameter: "f_max".into(),
                value: self.f_max,
                expected: "a value >= f_min",
            });
        }
        non_negative(|| "rms".into(), self.rms)?;
        if self.rms > 1e300 {
            return Err(SignalError::InvalidParameter {
                parameter: "rms".into(),
                value: self.rms,
                expected: "a value in 0 ..= 1e300 (so the lines add up to a finite value)",
            });
        }
        if self.f_max > super::Signal::MAX_FREQUENCY {
            return Err(SignalError::InvalidParameter {
                parameter: "f_max".into(),
                value: self.f_max,
                expected: "a frequency of at most 1e12 Hz",
            });
        }
        finite(|| "t_start".into(), self.t_start)?;
        if let Some(c) = &self.crest_factor_reduction
            && !(c.clip_ratio > 0.0 && c.clip_ratio < 1.0)
        {
            return Err(SignalError::InvalidParameter {
                parameter: "crest_factor_reduction.clip_ratio".into(),
                value: c.clip_ratio,
                expected: "a value in (0, 1)",
            });
        }
        let k_max = (self.f_max / self.base_frequency * (1.0 + 1e-9)).floor();
        if k_max > MULTISINE_MAX_HARMONIC as f64 {
            return Err(SignalError::TooManyLines {
                harmonic: k_max as u64,
                max: MULTISINE_MAX_HARMONIC,
            });
        }
        Ok(())
    }
}

/// A prepared multisine: spec, lines, phases and crest factor (evaluation never
/// allocates). Serialises as its [`MultisineSpec`].
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(try_from = "MultisineSpec", into = "MultisineSpec")]
pub struct Multisine {
    spec: MultisineSpec,
    harmonics: Vec<u32>,
    omegas: Vec<f64>,
    phases: Vec<f64>,
    amplitude: f64,
    crest_factor: f64,
}

impl PartialEq for Multisine {
    fn eq(&self, other: &Self) -> bool {
        self.spec == other.spec
    }
}

impl TryFrom<MultisineSpec> for Multisine {
    type Error = SignalError;
    fn try_from(spec: MultisineSpec) -> Result<Self> {
        Multisine::new(spec)
    }
}

impl From<Multisine> for MultisineSpec {
    fn from(m: Multisine) -> Self {
        m.spec
    }
}

fn select_lines(spec: &MultisineSpec) -> Vec<u32> {
    let f0 = spec.base_frequency;
    let k_min = ((spec.f_min / f0) * (1.0 - 1e-9)).ceil().max(1.0) as u32;
    let k_max = (spec.f_max / f0 * (1.0 + 1e-9)).floor() as u32;
    let all =
        (k_min..=k_max).filter(|&k| k_min <= k_max && (k as f64) * f0 >= spec.f_min * (1.0 - 1e-9));
    match spec.lines {
        LineSelection::All => all.collect(),
        LineSelection::Odd => all.filter(|k| k % 2 == 1).collect(),
        LineSelection::RandomOdd => {
            let odd: Vec<u32> = all.filter(|k| k % 2 == 1).collect();
            let mut rng = stream_rng(spec.seed, "multisine.lines");
            let mut kept = Vec::with_capacity(odd.len());
            for group in odd.chunks(3) {
                if group.len() == 3 {
                    let drop = rng.random_range(0..3usize);
                    kept.extend(
                        group
                            .iter()
                            .enumerate()
                            .filter(|(i, _)| *i != drop)
                            .map(|(_, &k)| k),
                    );
                } else {
                    kept.extend_from_slice(group);
                }
            }
            kept
        }
    }
}

/// One period on `n` points, from the lines' complex amplitudes.
struct Synth {
    n: usize,
    inverse: std::sync::Arc<dyn rustfft::Fft<f64>>,
    forward: std::sync::Arc<dyn rustfft::Fft<f64>>,
    buf: Vec<Complex64>,
}

impl Synth {
    fn new(k_max: u32) -> Self {
        let n = (16 * k_max as usize).next_power_of_two().max(256);
        let mut planner = FftPlannerScalar::new();
        Synth {
            n,
            inverse: planner.plan_fft_inverse(n),
            forward: planner.plan_fft_forward(n),
            buf: Vec::new(),
        }
    }

    /// Fills `x` with Σ a·sin(2πkn/N + φ) (a·sin θ = Re(a·e^{i(θ − π/2)})).
    fn synthesise(&mut self, harmonics: &[u32], a: f64, phases: &[f64], x: &mut Vec<f64>) {
        self.buf.clear();
        self.buf.resize(self.n, Complex64::new(0.0, 0.0));
        for (&k, &phi) in harmonics.iter().zip(phases) {
            self.buf[k as usize] = Complex64::from_polar(a, phi - FRAC_PI_2);
        }
        self.inverse.process(&mut self.buf);
        x.clear();
        x.extend(self.buf.iter().map(|c| c.re));
    }

    /// Phases at the lines of the spectrum of `x`: φ = arg X[k] + π/2.
    fn phases_of(&mut self, x: &[f64], harmonics: &[u32], phases: &mut [f64]) {
        self.buf.clear();
        self.buf.extend(x.iter().map(|&v| Complex64::new(v, 0.0)));
        self.forward.process(&mut self.buf);
        for (&k, phi) in harmonics.iter().zip(phases.iter_mut()) {
            *phi = self.buf[k as usize].arg() + FRAC_PI_2;
        }
    }
}

fn crest(x: &[f64]) -> f64 {
    let peak = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let rms = (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt();
    if rms > 0.0 { peak / rms } else { 1.0 }
}

impl Multisine {
    /// Validates the spec, selects the lines, computes the phases (and runs the
    /// crest-factor reduction if asked).
    pub fn new(spec: MultisineSpec) -> Result<Self> {
        spec.validate()?;
        let harmonics = select_lines(&spec);
        if harmonics.is_empty() {
            return Err(SignalError::NoMultisineLines {
                base_frequency: spec.base_frequency,
                f_min: spec.f_min,
                f_max: spec.f_max,
            });
        }
        let k = harmonics.len();
        let mut phases: Vec<f64> = match spec.phases {
            PhaseScheme::Schroeder => (1..=k)
                .map(|j| -PI * j as f64 * (j as f64 - 1.0) / k as f64)
                .collect(),
            PhaseScheme::Random => {
                let mut rng = stream_rng(spec.seed, "multisine.phases");
                (0..k).map(|_| TAU * rng.random::<f64>()).collect()
            }
        };
        let amplitude = spec.rms * (2.0 / k as f64).sqrt();
        let k_max = *harmonics.last().unwrap_or(&1);
        let mut synth = Synth::new(k_max);
        let mut x = Vec::new();
        synth.synthesise(&harmonics, 1.0, &phases, &mut x);
        let mut crest_factor = crest(&x);
        if let Some(opts) = spec.crest_factor_reduction {
            let mut trial = phases.clone();
            for _ in 0..opts.iterations {
                let peak = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let level = opts.clip_ratio * peak;
                x.iter_mut().for_each(|v| *v = v.clamp(-level, level));
                synth.phases_of(&x, &harmonics, &mut trial);
                synth.synthesise(&harmonics, 1.0, &trial, &mut x);
                let cf = crest(&x);
                if cf < crest_factor {
                    crest_factor = cf;
                    phases.copy_from_slice(&trial);
                }
            }
        }
        let omegas = harmonics
            .iter()
            .map(|&h| TAU * h as f64 * spec.base_frequency)
            .collect();
        debug_assert!(crest_factor.is_finite() && crest_factor >= 1.0 - 1e-12);
        Ok(Multisine {
            spec,
            harmonics,
            omegas,
            phases,
            amplitude,
            crest_factor,
        })
    }

    /// The parameters.
    pub fn spec(&self) -> &MultisineSpec {
        &self.spec
    }

    /// The excited harmonic indices k (line frequencies k·f₀), increasing.
    pub fn harmonics(&self) -> &[u32] {
        &self.harmonics
    }

    /// The phase of each line in radians (after any crest-factor reduction).
    pub fn phases(&self) -> &[f64] {
        &self.phases
    }

    /// The amplitude of each line, rms·√(2/K).
    pub fn line_amplitude(&self) -> f64 {
        self.amplitude
    }

    /// Crest factor max|u|/rms over one period (sampled at N ≥ 16·k_max points).
    pub fn crest_factor(&self) -> f64 {
        self.crest_factor
    }

    /// The period 1/f₀ in seconds.
    pub fn period(&self) -> f64 {
        1.0 / self.spec.base_frequency
    }

    pub(crate) fn eval(&self, t: f64, left: bool) -> f64 {
        let start = self.spec.t_start;
        let on = if left { t > start } else { t >= start };
        if !on {
            return 0.0;
        }
        let tau = (t - start).rem_euclid(self.period());
        self.omegas
            .iter()
            .zip(&self.phases)
            .map(|(w, p)| (w * tau + p).sin())
            .sum::<f64>()
            * self.amplitude
    }
}
