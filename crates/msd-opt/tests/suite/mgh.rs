//! Test problems of Moré, Garbow & Hillstrom (1981), "Testing unconstrained
//! optimization software", ACM TOMS 7(1): residuals, analytic Jacobians, standard
//! starting points and published minima of f = Σ rᵢ².

use msd_opt::LeastSquaresProblem;
use nalgebra::DMatrix;

/// One MGH problem.
#[derive(Clone)]
pub struct Mgh {
    pub name: &'static str,
    pub m: usize,
    pub x0: Vec<f64>,
    /// Published minimum values of f (the first is the global one).
    pub minima: &'static [f64],
    pub residuals: fn(&[f64], &mut [f64]),
    pub jacobian: fn(&[f64], &mut DMatrix<f64>),
    /// Supply the analytic Jacobian (else the solver uses finite differences).
    pub analytic: bool,
}

impl Mgh {
    pub fn sum_of_squares(&self, x: &[f64]) -> f64 {
        let mut r = vec![0.0; self.m];
        (self.residuals)(x, &mut r);
        r.iter().map(|v| v * v).sum()
    }

    /// Distance of f to the nearest published minimum: absolute for a zero
    /// minimum, relative otherwise.
    pub fn error(&self, f: f64) -> f64 {
        self.minima
            .iter()
            .map(|&s| if s == 0.0 { f.abs() } else { (f - s).abs() / s })
            .fold(f64::INFINITY, f64::min)
    }
}

impl LeastSquaresProblem for Mgh {
    fn residual_count(&self) -> usize {
        self.m
    }
    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> bool {
        (self.residuals)(x, out);
        true
    }
    fn jacobian(&mut self, x: &[f64], out: &mut DMatrix<f64>) -> bool {
        if self.analytic {
            (self.jacobian)(x, out);
        }
        self.analytic
    }
}

const BARD_Y: [f64; 15] = [
    0.14, 0.18, 0.22, 0.25, 0.29, 0.32, 0.35, 0.39, 0.37, 0.58, 0.73, 0.96, 1.34, 2.10, 4.39,
];
const MEYER_Y: [f64; 16] = [
    34780.0, 28610.0, 23650.0, 19630.0, 16370.0, 13720.0, 11540.0, 9744.0, 8261.0, 7030.0, 6005.0,
    5147.0, 4427.0, 3820.0, 3307.0, 2872.0,
];

fn helical_theta(x1: f64, x2: f64) -> f64 {
    let tp = 2.0 * std::f64::consts::PI;
    if x1 > 0.0 {
        (x2 / x1).atan() / tp
    } else if x1 < 0.0 {
        (x2 / x1).atan() / tp + 0.5
    } else {
        0.25_f64.copysign(x2)
    }
}

/// The ten problems named in the issue, with their standard starting points.
pub fn problems() -> Vec<Mgh> {
    let s5 = 5f64.sqrt();
    let _ = s5;
    vec![
        Mgh {
            name: "Rosenbrock",
            m: 2,
            x0: vec![-1.2, 1.0],
            minima: &[0.0],
            residuals: |x, r| {
                r[0] = 10.0 * (x[1] - x[0] * x[0]);
                r[1] = 1.0 - x[0];
            },
            jacobian: |x, j| {
                j[(0, 0)] = -20.0 * x[0];
                j[(0, 1)] = 10.0;
                j[(1, 0)] = -1.0;
                j[(1, 1)] = 0.0;
            },
            analytic: true,
        },
        Mgh {
            name: "Freudenstein-Roth",
            m: 2,
            x0: vec![0.5, -2.0],
            minima: &[0.0, 48.9842536792400],
            residuals: |x, r| {
                r[0] = -13.0 + x[0] + ((5.0 - x[1]) * x[1] - 2.0) * x[1];
                r[1] = -29.0 + x[0] + ((x[1] + 1.0) * x[1] - 14.0) * x[1];
            },
            jacobian: |x, j| {
                j[(0, 0)] = 1.0;
                j[(0, 1)] = x[1] * (10.0 - 3.0 * x[1]) - 2.0;
                j[(1, 0)] = 1.0;
                j[(1, 1)] = x[1] * (3.0 * x[1] + 2.0) - 14.0;
            },
            analytic: true,
        },
        Mgh {
            name: "Powell badly scaled",
            m: 2,
            x0: vec![0.0, 1.0],
            minima: &[0.0],
            residuals: |x, r| {
                r[0] = 1e4 * x[0] * x[1] - 1.0;
                r[1] = (-x[0]).exp() + (-x[1]).exp() - 1.0001;
            },
            jacobian: |x, j| {
                j[(0, 0)] = 1e4 * x[1];
                j[(0, 1)] = 1e4 * x[0];
                j[(1, 0)] = -(-x[0]).exp();
                j[(1, 1)] = -(-x[1]).exp();
            },
            analytic: true,
        },
        Mgh {
            name: "Brown badly scaled",
            m: 3,
            x0: vec![1.0, 1.0],
            minima: &[0.0],
            residuals: |x, r| {
                r[0] = x[0] - 1e6;
                r[1] = x[1] - 2e-6;
                r[2] = x[0] * x[1] - 2.0;
            },
            jacobian: |x, j| {
                j.fill(0.0);
                j[(0, 0)] = 1.0;
                j[(1, 1)] = 1.0;
                j[(2, 0)] = x[1];
                j[(2, 1)] = x[0];
            },
            analytic: true,
        },
        Mgh {
            name: "Beale",
            m: 3,
            x0: vec![1.0, 1.0],
            minima: &[0.0],
            residuals: |x, r| {
                for (i, (ri, y)) in r.iter_mut().zip([1.5, 2.25, 2.625]).enumerate() {
                    *ri = y - x[0] * (1.0 - x[1].powi(i as i32 + 1));
                }
            },
            jacobian: |x, j| {
                for i in 0..3 {
                    let k = i as i32 + 1;
                    j[(i, 0)] = -(1.0 - x[1].powi(k));
                    j[(i, 1)] = x[0] * k as f64 * x[1].powi(k - 1);
                }
            },
            analytic: true,
        },
        Mgh {
            name: "Helical valley",
            m: 3,
            x0: vec![-1.0, 0.0, 0.0],
            minima: &[0.0],
            residuals: |x, r| {
                r[0] = 10.0 * (x[2] - 10.0 * helical_theta(x[0], x[1]));
                r[1] = 10.0 * ((x[0] * x[0] + x[1] * x[1]).sqrt() - 1.0);
                r[2] = x[2];
            },
            jacobian: |x, j| {
                let tp = 2.0 * std::f64::consts::PI;
                let rho2 = x[0] * x[0] + x[1] * x[1];
                let rho = rho2.sqrt();
                j[(0, 0)] = 100.0 * x[1] / (tp * rho2);
                j[(0, 1)] = -100.0 * x[0] / (tp * rho2);
                j[(0, 2)] = 10.0;
                j[(1, 0)] = 10.0 * x[0] / rho;
                j[(1, 1)] = 10.0 * x[1] / rho;
                j[(1, 2)] = 0.0;
                j[(2, 0)] = 0.0;
                j[(2, 1)] = 0.0;
                j[(2, 2)] = 1.0;
            },
            analytic: true,
        },
        Mgh {
            name: "Bard",
            m: 15,
            x0: vec![1.0, 1.0, 1.0],
            minima: &[8.21487e-3, 17.4286],
            residuals: |x, r| {
                for (i, ri) in r.iter_mut().enumerate() {
                    let u = (i + 1) as f64;
                    let v = 16.0 - u;
                    let w = u.min(v);
                    *ri = BARD_Y[i] - (x[0] + u / (v * x[1] + w * x[2]));
                }
            },
            jacobian: |x, j| {
                for i in 0..15 {
                    let u = (i + 1) as f64;
                    let v = 16.0 - u;
                    let w = u.min(v);
                    let d = v * x[1] + w * x[2];
                    j[(i, 0)] = -1.0;
                    j[(i, 1)] = u * v / (d * d);
                    j[(i, 2)] = u * w / (d * d);
                }
            },
            analytic: true,
        },
        Mgh {
            name: "Meyer",
            m: 16,
            x0: vec![0.02, 4000.0, 250.0],
            minima: &[87.9458],
            residuals: |x, r| {
                for (i, ri) in r.iter_mut().enumerate() {
                    let t = 45.0 + 5.0 * (i + 1) as f64;
                    *ri = x[0] * (x[1] / (t + x[2])).exp() - MEYER_Y[i];
                }
            },
            jacobian: |x, j| {
                for i in 0..16 {
                    let t = 45.0 + 5.0 * (i + 1) as f64;
                    let d = t + x[2];
                    let e = (x[1] / d).exp();
                    j[(i, 0)] = e;
                    j[(i, 1)] = x[0] * e / d;
                    j[(i, 2)] = -x[0] * x[1] * e / (d * d);
                }
            },
            analytic: true,
        },
        Mgh {
            name: "Box 3-D",
            m: 10,
            x0: vec![0.0, 10.0, 20.0],
            minima: &[0.0],
            residuals: |x, r| {
                for (i, ri) in r.iter_mut().enumerate() {
                    let t = 0.1 * (i + 1) as f64;
                    *ri = (-t * x[0]).exp()
                        - (-t * x[1]).exp()
                        - x[2] * ((-t).exp() - (-10.0 * t).exp());
                }
            },
            jacobian: |x, j| {
                for i in 0..10 {
                    let t = 0.1 * (i + 1) as f64;
                    j[(i, 0)] = -t * (-t * x[0]).exp();
                    j[(i, 1)] = t * (-t * x[1]).exp();
                    j[(i, 2)] = -((-t).exp() - (-10.0 * t).exp());
                }
            },
            analytic: true,
        },
        Mgh {
            name: "Powell singular",
            m: 4,
            x0: vec![3.0, -1.0, 0.0, 1.0],
            minima: &[0.0],
            residuals: |x, r| {
                r[0] = x[0] + 10.0 * x[1];
                r[1] = 5f64.sqrt() * (x[2] - x[3]);
                r[2] = (x[1] - 2.0 * x[2]).powi(2);
                r[3] = 10f64.sqrt() * (x[0] - x[3]).powi(2);
            },
            jacobian: |x, j| {
                j.fill(0.0);
                j[(0, 0)] = 1.0;
                j[(0, 1)] = 10.0;
                j[(1, 2)] = 5f64.sqrt();
                j[(1, 3)] = -(5f64.sqrt());
                let a = x[1] - 2.0 * x[2];
                j[(2, 1)] = 2.0 * a;
                j[(2, 2)] = -4.0 * a;
                let b = x[0] - x[3];
                j[(3, 0)] = 2.0 * 10f64.sqrt() * b;
                j[(3, 3)] = -2.0 * 10f64.sqrt() * b;
            },
            analytic: true,
        },
    ]
}
