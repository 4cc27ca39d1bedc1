//! Coverage of a joint fit's 95 % intervals over seeds, on lab records whose drive is
//! measured with noise (a load cell, a base accelerometer): the test that the intervals
//! mean what they say under the noise a real lab has.
//!
//! Each seed draws a random-phase multisine (0.2–15 Hz, 20 s at 1 kHz), simulates the
//! plant (1.7 kg, 3.1 N·s/m, 950 N/m: fn 3.76 Hz, ζ 0.039) under the exact drive, adds
//! each sensor's white noise and an offset, and hands the fit the drive as its sensor
//! reads it: the exact drive plus white noise of `drive_noise` × its rms. Seeds run on a
//! local rayon pool and are reduced in seed order: the same options give the same
//! numbers for any thread count.

mod two_storey;

use crate::error::Result;
use crate::pool;
use msd_ident::records::{NoiseModel, NoiseModelFit, ResidualWhiteness, simulate_channels};
use msd_ident::{
    Channel, Drive, Excitation, Frame, InitialState, Interval, KnownParameter, Parameters, Record,
    RecordsFit, RecordsOptions, ResponseQuantity, fit_records,
};
use msd_signal::{Multisine, MultisineSpec, PhaseScheme, Signal, gaussian_noise};
use rayon::prelude::*;
use serde::Serialize;

/// The lab setups of the study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Setup {
    /// A force from a load cell, an accelerometer on the mass (σ 0.05 m/s²).
    Accelerometer,
    /// The same with a displacement sensor beside it (σ 10 µm).
    DisplacementAndAccelerometer,
    /// A shaker table: the base's acceleration from an accelerometer (2 m/s² rms), an
    /// accelerometer on the mass, the mass weighed.
    BaseExcitation,
    /// Three 10 s load-cell runs with an accelerometer, fitted jointly.
    Repeats,
    /// The two-storey chain of `configs/two-storey.toml` (2.0 and 1.5 kg on 8 and 6 kN/m,
    /// 3 and 2 N·s/m): a load cell's force (a 0.1–40 Hz multisine, 2 N rms) on the top
    /// floor, an accelerometer on each floor (σ 0.02 m/s²), 10 s at 500 Hz.
    TwoStorey,
}

impl Setup {
    /// Every setup, in the study's order.
    pub const ALL: [Setup; 5] = [
        Setup::Accelerometer,
        Setup::DisplacementAndAccelerometer,
        Setup::BaseExcitation,
        Setup::Repeats,
        Setup::TwoStorey,
    ];

    /// The setup's name in tables.
    pub fn name(self) -> &'static str {
        match self {
            Setup::Accelerometer => "accelerometer",
            Setup::DisplacementAndAccelerometer => "displacement + accelerometer",
            Setup::BaseExcitation => "base excitation",
            Setup::Repeats => "repeats (3 runs)",
            Setup::TwoStorey => "two-storey chain",
        }
    }
}

/// What one study runs.
///
/// By default the accelerometer setup, 1 % drive noise, 40 seeds from 1, the default
/// noise model, 2 threads.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CoverageOptions {
    /// The setup.
    pub setup: Setup,
    /// The drive sensor's white noise as a fraction of the drive's rms.
    pub drive_noise: f64,
    /// Number of seeds.
    pub seeds: usize,
    /// The first seed.
    pub first_seed: u64,
    /// The fit's noise model.
    pub noise_model: NoiseModel,
    /// Worker threads.
    pub threads: usize,
}

impl Default for CoverageOptions {
    fn default() -> Self {
        Self {
            setup: Setup::Accelerometer,
            drive_noise: 0.01,
            seeds: 40,
            first_seed: 1,
            noise_model: NoiseModel::default(),
            threads: 2,
        }
    }
}

/// One quantity's coverage over the seeds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QuantityCoverage {
    /// `mass`, `damping`, `stiffness`, `natural_frequency_hz` or `damping_ratio`; for a
    /// chain `m1`, `c1`, `k1`, …, `fn1`, `zeta1`, ….
    pub name: String,
    /// Share of the seeds whose 95 % interval holds the truth.
    pub coverage: f64,
    /// √(mean z²), z = (estimate − truth)/SE: 1 when the SEs are right.
    pub rms_z: f64,
    /// The estimates' standard deviation over the mean reported SE.
    pub spread_over_se: f64,
    /// The mean over the seeds of the fit's efficiency against the Cramér–Rao bound of
    /// the errors-in-variables model (`NoiseModelFit::efficiency`); `None` where the fit
    /// does not report it (the white model, a chain's modes).
    pub efficiency: Option<f64>,
}

/// What a study found.
///
/// Displays one line per quantity.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CoverageStudy {
    /// What ran.
    pub options: CoverageOptions,
    /// Each identified quantity.
    pub quantities: Vec<QuantityCoverage>,
    /// Share of the seeds whose drive noise the fit detected (p < 0.01).
    pub drive_noise_detected: f64,
    /// Share of the seeds with a channel flagged not white under the noise model.
    pub whiteness_flagged: f64,
    /// The mean σ̂_u over the drive's rms.
    pub mean_drive_noise_estimate: f64,
    /// The standard deviation of σ̂_u over the drive's rms across the seeds.
    pub sd_drive_noise_estimate: f64,
}

impl std::fmt::Display for CoverageStudy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let o = &self.options;
        write!(
            f,
            "{}, drive noise {:.1} %, {:?}, {} seeds: detected {:.2}, flagged {:.2}, σ̂_u {:.2} %",
            o.setup.name(),
            100.0 * o.drive_noise,
            o.noise_model,
            o.seeds,
            self.drive_noise_detected,
            self.whiteness_flagged,
            100.0 * self.mean_drive_noise_estimate
        )?;
        for q in &self.quantities {
            write!(
                f,
                "\n  {:<22} coverage {:.3}  rms z {:.2}  spread/SE {:.2}",
                q.name, q.coverage, q.rms_z, q.spread_over_se
            )?;
            if let Some(e) = q.efficiency {
                write!(f, "  efficiency {e:.3}")?;
            }
        }
        Ok(())
    }
}

/// The plant of every study.
pub const STUDY_PLANT: Parameters = Parameters {
    mass: 1.7,
    damping: 3.1,
    stiffness: 950.0,
};

/// Runs the study.
///
/// ```no_run
/// use msd_mc::coverage::{CoverageOptions, coverage_study};
/// let study = coverage_study(&CoverageOptions { seeds: 10, ..CoverageOptions::default() })?;
/// println!("{study}");
/// # Ok::<(), msd_mc::McError>(())
/// ```
pub fn coverage_study(options: &CoverageOptions) -> Result<CoverageStudy> {
    let fits: Vec<SeedFit> = pool(options.threads)?.install(|| {
        (0..options.seeds as u64)
            .into_par_iter()
            .map(|i| fit_seed(options, options.first_seed + i))
            .collect::<Result<Vec<_>>>()
    })?;
    let names = fits.first().map(|f| f.names()).unwrap_or_default();
    let quantities = names
        .iter()
        .enumerate()
        .filter_map(|(q, name)| {
            let truth = fits[0].quantities[q].1;
            let ivs: Vec<Interval> = fits.iter().map(|f| f.quantities[q].2).collect();
            let efficiencies: Vec<f64> = fits
                .iter()
                .filter_map(|f| f.noise_model.efficiency.get(name).copied())
                .collect();
            let efficiency = (efficiencies.len() == fits.len())
                .then(|| efficiencies.iter().sum::<f64>() / efficiencies.len().max(1) as f64);
            ivs.iter()
                .all(|iv| iv.standard_error > 0.0)
                .then(|| QuantityCoverage {
                    efficiency,
                    ..coverage_of(name, truth, &ivs)
                })
        })
        .collect();
    let fractions: Vec<f64> = fits
        .iter()
        .map(|f| f.noise_model.input_noise_fraction.unwrap_or(0.0))
        .collect();
    let n = fractions.len().max(1) as f64;
    let mean = fractions.iter().sum::<f64>() / n;
    let sd =
        (fractions.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt();
    let share = |f: &dyn Fn(&SeedFit) -> bool| {
        fits.iter().filter(|x| f(x)).count() as f64 / fits.len().max(1) as f64
    };
    Ok(CoverageStudy {
        options: options.clone(),
        quantities,
        drive_noise_detected: share(&|f| f.noise_model.p_value.is_some_and(|p| p < 0.01)),
        whiteness_flagged: share(&|f| f.whiteness.iter().any(|c| !c.passed)),
        mean_drive_noise_estimate: mean,
        sd_drive_noise_estimate: sd,
    })
}

/// One seed's fit as the study reads it: each quantity's name, truth and interval, and
/// what the noise model found.
struct SeedFit {
    quantities: Vec<(String, f64, Interval)>,
    noise_model: NoiseModelFit,
    whiteness: Vec<ResidualWhiteness>,
}

impl SeedFit {
    fn names(&self) -> Vec<String> {
        self.quantities.iter().map(|q| q.0.clone()).collect()
    }

    fn of_records(fit: RecordsFit) -> Self {
        let p = &fit.plant;
        let truth = STUDY_PLANT;
        let quantities = [
            ("mass", truth.mass, p.mass),
            ("damping", truth.damping, p.damping),
            ("stiffness", truth.stiffness, p.stiffness),
            (
                "natural_frequency_hz",
                truth.natural_frequency_hz(),
                Some(p.natural_frequency_hz),
            ),
            (
                "damping_ratio",
                truth.damping_ratio(),
                Some(p.damping_ratio),
            ),
        ]
        .into_iter()
        .filter_map(|(name, t, iv)| iv.map(|iv| (name.to_string(), t, iv)))
        .collect();
        Self {
            quantities,
            noise_model: fit.noise_model,
            whiteness: fit.whiteness,
        }
    }
}

fn coverage_of(name: &str, truth: f64, ivs: &[Interval]) -> QuantityCoverage {
    let n = ivs.len() as f64;
    let covered = ivs.iter().filter(|iv| iv.contains(truth)).count() as f64;
    let z2: f64 = ivs
        .iter()
        .map(|iv| ((iv.value - truth) / iv.standard_error).powi(2))
        .sum();
    let mean = ivs.iter().map(|iv| iv.value).sum::<f64>() / n;
    let variance = ivs.iter().map(|iv| (iv.value - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let mean_se = ivs.iter().map(|iv| iv.standard_error).sum::<f64>() / n;
    QuantityCoverage {
        name: name.to_string(),
        coverage: covered / n,
        rms_z: (z2 / n).sqrt(),
        spread_over_se: variance.sqrt() / mean_se,
        efficiency: None,
    }
}

/// One seed's records fitted.
fn fit_seed(options: &CoverageOptions, seed: u64) -> Result<SeedFit> {
    let (drive, known, runs, seconds) = match options.setup {
        Setup::TwoStorey => return two_storey::fit_seed(options, seed),
        Setup::BaseExcitation => (Drive::BaseAcceleration, KnownParameter::Mass(1.7), 1, 20.0),
        Setup::Repeats => (Drive::Force, KnownParameter::None, 3, 10.0),
        _ => (Drive::Force, KnownParameter::None, 1, 20.0),
    };
    let records = (0..runs)
        .map(|run| record(options, drive, seed, run, seconds))
        .collect::<Result<Vec<_>>>()?;
    let fit_options = RecordsOptions {
        drive,
        known,
        noise_model: options.noise_model,
        leave_one_out: false,
        hold_out: 0.0,
        ..RecordsOptions::default()
    };
    Ok(SeedFit::of_records(fit_records(&records, &fit_options)?))
}

/// One run: the drive as measured and the sensors' records.
fn record(
    options: &CoverageOptions,
    drive: Drive,
    seed: u64,
    run: usize,
    seconds: f64,
) -> Result<Record> {
    const DT: f64 = 1e-3;
    let n = (seconds / DT).round() as usize;
    let rms = if drive == Drive::Force { 5.0 } else { 2.0 };
    let spec = MultisineSpec {
        base_frequency: 0.1,
        f_min: 0.2,
        f_max: 15.0,
        rms,
        phases: PhaseScheme::Random,
        seed: seed * 16 + run as u64,
        ..MultisineSpec::default()
    };
    let signal = Signal::Multisine(Multisine::new(spec).map_err(ident)?);
    let exact = signal.sample(0.0, DT, n);
    let sensors: &[(&str, ResponseQuantity, f64)] = match options.setup {
        Setup::DisplacementAndAccelerometer => &[
            ("displacement", ResponseQuantity::Displacement, 1e-5),
            ("accelerometer", ResponseQuantity::Acceleration, 0.05),
        ],
        _ => &[("accelerometer", ResponseQuantity::Acceleration, 0.05)],
    };
    let kinds: Vec<_> = sensors.iter().map(|s| (s.1, Frame::Absolute)).collect();
    let input = Excitation::from_samples(0.0, DT, exact.clone())?;
    let clean = simulate_channels(
        &STUDY_PLANT,
        InitialState::REST,
        drive,
        Some(&input),
        n,
        DT,
        &kinds,
    )?;
    let stream = |name: &str| format!("{name}-{run}");
    let mut channels = Vec::new();
    for ((name, quantity, sigma), clean) in sensors.iter().zip(clean) {
        let noise = gaussian_noise(seed, &stream(name), *sigma, n).map_err(ident)?;
        let offset = 3.0 * sigma;
        let samples = clean.iter().zip(&noise).map(|(x, e)| x + e + offset);
        channels.push(Channel::new(*name, (*quantity).into(), samples.collect()));
    }
    let drive_noise =
        gaussian_noise(seed, &stream("drive"), options.drive_noise * rms, n).map_err(ident)?;
    let measured = exact.iter().zip(&drive_noise).map(|(u, e)| u + e).collect();
    Ok(Record {
        name: format!("run {}", run + 1),
        excitation: Excitation::from_samples(0.0, DT, measured)?,
        channels,
    })
}

fn ident(e: msd_signal::SignalError) -> msd_ident::IdentError {
    msd_ident::IdentError::from(e)
}
