//! Several modes: poles from the stabilization diagram, then every modal parameter
//! polished by weighted nonlinear least squares, with intervals.

use std::f64::consts::TAU;

use msd_opt::LmExit;
use msd_signal::{Complex64, FrequencyResponseEstimate, FrfKind};
use nalgebra::DMatrix;
use serde::Serialize;

use crate::options::ModalOptions;
use crate::polish::{PER_MODE, Polished, lsfd, model, polish};
use crate::stabilization::{diagram_of, why_too_few};
use msd_modal_core::diagram::{StabilizationDiagram, StableColumn};
use msd_modal_core::error::{ModalError, Result};
use msd_modal_core::input_noise::InputNoise;
use msd_modal_core::lines::Lines;
use msd_modal_core::lines::{FrfWeighting, prepare};
use msd_modal_core::mode::{Dof, Mode, ShapeEntry};
use msd_modal_core::noise_check::NoiseCheck;
use msd_modal_core::window::{WindowCorrection, unshift_pole};
use msd_opt::statistics::Interval;
use msd_opt::statistics::t_975;

/// The result of [`fit_modes`]: the modes, the residual terms, the diagram.
///
/// Displays a summary line, one line per mode and the residual terms; serializes with
/// every field (the diagram included).
///
/// ```
/// use msd_modal::{fit_modes, ModalOptions, synthetic_frequency_response, ModalParameters};
/// let modes = [(6.0, 0.02, 1.0), (15.0, 0.01, 0.3)].map(|(f, z, a)| ModalParameters {
///     natural_frequency_hz: f, damping_ratio: z, modal_constant: a, modal_constant_imaginary: 0.0 });
/// let f: Vec<f64> = (1..=800).map(|i| 0.025 * i as f64).collect();
/// let frf = synthetic_frequency_response(&f, 0.01, 1, |f| modes.iter().map(|m| m.receptance(f)).sum())?;
/// let fit = fit_modes(&frf, &ModalOptions::default())?;
/// assert_eq!(fit.modes.len(), 2);
/// assert!(fit.to_string().starts_with("2 modes fitted to 800 lines"));
/// let json = serde_json::to_value(&fit).expect("serializable");
/// assert_eq!(json["modes"][1]["natural_frequency_hz"]["value"], fit.modes[1].natural_frequency_hz.value);
/// // The fitted model beside the data, for a Bode or Nyquist plot.
/// assert!((fit.response(15.0) - frf.h[599]).norm() < 0.05 * frf.h[599].norm());
/// # Ok::<(), msd_modal::ModalError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModalFit {
    /// The modes, by frequency.
    pub modes: Vec<Mode>,
    /// The lower residual L of the term −L/ω² (the modes below the band).
    pub lower_residual: Interval,
    /// The upper residual U (the modes above the band).
    pub upper_residual: Interval,
    /// The stabilization diagram the poles came from.
    pub diagram: StabilizationDiagram,
    /// The first and last line fitted, Hz.
    pub band_hz: [f64; 2],
    /// Lines fitted (two residuals each).
    pub lines: usize,
    /// The weighting used (`coherence` where the coherence says nothing is `variance`
    /// or `uniform`).
    pub weighting: FrfWeighting,
    /// σ̂ = √(SSE/(2K − p)) of the weighted residuals.
    pub sigma: f64,
    /// 2K − p.
    pub degrees_of_freedom: usize,
    /// ‖H_model − H‖/‖H‖ over the lines (unweighted), in the measured quantity.
    pub relative_error: f64,
    /// The quantity the data measure (and `relative_error` is in).
    pub kind: FrfKind,
    /// Whether the data's phase rises through their resonances (the e^(−jωt)
    /// convention, or H = S_xy/S_xx as MATLAB's `cpsd` gives it): the fit was made on
    /// their complex conjugate; [`response`](Self::response) gives the model as the data
    /// show it.
    pub conjugated: bool,
    /// Levenberg–Marquardt iterations of the polish.
    pub iterations: usize,
    /// Its residual evaluations.
    pub evaluations: usize,
    /// Why it stopped.
    pub exit: LmExit,
    /// Modes the diagram selected that the final fit moved away (not in `modes`).
    pub refused: Vec<RefusedMode>,
    /// The residuals against the FRF's own noise, where the coherence gives each line's
    /// absolute variance (two or more averages); `None` otherwise.
    pub noise_check: Option<NoiseCheck>,
    /// The force's noise on an H1 estimate: measured (an impact test's force channel)
    /// and taken off the lines, or the coherence's sign of it; `None` when none.
    pub input_noise: Option<InputNoise>,
}

impl ModalFit {
    /// Mode `r`'s modal constant A + jB as two 95 % intervals (Student's t with the
    /// fit's degrees of freedom); None past the last mode.
    ///
    /// ```
    /// use msd_modal::{fit_modes, ModalOptions, synthetic_frequency_response, ModalParameters};
    /// let truth = ModalParameters { natural_frequency_hz: 12.0, damping_ratio: 0.02,
    ///     modal_constant: 0.5, modal_constant_imaginary: 0.0 };
    /// let f: Vec<f64> = (1..=400).map(|i| 0.05 * i as f64).collect();
    /// let frf = synthetic_frequency_response(&f, 0.01, 3, |f| truth.receptance(f))?;
    /// let fit = fit_modes(&frf, &ModalOptions { orders: [2, 20], ..ModalOptions::default() })?;
    /// let [a, b] = fit.modal_constant(0).expect("one mode");
    /// assert!((a.value / 0.5 - 1.0).abs() < 1e-2 && b.value.abs() < 1e-2);
    /// assert!(fit.modes[0].stable_orders >= Some(5));
    /// # Ok::<(), msd_modal::ModalError>(())
    /// ```
    pub fn modal_constant(&self, r: usize) -> Option<[Interval; 2]> {
        let t = t_975(self.degrees_of_freedom);
        self.modes.get(r)?.modal_constants.first()?.intervals(t)
    }

    /// The receptance of the model as fitted at `frequency_hz` (with an exponential
    /// window: the windowed response, which the data show).
    pub fn response(&self, frequency_hz: f64) -> Complex64 {
        let w = TAU * frequency_hz;
        let modes: Complex64 = self
            .modes
            .iter()
            .map(|m| {
                let mut p = m.parameters();
                if let Some(c) = m.window_correction {
                    p.natural_frequency_hz = c.natural_frequency_hz_windowed;
                    p.damping_ratio = c.damping_ratio_windowed;
                }
                p.receptance(frequency_hz)
            })
            .sum();
        let h = modes
            + Complex64::new(
                self.upper_residual.value - self.lower_residual.value / (w * w),
                0.0,
            );
        msd_modal_core::lines::as_measured(h, self.conjugated, self.kind)
    }
}

impl std::fmt::Display for ModalFit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let what = format!("{} modes", self.modes.len());
        let (lines, band, iterations) = (self.lines, self.band_hz, self.iterations);
        msd_modal_core::lines::fit_line(
            f,
            &what,
            lines,
            band,
            self.weighting,
            iterations,
            self.relative_error,
        )?;
        write!(f, " in {}", self.kind)?;
        if self.conjugated {
            write!(f, "\n{}", msd_modal_core::lines::CONJUGATED)?;
        }
        for (i, m) in self.modes.iter().enumerate() {
            write!(
                f,
                "\nmode {}: {}",
                i + 1,
                Mode::new(m.natural_frequency_hz, m.damping_ratio)
            )?;
            if let Some([a, b]) = self.modal_constant(i) {
                write!(f, ", A = {}, B = {}", scientific(&a), scientific(&b))?;
            }
            if let Some(c) = &m.window_correction {
                write!(f, "; {c}")?;
            }
        }
        for r in &self.refused {
            write!(f, "\nrefused: {r}")?;
        }
        write!(
            f,
            "\nlower residual L = {}, upper residual U = {}",
            scientific(&self.lower_residual),
            scientific(&self.upper_residual)
        )?;
        if let Some(check) = &self.noise_check {
            write!(f, "\n{check}")?;
        }
        if let Some(noise) = &self.input_noise {
            write!(f, "\n{noise}")?;
        }
        Ok(())
    }
}

/// An interval in scientific notation: `value ± standard error (95 % CI low … high)`.
fn scientific(i: &Interval) -> String {
    format!(
        "{:.4e} ± {:.2e} (95 % CI {:.4e} … {:.4e})",
        i.value, i.standard_error, i.ci95[0], i.ci95[1]
    )
}

/// Fits several modes to `frf` (converted to receptance): H(ω) = Σ_r H_r(ω) − L/ω² + U.
///
/// ## The algorithm
/// The [`stabilization_diagram`](crate::stabilization::stabilization_diagram) gives the poles (fn, ζ)
/// of the selected modes; LSFD (linear least squares for fixed poles) the modal
/// constants A + jB and the residual terms L and U; weights relative to |H| are then
/// taken from this model rather than the measured |H| (as in msd-ident's `fit_one_mode`),
/// and Levenberg–Marquardt (msd-opt, analytic Jacobian) polishes all 4M + 2 parameters
/// at once. The covariance is s²(JᵀJ)⁻¹ with s² = SSE/(2K − p), times the estimate's
/// noise bandwidth (as in msd-ident's `fit_one_mode`), the intervals
/// Student's t with 2K − p degrees of freedom. With an exponential window each pole is moved back
/// by 1/τ ([`WindowCorrection`]) and its fn and ζ intervals follow by the delta method;
/// the modal constants and residual terms are those of the windowed response.
///
/// Errors: those of the diagram, no stable mode, modes that cannot be told apart, a fit
/// that does not converge.
///
/// ```
/// use msd_modal::{fit_modes, ModalOptions, ModalParameters};
/// use msd_signal::FrequencyResponseEstimate;
/// let truth = [(8.0, 0.02, 1.0), (17.0, 0.01, -0.5)].map(|(f, z, a)| ModalParameters {
///     natural_frequency_hz: f, damping_ratio: z, modal_constant: a, modal_constant_imaginary: 0.0 });
/// let f: Vec<f64> = (1..=1000).map(|i| 0.025 * i as f64).collect();
/// let h = f.iter().map(|&f| truth.iter().map(|m| m.receptance(f)).sum()).collect();
/// let fit = fit_modes(&FrequencyResponseEstimate::new(f, h)?, &ModalOptions::default())?;
/// assert_eq!(fit.modes.len(), 2);
/// for (mode, truth) in fit.modes.iter().zip(&truth) {
///     assert!((mode.natural_frequency_hz.value / truth.natural_frequency_hz - 1.0).abs() < 1e-9);
///     assert!((mode.damping_ratio.value / truth.damping_ratio - 1.0).abs() < 1e-7);
///     assert!((mode.parameters().modal_constant / truth.modal_constant - 1.0).abs() < 1e-7);
/// }
/// println!("{fit}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// With no mode in the data the error keeps the diagram, drawn as usual:
///
/// ```
/// use msd_modal::{ModalError, ModalOptions, fit_modes};
/// use msd_signal::{Complex64, FrequencyResponseEstimate};
/// // A smooth response with no mode in it.
/// let f: Vec<f64> = (1..=200).map(|i| i as f64).collect();
/// let h = f.iter().map(|&f| Complex64::new(1.0 + 1e-3 * f, 0.0)).collect();
/// let err = fit_modes(&FrequencyResponseEstimate::new(f, h)?, &ModalOptions::default()).unwrap_err();
/// let ModalError::TooFewModes { diagram, .. } = &err else { panic!("{err}") };
/// assert_eq!(diagram.orders.len(), 20); // orders 2, 4, …, 40, drawn as usual
/// assert!(err.to_string().contains("no mode is stable"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn fit_modes(frf: &FrequencyResponseEstimate, options: &ModalOptions) -> Result<ModalFit> {
    options.validate()?;
    let mut fit = or_conjugated(
        fit_as_given(frf, options),
        || fit_as_given(&frf.conjugate(), options),
        |fit| fit.relative_error,
    )?;
    fit.0.conjugated = fit.1;
    Ok(fit.0)
}

/// `first` (a fit of the data as they are), or `conjugated` (the same fit of their
/// complex conjugate), marked `true`, when `first` finds no mode or explains nothing of
/// the data (`error`, the relative error in the measured quantity, at least 0.9: data
/// whose phase rises through their resonances have only unstable poles as they are, or
/// poles that fit them no better than zero) and the conjugate does better. Else the
/// first result.
pub(crate) fn or_conjugated<T>(
    first: Result<T>,
    conjugated: impl FnOnce() -> Result<T>,
    error: impl Fn(&T) -> f64,
) -> Result<(T, bool)> {
    match first {
        Err(e @ (ModalError::TooFewModes { .. } | ModalError::NotIdentifiable { .. })) => {
            conjugated().map(|fit| (fit, true)).map_err(|_| e)
        }
        Ok(fit) if error(&fit) >= EXPLAINS_NOTHING || error(&fit).is_nan() => match conjugated() {
            Ok(other) if error(&other) < error(&fit) => Ok((other, true)),
            _ => Ok((fit, false)),
        },
        other => other.map(|fit| (fit, false)),
    }
}

/// A relative error in the measured quantity from which a fit explains nothing (the
/// model's residual is 90 % of the data's norm).
const EXPLAINS_NOTHING: f64 = 0.9;

/// [`fit_modes`] on the data as they are.
fn fit_as_given(frf: &FrequencyResponseEstimate, options: &ModalOptions) -> Result<ModalFit> {
    let lines = prepare(
        frf,
        options.band_hz,
        options.weighting,
        options.orders[1] + 1,
    )?;
    let diagram = diagram_of(&lines, options)?;
    if diagram.modes.is_empty() {
        return Err(ModalError::TooFewModes {
            reason: format!(
                "no mode is stable in the stabilization diagram{}",
                why_too_few(&diagram, options)
            ),
            diagram: Box::new(diagram),
        });
    }
    let (polished, lines, selected, refused) = polish_selected(lines, &diagram)?;
    let t = t_975(polished.degrees_of_freedom);
    let theta = &polished.theta;
    let decay = lines.exponential_decay;
    let modes = selected
        .iter()
        .enumerate()
        .map(|(r, stable)| {
            mode(
                theta,
                &polished.covariance,
                r,
                t,
                decay,
                stable.stable_orders,
            )
        })
        .collect();
    let p = theta.len();
    let interval =
        |j: usize| Interval::new(theta[j], polished.covariance[(j, j)].max(0.0).sqrt(), t);
    Ok(ModalFit {
        modes,
        lower_residual: interval(p - 2),
        upper_residual: interval(p - 1),
        relative_error: lines.relative_error(|w| model(theta, w)),
        kind: frf.kind,
        conjugated: false,
        band_hz: lines.band_hz,
        lines: lines.omega.len(),
        weighting: lines.weighting,
        sigma: polished.sigma,
        degrees_of_freedom: polished.degrees_of_freedom,
        iterations: polished.fit.iterations,
        evaluations: polished.fit.evaluations,
        exit: polished.fit.exit,
        refused,
        diagram,
        noise_check: polished.noise_check,
        input_noise: polished.input_noise,
    })
}

/// LSFD and the polish on the diagram's modes; a mode the polish moves by more than
/// its half-power bandwidth, or nearer to another selected mode than to its own column,
/// is refused and the rest fitted again; so, one at a time, is a mode whose modal
/// constant the fit cannot tell from zero (while another mode is left). Returns the
/// polish, the lines as weighted for it, the modes kept and those refused.
fn polish_selected(
    lines: Lines,
    diagram: &StabilizationDiagram,
) -> Result<(Polished, Lines, Vec<StableColumn>, Vec<RefusedMode>)> {
    let mut selected = diagram.modes.clone();
    let mut refused = Vec::new();
    loop {
        let poles: Vec<(f64, f64)> = selected
            .iter()
            .map(|m| (TAU * m.natural_frequency_hz, m.damping_ratio))
            .collect();
        if 2 * lines.omega.len() <= PER_MODE * poles.len() + 2 {
            return Err(ModalError::TooFewSamples {
                got: lines.omega.len(),
                needed: (PER_MODE * poles.len() + 2) / 2 + 1,
                why: "lines for the modal parameters of every stable mode",
            });
        }
        let mut weighted = lines.clone();
        let start = lsfd(&weighted, &poles)?;
        // Weights from the coherence's noise model (every line's own coherence from a
        // few averages is a noisy weight), which also splits each line's variance
        // between the force's noise and the response's for the covariance.
        weighted.smooth_coherence_weights(|w| model(&start, w));
        // Noise on the force biases H1 low: raised where the force's noise is known.
        let input_noise = weighted.correct_input_noise();
        let mut polished = match polish(&weighted, lsfd(&weighted, &poles)?) {
            Err(ModalError::EstimationFailed { reason }) if selected.len() > 1 => {
                let r = least_stable(&selected);
                refused.push(RefusedMode {
                    natural_frequency_hz: selected[r].natural_frequency_hz,
                    fitted_hz: f64::NAN,
                    reason: format!(
                        "with it the fit failed ({reason}); stable at {} orders, the fewest",
                        selected[r].stable_orders
                    ),
                });
                selected.remove(r);
                continue;
            }
            result => result?,
        };
        polished.input_noise = input_noise;
        let moved: Vec<RefusedMode> = (0..selected.len())
            .filter_map(|r| moved(&polished.theta, &selected, r, &lines))
            .collect();
        if !moved.is_empty() {
            drop_moved(&mut selected, &mut refused, moved)?;
            continue;
        }
        match insignificant(&polished, &selected) {
            Some(mode) if selected.len() > 1 => {
                drop_moved(&mut selected, &mut refused, vec![mode])?
            }
            _ => return Ok((polished, weighted, selected, refused)),
        }
    }
}

/// χ²₂ at 0.95: the Wald statistic of a complex modal constant below which it is not
/// told apart from zero.
const CHI2_2_95: f64 = 5.991_464_547_107_979;

/// The selected mode whose modal constant (A, B) the data tell least from zero, if its
/// Wald statistic (A, B)·Cov⁻¹·(A, B)ᵀ is under χ²₂(0.95): a column of noise (the
/// stabilization diagram's poles can stabilise on it) rather than a mode of the FRF.
fn insignificant(polished: &Polished, selected: &[StableColumn]) -> Option<RefusedMode> {
    let (theta, c) = (&polished.theta, &polished.covariance);
    let wald = |r: usize| {
        let j = PER_MODE * r + 2;
        let (a, b) = (theta[j], theta[j + 1]);
        let (saa, sab, sbb) = (c[(j, j)], c[(j, j + 1)], c[(j + 1, j + 1)]);
        let det = saa * sbb - sab * sab;
        (det > 0.0).then(|| (a * a * sbb - 2.0 * a * b * sab + b * b * saa) / det)
    };
    let (r, w) = (0..selected.len())
        .filter_map(|r| Some((r, wald(r)?)))
        .min_by(|x, y| x.1.total_cmp(&y.1))?;
    (w < CHI2_2_95).then(|| RefusedMode {
        natural_frequency_hz: selected[r].natural_frequency_hz,
        fitted_hz: theta[PER_MODE * r] / TAU,
        reason: format!(
            "its modal constant is not told apart from zero (Wald statistic {w:.2} < χ²₂(0.95) = 5.99): the FRF's noise, not a mode"
        ),
    })
}

/// The selected mode stable at the fewest orders (the highest of those tied): the one
/// the data support least.
fn least_stable(selected: &[StableColumn]) -> usize {
    (0..selected.len())
        .rev()
        .min_by_key(|&r| selected[r].stable_orders)
        .unwrap_or(0)
}

/// Takes the `moved` modes out of `selected` into `refused`; an error when none is left.
pub(crate) fn drop_moved(
    selected: &mut Vec<StableColumn>,
    refused: &mut Vec<RefusedMode>,
    moved: Vec<RefusedMode>,
) -> Result<()> {
    selected.retain(|m| {
        !moved
            .iter()
            .any(|x| x.natural_frequency_hz == m.natural_frequency_hz)
    });
    refused.extend(moved);
    if selected.is_empty() {
        let list: Vec<String> = refused.iter().map(ToString::to_string).collect();
        return Err(ModalError::NotIdentifiable {
            reason: format!(
                "the final fit moved every selected mode away from its column of the stabilization diagram: {}",
                list.join("; ")
            ),
        });
    }
    Ok(())
}

/// Mode `r` refused if the polish moved it out of its half-power band or nearer to
/// another selected mode.
fn moved(theta: &[f64], selected: &[StableColumn], r: usize, lines: &Lines) -> Option<RefusedMode> {
    let j = PER_MODE * r;
    let f = theta[j] / TAU;
    moved_from_column(f, theta[j + 1], selected, r, lines.spacing_hz(f))
}

/// Mode `r` of `selected`, fitted at `fitted_hz` with damping `zeta`, refused if that
/// is out of its column's half-power band (or, for a mode narrower than the lines, the
/// line spacing `spacing_hz` there: on noisy lines a column's poles scatter by that
/// much) or nearer to another selected mode.
pub(crate) fn moved_from_column(
    fitted_hz: f64,
    zeta: f64,
    selected: &[StableColumn],
    r: usize,
    spacing_hz: f64,
) -> Option<RefusedMode> {
    let column = selected[r];
    let bandwidth = (2.0 * zeta * fitted_hz)
        .max(2.0 * column.damping_ratio * column.natural_frequency_hz)
        .max(spacing_hz);
    let distance = |m: &StableColumn| (m.natural_frequency_hz - fitted_hz).abs();
    let nearest = selected
        .iter()
        .min_by(|a, b| distance(a).total_cmp(&distance(b)))
        .filter(|m| m.natural_frequency_hz != column.natural_frequency_hz);
    let reason = if let Some(other) = nearest {
        format!(
            "moved onto the mode selected at {:.4} Hz",
            other.natural_frequency_hz
        )
    } else if distance(&column).is_nan() || distance(&column) > bandwidth {
        format!(
            "moved by {:.4} Hz, more than its half-power bandwidth (or the line spacing) {:.4} Hz",
            fitted_hz - column.natural_frequency_hz,
            bandwidth
        )
    } else {
        return None;
    };
    Some(RefusedMode {
        natural_frequency_hz: column.natural_frequency_hz,
        fitted_hz,
        reason,
    })
}

/// A mode the stabilization diagram selected but the final fit did not keep at its
/// column: it is not reported (see [`ModalFit::refused`]).
///
/// ```
/// use msd_modal::RefusedMode;
/// let r = RefusedMode { natural_frequency_hz: 278.68, fitted_hz: 142.17,
///     reason: "moved onto the mode selected at 142.1812 Hz".into() };
/// assert!(r.to_string().starts_with("278.6800 Hz (fitted at 142.1700 Hz): moved onto"));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RefusedMode {
    /// Where the diagram selected it, Hz.
    pub natural_frequency_hz: f64,
    /// Where the final fit put it, Hz (NaN where the fit with it failed).
    pub fitted_hz: f64,
    /// Why it was refused.
    pub reason: String,
}

impl std::fmt::Display for RefusedMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:.4} Hz", self.natural_frequency_hz)?;
        if self.fitted_hz.is_finite() {
            write!(f, " (fitted at {:.4} Hz)", self.fitted_hz)?;
        }
        write!(f, ": {}", self.reason)
    }
}

/// Mode `r` of θ with its intervals (quantile `t`), corrected for an exponential window
/// of decay time `decay`.
fn mode(
    theta: &[f64],
    covariance: &DMatrix<f64>,
    r: usize,
    t: f64,
    decay: Option<f64>,
    stable_orders: usize,
) -> Mode {
    let j = PER_MODE * r;
    let se = |i: usize| covariance[(j + i, j + i)].max(0.0).sqrt();
    let block = [
        [covariance[(j, j)], covariance[(j, j + 1)]],
        [covariance[(j + 1, j)], covariance[(j + 1, j + 1)]],
    ];
    let pole = pole_intervals(theta[j], theta[j + 1], block, t, decay);
    let constant = ShapeEntry {
        standard_error: Some([se(2), se(3)]),
        ..ShapeEntry::new(Dof::default(), Complex64::new(theta[j + 2], theta[j + 3]))
    };
    Mode {
        modal_constants: vec![constant],
        stable_orders: Some(stable_orders),
        window_correction: pole.window_correction,
        cluster_spread: None,
        ..Mode::new(pole.natural_frequency_hz, pole.damping_ratio)
    }
}

/// fn and ζ of a fitted pole with their intervals, and the window's correction.
pub(crate) struct PoleIntervals {
    pub natural_frequency_hz: Interval,
    pub damping_ratio: Interval,
    pub window_correction: Option<WindowCorrection>,
}

/// The pole (ωn, ζ) with the covariance `c` of (ωn, ζ): fn and ζ with their intervals
/// (quantile `t`; ζ's on ln ζ), corrected for an exponential window of decay time
/// `decay` (delta method: Cov' = G·Cov·Gᵀ).
pub(crate) fn pole_intervals(
    wn: f64,
    zeta: f64,
    c: [[f64; 2]; 2],
    t: f64,
    decay: Option<f64>,
) -> PoleIntervals {
    let (mut wn_se, mut zeta_se) = (c[0][0].max(0.0).sqrt(), c[1][1].max(0.0).sqrt());
    let mut corrected = (wn, zeta);
    let window_correction = decay.map(|tau| {
        let ([w0, z0], g) = unshift_pole(wn, zeta, 1.0 / tau);
        let var = |row: [f64; 2]| {
            let mut v = 0.0;
            for a in 0..2 {
                for b in 0..2 {
                    v += row[a] * c[a][b] * row[b];
                }
            }
            v.max(0.0).sqrt()
        };
        (wn_se, zeta_se) = (var(g[0]), var(g[1]));
        corrected = (w0, z0);
        WindowCorrection {
            decay_time: tau,
            natural_frequency_hz_windowed: wn / TAU,
            damping_ratio_windowed: zeta,
            damping_ratio_added: zeta - z0,
        }
    });
    PoleIntervals {
        natural_frequency_hz: Interval::new(corrected.0 / TAU, wn_se / TAU, t),
        damping_ratio: if corrected.1 > 0.0 {
            Interval::positive(corrected.1, zeta_se, t)
        } else {
            Interval::new(corrected.1, zeta_se, t)
        },
        window_correction,
    }
}
