//! The chain with its sensors as one linear system, and its exact derivatives.
//!
//! ## The equations
//! Displacements q (relative to the ground under a base acceleration a_g) and velocities
//! q′ form the plant's state; with W = M⁻¹,
//!
//! q″ = −W·K·q − W·C·q′ + W·e_f·F   (force on mass f), or
//! q″ = −W·K·q − W·C·q′ − 1·a_g     (base acceleration).
//!
//! A channel reads y = c·x + d·u: a displacement or velocity from the state, an
//! acceleration from the state equation's row (plus a_g for an accelerometer under a base
//! acceleration). A sensor's low-pass filter adds one or two states driven by that y and
//! reads its output instead. The whole is x′ = A·x + b·u, y = C·x + D·u.
//!
//! Every entry is affine in each of w = 1/m, c and k when the other two are held: so the
//! derivative to c_j is the system at c = e_j minus the system at c = 0, exactly. With
//! θ = ln p the fit's parameters, ∂/∂ln k_j = k_j·∂/∂k_j and ∂/∂ln m_j = −w_j·∂/∂w_j.

use super::setup::{ChainDrive, ChainSetup};
use crate::plant::{Input, state_space};
use msd_signal::ResponseQuantity;
use nalgebra::{DMatrix, DVector};
use std::f64::consts::TAU;

/// x′ = A·x + b·u, y = C·x + D·u.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct System {
    pub a: DMatrix<f64>,
    pub b: DVector<f64>,
    pub c: DMatrix<f64>,
    pub d: DVector<f64>,
}

/// Which physical parameter a fitted column is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Family {
    Mass,
    Damper,
    Spring,
    /// An extra damper from a mass to the ground.
    GroundDamper,
    /// An extra spring from a mass to the ground.
    GroundSpring,
}

/// The chain's parameters as vectors: inverse masses w, dampers c, springs k, and the
/// extra dampers cg and springs kg to the ground (zeros where there are none).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Values {
    pub w: Vec<f64>,
    pub c: Vec<f64>,
    pub k: Vec<f64>,
    pub cg: Vec<f64>,
    pub kg: Vec<f64>,
}

impl Values {
    fn family_mut(&mut self, family: Family) -> &mut Vec<f64> {
        match family {
            Family::Mass => &mut self.w,
            Family::Damper => &mut self.c,
            Family::Spring => &mut self.k,
            Family::GroundDamper => &mut self.cg,
            Family::GroundSpring => &mut self.kg,
        }
    }
}

/// The number of states: the plant's 2n and each filter's order.
pub(crate) fn state_count(setup: &ChainSetup) -> usize {
    2 * setup.masses
        + setup
            .sensors
            .iter()
            .map(|s| s.low_pass.map_or(0, |f| usize::from(f.order)))
            .sum::<usize>()
}

/// The chain's stiffness-like matrix of `values`: element i joins mass i to i − 1.
pub(crate) fn chain_matrix(values: &[f64]) -> DMatrix<f64> {
    let n = values.len();
    let mut out = DMatrix::zeros(n, n);
    for (i, &v) in values.iter().enumerate() {
        out[(i, i)] += v;
        if i > 0 {
            out[(i - 1, i - 1)] += v;
            out[(i, i - 1)] -= v;
            out[(i - 1, i)] -= v;
        }
    }
    out
}

/// The system of `setup` at `values`.
pub(crate) fn system(setup: &ChainSetup, values: &Values) -> System {
    let n = setup.masses;
    let ns = state_count(setup);
    let (mut kk, mut cc) = (chain_matrix(&values.k), chain_matrix(&values.c));
    for i in 0..n {
        kk[(i, i)] += values.kg[i];
        cc[(i, i)] += values.cg[i];
    }
    let input = match setup.drive {
        ChainDrive::Force => Input::Force {
            at: setup.force_at - 1,
        },
        ChainDrive::BaseAcceleration => Input::BaseAcceleration,
    };
    let (plant_a, plant_b) = state_space(&values.w, &cc, &kk, input);
    let mut a = DMatrix::zeros(ns, ns);
    let mut b = DVector::zeros(ns);
    a.view_mut((0, 0), (2 * n, 2 * n)).copy_from(&plant_a);
    b.rows_mut(0, 2 * n).copy_from(&plant_b);
    let base = f64::from(u8::from(setup.drive == ChainDrive::BaseAcceleration));
    let mut c = DMatrix::zeros(setup.sensors.len(), ns);
    let mut d = DVector::zeros(setup.sensors.len());
    let mut next = 2 * n;
    for (channel, sensor) in setup.sensors.iter().enumerate() {
        let i = sensor.at - 1;
        let (mut row, mut feed) = (DVector::zeros(ns), 0.0);
        match sensor.quantity {
            ResponseQuantity::Displacement => row[i] = 1.0,
            ResponseQuantity::Velocity => row[n + i] = 1.0,
            ResponseQuantity::Acceleration => {
                row.copy_from(&a.row(n + i).transpose());
                feed = b[n + i] + base;
            }
        }
        match sensor.low_pass {
            None => {
                c.set_row(channel, &row.transpose());
                d[channel] = feed;
            }
            Some(filter) => {
                let wc = TAU * filter.cutoff_hz;
                let f = next;
                if filter.order == 1 {
                    // f′ = ωc·(y − f)
                    for j in 0..ns {
                        a[(f, j)] += wc * row[j];
                    }
                    a[(f, f)] -= wc;
                    b[f] = wc * feed;
                } else {
                    // f″ = ωc²·(y − f) − 2ζc·ωc·f′
                    a[(f, f + 1)] = 1.0;
                    for j in 0..ns {
                        a[(f + 1, j)] += wc * wc * row[j];
                    }
                    a[(f + 1, f)] -= wc * wc;
                    a[(f + 1, f + 1)] -= 2.0 * filter.damping_ratio * wc;
                    b[f + 1] = wc * wc * feed;
                }
                c[(channel, f)] = 1.0;
                next += usize::from(filter.order);
            }
        }
    }
    debug_assert_eq!(next, ns);
    System { a, b, c, d }
}

/// ∂System/∂p for p the `index`-th value of `family` (exact: the system is affine in it).
pub(crate) fn derivative(
    setup: &ChainSetup,
    values: &Values,
    family: Family,
    index: usize,
) -> System {
    let mut unit = values.clone();
    let mut zero = values.clone();
    let (u, z) = (unit.family_mut(family), zero.family_mut(family));
    u.iter_mut().for_each(|v| *v = 0.0);
    z.iter_mut().for_each(|v| *v = 0.0);
    u[index] = 1.0;
    let (s1, s0) = (system(setup, &unit), system(setup, &zero));
    System {
        a: s1.a - s0.a,
        b: s1.b - s0.b,
        c: s1.c - s0.c,
        d: s1.d - s0.d,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chain::{ChainSensor, LowPass};

    fn setup() -> ChainSetup {
        ChainSetup {
            masses: 2,
            force_at: 2,
            sensors: vec![
                ChainSensor {
                    at: 1,
                    quantity: ResponseQuantity::Acceleration,
                    low_pass: Some(LowPass {
                        cutoff_hz: 30.0,
                        order: 2,
                        ..LowPass::default()
                    }),
                    ..ChainSensor::default()
                },
                ChainSensor {
                    at: 2,
                    quantity: ResponseQuantity::Velocity,
                    low_pass: Some(LowPass {
                        cutoff_hz: 50.0,
                        ..LowPass::default()
                    }),
                    ..ChainSensor::default()
                },
                ChainSensor {
                    at: 2,
                    ..ChainSensor::default()
                },
            ],
            ..ChainSetup::default()
        }
    }

    #[test]
    fn derivatives_match_central_differences() {
        let values = Values {
            w: vec![0.5, 1.0],
            c: vec![4.0, 2.0],
            k: vec![2e4, 1e4],
            cg: vec![0.0, 0.5],
            kg: vec![0.0, 3e3],
        };
        for (family, index) in [
            (Family::Mass, 1),
            (Family::Damper, 0),
            (Family::Spring, 1),
            (Family::GroundSpring, 1),
            (Family::GroundDamper, 1),
        ] {
            let exact = derivative(&setup(), &values, family, index);
            let (mut up, mut down) = (values.clone(), values.clone());
            let h = 1e-3 * up.family_mut(family)[index];
            up.family_mut(family)[index] += h;
            down.family_mut(family)[index] -= h;
            let (s1, s0) = (system(&setup(), &up), system(&setup(), &down));
            // Affine: the central difference is exact up to rounding of entries ≈ 1e6
            // (ωc²·k·w), divided by 2h.
            let fd = (&s1.a - &s0.a) / (2.0 * h);
            assert!((fd - &exact.a).abs().max() < 1e-6 * exact.a.abs().max().max(1.0));
            let fd = (&s1.b - &s0.b) / (2.0 * h);
            assert!((fd - &exact.b).abs().max() < 1e-6 * exact.b.abs().max().max(1.0));
        }
    }

    #[test]
    fn a_filter_has_unit_gain_at_zero_frequency() {
        // Static force 1 N on mass 2: q = K⁻¹·e₂, and each filtered channel reads its
        // unfiltered value: y = D − C·A⁻¹·b.
        let values = Values {
            w: vec![0.5, 1.0],
            c: vec![4.0, 2.0],
            k: vec![2e4, 1e4],
            cg: vec![0.0, 0.0],
            kg: vec![0.0, 0.0],
        };
        let s = system(&setup(), &values);
        let x = -s.a.clone().lu().solve(&s.b).expect("a stable system");
        let y = &s.c * &x + &s.d;
        // Displacement of mass 2 under 1 N: 1/2e4 + 1/1e4; velocity and acceleration 0.
        assert!((y[2] - 1.5e-4).abs() < 1e-18);
        assert!(y[0].abs() < 1e-15 && y[1].abs() < 1e-15);
    }
}
