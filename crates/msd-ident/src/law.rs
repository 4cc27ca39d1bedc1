//! The damping laws f_d(x′) in one place, for the two engines that fit them: the
//! nonlinear time-domain fit (`nonlinear`, which simulates the law) and the damper test
//! machine (`dynamometer`, which regresses the force on the law's term). A law has a
//! name and a formula, the coefficient it adds to c (none, F_c or c₂), its regression
//! term, and — with its coefficients — the force and its slope.
//!
//! The Coulomb term F_c·sign(x′) is regularised as F_c·tanh(x′/v_s), v_s the smoothing
//! velocity; `tanh` is taken as ±1 past |x′/v_s| = 20, where it rounds to ±1 anyway.

use serde::{Deserialize, Serialize};

/// The damping force f_d(x′).
///
/// ```
/// use msd_ident::law::DampingLaw;
/// assert_eq!(DampingLaw::QuadraticViscous.coefficient(), Some("quadratic_damping"));
/// assert_eq!(DampingLaw::CoulombViscous.term(0.2, 1.0 / 1e-3), Some(1.0));
/// assert_eq!(DampingLaw::QuadraticViscous.term(-0.5, 0.0), Some(-0.25));
/// assert_eq!(DampingLaw::Viscous.term(0.5, 0.0), None);
/// assert_eq!(DampingLaw::ALL.map(DampingLaw::name), ["viscous", "coulomb_viscous", "quadratic_viscous"]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DampingLaw {
    /// c·x'.
    Viscous,
    /// F_c·sign(x') + c·x', the sign regularised as tanh(x'/v_s) (see the module doc).
    CoulombViscous,
    /// c₂·x'|x'| + c·x'.
    QuadraticViscous,
}

impl DampingLaw {
    /// Every law, viscous first.
    pub const ALL: [DampingLaw; 3] = [
        DampingLaw::Viscous,
        DampingLaw::CoulombViscous,
        DampingLaw::QuadraticViscous,
    ];

    /// Its name in configs and results (snake case).
    pub fn name(self) -> &'static str {
        match self {
            DampingLaw::Viscous => "viscous",
            DampingLaw::CoulombViscous => "coulomb_viscous",
            DampingLaw::QuadraticViscous => "quadratic_viscous",
        }
    }

    /// Its formula, for reports.
    pub fn formula(self) -> &'static str {
        match self {
            DampingLaw::Viscous => "viscous c·x′",
            DampingLaw::CoulombViscous => "Coulomb + viscous F_c·sign(x′) + c·x′",
            DampingLaw::QuadraticViscous => "quadratic + viscous c₂·x′|x′| + c·x′",
        }
    }

    /// The name of the coefficient it adds to the viscous c: `coulomb_force` (N) or
    /// `quadratic_damping` (N·s²/m²); none for the viscous law.
    pub fn coefficient(self) -> Option<&'static str> {
        match self {
            DampingLaw::Viscous => None,
            DampingLaw::CoulombViscous => Some("coulomb_force"),
            DampingLaw::QuadraticViscous => Some("quadratic_damping"),
        }
    }

    /// Its regression term at velocity `v` (the column its coefficient multiplies):
    /// tanh(v/v_s) with `inverse_smoothing` = 1/v_s, or v|v|; none for the viscous law.
    pub fn term(self, v: f64, inverse_smoothing: f64) -> Option<f64> {
        match self {
            DampingLaw::Viscous => None,
            DampingLaw::CoulombViscous => Some(smoothed_sign(v * inverse_smoothing)),
            DampingLaw::QuadraticViscous => Some(v * v.abs()),
        }
    }
}

/// tanh(z), as ±1 past |z| = 20 (where tanh rounds to ±1: the same values, faster on
/// the many samples far above a small v_s).
#[inline(always)]
pub fn smoothed_sign(z: f64) -> f64 {
    if z.abs() > 20.0 { z.signum() } else { z.tanh() }
}

/// A law with its coefficients: f_d(v) = c·v + c₂·v|v| + F_c·tanh(v/v_s), the terms a
/// law lacks zero (and `inverse_smoothing` 0 without a Coulomb term).
///
/// ```
/// use msd_ident::law::DampingForce;
/// let f = DampingForce { viscous: 2.0, quadratic: 0.5, coulomb: 0.0, inverse_smoothing: 0.0 };
/// assert_eq!(f.force(-2.0), -4.0 - 2.0);
/// let (force, slope, _) = f.force_and_slope(-2.0);
/// assert_eq!((force, slope), (-6.0, 2.0 + 2.0));
/// let coulomb = DampingForce { viscous: 0.0, quadratic: 0.0, coulomb: 10.0, inverse_smoothing: 1e3 };
/// assert_eq!(coulomb.force(0.5), 10.0); // far above v_s = 1 mm/s: the full friction force
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DampingForce {
    /// c, N·s/m.
    pub viscous: f64,
    /// c₂, N·s²/m².
    pub quadratic: f64,
    /// F_c, N.
    pub coulomb: f64,
    /// 1/v_s, s/m (0 without a Coulomb term).
    pub inverse_smoothing: f64,
}

impl DampingForce {
    /// tanh(v/v_s), 0 without a Coulomb term.
    #[inline(always)]
    pub fn sign(&self, v: f64) -> f64 {
        if self.inverse_smoothing == 0.0 {
            0.0
        } else {
            smoothed_sign(v * self.inverse_smoothing)
        }
    }

    /// f_d(v).
    #[inline(always)]
    pub fn force(&self, v: f64) -> f64 {
        self.viscous * v + self.quadratic * v * v.abs() + self.coulomb * self.sign(v)
    }

    /// f_d(v), its slope f_d′(v) = c + 2c₂|v| + (F_c/v_s)·(1 − tanh²) and tanh(v/v_s).
    #[inline(always)]
    pub fn force_and_slope(&self, v: f64) -> (f64, f64, f64) {
        let (tanh, speed) = (self.sign(v), v.abs());
        let force = self.viscous * v + self.quadratic * v * speed + self.coulomb * tanh;
        let slope = self.viscous
            + 2.0 * self.quadratic * speed
            + self.coulomb * self.inverse_smoothing * (1.0 - tanh * tanh);
        (force, slope, tanh)
    }
}
