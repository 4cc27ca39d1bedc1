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
/// with sensitivities the rates ẏ(t_k − τ) for the delays (the columns ∂y/∂θ_p go
/// straight into the caller's Jacobian).
#[derive(Debug, Clone)]
pub(crate) struct Simulation {
    pub outputs: Vec<f64>,
    pub rates: Vec<f64>,
}

/// How a channel reads the big state at its delayed instant: y = M·vec(S_j) + m_u·u_j +
/// m_v·u′_j + D·u(t), rows (value, ∂/∂θ₁, …), and its rate ẏ = r·x_j + r_u·u_j + r_v·u′_j.
struct Reader {
    lag: usize,
    s: f64,
    /// At s = 0 the rows are sparse: y = c·x + d·u, ∂y/∂θ_p = c·x_p + c_p·x + d_p·u.
    direct: Option<(DVector<f64>, DMatrix<f64>)>,
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
    (dt, samples): (f64, usize),
) -> Result<Reader, OdeError> {
    let ns = plant.a.nrows();
    let q = delay / dt;
    // A delay past the record's end reads nothing (rest) throughout.
    let (lag, s) = if q < samples as f64 {
        let lag = q.ceil() as usize;
        (lag, (lag as f64 - q) * dt)
    } else {
        (samples, 0.0)
    };
    let (c, d) = output_rows(plant, partials, ch);
    let c_row = plant.c.row(ch).transpose();
    let ca = plant.a.tr_mul(&c_row);
    let cb = c_row.dot(&plant.b);
    if s <= 0.0 {
        let rows = d.len();
        let mut c_p = DMatrix::zeros(partials.len(), ns);
        for (p, partial) in partials.iter().enumerate() {
            c_p.set_row(p, &partial.c.row(ch));
        }
        return Ok(Reader {
            lag,
            s: 0.0,
            direct: Some((c_row, c_p)),
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
        direct: None,
        m: &c * &step.phi,
        m_u: &c * &step.input,
        m_v: &c * &step.slope,
        d,
        r: phi_x.tr_mul(&ca),
        r_u: ca.dot(&step.input.rows(0, ns)) + cb,
        r_v: ca.dot(&step.slope.rows(0, ns)) + cb * s + plant.d[ch],
    })
}

/// Simulates `plant` on `input`, each channel read `delays[ch]` seconds late; with a
/// `jacobian`, also the sensitivities to the parameters whose derivative systems are
/// `partials`, written into its first columns (row = channel·samples + sample).
pub(crate) fn simulate(
    plant: &System,
    partials: &[System],
    delays: &[f64],
    input: &[f64],
    dt: f64,
    jacobian: Option<&mut DMatrix<f64>>,
) -> Result<Simulation, OdeError> {
    // The state's size as a constant where it is a common one: the loops over it then
    // unroll and vectorise (5–10× faster than with a run-time size).
    let sized = match plant.a.nrows() {
        2 => simulate_sized::<2>,
        3 => simulate_sized::<3>,
        4 => simulate_sized::<4>,
        5 => simulate_sized::<5>,
        6 => simulate_sized::<6>,
        7 => simulate_sized::<7>,
        8 => simulate_sized::<8>,
        10 => simulate_sized::<10>,
        12 => simulate_sized::<12>,
        _ => simulate_sized::<0>,
    };
    sized(plant, partials, delays, input, dt, jacobian)
}

/// [`simulate`] for a state of `NS` entries (0: as many as the plant has).
fn simulate_sized<const NS: usize>(
    plant: &System,
    partials: &[System],
    delays: &[f64],
    input: &[f64],
    dt: f64,
    jacobian: Option<&mut DMatrix<f64>>,
) -> Result<Simulation, OdeError> {
    let with_sensitivities = jacobian.is_some();
    let partials = if with_sensitivities { partials } else { &[] };
    let ns = if NS == 0 { plant.a.nrows() } else { NS };
    debug_assert_eq!(ns, plant.a.nrows());
    let (p, samples) = (partials.len(), input.len());
    let channels = plant.c.nrows();
    let big = big_system(plant, partials);
    let step = RampStep::new(&big.0, &big.1, dt)?;
    let readers = (0..channels)
        .map(|ch| reader(plant, partials, &big, ch, delays[ch], (dt, samples)))
        .collect::<Result<Vec<_>, _>>()?;
    let w = 1 + p;
    // Column-major copies for the loops below: Φ (ns × ns), and for each sensitivity its
    // coupling Ψ_p (ns × ns) to the state.
    let phi: Vec<f64> = step.phi.view((0, 0), (ns, ns)).iter().copied().collect();
    let psi: Vec<f64> = (0..p)
        .flat_map(|q| {
            step.phi
                .view((ns * (q + 1), 0), (ns, ns))
                .iter()
                .copied()
                .collect::<Vec<_>>()
        })
        .collect();
    let (g_u, g_v) = (step.input.as_slice(), step.slope.as_slice());
    let depth = readers.iter().map(|r| r.lag).max().unwrap_or(0) + 1;
    let mut ring = vec![0.0; depth * ns * w];
    let mut next = vec![0.0; ns * w];
    let mut row = DVector::<f64>::zeros(w);
    let mut outputs = vec![0.0; channels * samples];
    let mut rates = vec![
        0.0;
        if with_sensitivities {
            channels * samples
        } else {
            0
        }
    ];
    let mut sensitivities = jacobian;
    if let Some(jac) = sensitivities.as_deref_mut() {
        debug_assert!(jac.nrows() == channels * samples && jac.ncols() >= p);
        jac.columns_mut(0, p).fill(0.0);
    }
    let slope = |j: usize| input.get(j + 1).map_or(0.0, |next| (next - input[j]) / dt);
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    for k in 0..samples {
        for (ch, rd) in readers.iter().enumerate() {
            let Some(j) = k.checked_sub(rd.lag) else {
                continue;
            };
            let state = &ring[(j % depth) * ns * w..][..ns * w];
            let x = &state[..ns];
            let (u, v) = (input[j], slope(j));
            let at = u + v * rd.s;
            match &rd.direct {
                Some((c, c_p)) => {
                    row[0] = dot(c.as_slice(), x);
                    for q in 1..w {
                        let coupling = c_p
                            .row(q - 1)
                            .iter()
                            .zip(x)
                            .map(|(a, b)| a * b)
                            .sum::<f64>();
                        row[q] = dot(c.as_slice(), &state[q * ns..][..ns]) + coupling;
                    }
                }
                None => {
                    let big = DVectorView::from_slice(state, state.len());
                    row.gemv(1.0, &rd.m, &big, 0.0);
                    row.axpy(u, &rd.m_u, 1.0);
                    row.axpy(v, &rd.m_v, 1.0);
                }
            }
            row.axpy(at, &rd.d, 1.0);
            let index = ch * samples + k;
            outputs[index] = row[0];
            if let Some(jac) = sensitivities.as_deref_mut() {
                for q in 0..p {
                    jac[(index, q)] = row[q + 1];
                }
                rates[index] = dot(rd.r.as_slice(), x) + rd.r_u * u + rd.r_v * v;
            }
        }
        if k + 1 == samples {
            break;
        }
        let (u, v) = (input[k], slope(k));
        let current = &ring[(k % depth) * ns * w..][..ns * w];
        advance::<NS>(current, &mut next, &phi, &psi, (g_u, g_v), (u, v), ns);
        let at = ((k + 1) % depth) * ns * w;
        ring[at..at + ns * w].copy_from_slice(&next);
    }
    Ok(Simulation { outputs, rates })
}

/// One step of S = [x, x₁, …, x_P] (column-major in `current`): each column advanced by
/// Φ, each sensitivity column also driven by its coupling Ψ_p·x, plus the ramp's terms.
/// Written as sums of columns (axpy), whose rows are independent: no chain of dependent
/// additions, so the loops run at the machine's throughput rather than its latency.
#[inline(always)]
fn advance<const NS: usize>(
    current: &[f64],
    next: &mut [f64],
    phi: &[f64],
    psi: &[f64],
    (g_u, g_v): (&[f64], &[f64]),
    (u, v): (f64, f64),
    ns: usize,
) {
    debug_assert_eq!(current.len(), next.len());
    let ns = if NS == 0 { ns } else { NS };
    let x = &current[..ns];
    for (n, (a, b)) in next.iter_mut().zip(g_u.iter().zip(g_v)) {
        *n = a * u + b * v;
    }
    for (q, (out, column)) in next
        .chunks_exact_mut(ns)
        .zip(current.chunks_exact(ns))
        .enumerate()
    {
        for (c, &xc) in column.iter().enumerate() {
            for (o, a) in out.iter_mut().zip(&phi[c * ns..][..ns]) {
                *o += a * xc;
            }
        }
        if q > 0 {
            let coupling = &psi[(q - 1) * ns * ns..][..ns * ns];
            for (c, &xc) in x.iter().enumerate() {
                for (o, a) in out.iter_mut().zip(&coupling[c * ns..][..ns]) {
                    *o += a * xc;
                }
            }
        }
    }
}
