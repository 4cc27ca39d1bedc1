//! The efficient estimate under a noisy drive: the frequency-domain maximum-likelihood
//! estimator of the errors-in-variables model (Pintelon and Schoukens' SML), run after
//! the output-error fit has found θ and the noise model its variances.
//!
//! ## The method
//! Each line k of a record's residual R_k(θ) = DFT(y − f(θ) − G(θ)·x₀) (unitary
//! scaling, the mean and Nyquist lines left out: the offsets live on the mean line) is a
//! complex Gaussian with covariance S_k(θ) = D + σ²_u·G_k(θ)·G_k(θ)ᴴ: the sensors' noise
//! and the drive's, seen through the plant at θ. With the variances held at the noise
//! model's, the estimate minimises V(θ) = Σ_k R_kᴴ·S_k(θ)⁻¹·R_k, the true drive
//! eliminated (the SML cost); the initial states x₀ are concentrated out by weighted
//! least squares at each θ. S_k's θ-dependence is kept: with it the drive's noise no
//! longer biases the estimate (at a line the drive does not excite, E[V_k] = 1 at every
//! θ), where the output-error fit's equations carry a bias of σ²_u·Σ Re(∂G·Ḡ) — the
//! errors-in-variables bias of least squares.
//!
//! Gauss–Newton on the whitened lines ε_k = S_k^(−1/2)·R_k (Woodbury: S is diagonal
//! plus rank one), the Jacobian by forward differences in ln θ at the start (the chord
//! method), each step halved until V falls (twice at most once the step is below 0.1
//! standard errors: the chord's resolution), until a step is below 1e-4 standard errors
//! (the Newton decrement). Its information is F = Σ_k 2·Re(∂R_kᴴ·S_k⁻¹·∂R_k) over the
//! lines (∂R_k exact: the transforms of the sensitivity system's outputs), each
//! record's initial state concentrated out in S's metric (a Schur complement): F⁻¹ is
//! the Cramér–Rao bound of the model as fitted. The covariance reported is the
//! sandwich F⁻¹·B·F⁻¹ of the estimating equations s = Σ_k 2·Re(∂R_kᴴ·S_k⁻¹·R_k):
//! s is a fixed linear function of the residual's samples, s_p = Σ_t w_p(t)·r(t), and
//! B = Var(s) = wᵀ·Σ·w is taken under the time-domain noise covariance Σ as the
//! output-error sandwich takes it ([`crate::input_noise`]'s middle matrix), exact
//! where the Whittle lines are an approximation (a record's ends, the lines'
//! leakage). Under the Whittle model B = F and the sandwich is the bound (on the
//! simulated load-cell records of `cargo xtask noise-study` they agree to three
//! digits), and the estimate's spread over 400 seeds is 0.91–1.13 of it.

use super::model::OutputMap;
use super::problem::{Joint, RecordRows};
use super::spectra::{free_columns, free_rows, line_points};
use crate::input_noise::{SpectralModel, concentrate, likelihood_lines, spectra};
use crate::plant::Plant;
use msd_ode::{ExactSimulator, SVector, SampledInput};
use nalgebra::{DMatrix, DVector};
use rustfft::num_complex::Complex64;

/// The weighted estimate.
pub(super) struct Weighted {
    /// θ̂ (m, c, k in the model's units).
    pub theta: [f64; 3],
    /// F⁻¹: the Cramér–Rao bound of the free ln θ.
    pub inverse: DMatrix<f64>,
    /// The estimating equations' weights w_p(t), one column per free parameter, in the
    /// problem's rows (record, channel, sample).
    pub weights: DMatrix<f64>,
    /// V(θ̂) over its expectation (the real parts less the estimated quantities):
    /// near 1 when the noise model describes the residuals.
    pub cost_ratio: f64,
}

/// The Newton decrement (the step in standard errors) and the relative change of V
/// below which the steps stop, and the most steps.
const DECREMENT: f64 = 1e-4;
const TOLERANCE: f64 = 1e-12;
const MAX_STEPS: usize = 30;
/// The step, in standard errors, below which the chord's direction is not searched
/// past half its length.
const RESOLUTION: f64 = 0.1;
/// The forward-difference step in ln θ. Its truncation moves the chord's fixed point:
/// on the 1 % load-cell bench record by 1.3e-3 standard errors from central
/// differences' (5e-3 at a step of 1e-4; at 1e-6 the chord stalls short of its fixed
/// point, two evaluations more), far inside the estimate's precision; three
/// evaluations fewer than central differences.
const STEP: f64 = 1e-5;

/// The weighted estimate from `theta0` under the noise variances of `model`; `None`
/// where the model cannot be simulated or the normal matrix is singular (the caller
/// keeps the output-error estimate). Leaves `problem` prepared at θ̂ with its
/// least-squares initial states and offsets.
pub(super) fn refit(
    problem: &mut Joint<'_>,
    theta0: [f64; 3],
    model: &SpectralModel,
) -> Option<Weighted> {
    let variances = Variances::of(model, problem)?;
    let mut x = problem.pack(theta0);
    let mut at = whitened(problem, &x, &variances)?;
    let mut cost = at.e.norm_squared();
    // The chord method: the Jacobian of the start kept for every step (three evaluations
    // saved per step). The estimate moves from the output-error one by a few standard
    // errors, over which J changes little; its fixed point J₀ᵀ·ε = 0 lies off the
    // optimum's J*ᵀ·ε = 0 by up to 6e-4 of a standard error (scipy's SML on 20 records).
    let j = jacobian(problem, &x, &at.e, &variances)?;
    let normal = j.tr_mul(&j);
    let factor = normal.clone().cholesky()?;
    for _ in 0..MAX_STEPS {
        let step = factor.solve(&(-j.tr_mul(&at.e)));
        // The step in standard errors (ε is whitened: JᵀJ is the information), the
        // Newton decrement: below DECREMENT the estimate sits far inside its precision.
        let decrement = (step.transpose() * &normal * &step)[(0, 0)].sqrt();
        if decrement < DECREMENT {
            break;
        }
        // A short step V does not lower at full or half length ends the iteration: the
        // chord's direction is then at its resolution, where halving it further
        // finds only the gap between J₀ and J* (ten more evaluations for nothing).
        let trials = if decrement < RESOLUTION { 2 } else { 12 };
        let (mut scale, mut accepted) = (1.0, None);
        for _ in 0..trials {
            let trial: Vec<f64> = x.iter().zip(&step).map(|(a, d)| a + scale * d).collect();
            if let Some(t) = whitened(problem, &trial, &variances) {
                let c = t.e.norm_squared();
                if c <= cost {
                    accepted = Some((trial, t, c));
                    break;
                }
            }
            scale *= 0.5;
        }
        let Some((trial, t, c)) = accepted else {
            break;
        };
        let change = (cost - c) / cost;
        (x, at, cost) = (trial, t, c);
        if change < TOLERANCE || step.norm() * scale < 1e-10 {
            break;
        }
    }
    let residuals = at.e.len();
    let sensitivities = sensitivities(problem, &x, at)?;
    let (f, columns) = information(&sensitivities, &variances);
    let inverse = f.try_inverse()?;
    let weights = score_weights(problem, &sensitivities, &columns, &variances);
    let theta = problem.theta(&x);
    if !problem.prepare(theta) {
        return None;
    }
    problem.solve_linear();
    let expected = residuals
        .saturating_sub(x.len() + 2 * problem.records.len())
        .max(1);
    Some(Weighted {
        theta,
        inverse,
        weights,
        cost_ratio: cost / expected as f64,
    })
}

/// The noise variances of the model, the drive's and each sensor group's, with each
/// record's measured spectra: what the refit holds fixed.
struct Variances {
    input: f64,
    sensors: Vec<f64>,
    measured: Vec<Measured>,
}

impl Variances {
    fn of(model: &SpectralModel, problem: &Joint<'_>) -> Option<Self> {
        Some(Self {
            input: model.input_variance,
            sensors: model.sensor_variance.clone(),
            measured: (problem.records.iter())
                .map(|rec| Measured::of(problem, rec))
                .collect::<Option<_>>()?,
        })
    }
}

/// One record in the frequency domain at θ, at its likelihood lines, per channel: the
/// residual from rest, the two initial-state responses (when estimated) and the
/// transfer spectrum (unitary scaling but for the transfer's).
struct RecordSpectra {
    groups: Vec<usize>,
    residual: Vec<Vec<Complex64>>,
    basis: [Vec<Vec<Complex64>>; 2],
    transfer: Vec<Vec<Complex64>>,
}

/// Every record's spectra at ln θ = `x`, in closed form: the model's lines from the
/// measured drive's transforms ([`msd_ode::ExactSimulator::state_spectrum`]); the
/// response is simulated for its last state alone and nothing is transformed.
fn spectra_at(problem: &Joint<'_>, x: &[f64], variances: &Variances) -> Option<Vec<RecordSpectra>> {
    let theta = problem.theta(x);
    if !theta.iter().all(|v| v.is_finite() && *v > 0.0) {
        return None;
    }
    let plant = Plant {
        theta,
        drive: problem.drive,
    };
    let sim = plant.response(problem.dt, problem.hold).ok()?;
    (problem.records.iter().zip(&variances.measured))
        .map(|(rec, measured)| {
            let maps: Vec<OutputMap> = rec.kinds.iter().map(|k| plant.output(*k)).collect();
            let input = problem.drive_input(rec);
            let mut spectra = measured.model_lines(&sim, &maps, input, problem.state)?;
            spectra.groups = rec.groups.clone();
            Some(spectra)
        })
        .collect()
}

/// One record's measured spectra at its likelihood lines, unitary scaling: each
/// channel's, the drive's and the transforms Mⱼ of its hold's coefficients, which
/// give the model's lines at any θ in closed form.
struct Measured {
    /// The DFT points of the lines 0..=N/2.
    points: Vec<Complex64>,
    /// Each channel's spectrum at the likelihood lines.
    outputs: Vec<Vec<Complex64>>,
    /// The drive's spectrum at the likelihood lines.
    drive: Vec<Complex64>,
    /// Mⱼ at the likelihood lines.
    hold: Vec<[Complex64; 4]>,
    /// The hold's interior transforms Pⱼ at the likelihood lines: the transfer's.
    stencil: Vec<[Complex64; 4]>,
}

impl Measured {
    fn of(problem: &Joint<'_>, rec: &RecordRows<'_>) -> Option<Self> {
        let n = rec.len;
        let lines = likelihood_lines(n);
        let cut = |v: Vec<Complex64>| v[lines.clone()].to_vec();
        let input = problem.drive_input(rec);
        let polynomials = input.hold_polynomials(problem.hold).ok()?;
        // Mⱼ = Σ_{t≥1} aⱼ(t)·z⁻ᵗ: the coefficient of the step into sample t at t; then
        // the drive's and each channel's spectra.
        let coefficients = (0..4).map(|j| {
            let steps = polynomials.iter().map(|a| a[j]);
            std::iter::once(0.0).chain(steps).collect::<Vec<f64>>()
        });
        let measured = (coefficients.chain(std::iter::once(input.values.to_vec())))
            .chain(rec.record.channels.iter().map(|c| c.samples.clone()));
        let mut all = spectra(measured.map(Vec::into_iter), n, 1.0 / (n as f64).sqrt())
            .into_iter()
            .map(cut);
        let transforms: [Vec<Complex64>; 4] =
            std::array::from_fn(|_| all.next().unwrap_or_default());
        let drive = all.next()?;
        let points = line_points(n);
        Some(Self {
            stencil: (points[lines.clone()].iter())
                .map(|z| problem.hold.interior_transforms(*z))
                .collect(),
            points,
            outputs: all.collect(),
            drive,
            hold: (0..lines.len())
                .map(|k| std::array::from_fn(|j| transforms[j][k]))
                .collect(),
        })
    }

    /// The record's spectra at the plant `sim` discretises (its outputs `maps`, the
    /// record's `input`): each channel's residual from rest y − f(θ), f's state from
    /// the closed form with its last state simulated; the free responses when the
    /// initial `state` is estimated; the transfer. One resolvent per line serves all
    /// three. `groups` is left for the caller.
    fn model_lines(
        &self,
        sim: &ExactSimulator<2>,
        maps: &[OutputMap],
        input: SampledInput<'_>,
        state: bool,
    ) -> Option<RecordSpectra> {
        let n = input.values.len();
        let mut last = SVector::<f64, 2>::zeros();
        (sim.simulate_with(&SVector::zeros(), &input, |i, s| {
            if i + 1 == n {
                last = *s;
            }
        }))
        .ok()?;
        last /= (n as f64).sqrt();
        let first = likelihood_lines(n).start;
        let rows = if state {
            free_rows(sim, maps, n)
        } else {
            Vec::new()
        };
        let lines = self.hold.len();
        let empty = || vec![Vec::with_capacity(lines); maps.len()];
        let (mut basis, mut gains) = ([empty(), empty()], empty());
        let mut residual: Vec<Vec<Complex64>> = self.outputs.clone();
        for (j, hold) in self.hold.iter().enumerate() {
            let line = sim.resolvent(self.points[first + j])?;
            let x = line.state_spectrum(&SVector::zeros(), &last, hold)?;
            for (r, map) in residual.iter_mut().zip(maps) {
                r[j] -= x[0] * map.c[0] + x[1] * map.c[1] + self.drive[j] * map.d;
            }
            let g = line.held_response(&self.stencil[j])?;
            for (t, map) in gains.iter_mut().zip(maps) {
                t.push(map.c[0] * g[0] + map.c[1] * g[1] + map.d);
            }
            if state {
                let columns = free_columns(&line)?;
                for (ch, row) in rows.iter().enumerate() {
                    for (b, x) in basis.iter_mut().zip(&columns) {
                        b[ch].push(row[0] * x[0] + row[1] * x[1]);
                    }
                }
            }
        }
        Some(RecordSpectra {
            groups: Vec::new(),
            residual,
            basis: if state {
                basis
            } else {
                [Vec::new(), Vec::new()]
            },
            transfer: gains,
        })
    }
}

/// ε at ln θ = `x`: every record's lines whitened by S_k(θ), √2·Re then √2·Im of each
/// channel's line, each record's initial state concentrated out; with each record's
/// initial state and spectra.
struct Evaluation {
    e: DVector<f64>,
    states: Vec<[f64; 2]>,
    spectra: Vec<RecordSpectra>,
}

fn whitened(problem: &Joint<'_>, x: &[f64], variances: &Variances) -> Option<Evaluation> {
    let mut out = Vec::new();
    let mut states = Vec::new();
    let spectra = spectra_at(problem, x, variances)?;
    for record in &spectra {
        let whitening = Whitening::of(record, variances);
        let metric = |k: usize, v: &mut [Complex64]| whitening.apply(k, v);
        let residual = columns(&record.residual, metric);
        let (e, state) = if problem.state {
            let basis = record.basis.each_ref().map(|b| columns(b, metric));
            concentrate(residual, &basis)
        } else {
            (residual, [0.0; 2])
        };
        let root2 = std::f64::consts::SQRT_2;
        out.extend(e.iter().flat_map(|v| [root2 * v.re, root2 * v.im]));
        states.push(state);
    }
    (out.iter().all(|v| v.is_finite())).then(|| Evaluation {
        e: DVector::from_vec(out),
        states,
        spectra,
    })
}

/// ∂ε/∂ln θ by forward differences from ε at `x` (`at`): one evaluation per parameter.
fn jacobian(
    problem: &Joint<'_>,
    x: &[f64],
    at: &DVector<f64>,
    variances: &Variances,
) -> Option<DMatrix<f64>> {
    let mut columns = Vec::with_capacity(x.len());
    for p in 0..x.len() {
        let mut shifted = x.to_vec();
        shifted[p] = x[p] + STEP;
        let up = whitened(problem, &shifted, variances)?.e;
        columns.push((up - at) / STEP);
    }
    Some(DMatrix::from_columns(&columns))
}

/// A record at θ̂ for the information: its spectra and ∂R/∂ln θ at its initial state.
struct Sensitivities {
    at: RecordSpectra,
    derivatives: Vec<Vec<Vec<Complex64>>>,
}

/// Each record's spectra at ln θ = `x` (those of the evaluation `at`) and the
/// derivatives of its residual R = y − f(θ) − B(θ)·x₀ at its initial state: the
/// transforms of the sensitivity system's output derivatives, exact (the closed-form
/// lines are the simulated record's DFT).
fn sensitivities(problem: &Joint<'_>, x: &[f64], at: Evaluation) -> Option<Vec<Sensitivities>> {
    let theta = problem.theta(x);
    (problem.records.iter().zip(at.spectra).zip(&at.states))
        .map(|((rec, at), state)| {
            let series = problem.output_sensitivities(rec, theta, *state).ok()?;
            let (n, lines) = (rec.len, likelihood_lines(rec.len));
            // ∂R = −∂y, transformed as the residual is.
            let scale = -1.0 / (n as f64).sqrt();
            let derivatives = (series.iter())
                .map(|channels| {
                    let all = spectra(channels.iter().map(|c| c.iter().copied()), n, scale);
                    all.into_iter().map(|s| s[lines.clone()].to_vec()).collect()
                })
                .collect();
            Some(Sensitivities { at, derivatives })
        })
        .collect()
}

/// F = Σ_k 2·Re(∂R_kᴴ·S_k⁻¹·∂R_k) under `variances`, each record's initial state
/// concentrated out (the Schur complement of its block); with each record's whitened
/// sensitivities so concentrated (per parameter, line-major channel values).
fn information(
    records: &[Sensitivities],
    variances: &Variances,
) -> (DMatrix<f64>, Vec<Vec<Vec<Complex64>>>) {
    let p = records.first().map_or(0, |r| r.derivatives.len());
    let mut f = DMatrix::<f64>::zeros(p, p);
    let mut concentrated = Vec::with_capacity(records.len());
    for record in records {
        let whitening = Whitening::of(&record.at, variances);
        let metric = |k: usize, v: &mut [Complex64]| whitening.apply(k, v);
        let mut all: Vec<Vec<Complex64>> = (record.derivatives.iter())
            .map(|d| columns(d, metric))
            .collect();
        if !record.at.basis[0].is_empty() {
            all.extend(record.at.basis.iter().map(|b| columns(b, metric)));
        }
        let q = all.len();
        let gram = DMatrix::from_fn(q, q, |a, b| {
            2.0 * all[a]
                .iter()
                .zip(&all[b])
                .map(|(x, y)| (x.conj() * y).re)
                .sum::<f64>()
        });
        let block = gram.view((0, 0), (p, p)).into_owned();
        let state = (q > p).then(|| gram.view((p, p), (2, 2)).into_owned().try_inverse());
        if let Some(Some(inverse)) = state {
            let cross = gram.view((0, p), (p, 2)).into_owned();
            // ∂R̃ = ∂R − B·β, β = (BᴴS⁻¹B)⁻¹·BᴴS⁻¹·∂R, per parameter.
            let beta = &inverse * cross.transpose();
            let (b0, b1) = (all[p].clone(), all[p + 1].clone());
            for c in 0..p {
                for ((v, x), y) in all[c].iter_mut().zip(&b0).zip(&b1) {
                    *v -= x * beta[(0, c)] + y * beta[(1, c)];
                }
            }
            f += block - &cross * inverse * cross.transpose();
        } else {
            f += block;
        }
        all.truncate(p);
        concentrated.push(all);
    }
    (f, concentrated)
}

/// The weights w_p(t) of the estimating equations s_p = Σ_k 2·Re(q_kᴴ·R_k),
/// q_k = S_k⁻¹·∂R̃_k (the whitened concentrated sensitivities `columns` whitened once
/// more, by the adjoint), as functions of the residual's samples:
/// w_p(t) = (2/√N)·Re Σ_k q_k·e^(2πikt/N), one inverse FFT per channel.
fn score_weights(
    problem: &Joint<'_>,
    records: &[Sensitivities],
    columns: &[Vec<Vec<Complex64>>],
    variances: &Variances,
) -> DMatrix<f64> {
    let p = columns.first().map_or(0, Vec::len);
    let mut w = DMatrix::<f64>::zeros(problem.rows, p);
    for ((rec, record), columns) in problem.records.iter().zip(records).zip(columns) {
        let (n, c) = (rec.len, rec.maps.len());
        let first = likelihood_lines(n).start;
        let inverse = crate::fft::inverse(n);
        let whitening = Whitening::of(&record.at, variances);
        for (col, values) in columns.iter().enumerate() {
            let mut per_channel = vec![vec![Complex64::new(0.0, 0.0); n]; c];
            let mut z = vec![Complex64::new(0.0, 0.0); c];
            for (j, line) in values.chunks(c).enumerate() {
                z.copy_from_slice(line);
                whitening.adjoint(j, &mut z);
                for (buffer, v) in per_channel.iter_mut().zip(&z) {
                    buffer[first + j] = *v;
                }
            }
            let scale = 2.0 / (n as f64).sqrt();
            for (ch, mut buffer) in per_channel.into_iter().enumerate() {
                inverse.process(&mut buffer);
                for (t, v) in buffer.iter().enumerate() {
                    w[(rec.start + ch * n + t, col)] = scale * v.re;
                }
            }
        }
    }
    w
}

/// A per-channel spectrum whitened line by line, flattened line-major.
fn columns(spectra: &[Vec<Complex64>], metric: impl Fn(usize, &mut [Complex64])) -> Vec<Complex64> {
    let lines = spectra.first().map_or(0, Vec::len);
    let mut out = Vec::with_capacity(lines * spectra.len());
    let mut z = vec![Complex64::new(0.0, 0.0); spectra.len()];
    for k in 0..lines {
        for (z, s) in z.iter_mut().zip(spectra) {
            *z = s[k];
        }
        metric(k, &mut z);
        out.extend_from_slice(&z);
    }
    out
}

/// S_k^(−1/2) at each line of one record, factored once per θ: S_k = D + σ²_u·g·gᴴ
/// whitens as (I − α·v·vᴴ)·D^(−1/2)·z, v = h/‖h‖ for h = D^(−1/2)·g,
/// α = 1 − 1/√(1 + σ²_u·‖h‖²) (then (I − α·v·vᴴ)² = (I + σ²_u·h·hᴴ)⁻¹).
struct Whitening {
    /// Each channel's 1/√σ²_a.
    inverse_roots: Vec<f64>,
    /// h at each line, line-major.
    h: Vec<Complex64>,
    /// α/‖h‖² at each line (0 where the drive's noise is nil there).
    shrink: Vec<f64>,
}

impl Whitening {
    fn of(record: &RecordSpectra, variances: &Variances) -> Self {
        let inverse_roots: Vec<f64> = (record.groups.iter())
            .map(|&g| 1.0 / variances.sensors[g].sqrt())
            .collect();
        let lines = record.transfer.first().map_or(0, Vec::len);
        let mut h = Vec::with_capacity(lines * inverse_roots.len());
        let mut shrink = Vec::with_capacity(lines);
        for k in 0..lines {
            let start = h.len();
            h.extend((record.transfer.iter().zip(&inverse_roots)).map(|(g, r)| g[k] * r));
            let norm2: f64 = h[start..].iter().map(|v| v.norm_sqr()).sum();
            let s = variances.input * norm2;
            shrink.push(if norm2 > 0.0 && s > 0.0 {
                (1.0 - 1.0 / (1.0 + s).sqrt()) / norm2
            } else {
                0.0
            });
        }
        Self {
            inverse_roots,
            h,
            shrink,
        }
    }

    /// S_k^(−1/2)·z for the channels' values `z` at line k.
    fn apply(&self, k: usize, z: &mut [Complex64]) {
        for (z, r) in z.iter_mut().zip(&self.inverse_roots) {
            *z *= r;
        }
        self.shrink_at(k, z);
    }

    /// The adjoint of [`apply`](Self::apply): D^(−1/2)·(I − α·v·vᴴ)·z, so that
    /// whitening then this gives S_k⁻¹.
    fn adjoint(&self, k: usize, z: &mut [Complex64]) {
        self.shrink_at(k, z);
        for (z, r) in z.iter_mut().zip(&self.inverse_roots) {
            *z *= r;
        }
    }

    /// z ← (I − α·v·vᴴ)·z at line k.
    fn shrink_at(&self, k: usize, z: &mut [Complex64]) {
        let c = self.inverse_roots.len();
        let h = &self.h[k * c..(k + 1) * c];
        let dot: Complex64 = h.iter().zip(z.iter()).map(|(h, z)| h.conj() * z).sum();
        let coefficient = self.shrink[k] * dot;
        for (z, h) in z.iter_mut().zip(h) {
            *z -= h * coefficient;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The whitening is S^(−1/2): ‖S^(−1/2)·z‖² = zᴴ·S⁻¹·z, by Sherman–Morrison
    /// zᴴD⁻¹z − σ²_u·|gᴴD⁻¹z|² / (1 + σ²_u·gᴴD⁻¹g).
    #[test]
    fn the_whitening_squares_to_the_inverse_spectrum() {
        let g = [Complex64::new(0.3, -1.2), Complex64::new(2.0, 0.5)];
        let z0 = [Complex64::new(1.0, 0.4), Complex64::new(-0.7, 2.2)];
        let (d, input) = ([0.5, 2.0], 0.8);
        let record = RecordSpectra {
            groups: vec![0, 1],
            residual: Vec::new(),
            basis: [Vec::new(), Vec::new()],
            transfer: vec![vec![g[0]], vec![g[1]]],
        };
        let variances = Variances {
            input,
            sensors: d.to_vec(),
            measured: Vec::new(),
        };
        let mut z = z0;
        let whitening = Whitening::of(&record, &variances);
        whitening.apply(0, &mut z);
        let whitened: f64 = z.iter().map(|v| v.norm_sqr()).sum();
        let plain: f64 = (0..2).map(|a| z0[a].norm_sqr() / d[a]).sum();
        let dot: Complex64 = (0..2).map(|a| g[a].conj() * z0[a] / d[a]).sum();
        let gdg: f64 = (0..2).map(|a| g[a].norm_sqr() / d[a]).sum();
        let expected = plain - input * dot.norm_sqr() / (1.0 + input * gdg);
        assert!(
            (whitened - expected).abs() < 1e-12 * expected,
            "{whitened} {expected}"
        );
        // The adjoint after the whitening is S⁻¹: z₀ᴴ·S⁻¹·z₀ again.
        whitening.adjoint(0, &mut z);
        let quadratic: Complex64 = z0.iter().zip(&z).map(|(a, b)| a.conj() * b).sum();
        assert!(
            (quadratic.re - expected).abs() < 1e-12 * expected,
            "{quadratic}"
        );
        assert!(quadratic.im.abs() < 1e-12 * expected, "{quadratic}");
    }
}
