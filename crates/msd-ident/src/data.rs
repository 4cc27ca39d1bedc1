//! Excitations (a known input on a uniform grid) and data sets (input plus measured
//! displacement).

use crate::error::{IdentError, Result};
use msd_ode::Breakpoint;
use msd_signal::{PreparedSignal, Signal};

/// Smallest record the estimators accept.
pub const MIN_SAMPLES: usize = 10;

/// A known input force on a uniform time grid tᵢ = t₀ + i·dt.
///
/// When built from a [`Signal`] it keeps the signal, so the adaptive solver can
/// evaluate the force at any time (the paper's way) and the exact solver knows every
/// jump and kink. From plain samples the force between samples is taken as linear.
///
/// ```
/// use msd_ident::Excitation;
/// use msd_signal::paper_identification_input;
/// let e = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
/// assert_eq!(e.len(), 7501);
/// assert_eq!(e.breakpoints().len(), 3); // the step at 0.5 s, the sine switches at 3 s and 9 s
/// assert_eq!(e.value(0.5), 6.0);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Excitation {
    t0: f64,
    dt: f64,
    samples: Vec<f64>,
    times: Vec<f64>,
    breakpoints: Vec<Breakpoint>,
    signal: Option<Signal>,
    /// The signal prepared for evaluation at any time (the ode45 force).
    prepared: Option<PreparedSignal>,
}

impl Excitation {
    /// Samples `signal` on `n` points from `t0` with step `dt`, recording its breakpoints.
    ///
    /// A breakpoint within 1e-9·dt of a sample instant is placed on it with its left and
    /// right values (exact for the exact solver). One between samples cannot be
    /// represented by samples; its two neighbouring samples are marked so that no
    /// higher-order stencil crosses it (first-order accurate there). A signal with more
    /// than about two breakpoints per sample interval (a PRBS clocked faster than the
    /// grid) is refused.
    pub fn from_signal(signal: Signal, t0: f64, dt: f64, n: usize) -> Result<Self> {
        check_grid(t0, dt, n)?;
        signal.validate()?;
        let t_end = t0 + dt * (n - 1) as f64;
        // More jumps than samples (a PRBS clocked faster than the grid) cannot be
        // represented by samples, and listing them could take forever: refuse first.
        let edges = signal.max_breakpoints(t0, t_end);
        if edges.is_nan() || edges > (2 * n + 16) as f64 {
            return Err(IdentError::InvalidParameter {
                name: "signal breakpoints (a PRBS clock_period below the sampling interval?)",
                value: edges,
                expected: "at most about two jumps or kinks per sample interval",
            });
        }
        let samples = signal.sample(t0, dt, n);
        check_finite("input", &samples)?;
        let mut breakpoints: Vec<Breakpoint> = Vec::new();
        let mut push = |bp: Breakpoint| match breakpoints.last_mut() {
            Some(last) if last.index == bp.index => {
                // Keep the outermost values: left of the first, right of the last.
                last.right = bp.right;
            }
            _ => breakpoints.push(bp),
        };
        for bp in signal.breakpoints(t0, t_end) {
            let position = (bp.time - t0) / dt;
            let nearest = position.round();
            if (position - nearest).abs() <= 1e-9 * position.abs().max(1.0) {
                let index = nearest as usize;
                if index < n {
                    push(Breakpoint {
                        index,
                        left: bp.left,
                        right: bp.right,
                    });
                }
            } else {
                for index in [position.floor() as usize, position.ceil() as usize] {
                    if index < n {
                        push(Breakpoint {
                            index,
                            left: samples[index],
                            right: samples[index],
                        });
                    }
                }
            }
        }
        let times = grid(t0, dt, n);
        Ok(Self {
            t0,
            dt,
            samples,
            times,
            breakpoints,
            prepared: Some(signal.prepare()),
            signal: Some(signal),
        })
    }

    /// An excitation known only by its samples (measured force): linear between samples.
    pub fn from_samples(t0: f64, dt: f64, samples: Vec<f64>) -> Result<Self> {
        check_grid(t0, dt, samples.len())?;
        check_finite("input", &samples)?;
        let times = grid(t0, dt, samples.len());
        Ok(Self {
            t0,
            dt,
            samples,
            times,
            breakpoints: Vec::new(),
            signal: None,
            prepared: None,
        })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// Always false: an excitation has at least one sample.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// Start time t₀.
    pub fn t0(&self) -> f64 {
        self.t0
    }

    /// Sampling interval dt.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The sample times.
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// The sampled force (right values at jumps).
    pub fn samples(&self) -> &[f64] {
        &self.samples
    }

    /// Jumps and kinks at sample instants, for the exact solver.
    pub fn breakpoints(&self) -> &[Breakpoint] {
        &self.breakpoints
    }

    /// The generating signal, when known.
    pub fn signal(&self) -> Option<&Signal> {
        self.signal.as_ref()
    }

    /// The force at any time: the signal when known, else linear interpolation of the
    /// samples (held constant outside the record).
    pub fn value(&self, t: f64) -> f64 {
        match &self.prepared {
            Some(s) => s.value(t),
            None => {
                let position = (t - self.t0) / self.dt;
                if position <= 0.0 {
                    return self.samples[0];
                }
                let last = self.samples.len() - 1;
                if position >= last as f64 {
                    return self.samples[last];
                }
                let i = position.floor() as usize;
                let s = position - i as f64;
                self.samples[i] + s * (self.samples[i + 1] - self.samples[i])
            }
        }
    }

    /// [`value`](Self::value) at the times `t[l]` of the lanes with `active[l]`, into
    /// `out[l]` (the others are left as they are), each bit for bit `value(t[l])`: a
    /// known signal is evaluated once for all the times (faster than one call each).
    ///
    /// ```
    /// use msd_ident::Excitation;
    /// use msd_signal::paper_validation_input;
    /// let e = Excitation::from_signal(paper_validation_input(), 0.0, 0.002, 7501)?;
    /// let mut out = [0.0; 3];
    /// e.values(&[0.5, 1.0, 3.3], &[true; 3], &mut out);
    /// assert_eq!(out[2], e.value(3.3));
    /// # Ok::<(), msd_ident::IdentError>(())
    /// ```
    pub fn values<const B: usize>(&self, t: &[f64; B], active: &[bool; B], out: &mut [f64; B]) {
        match &self.prepared {
            Some(s) => s.values(t, active, out),
            None => {
                for l in (0..B).filter(|&l| active[l]) {
                    out[l] = self.value(t[l]);
                }
            }
        }
    }

    /// The samples `range` as a new excitation starting at their first time.
    pub fn slice(&self, start: usize, end: usize) -> Result<Self> {
        if start >= end || end > self.len() {
            return Err(IdentError::RangeOutOfBounds {
                start,
                end,
                len: self.len(),
            });
        }
        let t0 = self.times[start];
        let breakpoints = self
            .breakpoints
            .iter()
            .filter(|bp| bp.index >= start && bp.index < end)
            .map(|bp| Breakpoint {
                index: bp.index - start,
                ..*bp
            })
            .collect();
        Ok(Self {
            t0,
            dt: self.dt,
            samples: self.samples[start..end].to_vec(),
            times: self.times[start..end].to_vec(),
            breakpoints,
            signal: self.signal.clone(),
            prepared: self.prepared.clone(),
        })
    }
}

/// A test record: a known excitation and the measured displacement at the same instants.
///
/// ```
/// use msd_ident::{DataSet, Excitation};
/// let input = Excitation::from_samples(0.0, 0.01, vec![1.0; 20])?;
/// let data = DataSet::new("bench test", input, vec![0.0; 20])?;
/// assert_eq!(data.len(), 20);
/// let short = DataSet::new("short", Excitation::from_samples(0.0, 0.01, vec![1.0; 20])?, vec![0.0; 19]);
/// assert!(short.is_err());
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct DataSet {
    /// A name for reports.
    pub name: String,
    /// The input force.
    pub excitation: Excitation,
    /// Measured displacement, one per input sample.
    pub output: Vec<f64>,
    /// Unit of the input (for reports). By default "N".
    pub input_unit: String,
    /// Unit of the output (for reports). By default "m".
    pub output_unit: String,
}

impl DataSet {
    /// Checked constructor: equal lengths, at least [`MIN_SAMPLES`], finite output.
    pub fn new(name: impl Into<String>, excitation: Excitation, output: Vec<f64>) -> Result<Self> {
        if output.len() != excitation.len() {
            return Err(IdentError::LengthMismatch {
                what: "output",
                expected: excitation.len(),
                got: output.len(),
            });
        }
        if output.len() < MIN_SAMPLES {
            return Err(IdentError::TooFewSamples {
                got: output.len(),
                needed: MIN_SAMPLES,
                why: "a data set",
            });
        }
        check_finite("output", &output)?;
        Ok(Self {
            name: name.into(),
            excitation,
            output,
            input_unit: "N".into(),
            output_unit: "m".into(),
        })
    }

    /// From time stamps, input and output columns (e.g. a CSV file): the time stamps must
    /// be finite, increasing and uniform within 1e-6 relative.
    pub fn from_columns(
        name: impl Into<String>,
        time: &[f64],
        input: Vec<f64>,
        output: Vec<f64>,
    ) -> Result<Self> {
        if input.len() != time.len() {
            return Err(IdentError::LengthMismatch {
                what: "input",
                expected: time.len(),
                got: input.len(),
            });
        }
        if time.len() < MIN_SAMPLES {
            return Err(IdentError::TooFewSamples {
                got: time.len(),
                needed: MIN_SAMPLES,
                why: "a data set",
            });
        }
        check_finite("time", time)?;
        let dt = (time[time.len() - 1] - time[0]) / (time.len() - 1) as f64;
        for (i, w) in time.windows(2).enumerate() {
            let step = w[1] - w[0];
            if step <= 0.0 || step.is_nan() || (step - dt).abs() > 1e-6 * dt.abs() {
                return Err(IdentError::NonUniformTime {
                    index: i + 1,
                    step,
                    expected: dt,
                });
            }
        }
        Self::new(name, Excitation::from_samples(time[0], dt, input)?, output)
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.output.len()
    }

    /// Always false: a data set has at least [`MIN_SAMPLES`] samples.
    pub fn is_empty(&self) -> bool {
        self.output.is_empty()
    }

    /// The samples `start..end` as a new data set.
    pub fn slice(&self, start: usize, end: usize) -> Result<Self> {
        let excitation = self.excitation.slice(start, end)?;
        let mut data = Self::new(
            self.name.clone(),
            excitation,
            self.output[start..end].to_vec(),
        )?;
        data.input_unit = self.input_unit.clone();
        data.output_unit = self.output_unit.clone();
        Ok(data)
    }
}

fn grid(t0: f64, dt: f64, n: usize) -> Vec<f64> {
    (0..n).map(|i| t0 + dt * i as f64).collect()
}

fn check_grid(t0: f64, dt: f64, n: usize) -> Result<()> {
    if !t0.is_finite() {
        return Err(IdentError::InvalidParameter {
            name: "t0",
            value: t0,
            expected: "a finite number",
        });
    }
    if !(dt.is_finite() && dt > 0.0) {
        return Err(IdentError::InvalidParameter {
            name: "dt",
            value: dt,
            expected: "a finite number > 0",
        });
    }
    if n < 2 {
        return Err(IdentError::TooFewSamples {
            got: n,
            needed: 2,
            why: "an excitation",
        });
    }
    Ok(())
}

pub(crate) fn check_finite(field: &'static str, x: &[f64]) -> Result<()> {
    match x.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(IdentError::NonFiniteSample {
            field,
            index,
            value: x[index],
        }),
        None => Ok(()),
    }
}
