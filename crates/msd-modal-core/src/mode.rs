//! One mode, whatever found it: a fit of one frequency response, a set of them, a chain
//! of masses' fitted physical model (msd-ident), and next the output-only analysis. Each
//! method fills what it measures and leaves the rest empty (`None`, no entries).

use msd_opt::statistics::Interval;
use msd_signal::Complex64;
use serde::{Deserialize, Serialize};

use crate::modal::ModalParameters;
use crate::phase::{mean_phase_deviation, modal_phase_collinearity};
use crate::window::WindowCorrection;

/// A measurement point and direction, msd-signal's: the same in a recording's channels
/// and in a mode's shape.
pub use msd_signal::Dof;

/// One entry of a mode shape (or of a mode's modal constants): a DOF, the complex value
/// there and, where the method gives them, the standard errors of its real and
/// imaginary parts.
///
/// ```
/// use msd_modal_core::{Dof, ShapeEntry};
/// use msd_signal::Complex64;
/// let e = ShapeEntry::new(Dof { node: 4, direction: 3 }, Complex64::new(0.5, -0.1));
/// assert_eq!((e.node, e.direction, e.re, e.im, e.standard_error), (4, 3, 0.5, -0.1, None));
/// assert_eq!(e.value(), Complex64::new(0.5, -0.1));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShapeEntry {
    /// The node.
    pub node: u32,
    /// The direction.
    pub direction: i32,
    /// Real part.
    pub re: f64,
    /// Imaginary part.
    pub im: f64,
    /// The standard errors of `re` and `im`, where the method gives them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub standard_error: Option<[f64; 2]>,
}

impl ShapeEntry {
    /// `value` at `dof`, without standard errors.
    pub fn new(dof: Dof, value: Complex64) -> Self {
        Self {
            node: dof.node,
            direction: dof.direction,
            re: value.re,
            im: value.im,
            standard_error: None,
        }
    }

    /// The DOF.
    pub fn dof(&self) -> Dof {
        Dof {
            node: self.node,
            direction: self.direction,
        }
    }

    /// The complex value.
    pub fn value(&self) -> Complex64 {
        Complex64::new(self.re, self.im)
    }

    /// The real and imaginary parts as intervals at the quantile `t` (None without
    /// standard errors).
    pub fn intervals(&self, t: f64) -> Option<[Interval; 2]> {
        let [re, im] = self.standard_error?;
        Some([Interval::new(self.re, re, t), Interval::new(self.im, im, t)])
    }
}

/// One mode: natural frequency and damping ratio with their 95 % intervals, the shape
/// over named DOFs, the modal constants where a force was measured, and the quantities
/// that judge a shape. Every method of the toolkit reports its modes as this type:
/// msd-modal's `fit_modes` (one FRF: one modal constant, no shape),
/// `fit_mode_set` (a set: constants, shape, MPC/MPD, modal mass),
/// msd-ident's chains (the shape over the masses with standard errors).
///
/// Displays as one line: fn, ζ, then what the method measured.
///
/// ```
/// use msd_modal_core::{Dof, Mode, ShapeEntry};
/// use msd_opt::statistics::Interval;
/// use msd_signal::Complex64;
/// let shape = [1.0, -0.62].iter().enumerate()
///     .map(|(i, &v)| ShapeEntry::new(Dof { node: i as u32 + 1, direction: 1 }, Complex64::new(v, 0.0)))
///     .collect();
/// let mode = Mode::new(Interval::new(11.25, 0.01, 1.96), Interval::positive(0.012, 1e-4, 1.96))
///     .with_shape(shape);
/// assert_eq!(mode.mpc, Some(1.0)); // a real shape
/// assert!(mode.to_string().starts_with("fn = 11.250000 ± 1.00e-2"));
/// assert!(mode.to_string().ends_with("shape [1:+1 1.0000, 2:+1 -0.6200]"));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Mode {
    /// Natural frequency, Hz (with an exponential window: corrected for it).
    pub natural_frequency_hz: Interval,
    /// Damping ratio (idem); its interval computed on ln ζ, so that it stays above zero.
    pub damping_ratio: Interval,
    /// The shape over the measured DOFs, scaled so that its largest entry is 1 (none for
    /// a single frequency response).
    pub shape: Vec<ShapeEntry>,
    /// The modal constants A + jB (receptance, as in [`ModalParameters`]) of each
    /// frequency response fitted, at its roving DOF (a single FRF's at the unnamed DOF
    /// 0:+0, with standard errors); none where no force was measured.
    pub modal_constants: Vec<ShapeEntry>,
    /// Modal phase collinearity of the shape (1 for a real mode); None without a shape.
    pub mpc: Option<f64>,
    /// Mean phase deviation of the shape, degrees (0 for a real mode); None without one.
    pub mpd_deg: Option<f64>,
    /// The modal mass of `shape` (with a driving point whose modal constant is positive;
    /// in the units of the force and response): 1/ψ² at the shape's largest entry, ψ the
    /// mass-normalised shape A_i/√A_dd.
    pub modal_mass: Option<f64>,
    /// The mass-normalised shape ψ (idem).
    pub mass_normalised_shape: Option<Vec<ShapeEntry>>,
    /// At how many orders of the stabilization diagram it was stable (None for a mode
    /// that did not come from a diagram).
    pub stable_orders: Option<usize>,
    /// What an exponential window added and how it was taken off, if there was one.
    pub window_correction: Option<WindowCorrection>,
    /// The standard deviations of fn (Hz) and ζ over the poles of the diagram's cluster
    /// that formed the mode (output-only analysis), a measure of how much the model order
    /// moves it; `None` elsewhere.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cluster_spread: Option<[f64; 2]>,
}

impl Mode {
    /// A mode with only its frequency and damping ratio.
    pub fn new(natural_frequency_hz: Interval, damping_ratio: Interval) -> Self {
        Self {
            natural_frequency_hz,
            damping_ratio,
            shape: Vec::new(),
            modal_constants: Vec::new(),
            mpc: None,
            mpd_deg: None,
            modal_mass: None,
            mass_normalised_shape: None,
            stable_orders: None,
            window_correction: None,
            cluster_spread: None,
        }
    }

    /// The mode with `shape`, and its MPC and MPD.
    pub fn with_shape(mut self, shape: Vec<ShapeEntry>) -> Self {
        let values: Vec<Complex64> = shape.iter().map(ShapeEntry::value).collect();
        self.mpc = Some(modal_phase_collinearity(&values));
        self.mpd_deg = Some(mean_phase_deviation(&values));
        self.shape = shape;
        self
    }

    /// The shape's values, in its order.
    pub fn shape_values(&self) -> Vec<Complex64> {
        self.shape.iter().map(ShapeEntry::value).collect()
    }

    /// The estimates of fn and ζ and the first modal constant (0 where there is none),
    /// without intervals: the mode's contribution to a receptance.
    pub fn parameters(&self) -> ModalParameters {
        let a = self
            .modal_constants
            .first()
            .map_or(Complex64::new(0.0, 0.0), ShapeEntry::value);
        ModalParameters {
            natural_frequency_hz: self.natural_frequency_hz.value,
            damping_ratio: self.damping_ratio.value,
            modal_constant: a.re,
            modal_constant_imaginary: a.im,
        }
    }
}

impl std::fmt::Display for Mode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "fn = {:.6} Hz, ζ = {:.6}",
            self.natural_frequency_hz, self.damping_ratio
        )?;
        match (self.mpc, self.mpd_deg) {
            (Some(mpc), Some(mpd)) if self.shape.len() > 1 && (mpc < 1.0 || mpd > 0.0) => {
                write!(f, ", MPC = {mpc:.3}, MPD = {mpd:.1}°")?;
            }
            _ => {}
        }
        if let Some(m) = self.modal_mass {
            write!(f, ", modal mass {m:.4e}")?;
        }
        if !self.shape.is_empty() {
            write!(f, ", shape [")?;
            for (i, e) in self.shape.iter().enumerate() {
                let sep = if i == 0 { "" } else { ", " };
                write!(f, "{sep}{} {:.4}", e.dof(), e.re)?;
                if e.im != 0.0 {
                    write!(f, "{:+.4}j", e.im)?;
                }
                if let Some([se, _]) = e.standard_error {
                    write!(f, " ± {se:.1e}")?;
                }
            }
            write!(f, "]")?;
        }
        Ok(())
    }
}
