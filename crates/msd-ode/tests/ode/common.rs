//! Shared helpers: the mass–spring–damper and its analytic solutions.
#![allow(dead_code)]

use msd_ode::{LtiModel, SMatrix, SVector};

/// m x'' + c x' + k x = F(t).
#[derive(Debug, Clone, Copy)]
pub struct Plant {
    pub m: f64,
    pub c: f64,
    pub k: f64,
}

impl Plant {
    pub const PAPER: Plant = Plant {
        m: 2.5,
        c: 1.8,
        k: 120.0,
    };

    pub fn with_damping_ratio(zeta: f64) -> Plant {
        let (m, k) = (2.5, 120.0);
        Plant {
            m,
            c: 2.0 * zeta * (m * k).sqrt(),
            k,
        }
    }
    pub fn omega_n(&self) -> f64 {
        (self.k / self.m).sqrt()
    }
    pub fn zeta(&self) -> f64 {
        self.c / (2.0 * (self.m * self.k).sqrt())
    }
    pub fn matrix(&self) -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::new(0.0, 1.0, -self.k / self.m, -self.c / self.m)
    }
    pub fn model(&self) -> LtiModel<2> {
        LtiModel {
            a: self.matrix(),
            b: SVector::<f64, 2>::new(0.0, 1.0 / self.m),
        }
    }
    /// Free decay from x(0) = x0, v(0) = 0: (x, v) at t, for any damping.
    pub fn free_decay(&self, x0: f64, t: f64) -> (f64, f64) {
        let wn = self.omega_n();
        let z = self.zeta();
        if (z - 1.0).abs() < 1e-12 {
            let e = (-wn * t).exp();
            (x0 * (1.0 + wn * t) * e, -x0 * wn * wn * t * e)
        } else if z < 1.0 {
            let wd = wn * (1.0 - z * z).sqrt();
            let e = (-z * wn * t).exp();
            let (s, c) = (wd * t).sin_cos();
            let x = e * x0 * (c + z * wn / wd * s);
            let v = -e * x0 * wn * wn / wd * s;
            (x, v)
        } else {
            let root = wn * (z * z - 1.0).sqrt();
            let (r1, r2) = (-z * wn + root, -z * wn - root);
            let (e1, e2) = ((r1 * t).exp(), (r2 * t).exp());
            let x = x0 * (r2 * e1 - r1 * e2) / (r2 - r1);
            let v = x0 * r1 * r2 * (e1 - e2) / (r2 - r1);
            (x, v)
        }
    }
    /// Response from rest to a step of height f0 applied at t = 0.
    pub fn step_response(&self, f0: f64, t: f64) -> (f64, f64) {
        let (x, v) = self.free_decay(1.0, t);
        (f0 / self.k * (1.0 - x), -f0 / self.k * v)
    }
    /// Steady-state response to F = f0 sin(ωt): (x, v) at t.
    pub fn steady_sine(&self, f0: f64, omega: f64, t: f64) -> (f64, f64) {
        let re = self.k - self.m * omega * omega;
        let im = self.c * omega;
        let amplitude = f0 / (re * re + im * im).sqrt();
        let phase = im.atan2(re);
        let arg = omega * t - phase;
        (amplitude * arg.sin(), amplitude * omega * arg.cos())
    }
    /// Response from rest to the ramp F = α t.
    pub fn ramp_response(&self, alpha: f64, t: f64) -> (f64, f64) {
        // Particular: x_p = α/k (t − c/k); homogeneous part cancels x_p(0) and x_p'(0).
        let xp0 = -alpha * self.c / (self.k * self.k);
        let vp0 = alpha / self.k;
        let (fx, fv) = self.free_decay(1.0, t); // from (1, 0)
        let (gx, gv) = self.velocity_decay(t); // from (0, 1)
        let x = alpha / self.k * (t - self.c / self.k) - xp0 * fx - vp0 * gx;
        let v = alpha / self.k - xp0 * fv - vp0 * gv;
        (x, v)
    }
    /// Free response from x(0) = 0, v(0) = 1 (the impulse response times m), any damping.
    pub fn velocity_decay(&self, t: f64) -> (f64, f64) {
        let e = (self.matrix() * t).exp();
        (e[(0, 1)], e[(1, 1)])
    }
    /// sup over [0, horizon] of ‖e^{At}‖∞: how much the flow can amplify a local error.
    pub fn amplification(&self, horizon: f64) -> f64 {
        (0..=2000)
            .map(|i| {
                let e = (self.matrix() * (horizon * i as f64 / 2000.0)).exp();
                (0..2)
                    .map(|r| e[(r, 0)].abs() + e[(r, 1)].abs())
                    .fold(0.0, f64::max)
            })
            .fold(1.0, f64::max)
    }
}

/// The paper's identification input (docs/paper-experiment.md), right-continuous.
pub fn paper_input(t: f64) -> f64 {
    use std::f64::consts::PI;
    let step = if t >= 0.5 { 6.0 } else { 0.0 };
    let low = if (3.0..9.0).contains(&t) {
        3.0 * (2.0 * PI * 0.5 * t).sin()
    } else {
        0.0
    };
    let high = if (9.0..=15.0).contains(&t) {
        2.5 * (2.0 * PI * 1.4 * t).sin()
    } else {
        0.0
    };
    step + low + high
}

/// Its value just before t (the left limit).
pub fn paper_input_left(t: f64) -> f64 {
    use std::f64::consts::PI;
    let step = if t > 0.5 { 6.0 } else { 0.0 };
    let low = if t > 3.0 && t <= 9.0 {
        3.0 * (2.0 * PI * 0.5 * t).sin()
    } else {
        0.0
    };
    let high = if t > 9.0 && t <= 15.0 {
        2.5 * (2.0 * PI * 1.4 * t).sin()
    } else {
        0.0
    };
    step + low + high
}

/// The paper's grid: 0..15 s in 2 ms steps.
pub fn paper_grid() -> Vec<f64> {
    (0..7501).map(|i| i as f64 * 0.002).collect()
}
