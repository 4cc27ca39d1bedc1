//! Exact simulation of a chain with its sensors, and of its sensitivities.
//!
//! The state x and its sensitivities x_p = ∂x/∂θ_p (x_p′ = A·x_p + A_p·x + b_p·u from
//! rest) form one block-triangular linear system, discretised once per evaluation by
//! [`RampStep`] (the first-order hold of the input, exact). Its state is kept as an
//! ns × (1 + P) matrix S = [x, x₁, …, x_P] whose column-major storage is the big state.
//!
//! A channel with delay τ reads the motion at t_k − τ = t_j + s, j = k − ⌈τ/dt⌉,
//! 0 ≤ s < dt: the state at t_j advanced by s with the same ramp (a second [`RampStep`]).
//! Before the record the chain is at rest with no input, so such a channel reads 0.

use super::model::System;
use msd_ode::{OdeError, RampStep};
use nalgebra::{DMatrix, DVector, DVectorView};

/// What one simulation gives: each channel's series (channel-major, `samples` each), and
/// with sensitivities the columns ∂y/∂θ_p and the rates ẏ(t_k − τ) for the delays.
#[derive(Debug, Clone)]
pub(crate) struct Simulation {
    pub outputs: Vec<f64>,
    pub sensitivities: Option<DMatrix<f64>>,
    pub rates: Vec<f64>,
}

/// How a channel reads the big state at its delayed instant: y = M·vec(S_j) + m_u·u_j +
/// m_v·u′_j + D·u(t), rows (value, ∂/∂θ₁, …), and its rate ẏ = r·x_j + r_u·u_j + r_v·u′_j.
struct Reader {
    lag: usize,
    s: f64,
    m: DMatrix<f64>,
    m_u: DVector<f64>,
    m_v: DVector<f64>,
    d: DVector<f64>,
    r: DVector<f64>,
    r_u: f64,
    r_v: f64,
}

/// The block-triangular system of `plant` and its derivative systems `partials`.
fn big_system(plant: &System, partials: &[System]) -> (DMatrix<f64>, DVector<f64>) {
    let ns = plant.a.nrows();
    let size = ns * (1 + partials.len());
    let mut a = DMatrix::zeros(size, size);
    let mut b = DVector::zeros(size);
    a.view_mut((0, 0), (ns, ns)).copy_from(&plant.a);
    b.rows_mut(0, ns).copy_from(&plant.b);
    for (p, partial) in partials.iter().enumerate() {
        let r = ns * (p + 1);
        a.view_mut((r, r), (ns, ns)).copy_from(&plant.a);
        a.view_mut((r, 0), (ns, ns)).copy_from(&partial.a);
        b.rows_mut(r, ns).copy_from(&partial.b);
    }
    (a, b)
}

/// The output rows of channel `ch` on the big state: (value, ∂/∂θ_p) = Cbig·vec(S) + D.
fn output_rows(plant: &System, partials: &[System], ch: usize) -> (DMatrix<f64>, DVector<f64>) {
    let ns = plant.a.nrows();
    let rows = 1 + partials.len();
    let mut c = DMatrix::zeros(rows, ns * rows);
    let mut d = DVector::zeros(rows);
    for r in 0..rows {
        c.view_mut((r, ns * r), (1, ns)).copy_from(&plant.c.row(ch));
    }
    d[0] = plant.d[ch];
    for (p, partial) in partials.iter().enumerate() {
        c.view_mut((p + 1, 0), (1, ns))
            .copy_from(&partial.c.row(ch));
        d[p + 1] = partial.d[ch];
    }
    (c, d)
}

fn reader(
    plant: &System,
    partials: &[System],
    big: &(DMatrix<f64>, DVector<f64>),
    ch: usize,
    delay: f64,
    dt: f64,
) -> Result<Reader, OdeError> {
    let ns = plant.a.nrows();
    let q = delay / dt;
    let lag = q.ceil() as usize;
    let s = (lag as f64 - q) * dt;
    let (c, d) = output_rows(plant, partials, ch);
    let c_row = plant.c.row(ch).transpose();
    let ca = plant.a.tr_mul(&c_row);
    let cb = c_row.dot(&plant.b);
    if s <= 0.0 {
        let rows = d.len();
        return Ok(Reader {
            lag,
            s: 0.0,
            m: c,
            m_u: DVector::zeros(rows),
            m_v: DVector::zeros(rows),
            d,
            r: ca,
            r_u: cb,
            r_v: plant.d[ch],
        });
    }
    let step = RampStep::new(&big.0, &big.1, s)?;
    let phi_x = step.phi.view((0, 0), (ns, ns));
    Ok(Reader {
        lag,
        s,
        m: &c * &step.phi,
        m_u: &c * &step.input,
        m_v: &c * &step.slope,
        d,
        r: phi_x.tr_mul(&ca),
        r_u: ca.dot(&step.input.rows(0, ns)) + cb,
        r_v: ca.dot(&step.slope.rows(0, ns)) + cb * s + plant.d[ch],
    })
}

/// Simulates `plant` (and its sensitivities to the parameters whose derivative systems
/// are `partials`, when `with_sensitivities`) on `input`, each channel read `delays[ch]`
/// seconds late.
pub(crate) fn simulate(
    plant: &System,
    partials: &[System],
    delays: &[f64],
    input: &[f64],
    dt: f64,
    with_sensitivities: bool,
) -> Result<Simulation, OdeError> {
    let partials = if with_sensitivities { partials } else { &[] };
    let (ns, p, samples) = (plant.a.nrows(), partials.len(), input.len());
    let channels = plant.c.nrows();
    let big = big_system(plant, partials);
    let step = RampStep::new(&big.0, &big.1, dt)?;
    let readers = (0..channels)
        .map(|ch| reader(plant, partials, &big, ch, delays[ch], dt))
        .collect::<Result<Vec<_>, _>>()?;
    let phi = step.phi.view((0, 0), (ns, ns)).clone_owned();
    let psi = step.phi.view((ns, 0), (ns * p, ns)).clone_owned();
    let g_u = DMatrix::from_column_slice(ns, 1 + p, step.input.as_slice());
    let g_v = DMatrix::from_column_slice(ns, 1 + p, step.slope.as_slice());
    let depth = readers.iter().map(|r| r.lag).max().unwrap_or(0) + 1;
    let mut ring = vec![DMatrix::<f64>::zeros(ns, 1 + p); depth];
    let mut next = DMatrix::<f64>::zeros(ns, 1 + p);
    let mut coupling = DVector::<f64>::zeros(ns * p);
    let mut row = DVector::<f64>::zeros(1 + p);
    let mut outputs = vec![0.0; channels * samples];
    let mut rates = vec![
        0.0;
        if with_sensitivities {
            channels * samples
        } else {
            0
        }
    ];
    let mut sensitivities = with_sensitivities.then(|| DMatrix::zeros(channels * samples, p));
    let slope = |j: usize| input.get(j + 1).map_or(0.0, |next| (next - input[j]) / dt);
    for k in 0..samples {
        for (ch, rd) in readers.iter().enumerate() {
            let Some(j) = k.checked_sub(rd.lag) else {
                continue;
            };
            let state = &ring[j % depth];
            let (u, v) = (input[j], slope(j));
            let at = u + v * rd.s;
            let x = DVectorView::from_slice(state.as_slice(), state.len());
            row.gemv(1.0, &rd.m, &x, 0.0);
            row.axpy(u, &rd.m_u, 1.0);
            row.axpy(v, &rd.m_v, 1.0);
            row.axpy(at, &rd.d, 1.0);
            let index = ch * samples + k;
            outputs[index] = row[0];
            if let Some(jac) = sensitivities.as_mut() {
                for q in 0..p {
                    jac[(index, q)] = row[q + 1];
                }
                rates[index] = rd.r.dot(&state.column(0)) + rd.r_u * u + rd.r_v * v;
            }
        }
        if k + 1 == samples {
            break;
        }
        let (u, v) = (input[k], slope(k));
        let current = &ring[k % depth];
        next.gemm(1.0, &phi, current, 0.0);
        if p > 0 {
            coupling.gemv(1.0, &psi, &current.column(0), 0.0);
            // Columns 1… of S follow column 0 in its storage.
            for (n, c) in next.as_mut_slice()[ns..].iter_mut().zip(coupling.iter()) {
                *n += c;
            }
        }
        next.zip_zip_apply(&g_u, &g_v, |n, gu, gv| *n += gu * u + gv * v);
        std::mem::swap(&mut ring[(k + 1) % depth], &mut next);
    }
    Ok(Simulation {
        outputs,
        sensitivities,
        rates,
    })
}
