//! Base excitation: the base (a shaker table) moves, measured by an accelerometer, and
//! the mass's motion relative to the base, y = x − z, is measured:
//!
//! m·y″ + c·y′ + k·y = −m·z″,  so  y″ + 2ζωn·y′ + ωn²·y = −z″.
//!
//! The record fixes c/m and k/m, hence ωn and ζ, but never m: every plant with the same
//! ratios moves the same way. [`base_excitation`] therefore fits the unit-mass model
//! driven by −z″ and reports ωn and ζ with intervals; a known (weighed) mass gives c and k.

use crate::free_decay::PhysicalParameters;
use crate::{
    DataSet, Estimate, EstimationOptions, Excitation, FixedParameters, IdentError, Interval,
    Result, estimate,
};
use serde::Serialize;

/// Options of [`base_excitation`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BaseExcitationOptions {
    /// The weighed mass, kg: gives c and k. By default unknown.
    pub known_mass: Option<f64>,
    /// How the unit-mass model is estimated (its `fixed` must be empty: the mass is fixed
    /// at 1 here, and c/m, k/m are what is estimated). By default Levenberg–Marquardt on
    /// the exact simulation.
    pub estimation: EstimationOptions,
}

/// ωn and ζ of a base-excited plant (and c, k with a known mass).
#[derive(Debug, Clone, Serialize)]
pub struct BaseExcitation {
    /// The quantities the record identifies, by name.
    pub identifiable: Vec<&'static str>,
    /// fn, Hz.
    pub natural_frequency_hz: Interval,
    /// ζ.
    pub damping_ratio: Interval,
    /// c/m, 1/s.
    pub damping_per_mass: Interval,
    /// k/m, 1/s².
    pub stiffness_per_mass: Interval,
    /// m, c, k when the mass is known.
    pub parameters: Option<PhysicalParameters>,
    /// Why m, c and k are not given, when they are not.
    pub note: Option<String>,
    /// The unit-mass fit (its "damping" is c/m, its "stiffness" k/m).
    #[serde(skip)]
    pub unit_mass_fit: Estimate,
}

impl std::fmt::Display for BaseExcitation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "base excitation (relative motion against base acceleration)"
        )?;
        writeln!(f, "  fn = {:.6} Hz", self.natural_frequency_hz)?;
        write!(f, "  ζ  = {:.6}", self.damping_ratio)?;
        if let Some(p) = &self.parameters {
            write!(
                f,
                "\n  c  = {:.6} N·s/m\n  k  = {:.6} N/m",
                p.damping, p.stiffness
            )?;
        }
        if let Some(note) = &self.note {
            write!(f, "\n  note: {note}")?;
        }
        Ok(())
    }
}

/// Identifies ωn and ζ from `record`: its excitation is the base acceleration z″ (m/s²),
/// its output the relative displacement y = x − z (m). With `options.known_mass`, also
/// c and k (the mass exact, their intervals scaled from c/m and k/m).
///
/// ```
/// use msd_ident::{base_excitation, BaseExcitationOptions, DataSet, Excitation, Parameters, simulate, Backend, InitialState};
/// use msd_signal::paper_identification_input;
/// // A 2.5 kg plant on a table shaking with the paper's input as its acceleration.
/// let base = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
/// let force = Excitation::from_samples(0.0, 0.002, base.samples().iter().map(|a| -2.5 * a).collect())?;
/// let y = simulate(&Parameters::PAPER, &force, InitialState::REST, &Backend::EXACT)?;
/// let fit = base_excitation(&DataSet::new("table", base, y)?, &BaseExcitationOptions::default())?;
/// assert!(fit.parameters.is_none() && fit.note.is_some());
/// assert!((fit.natural_frequency_hz.value - Parameters::PAPER.natural_frequency_hz()).abs() < 1e-6);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn base_excitation(
    record: &DataSet,
    options: &BaseExcitationOptions,
) -> Result<BaseExcitation> {
    if options.estimation.fixed != FixedParameters::default() {
        return Err(IdentError::InvalidParameter {
            name: "estimation.fixed",
            value: f64::NAN,
            expected: "nothing fixed: base excitation fixes the mass at 1 and estimates c/m and k/m (give a weighed mass as known_mass)",
        });
    }
    if let Some(m) = options.known_mass
        && !(m.is_finite() && m > 0.0)
    {
        return Err(IdentError::InvalidParameter {
            name: "known mass",
            value: m,
            expected: "a finite mass > 0 kg",
        });
    }
    let e = &record.excitation;
    let force = Excitation::from_samples(e.t0(), e.dt(), e.samples().iter().map(|a| -a).collect())?;
    let mut unit = DataSet::new(record.name.clone(), force, record.output.clone())?;
    unit.input_unit = "m/s²".into();
    unit.output_unit = record.output_unit.clone();
    let estimation = EstimationOptions {
        fixed: FixedParameters {
            mass: Some(1.0),
            ..FixedParameters::default()
        },
        ..options.estimation.clone()
    };
    let fit = estimate(&unit, &estimation)?;
    let u = &fit.uncertainty;
    let scaled = |iv: Interval, m: f64| Interval {
        value: m * iv.value,
        standard_error: m * iv.standard_error,
        ci95: [m * iv.ci95[0], m * iv.ci95[1]],
    };
    let parameters = options.known_mass.map(|m| PhysicalParameters {
        mass: Interval {
            value: m,
            standard_error: 0.0,
            ci95: [m, m],
        },
        damping: scaled(u.damping, m),
        stiffness: scaled(u.stiffness, m),
    });
    let mut identifiable = vec!["natural_frequency_hz", "damping_ratio"];
    if parameters.is_some() {
        identifiable.extend(["mass", "damping", "stiffness"]);
    }
    Ok(BaseExcitation {
        identifiable,
        natural_frequency_hz: u.natural_frequency_hz,
        damping_ratio: u.damping_ratio,
        damping_per_mass: u.damping,
        stiffness_per_mass: u.stiffness,
        note: parameters.is_none().then(|| {
            "m, c and k are not separately identifiable from base motion alone (every plant with the same c/m and k/m moves the same way): give the weighed mass to get c and k; ωn and ζ are identified".to_string()
        }),
        parameters,
        unit_mass_fit: fit,
    })
}
