//! Every drive as one linear model with exact sensitivities.
//!
//! ## The equations
//! State s = (s₀, s₁), input u, θ = (m, c, k) (m = 1 and c, k per unit mass for the
//! drives that cannot fix the mass):
//!
//! s′ = A(θ)·s + b(θ)·u,  A = [[0, 1], [−k/m, −c/m]],
//!
//! with b = (0, 1/m) for a force, (0, −1) for a base acceleration (s is the relative
//! motion), (c/m, k/m − c²/m²) for a base displacement (s = (x, x′ − (c/m)·z), so
//! x″ = −(k/m)·x − (c/m)·x′ + (c/m)·z′ + (k/m)·z without z′), and 0 for a free decay.
//! Each channel is y = C(θ)·s + D(θ)·u (+ its offset), see [`OutputKind`]. The
//! sensitivities s_p = ∂s/∂θ_p obey s_p′ = A·s_p + A_p·s + b_p·u from zero: with s they
//! form one 8-state linear system that msd-ode simulates exactly, and
//! ∂y/∂θ_p = C·s_p + C_p·s + D_p·u.

use crate::plant::{Drive, Plant};

/// What a channel reads off the state s and the input u.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum OutputKind {
    /// s₀: the displacement (relative to the base under a base acceleration).
    Displacement,
    /// s₁: the velocity (relative under a base acceleration).
    Velocity,
    /// s₁′ = A₁·s + b₁·u: the acceleration (relative under a base acceleration).
    Acceleration,
    /// A₁·s = y″ + z″: the mass's own acceleration under a base acceleration.
    AbsoluteAcceleration,
    /// s₀ − u = x − z under a base displacement.
    RelativeDisplacement,
    /// s₁ + b₀·u = x′ under a base displacement.
    AbsoluteVelocity,
}

/// y = c·s + d·u and its derivatives to θ.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct OutputMap {
    pub c: [f64; 2],
    pub d: f64,
    pub dc: [[f64; 2]; 3],
    pub dd: [f64; 3],
}

impl OutputMap {
    #[inline(always)]
    pub(crate) fn value(&self, s: [f64; 2], u: f64) -> f64 {
        self.c[0] * s[0] + self.c[1] * s[1] + self.d * u
    }

    /// ∂y/∂θ_p from the state s, its sensitivity s_p and the input (the Jacobian folds
    /// the same sum into one row of coefficients).
    #[cfg(test)]
    pub(crate) fn derivative(&self, p: usize, s: [f64; 2], sp: [f64; 2], u: f64) -> f64 {
        self.c[0] * sp[0]
            + self.c[1] * sp[1]
            + self.dc[p][0] * s[0]
            + self.dc[p][1] * s[1]
            + self.dd[p] * u
    }
}

impl Plant {
    /// The channel map of `kind` at θ.
    pub(crate) fn output(&self, kind: OutputKind) -> OutputMap {
        let (a, da, b, db) = (self.a(), self.da(), self.b(), self.db());
        let rate = OutputMap {
            c: a[1],
            d: b[1],
            dc: [da[0][1], da[1][1], da[2][1]],
            dd: [db[0][1], db[1][1], db[2][1]],
        };
        match kind {
            OutputKind::Displacement => OutputMap {
                c: [1.0, 0.0],
                ..OutputMap::default()
            },
            OutputKind::Velocity => OutputMap {
                c: [0.0, 1.0],
                ..OutputMap::default()
            },
            OutputKind::Acceleration => rate,
            OutputKind::AbsoluteAcceleration => OutputMap {
                d: 0.0,
                dd: [0.0; 3],
                ..rate
            },
            OutputKind::RelativeDisplacement => OutputMap {
                c: [1.0, 0.0],
                d: -1.0,
                ..OutputMap::default()
            },
            OutputKind::AbsoluteVelocity => OutputMap {
                c: [0.0, 1.0],
                d: b[0],
                dd: [db[0][0], db[1][0], db[2][0]],
                ..OutputMap::default()
            },
        }
    }

    /// The mass's velocity at the first sample from the model's state s and input u
    /// (s₁ is x′ − (c/m)·z under a base displacement).
    pub(crate) fn velocity(&self, s: [f64; 2], u: f64) -> f64 {
        match self.drive {
            Drive::BaseDisplacement => s[1] + self.b()[0] * u,
            _ => s[1],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every analytic derivative of A, b and the channel maps against central
    /// differences, for every drive.
    #[test]
    fn derivatives_match_central_differences() {
        let kinds = [
            OutputKind::Displacement,
            OutputKind::Velocity,
            OutputKind::Acceleration,
            OutputKind::AbsoluteAcceleration,
            OutputKind::RelativeDisplacement,
            OutputKind::AbsoluteVelocity,
        ];
        let drives = [
            Drive::Force,
            Drive::BaseAcceleration,
            Drive::BaseDisplacement,
            Drive::None,
        ];
        for drive in drives {
            let plant = Plant {
                theta: [2.5, 1.8, 120.0],
                drive,
            };
            for p in 0..3 {
                let h = 1e-6 * plant.theta[p];
                let (mut up, mut down) = (plant, plant);
                up.theta[p] += h;
                down.theta[p] -= h;
                let fd = |f: &dyn Fn(&Plant) -> f64| (f(&up) - f(&down)) / (2.0 * h);
                for r in 0..2 {
                    let tol = |x: f64| 1e-7 * (1.0 + x.abs());
                    let db = fd(&|q| q.b()[r]);
                    assert!(
                        (db - plant.db()[p][r]).abs() < tol(db),
                        "{drive:?} b {p} {r}"
                    );
                    for c in 0..2 {
                        let da = fd(&|q| q.a()[r][c]);
                        assert!((da - plant.da()[p][r][c]).abs() < tol(da), "{drive:?} A");
                    }
                }
                for kind in kinds {
                    let map = plant.output(kind);
                    let (s, u) = ([0.3, -0.7], 1.9);
                    let dy = fd(&|q| q.output(kind).value(s, u));
                    let analytic = map.derivative(p, s, [0.0, 0.0], u);
                    assert!((dy - analytic).abs() < 1e-6 * (1.0 + dy.abs()), "{kind:?}");
                }
            }
        }
    }
}
