//! The paper's robustness band for a chain of masses: every m, c and k (and connection
//! to the ground) drawn
//! independently uniform within ±p % of the estimate, each sensor's response simulated
//! exactly, and per sample the percentiles over the draws.

use crate::options::validate_percentiles;
use crate::quantile::percentiles;
use crate::{
    draw::sample_rng,
    error::{McError, Result},
};
use msd_ident::chain::{ChainParameters, ChainSetup, simulate_chain};
use msd_signal::Recording;
use rand::Rng;
use rayon::prelude::*;
use serde::Serialize;

/// Options of [`chain_band`].
///
/// ```
/// let options = msd_mc::ChainBandOptions::default();
/// assert_eq!((options.samples, options.percent, options.threads), (200, 10.0, 2));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ChainBandOptions {
    /// Draws. By default 200.
    pub samples: usize,
    /// Half-width p of each parameter's uniform range, percent (0 < p < 100). By default
    /// 10, the paper's.
    pub percent: f64,
    /// The band's lower and upper percentiles. By default [5, 95], the paper's 90 % band
    /// (one convention for every Monte Carlo band of the toolkit).
    pub percentiles: [f64; 2],
    /// Seed of the draws (draw i uses [`sample_rng`](seed, i)).
    pub seed: u64,
    /// Worker threads (a local pool). By default 2.
    pub threads: usize,
}

impl Default for ChainBandOptions {
    fn default() -> Self {
        Self {
            samples: 200,
            percent: 10.0,
            percentiles: [5.0, 95.0],
            seed: 1,
            threads: 2,
        }
    }
}

/// Each sensor's band, and how much of the measured record lies inside it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainBand {
    /// Per sensor, per sample: the lower percentile.
    pub lower: Vec<Vec<f64>>,
    /// Per sensor, per sample: the upper percentile.
    pub upper: Vec<Vec<f64>>,
    /// The percentiles.
    pub percentiles: [f64; 2],
    /// Draws simulated.
    pub samples: usize,
    /// Per sensor: the fraction of the measured samples inside the band (when given).
    pub coverage: Option<Vec<f64>>,
}

/// The band of `setup` around `parameters` driven by `record`'s drive, with the share of
/// `record`'s channels (one series per sensor, when it has them) it holds. Bit for bit the same for any thread
/// count: draw i depends on (seed, i) only, and the percentiles are taken in draw order.
///
/// ```
/// use msd_ident::{chain::{ChainParameters, ChainSetup}};
/// use msd_mc::{ChainBandOptions, chain_band};
/// let p = ChainParameters { masses: vec![2.5], dampers: vec![1.8], springs: vec![120.0], ..ChainParameters::default() };
/// let drive = ChainSetup::default().recording("step", 2e-3, vec![1.0; 500], Vec::new());
/// let band = chain_band(&ChainSetup::default(), &p, &drive, &ChainBandOptions::default())?;
/// assert_eq!(band.coverage, None); // no measured channel
/// assert!(band.lower[0][499] < band.upper[0][499]);
/// # Ok::<(), msd_mc::McError>(())
/// ```
pub fn chain_band(
    setup: &ChainSetup,
    parameters: &ChainParameters,
    record: &Recording,
    options: &ChainBandOptions,
) -> Result<ChainBand> {
    validate(options)?;
    let (input, dt) = (record.input(), record.dt);
    let nominal = simulate_chain(setup, parameters, input, dt)?;
    let p = options.percent / 100.0;
    let draw = |i: usize| -> Result<Vec<Vec<f64>>> {
        let mut rng = sample_rng(options.seed, i as u64);
        let mut scale = |v: &[f64]| -> Vec<f64> {
            v.iter()
                .map(|x| x * (1.0 + p * rng.random_range(-1.0..=1.0)))
                .collect()
        };
        let drawn = ChainParameters {
            masses: scale(&parameters.masses),
            dampers: scale(&parameters.dampers),
            springs: scale(&parameters.springs),
            ground_springs: scale(&parameters.ground_springs),
            ground_dampers: scale(&parameters.ground_dampers),
        };
        Ok(simulate_chain(setup, &drawn, input, dt)?)
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.threads)
        .build()
        .map_err(|e| McError::ThreadPool {
            threads: options.threads,
            source: e.into(),
        })?;
    let draws: Vec<Vec<Vec<f64>>> = pool.install(|| {
        (0..options.samples)
            .into_par_iter()
            .map(draw)
            .collect::<Result<Vec<_>>>()
    })?;
    let levels = options.percentiles;
    let mut column = vec![0.0; options.samples];
    let mut out = [0.0; 2];
    let (mut lower, mut upper) = (Vec::new(), Vec::new());
    for ch in 0..nominal.len() {
        let (mut lo, mut hi) = (
            Vec::with_capacity(input.len()),
            Vec::with_capacity(input.len()),
        );
        for k in 0..input.len() {
            for (c, d) in column.iter_mut().zip(&draws) {
                *c = d[ch][k];
            }
            percentiles(&column, &levels, &mut out);
            lo.push(out[0]);
            hi.push(out[1]);
        }
        lower.push(lo);
        upper.push(hi);
    }
    let coverage = (!record.channels.is_empty()).then(|| {
        record
            .responses()
            .zip(lower.iter().zip(&upper))
            .map(|(y, (lo, hi))| {
                let inside = y
                    .iter()
                    .zip(lo.iter().zip(hi))
                    .filter(|(v, (l, h))| (**l..=**h).contains(*v))
                    .count();
                inside as f64 / y.len().max(1) as f64
            })
            .collect()
    });
    Ok(ChainBand {
        lower,
        upper,
        percentiles: levels,
        samples: options.samples,
        coverage,
    })
}

fn validate(options: &ChainBandOptions) -> Result<()> {
    if options.samples == 0 {
        return Err(McError::ZeroSamples);
    }
    if options.threads == 0 {
        return Err(McError::ZeroThreads);
    }
    if options.threads > crate::options::MAX_THREADS {
        return Err(McError::TooManyThreads {
            threads: options.threads,
            max: crate::options::MAX_THREADS,
        });
    }
    if !(options.percent > 0.0 && options.percent < 100.0) {
        return Err(McError::InvalidPercent {
            percent: options.percent,
        });
    }
    validate_percentiles(&options.percentiles)
}

#[cfg(test)]
mod tests {
    use super::*;
    use msd_ident::{ResponseQuantity, chain::ChainSensor};

    fn two_storey() -> (ChainSetup, ChainParameters) {
        let setup = ChainSetup {
            masses: 2,
            force_at: 2,
            sensors: (1..=2)
                .map(|at| ChainSensor {
                    at,
                    quantity: ResponseQuantity::Displacement,
                    ..ChainSensor::default()
                })
                .collect(),
            ..ChainSetup::default()
        };
        let p = ChainParameters {
            masses: vec![2.0, 1.5],
            dampers: vec![3.0, 2.0],
            springs: vec![8000.0, 6000.0],
            ..ChainParameters::default()
        };
        (setup, p)
    }

    #[test]
    fn the_band_is_the_same_for_any_thread_count_and_holds_the_nominal_response() {
        let (setup, p) = two_storey();
        let force = vec![1.0; 40_000];
        let options = ChainBandOptions {
            samples: 64,
            ..ChainBandOptions::default()
        };
        let nominal = simulate_chain(&setup, &p, &force, 2e-3).unwrap();
        let record = setup.recording("nominal", 2e-3, force, nominal);
        let one = chain_band(
            &setup,
            &p,
            &record,
            &ChainBandOptions {
                threads: 1,
                ..options.clone()
            },
        )
        .unwrap();
        let two = chain_band(&setup, &p, &record, &options).unwrap();
        assert_eq!(one, two);
        // The static deflection under 1 N is Σ 1/k_i: every draw's springs within
        // ±10 %, so the band at the end (80 s: the slowest decay e^(−ζωn·t) is below 1e-9
        // for every draw) lies within [1/1.1, 1/0.9] of it.
        let end = 39_999;
        let statics = 1.0 / 8000.0 + 1.0 / 6000.0;
        assert!(two.lower[1][end] >= statics / 1.1 * (1.0 - 1e-3));
        assert!(two.upper[1][end] <= statics / 0.9 * (1.0 + 1e-3));
        // Most of the nominal response lies inside (it is the centre of the draws).
        assert!(two.coverage.unwrap().iter().all(|c| *c > 0.9));
    }

    #[test]
    fn bad_options_are_refused() {
        let (setup, p) = two_storey();
        for options in [
            ChainBandOptions {
                samples: 0,
                ..ChainBandOptions::default()
            },
            ChainBandOptions {
                percent: 100.0,
                ..ChainBandOptions::default()
            },
            ChainBandOptions {
                threads: 0,
                ..ChainBandOptions::default()
            },
            ChainBandOptions {
                percentiles: [97.5, 2.5],
                ..ChainBandOptions::default()
            },
        ] {
            let drive = setup.recording("short", 1e-3, vec![1.0; 10], Vec::new());
            assert!(chain_band(&setup, &p, &drive, &options).is_err());
        }
    }
}
