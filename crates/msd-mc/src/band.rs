//! Monte Carlo robustness band: N parameter samples around θ̂ re-simulate a given input.

use crate::batch::{BatchSimulator, LANES};
use crate::engine::{self, MemoryPlan, Restart};
use crate::order::similarity_order;
use crate::tracker::TrackerCounts;
use crate::{
    draw::Sampler,
    error::{McError, Result, SampleFailure},
    options::{McOptions, Sampling},
    quantile::Summary,
};
use msd_ident::{Backend, Excitation, Parameters, simulate};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Pointwise percentiles of the simulated responses, and what they say.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Band {
    /// Sample times.
    pub times: Vec<f64>,
    /// Response with the nominal parameters θ̂.
    pub nominal: Vec<f64>,
    /// (level in percent, pointwise percentile) for each requested level, ascending.
    pub percentiles: Vec<(f64, Vec<f64>)>,
    /// Band width over time: last minus first percentile.
    pub width: Vec<f64>,
    /// Share of the measurements within [lower, upper] (inclusive), when given.
    pub coverage: Option<f64>,
    /// Natural frequency fn = √(k/m)/2π (Hz) across the successful samples.
    pub natural_frequency_hz: Summary,
    /// Damping ratio ζ = c/(2√(mk)) across the successful samples.
    pub damping_ratio: Summary,
    /// N, samples drawn.
    pub samples: usize,
    /// Samples that were non-physical after every redraw or failed to simulate; they are
    /// left out of the percentiles and summaries.
    pub failed_samples: usize,
    /// Worker threads used.
    pub threads: usize,
    /// The sampling used.
    pub sampling: Sampling,
    /// The backend used.
    pub backend: Backend,
    /// The time chunking and memory of the run.
    pub memory: MemoryPlan,
}

impl Band {
    /// The lowest percentile (the band's lower edge).
    pub fn lower(&self) -> &[f64] {
        &self.percentiles[0].1
    }

    /// The highest percentile (the band's upper edge).
    pub fn upper(&self) -> &[f64] {
        &self.percentiles[self.percentiles.len() - 1].1
    }

    /// The 50th percentile, when requested.
    pub fn median(&self) -> Option<&[f64]> {
        self.percentile(50.0)
    }

    /// The percentile at `level`, when requested.
    pub fn percentile(&self, level: f64) -> Option<&[f64]> {
        self.percentiles
            .iter()
            .find(|(l, _)| *l == level)
            .map(|(_, v)| v.as_slice())
    }
}

impl std::fmt::Display for Band {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let levels: Vec<String> = self
            .percentiles
            .iter()
            .map(|(l, _)| format!("{l}"))
            .collect();
        writeln!(
            f,
            "Monte Carlo band: {} samples ({} failed), {} threads, {} backend, {} time chunk(s)",
            self.samples,
            self.failed_samples,
            self.threads,
            self.backend.name(),
            self.memory.chunks
        )?;
        writeln!(f, "  percentiles: {} %", levels.join(", "))?;
        if let Some(c) = self.coverage {
            writeln!(
                f,
                "  coverage: {:.1} % of measurements inside the band",
                100.0 * c
            )?;
        }
        let (imax, wmax) =
            self.width
                .iter()
                .enumerate()
                .fold(
                    (0, f64::NEG_INFINITY),
                    |a, (i, &w)| if w > a.1 { (i, w) } else { a },
                );
        let mean = self.width.iter().sum::<f64>() / self.width.len() as f64;
        writeln!(
            f,
            "  width: mean {mean:.6}, max {wmax:.6} at t = {:.3}",
            self.times[imax]
        )?;
        writeln!(f, "  fn (Hz): {}", self.natural_frequency_hz)?;
        write!(f, "  zeta: {}", self.damping_ratio)
    }
}

/// Monte Carlo band of the response to `excitation` around `nominal`, with the coverage
/// of `measured` (one value per excitation sample) when given. See
/// [`monte_carlo_band_with_progress`].
pub fn monte_carlo_band(
    nominal: &Parameters,
    excitation: &Excitation,
    measured: Option<&[f64]>,
    options: &McOptions,
) -> Result<Band> {
    monte_carlo_band_with_progress(nominal, excitation, measured, options, &|_, _| {})
}

/// As [`monte_carlo_band`], calling `progress(done, total)` each time a block of up to
/// 8 samples has been simulated through a time chunk (from the worker threads; `done`
/// counts samples × chunks, `total` = N × chunks).
///
/// ## The algorithm
/// Sample i draws its parameters from its own generator ([`sample_rng`](crate::draw::sample_rng)
/// (seed, i)), simulates the excitation with the chosen backend, and contributes to the
/// pointwise percentiles (MATLAB `prctile` convention) computed exactly per time chunk
/// (see [`MemoryPlan`]). Everything runs on a local rayon pool of `options.threads`
/// threads; the result is bit-for-bit independent of the thread count.
pub fn monte_carlo_band_with_progress(
    nominal: &Parameters,
    excitation: &Excitation,
    measured: Option<&[f64]>,
    options: &McOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Band> {
    band_and_counts(nominal, excitation, measured, options, progress).map(|(band, _)| band)
}

/// The band and how each level's tracker found its percentiles (the last run's).
fn band_and_counts(
    nominal: &Parameters,
    excitation: &Excitation,
    measured: Option<&[f64]>,
    options: &McOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<(Band, Vec<TrackerCounts>)> {
    options.validate()?;
    nominal.validate()?;
    let points = excitation.len();
    if let Some(y) = measured
        && y.len() != points
    {
        return Err(McError::LengthMismatch {
            what: "measurements",
            expected: points,
            got: y.len(),
        });
    }
    let (n, levels) = (options.samples, options.percentiles.as_slice());
    let (backend, initial) = (&options.backend, options.initial_state);
    let sampler = Sampler::new(nominal, &options.sampling)?;
    let pool = crate::pool(options.threads)?;
    let nominal_response = simulate(nominal, excitation, initial, backend)?;
    let batch = BatchSimulator::new(excitation, backend)?;
    let plan = MemoryPlan::new(n, points, levels.len(), options.max_buffer_bytes);

    let drawn: Vec<Option<Parameters>> = pool.install(|| {
        (0..n)
            .into_par_iter()
            .map(|i| sampler.draw(options.seed, i))
            .collect()
    });
    // Similar draws side by side (percentiles do not depend on the order; the trackers
    // are faster): position s simulates draw order[s].
    let order = similarity_order(&drawn);
    let mut slots: Vec<Option<Parameters>> = order.iter().map(|&i| drawn[i]).collect();
    // A sample that fails after its values entered a percentile (an overflow or a
    // solver failure late in the record: never for a physical plant on a sane input)
    // is left out and the band run again, until no sample fails late.
    let out = loop {
        let lanes = |b: usize| &slots[(b * LANES).min(n)..((b + 1) * LANES).min(n)];
        let run = engine::run(
            &pool,
            &plan,
            levels,
            progress,
            |b| batch.start(lanes(b), initial),
            |run, until, out, stride| run.advance_strided(&batch, until, out, stride),
        );
        match run {
            Ok(out) => break out,
            Err(Restart(ok)) => {
                for (slot, ok) in slots.iter_mut().zip(ok) {
                    if !ok {
                        *slot = None;
                    }
                }
            }
        }
    };
    // The good draws in draw order (the summaries sum in that order).
    let mut ok = vec![false; n];
    for (s, &i) in order.iter().enumerate() {
        ok[i] = out.ok[s] && slots[s].is_some();
    }
    let good: Vec<Parameters> = (0..n).filter(|&i| ok[i]).filter_map(|i| drawn[i]).collect();
    if good.is_empty() {
        let first = match drawn[0] {
            None => SampleFailure::NonPhysical {
                redraws: crate::draw::MAX_REDRAWS,
            },
            Some(p) => simulate(&p, excitation, initial, backend)
                .err()
                .map_or(SampleFailure::Unknown, SampleFailure::Simulation),
        };
        return Err(McError::AllSamplesFailed { samples: n, first });
    }
    let percentiles: Vec<(f64, Vec<f64>)> = levels.iter().copied().zip(out.percentiles).collect();
    let (lower, upper) = (&percentiles[0].1, &percentiles[levels.len() - 1].1);
    let width = upper.iter().zip(lower).map(|(u, l)| u - l).collect();
    let coverage = measured.map(|y| {
        let inside = (0..points)
            .filter(|&t| lower[t] <= y[t] && y[t] <= upper[t])
            .count();
        inside as f64 / points as f64
    });
    let fnat: Vec<f64> = good.iter().map(Parameters::natural_frequency_hz).collect();
    let zeta: Vec<f64> = good.iter().map(Parameters::damping_ratio).collect();
    let band = Band {
        times: excitation.times().to_vec(),
        nominal: nominal_response,
        percentiles,
        width,
        coverage,
        natural_frequency_hz: Summary::new(&fnat, levels),
        damping_ratio: Summary::new(&zeta, levels),
        samples: n,
        failed_samples: n - good.len(),
        threads: options.threads,
        sampling: options.sampling,
        backend: options.backend,
        memory: plan,
    };
    Ok((band, out.counts))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quantile::percentiles;
    use msd_ident::{InitialState, PaperExperiment};

    /// The band is exactly (bit for bit) the percentiles of each draw simulated alone by
    /// `msd_ident::simulate`, column by column, whatever order the engine simulates the
    /// draws in: for both backends, N not a multiple of 8, several chunks.
    #[test]
    fn equals_the_percentiles_of_each_draw_simulated_alone() {
        let experiment = PaperExperiment::generate(3).unwrap();
        let input = experiment.validation.excitation.slice(0, 1200).unwrap();
        let measured = &experiment.validation.output[..1200];
        for backend in [Backend::EXACT, Backend::PAPER] {
            let options = McOptions {
                samples: 150,
                backend,
                seed: 9,
                percentiles: vec![2.5, 50.0, 90.0],
                max_buffer_bytes: crate::engine::GROUP_COLUMN_BYTES * 3 * 100,
                ..McOptions::default()
            };
            let band =
                monte_carlo_band(&Parameters::PAPER, &input, Some(measured), &options).unwrap();
            assert_eq!((band.memory.chunks, band.failed_samples), (12, 0));
            let sampler = Sampler::new(&Parameters::PAPER, &options.sampling).unwrap();
            let responses: Vec<Vec<f64>> = (0..150)
                .map(|i| {
                    let p = sampler.draw(9, i).unwrap();
                    simulate(&p, &input, InitialState::REST, &backend).unwrap()
                })
                .collect();
            let mut inside = 0;
            for t in 0..1200 {
                let column: Vec<f64> = responses.iter().map(|r| r[t]).collect();
                let mut expected = [0.0; 3];
                percentiles(&column, &options.percentiles, &mut expected);
                for (k, value) in expected.iter().enumerate() {
                    assert_eq!(band.percentiles[k].1[t].to_bits(), value.to_bits(), "t {t}");
                }
                inside += usize::from(expected[0] <= measured[t] && measured[t] <= expected[2]);
            }
            assert_eq!(band.coverage, Some(inside as f64 / 1200.0));
        }
    }

    /// Simulating similar draws side by side is what lets the trackers skip whole
    /// blocks: on the paper's band a level's window cuts fewer than a quarter of the 125
    /// blocks per search (in draw order the median's cuts 124 of them).
    #[test]
    fn similar_draws_side_by_side_let_the_trackers_skip_most_blocks() {
        let experiment = PaperExperiment::generate(0).unwrap();
        let v = &experiment.validation;
        let options = McOptions {
            backend: Backend::EXACT,
            ..McOptions::default()
        };
        let (_, counts) = band_and_counts(
            &Parameters::PAPER,
            &v.excitation,
            None,
            &options,
            &|_, _| {},
        )
        .unwrap();
        for c in counts {
            assert!(4 * c.cut_blocks < 125 * c.searches, "{c:?}");
            assert!(c.predicted > 9 * c.lipschitz, "{c:?}");
        }
    }
}
