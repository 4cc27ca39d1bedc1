//! A set of frequency responses of one test (a roving hammer or a roving accelerometer):
//! poles common to all of them, each one's modal constants, and the mode shapes.

use std::f64::consts::TAU;

use msd_signal::{Complex64, FrequencyResponseEstimate, FrfKind};
use serde::{Deserialize, Serialize};

use crate::modes::{RefusedMode, drop_moved, moved_from_column, or_conjugated, pole_intervals};
use crate::options::ModalOptions;
use crate::polish::{PER_MODE, lsfd, lsfd_system, model};
use crate::set_poles::{covariance_at, reduce, refine_poles};
use crate::shapes::{mac_matrix, unit_normalised};
use crate::shared_force::SharedForce;
use crate::stabilization::{diagram_of_set, why_too_few};
use msd_modal_core::diagram::{StabilizationDiagram, StableColumn};
use msd_modal_core::error::{ModalError, Result};
use msd_modal_core::input_noise::InputNoise;
use msd_modal_core::lines::{FrfWeighting, Lines, leverages, prepare};
use msd_modal_core::mode::{Dof, Mode, ShapeEntry};
use msd_modal_core::noise_check::NoiseCheck;
use msd_modal_core::phase::{mean_phase_deviation, modal_phase_collinearity};
use msd_opt::statistics::t_975;

/// One frequency response of a set, with where it was measured and where the force was.
#[derive(Debug, Clone, PartialEq)]
pub struct SetMember {
    /// The frequency response (every member on the same lines, of the same quantity).
    pub frf: FrequencyResponseEstimate,
    /// The response DOF.
    pub response: Dof,
    /// The reference (force) DOF.
    pub reference: Dof,
}

/// Which DOF changes from one member of a set to the next: the shapes are over it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Roving {
    /// One reference, the response roves (a roving accelerometer or shaker test); also
    /// a set of one.
    Response,
    /// One response, the force roves (a roving-hammer test; by reciprocity the shape over
    /// the hammer's points).
    Reference,
}

/// How well the model reproduces one member of a set.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MemberFit {
    /// The response DOF.
    pub response: Dof,
    /// The reference DOF.
    pub reference: Dof,
    /// ‖H_model − H‖/‖H‖ on the quantity measured.
    pub relative_error: f64,
    /// Its lower residual term L (−L/ω² in receptance).
    pub lower_residual: f64,
    /// Its upper residual term U.
    pub upper_residual: f64,
    /// The force's noise on its H1 estimate (measured, or the coherence's sign of it)
    /// and whether its lines were raised for it, as for one FRF
    /// ([`ModalFit::input_noise`](crate::ModalFit::input_noise)); `None` when none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub input_noise: Option<InputNoise>,
}

/// The result of [`fit_mode_set`]: the modes with their shapes, the auto-MAC, the fit of
/// each member, the stabilization diagram of the set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModeSetFit {
    /// The modes, by frequency.
    pub modes: Vec<Mode>,
    /// MAC of every shape with every other (`mac[i][j]`).
    pub mac: Vec<Vec<f64>>,
    /// Each member's fit, in the order given.
    pub members: Vec<MemberFit>,
    /// Which DOF roves (the shapes are over it).
    pub roving: Roving,
    /// The member whose response is at its reference, if any.
    pub driving_point: Option<Dof>,
    /// Why the modal masses are missing, when they are.
    pub modal_mass_note: Option<String>,
    /// The stabilization diagram of the set (common denominator).
    pub diagram: StabilizationDiagram,
    /// The first and last line fitted, Hz.
    pub band_hz: [f64; 2],
    /// Lines per member.
    pub lines: usize,
    /// The weighting used.
    pub weighting: FrfWeighting,
    /// σ̂ of the weighted residuals of all members.
    pub sigma: f64,
    /// Residuals less parameters.
    pub degrees_of_freedom: usize,
    /// Gauss–Newton iterations of the poles.
    pub iterations: usize,
    /// Modes the diagram selected that the fit moved away (not in `modes`).
    pub refused: Vec<RefusedMode>,
    /// The quantity the data measure (and each member's `relative_error` is in).
    pub kind: FrfKind,
    /// Whether the data's phase rises through their resonances: the fit was made on
    /// their complex conjugate (see [`ModalFit::conjugated`](crate::ModalFit::conjugated)).
    pub conjugated: bool,
    /// The residuals of every member against its own noise, where the coherence gives
    /// each line's absolute variance in every member (two or more averages); `None`
    /// otherwise. The members' force noise is taken as common to them by
    /// [`shared_force`](Self::shared_force)'s fraction, their response noise as
    /// independent.
    pub noise_check: Option<NoiseCheck>,
    /// How much of the members' force noise is common to them (one force record read
    /// with every response), estimated from the residuals where every member's
    /// coherence gives its force's share of each line (a noise model); taken into the
    /// poles' covariance and the noise check. `None` otherwise: then the members are
    /// taken as independent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shared_force: Option<SharedForce>,
}

impl ModeSetFit {
    /// The member's force noise that biased its H1 most, if any member's did.
    pub fn largest_input_noise(&self) -> Option<InputNoise> {
        (self.members.iter())
            .filter_map(|m| m.input_noise)
            .max_by(|a, b| a.h1_bias.total_cmp(&b.h1_bias))
    }

    /// The receptance of the model of member `member` at `frequency_hz` (with an
    /// exponential window: the windowed response, which the data show).
    pub fn response(&self, member: usize, frequency_hz: f64) -> Complex64 {
        let w = TAU * frequency_hz;
        let fit = &self.members[member];
        let mut h = Complex64::new(fit.upper_residual - fit.lower_residual / (w * w), 0.0);
        for m in &self.modes {
            let (mut wn, mut zeta) = (TAU * m.natural_frequency_hz.value, m.damping_ratio.value);
            if let Some(c) = m.window_correction {
                (wn, zeta) = (
                    TAU * c.natural_frequency_hz_windowed,
                    c.damping_ratio_windowed,
                );
            }
            let a = m.modal_constants[member];
            h += msd_modal_core::modal::term(&[wn, zeta, a.re, a.im], w);
        }
        msd_modal_core::lines::as_measured(h, self.conjugated, self.kind)
    }
}

impl std::fmt::Display for ModeSetFit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let worst = self
            .members
            .iter()
            .map(|m| m.relative_error)
            .fold(0.0, f64::max);
        write!(
            f,
            "{} modes common to {} frequency responses, {} lines each, {:.4}–{:.4} Hz ({} weighting); largest fit error {:.2} %",
            self.modes.len(),
            self.members.len(),
            self.lines,
            self.band_hz[0],
            self.band_hz[1],
            self.weighting,
            100.0 * worst
        )?;
        write!(f, " in {}", self.kind)?;
        if self.conjugated {
            write!(f, "\n{}", msd_modal_core::lines::CONJUGATED)?;
        }
        for (i, m) in self.modes.iter().enumerate() {
            write!(
                f,
                "\nmode {}: fn = {:.6} Hz, ζ = {:.6}",
                i + 1,
                m.natural_frequency_hz,
                m.damping_ratio,
            )?;
            if let (Some(mpc), Some(mpd)) = (m.mpc, m.mpd_deg) {
                write!(f, ", MPC = {mpc:.3}, MPD = {mpd:.1}°")?;
            }
            if let Some(mass) = m.modal_mass {
                write!(f, ", modal mass {mass:.4e}")?;
            }
        }
        if let Some(check) = &self.noise_check {
            write!(f, "\n{check}")?;
        }
        if let Some(shared) = self.shared_force.filter(SharedForce::is_evident) {
            write!(f, "\n{shared}")?;
        }
        if let Some(noise) = self.largest_input_noise() {
            write!(f, "\n{noise} (the largest of the members)")?;
        }
        Ok(())
    }
}

/// Which DOF roves in `members`, and the driving point; errors name the member at fault.
fn check_members(members: &[SetMember]) -> Result<(Roving, Option<Dof>)> {
    let invalid = |reason: String| Err(ModalError::NotIdentifiable { reason });
    let Some(first) = members.first() else {
        return invalid("a set of frequency responses needs at least one member".into());
    };
    for (i, m) in members.iter().enumerate().skip(1) {
        if m.frf.frequency != first.frf.frequency || m.frf.kind != first.frf.kind {
            return invalid(format!(
                "member {} ({} / {}) has other frequency lines or another quantity than member 1: a set shares its lines and its quantity",
                i + 1,
                m.response,
                m.reference
            ));
        }
        if let Some(j) = members[..i]
            .iter()
            .position(|o| (o.response, o.reference) == (m.response, m.reference))
        {
            return invalid(format!(
                "members {} and {} are both response {} / reference {}: each pair once",
                j + 1,
                i + 1,
                m.response,
                m.reference
            ));
        }
    }
    let same = |get: fn(&SetMember) -> Dof| members.iter().all(|m| get(m) == get(first));
    let roving = if same(|m| m.reference) {
        Roving::Response
    } else if same(|m| m.response) {
        Roving::Reference
    } else {
        return invalid(
            "the members share neither one reference nor one response: a set is one roving-hammer or one roving-response test".into(),
        );
    };
    let driving = members
        .iter()
        .find(|m| m.response == m.reference)
        .map(|m| m.response);
    Ok((roving, driving))
}

/// Fits modes common to every member of a set: their poles, then every member's modal
/// constants and residual terms, the shapes, their MAC and complexity, and — with a
/// driving point — the modal masses.
///
/// ## The method
/// Each member's lines are prepared as for [`fit_modes`](crate::modes::fit_modes) (the same band
/// and weighting). The stabilization diagram is that of a common denominator: the LSCF
/// reduced normal matrices of the members summed (Peeters et al., "The PolyMAX
/// frequency-domain method", 2004, for one reference), its columns selected at the peaks
/// of the members' summed magnitude. For the selected poles, LSFD gives each member's
/// modal constants and residual terms; the poles are then refined by Gauss–Newton on the
/// residuals of all members with the linear parameters eliminated (variable projection),
/// and their covariance is σ̂²(Σ JᵀJ)⁻¹ of that reduced problem (the Schur complement,
/// exactly the poles' block of the full covariance).
///
/// Errors: members on different lines or of different quantities, a pair of DOFs twice,
/// members that share neither reference nor response, and those of
/// [`fit_modes`](crate::modes::fit_modes).
///
/// ```
/// use msd_modal::{ModalOptions, fit_mode_set, mac, Dof, ModalParameters, SetMember};
/// use msd_signal::{Complex64, FrequencyResponseEstimate, FrfKind};
/// // Two modes of a three-point structure, the force at point 1.
/// let shapes = [[1.0, 0.8, 0.4], [1.0, -0.5, -1.0]];
/// let (fns, zetas) = ([10.0, 24.0], [0.01, 0.02]);
/// let f: Vec<f64> = (1..=600).map(|i| 0.05 * i as f64).collect();
/// let members = (0..3).map(|i| {
///     let h = f.iter().map(|&f| (0..2).map(|r| ModalParameters {
///         natural_frequency_hz: fns[r], damping_ratio: zetas[r],
///         modal_constant: shapes[r][0] * shapes[r][i], modal_constant_imaginary: 0.0,
///     }.receptance(f)).sum()).collect();
///     SetMember { frf: FrequencyResponseEstimate::new(f.clone(), h).unwrap(),
///         response: Dof { node: i as u32 + 1, direction: 3 }, reference: Dof { node: 1, direction: 3 } }
/// }).collect::<Vec<_>>();
/// let fit = fit_mode_set(&members, &ModalOptions::default())?;
/// assert_eq!(fit.modes.len(), 2);
/// for (mode, truth) in fit.modes.iter().zip(&shapes) {
///     let estimated: Vec<Complex64> = mode.shape.iter().map(|e| Complex64::new(e.re, e.im)).collect();
///     let truth: Vec<Complex64> = truth.iter().map(|&x| Complex64::new(x, 0.0)).collect();
///     assert!(mac(&estimated, &truth) > 0.9999);
///     assert!((mode.modal_mass.unwrap() - 1.0).abs() < 1e-6); // unit shapes, unit modal mass
/// }
/// # Ok::<(), msd_modal::ModalError>(())
/// ```
pub fn fit_mode_set(members: &[SetMember], options: &ModalOptions) -> Result<ModeSetFit> {
    options.validate()?;
    let conjugate = || {
        let members: Vec<SetMember> = (members.iter())
            .map(|m| SetMember {
                frf: m.frf.conjugate(),
                ..m.clone()
            })
            .collect();
        set_as_given(&members, options)
    };
    let worst = |fit: &ModeSetFit| {
        (fit.members.iter())
            .map(|m| m.relative_error)
            .fold(0.0, f64::max)
    };
    let (mut fit, conjugated) = or_conjugated(set_as_given(members, options), conjugate, worst)?;
    fit.conjugated = conjugated;
    Ok(fit)
}

/// [`fit_mode_set`] on the data as they are.
fn set_as_given(members: &[SetMember], options: &ModalOptions) -> Result<ModeSetFit> {
    let (roving, driving_point) = check_members(members)?;
    let min_lines = options.orders[1] + 1;
    let lines: Vec<Lines> = members
        .iter()
        .map(|m| prepare(&m.frf, options.band_hz, options.weighting, min_lines))
        .collect::<Result<_>>()?;
    if let Some(i) = lines.iter().position(|l| l.omega != lines[0].omega) {
        return Err(ModalError::NotIdentifiable {
            reason: format!(
                "member {} keeps other lines than member 1 after weighting (a line without a usable weight in one of them); use weighting = \"uniform\"",
                i + 1
            ),
        });
    }
    let peaks = lines[0].summed_magnitudes(&lines);
    let diagram = diagram_of_set(&lines, &peaks, options)?;
    if diagram.modes.is_empty() {
        return Err(ModalError::TooFewModes {
            reason: format!(
                "no mode is stable in the stabilization diagram of the set{}",
                why_too_few(&diagram, options)
            ),
            diagram: Box::new(diagram),
        });
    }
    let mut selected = diagram.modes.clone();
    let mut refused = Vec::new();
    loop {
        let start: Vec<(f64, f64)> = selected
            .iter()
            .map(|m| (TAU * m.natural_frequency_hz, m.damping_ratio))
            .collect();
        let mut weighted = lines.clone();
        let mut input_noise = Vec::with_capacity(weighted.len());
        for l in &mut weighted {
            // Each member's weights from its coherence's noise model, as one FRF's
            // (relative to the model where there is none), and its H1 raised where the
            // force's noise is known.
            let theta = lsfd(l, &start)?;
            l.smooth_coherence_weights(|w| model(&theta, w));
            input_noise.push(l.correct_input_noise());
        }
        let mut poles = refine_poles(&weighted, start)?;
        if weighted[0].weighting == FrfWeighting::Uniform {
            // Each line's variance from the refined poles' residuals (the diagram's
            // poles leave their own misfit at the peaks), the poles kept.
            for l in &mut weighted {
                let theta = lsfd(l, &poles.poles)?;
                let (a, _) = lsfd_system(l, &poles.poles);
                l.residual_variances(|w| model(&theta, w), &leverages(&a));
            }
            let at = reduce(&weighted, &poles.poles)?;
            poles = covariance_at(&weighted, poles.poles, at, poles.iterations)?;
        }
        let moved: Vec<RefusedMode> = (0..selected.len())
            .filter_map(|r| {
                let (wn, zeta) = poles.poles[r];
                let f = wn / TAU;
                moved_from_column(f, zeta, &selected, r, lines[0].spacing_hz(f))
            })
            .collect();
        if moved.is_empty() {
            let parts = Parts {
                poles,
                selected,
                refused,
                diagram,
                roving,
                driving_point,
                input_noise,
            };
            return assemble(members, &weighted, parts);
        }
        drop_moved(&mut selected, &mut refused, moved)?;
    }
}

/// What [`assemble`] builds the result from.
struct Parts {
    poles: crate::set_poles::RefinedPoles,
    selected: Vec<StableColumn>,
    refused: Vec<RefusedMode>,
    diagram: StabilizationDiagram,
    roving: Roving,
    driving_point: Option<Dof>,
    input_noise: Vec<Option<InputNoise>>,
}

/// The result from the refined poles: every member's modal constants, the shapes, MAC.
fn assemble(members: &[SetMember], lines: &[Lines], parts: Parts) -> Result<ModeSetFit> {
    let Parts {
        poles,
        selected,
        refused,
        diagram,
        roving,
        driving_point,
        input_noise,
    } = parts;
    let thetas = lines
        .iter()
        .map(|l| lsfd(l, &poles.poles))
        .collect::<Result<Vec<_>>>()?;
    let t = t_975(poles.degrees_of_freedom);
    let decay = lines[0].exponential_decay;
    let dof = |m: &SetMember| match roving {
        Roving::Response => m.response,
        Roving::Reference => m.reference,
    };
    let driving = members.iter().position(|m| m.response == m.reference);
    let mut notes = Vec::new();
    let modes: Vec<Mode> = (0..poles.poles.len())
        .map(|r| {
            let (wn, zeta) = poles.poles[r];
            let c = &poles.covariance;
            let block = [
                [c[(2 * r, 2 * r)], c[(2 * r, 2 * r + 1)]],
                [c[(2 * r + 1, 2 * r)], c[(2 * r + 1, 2 * r + 1)]],
            ];
            let pole = pole_intervals(wn, zeta, block, t, decay);
            let constants: Vec<Complex64> = thetas
                .iter()
                .map(|th| Complex64::new(th[PER_MODE * r + 2], th[PER_MODE * r + 3]))
                .collect();
            let entries = |values: &[Complex64]| -> Vec<ShapeEntry> {
                members
                    .iter()
                    .zip(values)
                    .map(|(m, &v)| ShapeEntry::new(dof(m), v))
                    .collect()
            };
            let shape = unit_normalised(&constants);
            let mass = driving.and_then(|d| modal_mass(&constants, &shape, d, r, &mut notes));
            Mode {
                shape: entries(&shape),
                mpc: Some(modal_phase_collinearity(&constants)),
                mpd_deg: Some(mean_phase_deviation(&constants)),
                modal_constants: entries(&constants),
                modal_mass: mass.as_ref().map(|m| m.0),
                mass_normalised_shape: mass.map(|m| entries(&m.1)),
                stable_orders: Some(selected[r].stable_orders),
                window_correction: pole.window_correction,
                cluster_spread: None,
                ..Mode::new(pole.natural_frequency_hz, pole.damping_ratio)
            }
        })
        .collect();
    let shapes: Vec<Vec<Complex64>> = modes.iter().map(Mode::shape_values).collect();
    let fits = members
        .iter()
        .zip(lines)
        .zip(&thetas)
        .zip(input_noise)
        .map(|(((m, l), th), input_noise)| MemberFit {
            response: m.response,
            reference: m.reference,
            relative_error: l.relative_error(|w| model(th, w)),
            lower_residual: th[th.len() - 2],
            upper_residual: th[th.len() - 1],
            input_noise,
        })
        .collect();
    if driving.is_none() {
        notes.push("no member has its response at its reference (a driving point): the shapes are not mass-normalised".into());
    }
    Ok(ModeSetFit {
        mac: mac_matrix(&shapes, &shapes),
        modes,
        members: fits,
        roving,
        driving_point,
        modal_mass_note: (!notes.is_empty()).then(|| notes.join("; ")),
        band_hz: lines[0].band_hz,
        lines: lines[0].omega.len(),
        weighting: lines[0].weighting,
        sigma: poles.sigma,
        degrees_of_freedom: poles.degrees_of_freedom,
        iterations: poles.iterations,
        refused,
        diagram,
        kind: members[0].frf.kind,
        conjugated: false,
        noise_check: poles.noise_check,
        shared_force: poles.shared_force,
    })
}

/// The modal mass of mode `r` for its unit-normalised `shape` and the mass-normalised
/// shape ψ = A_i/√A_dd, from the driving point's modal constant (member `driving`);
/// `None` with a note when that constant's real part is not positive.
fn modal_mass(
    constants: &[Complex64],
    shape: &[Complex64],
    driving: usize,
    r: usize,
    notes: &mut Vec<String>,
) -> Option<(f64, Vec<Complex64>)> {
    let a_dd = constants[driving];
    if a_dd.re.is_nan() || a_dd.re <= 0.0 {
        notes.push(format!(
            "mode {}: the driving point's modal constant {:.4e} is not positive (a sign convention of the sensor, or not a driving point), so it has no modal mass",
            r + 1,
            a_dd.re
        ));
        return None;
    }
    let root = a_dd.sqrt();
    let psi: Vec<Complex64> = constants.iter().map(|a| a / root).collect();
    // shape = ψ/ψ_k with ψ_k the largest entry: the modal mass of `shape` is 1/ψ_k².
    let k = (0..shape.len())
        .max_by(|&a, &b| psi[a].norm_sqr().total_cmp(&psi[b].norm_sqr()))
        .unwrap_or(driving);
    Some((1.0 / psi[k].norm_sqr(), psi))
}
