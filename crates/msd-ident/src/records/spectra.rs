//! A record's spectra at θ in closed form: each channel's transfer from the drive and
//! its free responses, at every line of the record's DFT, from the exact simulator's
//! frequency response and its transition matrix — the DFTs of the simulated impulse and
//! free responses, without simulating or transforming them.
//!
//! The transfer is C·(zI − Φ)⁻¹·Σ_m W_m·z^{o_m} + D at z_k = e^{2πik/N}
//! ([`msd_ode::ExactSimulator::frequency_response`]): the plant as the simulator
//! discretises it, whole (an impulse response simulated over the record is cut at its
//! end). A free response C·Φᵗ·e_i over t < N has the DFT
//! C·(I − Φᴺ)·(I − Φ/z_k)⁻¹·e_i exactly (a geometric series; z_k^N = 1).

use super::model::OutputMap;
use msd_ode::{ExactSimulator, Resolvent, SMatrix, SVector};
use rustfft::num_complex::Complex64;

/// The points z_k = e^{2πik/N} of the lines k = 0..=N/2 of an N-point DFT (the rest are
/// their conjugates).
pub(super) fn line_points(n: usize) -> Vec<Complex64> {
    (0..=n / 2)
        .map(|k| Complex64::from_polar(1.0, 2.0 * std::f64::consts::PI * k as f64 / n as f64))
        .collect()
}

/// Each channel's transfer from the drive at the lines k = 0..=N/2 of the record's DFT
/// (`points`), at the plant `sim` discretises; `None` where zI − Φ is singular.
pub(super) fn transfer_spectra(
    sim: &ExactSimulator<2>,
    maps: &[OutputMap],
    points: &[Complex64],
) -> Option<Vec<Vec<Complex64>>> {
    let mut out = vec![Vec::with_capacity(points.len()); maps.len()];
    for z in points {
        let x = sim.frequency_response(*z)?;
        for (g, map) in out.iter_mut().zip(maps) {
            g.push(map.c[0] * x[0] + map.c[1] * x[1] + map.d);
        }
    }
    Some(out)
}

/// Each channel's two free responses (from a unit initial displacement and velocity)
/// at the lines k = 0..=N/2 of the record's N-point DFT (`points`), scaled by 1/√N as
/// a residual's spectrum, at the transition matrix of `sim`; `None` where zI − Φ is
/// singular.
pub(super) fn free_spectra(
    sim: &ExactSimulator<2>,
    maps: &[OutputMap],
    points: &[Complex64],
    n: usize,
) -> Option<Vec<[Vec<Complex64>; 2]>> {
    let rows = free_rows(sim, maps, n);
    let capacity = points.len();
    let mut out = vec![[Vec::with_capacity(capacity), Vec::with_capacity(capacity)]; maps.len()];
    for z in points {
        let columns = free_columns(&sim.resolvent(*z)?)?;
        for (pair, row) in out.iter_mut().zip(&rows) {
            for (column, x) in pair.iter_mut().zip(&columns) {
                column.push(row[0] * x[0] + row[1] * x[1]);
            }
        }
    }
    Some(out)
}

/// cᵀ·(I − Φᴺ)/√N per channel: the row that (I − Φ/z)⁻¹ ([`free_columns`]) turns into
/// the channel's free responses at a line of an N-point record.
pub(super) fn free_rows(sim: &ExactSimulator<2>, maps: &[OutputMap], n: usize) -> Vec<[f64; 2]> {
    let end = SMatrix::<f64, 2, 2>::identity() - sim.transition().pow(n as u32);
    let scale = 1.0 / (n as f64).sqrt();
    (maps.iter())
        .map(|m| {
            let r = nalgebra::RowVector2::new(m.c[0], m.c[1]) * end;
            [r[0] * scale, r[1] * scale]
        })
        .collect()
}

/// The columns of (I − Φ/z)⁻¹ = z·(zI − Φ)⁻¹ at a line.
pub(super) fn free_columns(line: &Resolvent<'_, 2>) -> Option<[SVector<Complex64, 2>; 2]> {
    let (z, zero) = (line.z(), Complex64::new(0.0, 0.0));
    Some([line.solve([z, zero])?, line.solve([zero, z])?])
}

/// The lines 0..=N/2 of a real sequence's DFT completed to N by conjugate symmetry.
pub(super) fn mirrored(mut half: Vec<Complex64>, n: usize) -> Vec<Complex64> {
    for k in half.len()..n {
        let v = half[n - k].conj();
        half.push(v);
    }
    half
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input_noise::spectrum;
    use crate::plant::{Drive, Plant};
    use crate::records::model::OutputKind;
    use msd_ode::Hold;

    /// The closed-form free responses are the DFT of C·Φᵗ·e_i over the record, for an
    /// accelerometer (its C from the dynamics) and a displacement, odd and even lengths.
    #[test]
    fn the_free_spectra_are_the_free_responses_dft() {
        let plant = Plant {
            theta: [1.7, 3.1, 950.0],
            drive: Drive::Force,
        };
        let sim = plant.response(1e-2, Hold::Cubic).expect("discretised");
        let maps = [
            plant.output(OutputKind::Acceleration),
            plant.output(OutputKind::Displacement),
        ];
        let phi = sim.transition();
        for n in [63usize, 64] {
            let free = free_spectra(&sim, &maps, &line_points(n), n).expect("regular");
            for (map, pair) in maps.iter().zip(&free) {
                for (i, closed) in pair.iter().enumerate() {
                    let mut state = SMatrix::<f64, 2, 1>::zeros();
                    state[i] = 1.0;
                    let samples = (0..n).map(|t| {
                        let x = phi.pow(t as u32) * state;
                        map.c[0] * x[0] + map.c[1] * x[1]
                    });
                    let dft = spectrum(samples, n, 1.0 / (n as f64).sqrt());
                    let peak = dft.iter().map(|v| v.norm()).fold(0.0, f64::max);
                    for (k, (a, b)) in closed.iter().zip(&dft).enumerate() {
                        assert!(
                            (a - b).norm() < 1e-12 * peak,
                            "n {n}, line {k}: {a} against {b}"
                        );
                    }
                }
            }
        }
    }
}
