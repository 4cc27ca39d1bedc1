//! From options to the design's layout and starting point, and from the optimised
//! amplitudes to a force that meets the limits.

use super::DesignOptions;
use super::basis::Layout;
use super::options::{DesignConstraints, StrokeOn};
use crate::{
    data::Excitation,
    error::{IdentError, Result},
    params::{InitialState, Parameters},
    simulate::{Backend, simulate},
};
use msd_signal::Signal;
use rustfft::num_complex::Complex64;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// The lines, segments and step of `options` on `reference`'s record (validated).
pub(super) fn layout(options: &DesignOptions, reference: &Excitation) -> Layout {
    let (samples, dt) = (reference.len(), reference.dt());
    let period = options.period_samples(reference);
    let spacing = 1.0 / (dt * period as f64);
    let [low, high] = options.constraints.band_hz;
    let first = ((low / spacing - 1e-9).ceil() as usize).max(1);
    let last = ((high / spacing + 1e-9).floor() as usize).min((period - 1) / 2);
    let all: Vec<usize> = (first..=last).collect();
    let lines = if all.len() <= options.lines {
        all
    } else if options.lines == 1 {
        vec![all[all.len() / 2]]
    } else {
        let step = (all.len() - 1) as f64 / (options.lines - 1) as f64;
        let mut picked: Vec<usize> = (0..options.lines)
            .map(|i| all[(i as f64 * step).round() as usize])
            .collect();
        picked.dedup();
        picked
    };
    let (s, record) = (options.segments, samples - 1);
    let edges: Vec<usize> = (0..=s)
        .map(|i| (i * record).div_ceil(s).min(record))
        .collect();
    let mut segments: Vec<(usize, usize)> = edges.windows(2).map(|e| (e[0], e[1])).collect();
    if let Some(last) = segments.last_mut() {
        last.1 = samples;
    }
    let step = options.constraints.step.map(|st| {
        let n = ((st.time - reference.t0()) / dt).round() as usize;
        n.min(samples - 1)
    });
    Layout {
        samples,
        dt,
        period,
        lines,
        segments,
        step,
        kept: (0..samples).collect(),
        weights: vec![1.0; samples],
    }
}

/// Start `start`'s amplitudes: every line at the same amplitude with Schroeder phases
/// (start 0) or seeded random ones, and a step as strong as the multisine's RMS.
pub(super) fn initial(
    layout: &Layout,
    start: usize,
    seed: u64,
    max_force: f64,
) -> Result<Vec<f64>> {
    let lines = layout.lines.len();
    let count = lines * layout.segments.len();
    let noise = msd_signal::gaussian_noise(
        seed.wrapping_add(start as u64),
        "design.phases",
        1.0,
        2 * count,
    )?;
    let a = max_force / (count as f64).sqrt();
    let mut w = Vec::with_capacity(layout.variables());
    for i in 0..count {
        let l = (i % lines) as f64;
        let phase = match start {
            0 => -PI * l * (l + 1.0) / lines as f64,
            _ => noise[2 * i + 1].atan2(noise[2 * i]),
        };
        w.extend([a * phase.cos(), a * phase.sin()]);
    }
    if layout.step.is_some() {
        w.push(a * (count as f64 / 2.0).sqrt());
    }
    Ok(w)
}

/// A design scaled to its limits, and its peaks.
pub(super) struct Scaled {
    pub signal: Signal,
    pub excitation: Excitation,
    pub step_amplitude: f64,
    pub peak_force: f64,
    pub rms_force: f64,
    /// The peak |displacement| on each plant, the prior first.
    pub peak_strokes: Vec<f64>,
}

/// A candidate force and its ratios to the limits.
struct Measured {
    signal: Signal,
    excitation: Excitation,
    peak_force: f64,
    rms_force: f64,
    peak_strokes: Vec<f64>,
    /// The largest ratio of a peak to its limit.
    ratio: f64,
}

/// The limit a step of the least height passes on its own, named by its key with its
/// configured value.
fn step_refused(
    alone: &Measured,
    limited: usize,
    constraints: &DesignConstraints,
    least: f64,
) -> IdentError {
    let stroke = alone.peak_strokes[..limited]
        .iter()
        .fold(0.0f64, |m, x| m.max(*x));
    let on = if limited > 1 {
        "on the box's plants"
    } else {
        "on the prior"
    };
    let mut limits = vec![
        (
            "constraints.max_force",
            constraints.max_force,
            alone.peak_force / constraints.max_force,
            format!("peak force {:.4} N", alone.peak_force),
        ),
        (
            "constraints.max_stroke",
            constraints.max_stroke,
            stroke / constraints.max_stroke,
            format!("peak stroke {stroke:.4} m {on}, its overshoot included"),
        ),
    ];
    if let Some(limit) = constraints.max_rms_force {
        limits.push((
            "constraints.max_rms_force",
            limit,
            alone.rms_force / limit,
            format!("RMS force {:.4} N", alone.rms_force),
        ));
    }
    let (key, value, _, what) = limits
        .into_iter()
        .max_by(|a, b| a.2.total_cmp(&b.2))
        .expect("two limits at least");
    IdentError::InvalidDesign {
        key,
        value,
        expected: format!(
            "a limit the step of the least height (constraints.step.min_amplitude = {least} N) meets on its own: it alone gives {what}"
        ),
    }
}

/// Scales `w` so that the largest of |force|/max_force, RMS/max_rms_force and, on the
/// exact response of the sampled force on the prior (or on each of `plants`, as
/// `stroke_on` says), |x|/max_stroke is 1 − 10⁻⁹. When that leaves the step below its
/// least height (its penalty is soft while optimising), the step is raised to it and
/// the multisine's gain bisected to the largest the limits allow (every peak, so the
/// largest ratio, is convex in that gain: the gains within the limits are an interval
/// from 0).
pub(super) fn scaled(
    layout: &Layout,
    w: &[f64],
    plants: &[Parameters],
    reference: &Excitation,
    constraints: &DesignConstraints,
) -> Result<Scaled> {
    let limited = match constraints.stroke_on {
        StrokeOn::Prior => 1,
        StrokeOn::EveryPlant => plants.len(),
    };
    let measure = |gain: f64, step: f64| -> Result<Measured> {
        let signal = to_signal(layout, w, gain, step, reference.t0());
        let excitation =
            Excitation::from_signal(signal.clone(), reference.t0(), layout.dt, layout.samples)?;
        let peak = |v: &[f64]| v.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let x = |p| simulate(p, &excitation, InitialState::REST, &Backend::EXACT);
        let peak_strokes = plants
            .iter()
            .map(|p| Ok(peak(&x(p)?)))
            .collect::<Result<Vec<f64>>>()?;
        let u = excitation.samples();
        let (peak_force, rms_force) = (
            peak(u),
            (u.iter().map(|u| u * u).sum::<f64>() / u.len() as f64).sqrt(),
        );
        let stroke = peak_strokes[..limited]
            .iter()
            .fold(0.0f64, |m, x| m.max(*x));
        let ratio = (peak_force / constraints.max_force)
            .max(stroke / constraints.max_stroke)
            .max(
                constraints
                    .max_rms_force
                    .map_or(0.0, |limit| rms_force / limit),
            );
        Ok(Measured {
            signal,
            excitation,
            peak_force,
            rms_force,
            peak_strokes,
            ratio,
        })
    };
    let d = layout.step_amplitude(w);
    let target = 1.0 - 1e-9;
    let gain = target / measure(1.0, d)?.ratio;
    let least = constraints.step.map_or(0.0, |s| s.min_amplitude);
    let (gain, step) = if (gain * d).abs() >= least {
        (gain, gain * d)
    } else {
        let step = least.copysign(d);
        let alone = measure(0.0, step)?;
        if alone.ratio > target {
            return Err(step_refused(&alone, limited, constraints, least));
        }
        let (mut low, mut high) = (0.0, gain);
        for _ in 0..40 {
            let mid = 0.5 * (low + high);
            if measure(mid, step)?.ratio <= target {
                low = mid;
            } else {
                high = mid;
            }
        }
        (low, step)
    };
    let m = measure(gain, step)?;
    Ok(Scaled {
        signal: m.signal,
        excitation: m.excitation,
        step_amplitude: step,
        peak_force: m.peak_force,
        rms_force: m.rms_force,
        peak_strokes: m.peak_strokes,
    })
}

/// The force `step`·H(t − step time) + gain·Σ windowed sines of `w`, in absolute time
/// from `t0`: Re(a·e^{iω(t − t0)}) = |a|·sin(ωt + arg a + π/2 − ω·t0).
fn to_signal(layout: &Layout, w: &[f64], gain: f64, step: f64, t0: f64) -> Signal {
    let mut terms = Vec::new();
    if let Some(n) = layout.step {
        terms.push(Signal::Step {
            amplitude: step,
            time: t0 + n as f64 * layout.dt,
        });
    }
    for (s, &(a, b)) in layout.segments.iter().enumerate() {
        for l in 0..layout.lines.len() {
            let amplitude: Complex64 = gain * layout.amplitude(w, s, l);
            let omega = layout.omega(l);
            let phase = (amplitude.arg() + FRAC_PI_2 - omega * t0).rem_euclid(TAU);
            terms.push(Signal::Sine {
                amplitude: amplitude.norm(),
                frequency: omega / TAU,
                phase,
                t_on: t0 + a as f64 * layout.dt,
                t_off: (b < layout.samples).then_some(t0 + b as f64 * layout.dt),
            });
        }
    }
    Signal::Sum { terms }
}

#[cfg(test)]
pub(super) fn to_signal_for_tests(layout: &Layout, w: &[f64], t0: f64) -> Signal {
    to_signal(layout, w, 1.0, layout.step_amplitude(w), t0)
}
