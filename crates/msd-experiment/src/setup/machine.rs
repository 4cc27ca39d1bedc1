//! The damper test machine's records: a sine stroke imposed on the plant, the force it
//! takes.

use super::data::Clean;
use crate::config::{Plant, StrokeCondition};
use std::f64::consts::PI;

/// The noise-free record of one condition: `cycles` whole periods of the stroke
/// x = X·sin ωt sampled every `dt`, and the force
/// F = m·x″ + c·x′ + k·x + F_c·sign(x′) + c₂·x′|x′| + k₃·x³ of the plant.
pub(crate) fn stroke_record(
    plant: &Plant,
    condition: &StrokeCondition,
    cycles: usize,
    dt: f64,
) -> msd_ident::Result<Clean> {
    let w = 2.0 * PI * condition.frequency;
    let amplitude = condition.amplitude;
    let n = (cycles as f64 / (condition.frequency * dt)).round() as usize;
    let mut stroke = Vec::with_capacity(n);
    let mut force = Vec::with_capacity(n);
    for i in 0..n {
        let t = i as f64 * dt;
        let (x, v, a) = (
            amplitude * (w * t).sin(),
            amplitude * w * (w * t).cos(),
            -amplitude * w * w * (w * t).sin(),
        );
        stroke.push(x);
        force.push(
            plant.mass * a
                + plant.damping * v
                + plant.stiffness * x
                + plant.coulomb_force * v.signum()
                + plant.quadratic_damping * v * v.abs()
                + plant.cubic_stiffness * x.powi(3),
        );
    }
    Ok(Clean {
        input: Some(stroke),
        t0: 0.0,
        dt,
        channels: vec![force],
    })
}
