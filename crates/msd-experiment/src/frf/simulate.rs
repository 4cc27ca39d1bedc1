//! Time records simulated on a known plant and turned into a frequency response: hammer
//! hits (half-sine pulses from rest) and a shaker's run (any force signal, the start
//! transient left out). The response is simulated with the force linear between points
//! `SUBSTEPS`× denser than the samples (the hammer's through an anti-aliasing filter
//! first) and is of the quantity of `estimator.kind`; the records are kept for the
//! time-domain fit.

use super::source::{Loaded, run_error};
use super::time_domain::TimeRecords;
use crate::config::{ChainPlant, HammerSource, ShakerSource};
use crate::error::ExperimentError;
use crate::error::Result;
use msd_ident::Hold;
use msd_signal::{FrfOptions, Record, frf_estimate, gaussian_noise};

/// `clean` plus Gaussian noise of standard deviation `sigma` (stream `name` of `seed`).
fn noisy(clean: &[f64], seed: u64, name: &str, sigma: f64) -> Result<Vec<f64>> {
    let noise = gaussian_noise(seed, name, sigma, clean.len()).map_err(run_error)?;
    Ok(clean.iter().zip(&noise).map(|(a, b)| a + b).collect())
}

fn rms(v: &[f64]) -> f64 {
    (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt()
}

/// The frequency response of `channels` ([force, response] per record) and the records
/// themselves, to be fitted with the force `hold` between samples.
fn estimate(
    channels: Vec<[Vec<f64>; 2]>,
    sample_rate: f64,
    options: &FrfOptions,
    hold: Hold,
    description: String,
    source: &str,
) -> Result<Loaded> {
    let records: Vec<Record<'_>> = channels
        .iter()
        .map(|[input, output]| Record { input, output })
        .collect();
    let frf = frf_estimate(&records, sample_rate, options).map_err(|e| match e {
        // The config's force is the cause (e.g. `rms = 0`): exit 2 naming it.
        msd_signal::SignalError::ZeroInputPower { .. } => ExperimentError::config(
            format!("frequency_response.{source}.force"),
            format!("{e}: the simulated force is constant; expected a force that drives the plant"),
        ),
        e => run_error(e),
    })?;
    Ok(Loaded {
        frf,
        description,
        time: Some(TimeRecords {
            channels,
            sample_rate,
            kind: options.kind,
            hold,
        }),
        members: Vec::new(),
        nodes: Vec::new(),
    })
}

/// One hit as the acquisition sees it: a half-sine pulse of `peak` N starting at
/// `h.trigger`, at `SUBSTEPS` points per sample of `n`, through the anti-aliasing
/// filter ([`anti_aliasing`]).
fn pulse(h: &HammerSource, peak: f64, n: usize) -> Vec<f64> {
    let rate = h.sample_rate * SUBSTEPS as f64;
    let first = ((h.trigger * rate).floor() as usize).min(n * SUBSTEPS);
    let last = (((h.trigger + h.pulse_width) * rate).ceil() as usize + 1).min(n * SUBSTEPS);
    let raw: Vec<(usize, f64)> = (first..last)
        .map(|i| {
            let t = i as f64 / rate - h.trigger;
            let inside = (0.0..=h.pulse_width).contains(&t);
            let value = if inside {
                peak * (std::f64::consts::PI * t / h.pulse_width).sin()
            } else {
                0.0
            };
            (i, value)
        })
        .collect();
    let taps = anti_aliasing();
    let half = taps.len() / 2;
    let mut out = vec![0.0; n * SUBSTEPS];
    for (i, value) in raw {
        let start = i.saturating_sub(half);
        for (j, o) in out.iter_mut().enumerate().take(i + half + 1).skip(start) {
            *o += value * taps[j + half - i];
        }
    }
    out
}

/// The acquisition's anti-aliasing filter at `SUBSTEPS` points per sample: a
/// windowed-sinc low-pass (Blackman window, 1025 taps, zero phase, unit gain at 0 Hz)
/// cut at 0.4 of the sample rate and below 1e-4 from half of it. A lab's filter acts
/// on both channels alike and so leaves H = X/F as the plant's; here it acts on the
/// force before the plant (the same, the plant being linear), so that the force's
/// samples are not aliased (a 5 ms half-sine keeps 1 % of its low-frequency spectrum at
/// the sample rate) and the response is that of a smooth force, simulated `SUBSTEPS`×
/// finer than sampled.
fn anti_aliasing() -> Vec<f64> {
    const TAPS: usize = 1025;
    let cut = 0.4 / SUBSTEPS as f64;
    let middle = (TAPS / 2) as f64;
    let taps: Vec<f64> = (0..TAPS)
        .map(|i| {
            let x = i as f64 - middle;
            let sinc = if x == 0.0 {
                2.0 * cut
            } else {
                (std::f64::consts::TAU * cut * x).sin() / (std::f64::consts::PI * x)
            };
            let phase = std::f64::consts::TAU * i as f64 / (TAPS - 1) as f64;
            sinc * (0.42 - 0.5 * phase.cos() + 0.08 * (2.0 * phase).cos())
        })
        .collect();
    let gain: f64 = taps.iter().sum();
    taps.into_iter().map(|t| t / gain).collect()
}

/// `h.hits` hits from rest, each its own record; the response noise is a share of the
/// peak response to a hit of the nominal force, the same sensor noise on every record
/// (a share of each record's own peak would make the noise follow the hit, which no
/// sensor does, and H1's variance differ from what the coherence says by about 20 %
/// at ±20 % hits: the hits' spectra weigh each record's noise in H1 but not in the
/// coherence's residual).
pub(super) fn hammer(
    h: &HammerSource,
    plant: &ChainPlant,
    options: &FrfOptions,
    seed: u64,
) -> Result<Loaded> {
    let n = (h.duration * h.sample_rate).round() as usize;
    let spread =
        gaussian_noise(seed, "hammer.force_peak", h.force_spread, h.hits).map_err(run_error)?;
    let dt = 1.0 / (h.sample_rate * SUBSTEPS as f64);
    let sampled = |v: Vec<f64>| -> Vec<f64> { v.into_iter().step_by(SUBSTEPS).collect() };
    let mut clean = Vec::with_capacity(h.hits);
    for s in &spread {
        let amplitude = (1.0 + s).max(0.1);
        let fine = pulse(h, h.force_peak * amplitude, n);
        let response = sampled(
            plant
                .sampled_response(&fine, dt, options.kind)
                .map_err(run_error)?,
        );
        clean.push((sampled(fine), response, amplitude));
    }
    // The response is linear in the hit: the first one's peak per unit amplitude.
    let (_, first, amplitude) = &clean[0];
    let sigma = h.response_noise * first.iter().fold(0.0f64, |m, v| m.max(v.abs())) / amplitude;
    let mut channels = Vec::with_capacity(h.hits);
    for (i, (force, response, _)) in clean.iter().enumerate() {
        channels.push([
            noisy(force, seed, &format!("hammer.force.{i}"), h.force_noise)?,
            noisy(response, seed, &format!("hammer.response.{i}"), sigma)?,
        ]);
    }
    let description = format!(
        "{} hammer hits simulated on the plant ({} s records at {} Hz, {} ms half-sine pulses of {} N ± {} %, noise {} N on the force and {} % of a nominal hit's peak on the response)",
        h.hits,
        h.duration,
        h.sample_rate,
        1e3 * h.pulse_width,
        h.force_peak,
        100.0 * h.force_spread,
        h.force_noise,
        100.0 * h.response_noise
    );
    // The force between samples is a band-limited signal, not a line.
    estimate(
        channels,
        h.sample_rate,
        options,
        Hold::Cubic,
        description,
        "hammer",
    )
}

/// Sub-steps per sample of the shaker's run: the force is a continuous signal, applied
/// linear between points 16× denser than the samples, which changes the response at f
/// by about (π·f/(16·fs))²/3 relative (the first-order hold's sinc²): 4e-5 at the
/// paper's 1.1 Hz sampled at 20 Hz.
const SUBSTEPS: usize = 16;

/// One run of the force from rest, `settle` seconds left out, then `records`
/// consecutive records; the noise is a share of each channel's RMS over the records.
pub(super) fn shaker(
    s: &ShakerSource,
    plant: &ChainPlant,
    options: &FrfOptions,
    seed: u64,
) -> Result<Loaded> {
    let dt = 1.0 / (s.sample_rate * SUBSTEPS as f64);
    let per = (s.duration * s.sample_rate).round() as usize;
    let skip = (s.settle * s.sample_rate).round() as usize;
    let fine: Vec<f64> = (0..(skip + s.records * per) * SUBSTEPS)
        .map(|i| s.force.value(i as f64 * dt))
        .collect();
    let sampled = |v: Vec<f64>| -> Vec<f64> { v.into_iter().step_by(SUBSTEPS).collect() };
    let response = sampled(
        plant
            .sampled_response(&fine, dt, options.kind)
            .map_err(run_error)?,
    );
    let force = sampled(fine);
    let sigma = [
        s.force_noise * rms(&force[skip..]),
        s.response_noise * rms(&response[skip..]),
    ];
    let mut channels = Vec::with_capacity(s.records);
    for i in 0..s.records {
        let range = skip + i * per..skip + (i + 1) * per;
        channels.push([
            noisy(
                &force[range.clone()],
                seed,
                &format!("shaker.force.{i}"),
                sigma[0],
            )?,
            noisy(
                &response[range],
                seed,
                &format!("shaker.response.{i}"),
                sigma[1],
            )?,
        ]);
    }
    let description = format!(
        "{} shaker records simulated on the plant ({} s each at {} Hz after {} s of settling; noise {} % of the RMS on the force and {} % on the response)",
        s.records,
        s.duration,
        s.sample_rate,
        s.settle,
        100.0 * s.force_noise,
        100.0 * s.response_noise
    );
    // The force between samples is the signal, not a line: a measured force's hold.
    estimate(
        channels,
        s.sample_rate,
        options,
        Hold::Cubic,
        description,
        "shaker",
    )
}
