//! The joint weighted least-squares problem in the plant's log-parameters, each record's
//! initial state and channel offsets eliminated (variable projection).
//!
//! ## The method
//! Per record ŷ = f(θ) + G(θ)·β: f the response from rest, G's columns C·Φⁱ (the
//! responses to a unit initial displacement and velocity) and one indicator per channel
//! (its offset). For each θ the best β solves a small weighted linear least-squares
//! problem, so the optimiser sees only θ (2 or 3 numbers) and r(θ) = W·(y − f − G·β̂),
//! W = diag(1/σ_channel). The Jacobian is Kaufman's: the exact sensitivities at β̂ with
//! the span of W·G projected out, P⊥·W·∂ŷ/∂θ. At the optimum its Gram matrix is the
//! Schur complement of the full Gauss–Newton matrix in (θ, β), so its inverse is the
//! full covariance of θ: the nuisance parameters are accounted for exactly.

use super::linear::LinearSolve;
use super::model::{OutputKind, OutputMap};
use super::setup::{Record, RecordsOptions};
use crate::error::Result;
use crate::plant::Drive;
use crate::plant::Plant;
use msd_ode::{Hold, SVector, SampledInput};
use msd_opt::LeastSquaresProblem;
use nalgebra::DMatrix;

/// One record's rows: channel-major, row = start + channel·len + sample.
pub(crate) struct RecordRows<'a> {
    pub record: &'a Record,
    pub kinds: Vec<OutputKind>,
    pub maps: Vec<OutputMap>,
    /// Index of each channel's noise group (channels of one name share σ).
    pub groups: Vec<usize>,
    /// 1/σ of each channel.
    pub weights: Vec<f64>,
    pub start: usize,
    pub len: usize,
    /// The factorised Gram matrix of W·G, when there is a β.
    pub linear: Option<LinearSolve>,
    /// β̂: the initial state (when estimated), then the offsets (when estimated).
    pub beta: Vec<f64>,
}

/// The problem over a set of records sharing one plant.
pub(crate) struct Joint<'a> {
    pub records: Vec<RecordRows<'a>>,
    pub drive: Drive,
    pub group_names: Vec<String>,
    pub hold: Hold,
    pub dt: f64,
    fixed: [Option<f64>; 3],
    pub free: Vec<usize>,
    pub state: bool,
    pub offset: bool,
    pub rows: usize,
    pub basis: Vec<[f64; 2]>,
    pub forced: Vec<f64>,
    zeros: Vec<f64>,
    pub evaluations: usize,
}

impl<'a> Joint<'a> {
    /// The problem on checked `records`, with m, c, k fixed as `fixed` says, every
    /// weight 1.
    pub(crate) fn new(
        records: &[&'a Record],
        kinds: &[Vec<OutputKind>],
        options: &RecordsOptions,
        fixed: [Option<f64>; 3],
    ) -> Self {
        let mut group_names: Vec<String> = Vec::new();
        let mut start = 0;
        let mut rows = Vec::with_capacity(records.len());
        for (record, kinds) in records.iter().zip(kinds) {
            let groups = record
                .channels
                .iter()
                .map(|c| match group_names.iter().position(|g| *g == c.name) {
                    Some(g) => g,
                    None => {
                        group_names.push(c.name.clone());
                        group_names.len() - 1
                    }
                })
                .collect();
            let (len, channels) = (record.excitation.len(), record.channels.len());
            rows.push(RecordRows {
                record,
                kinds: kinds.clone(),
                maps: vec![OutputMap::default(); channels],
                groups,
                weights: vec![1.0; channels],
                start,
                len,
                linear: None,
                beta: Vec::new(),
            });
            start += len * channels;
        }
        let longest = records.iter().map(|r| r.excitation.len()).max();
        Self {
            records: rows,
            drive: options.drive,
            group_names,
            hold: options.hold,
            dt: records.first().map_or(1.0, |r| r.excitation.dt()),
            free: (0..3).filter(|&p| fixed[p].is_none()).collect(),
            fixed,
            state: options.estimate_initial_state,
            offset: options.estimate_offset,
            rows: start,
            basis: vec![[0.0; 2]; start],
            forced: vec![0.0; start],
            zeros: vec![0.0; longest.unwrap_or(0)],
            evaluations: 0,
        }
    }

    /// Sets each channel's weight to 1/σ of its group.
    pub(crate) fn set_sigmas(&mut self, sigma: impl Fn(&str) -> f64) {
        let sigmas: Vec<f64> = self.group_names.iter().map(|g| sigma(g)).collect();
        for rec in &mut self.records {
            for (w, &g) in rec.weights.iter_mut().zip(&rec.groups) {
                debug_assert!(sigmas[g] > 0.0);
                *w = 1.0 / sigmas[g];
            }
        }
    }

    /// Number of linear parameters per record.
    pub(crate) fn linear_count(&self, channels: usize) -> usize {
        2 * usize::from(self.state) + channels * usize::from(self.offset)
    }

    /// θ from the optimiser's vector (logarithms of the free parameters).
    pub(crate) fn theta(&self, x: &[f64]) -> [f64; 3] {
        let mut j = 0;
        std::array::from_fn(|p| {
            self.fixed[p].unwrap_or_else(|| {
                j += 1;
                x[j - 1].exp()
            })
        })
    }

    /// The optimiser's vector of θ.
    pub(crate) fn pack(&self, theta: [f64; 3]) -> Vec<f64> {
        self.free.iter().map(|&p| theta[p].ln()).collect()
    }

    /// The response from rest f and the free-response basis C·Φⁱ at θ, and each
    /// record's Gram matrix; false if θ cannot be simulated or a Gram matrix is singular.
    pub(crate) fn prepare(&mut self, theta: [f64; 3]) -> bool {
        let plant = Plant {
            theta,
            drive: self.drive,
        };
        let Ok(sim) = plant.response(self.dt, self.hold) else {
            return false;
        };
        let phi = sim.transition();
        let phi = [[phi[(0, 0)], phi[(0, 1)]], [phi[(1, 0)], phi[(1, 1)]]];
        let mut records = std::mem::take(&mut self.records);
        let mut ok = true;
        for rec in &mut records {
            for (map, &kind) in rec.maps.iter_mut().zip(&rec.kinds) {
                *map = plant.output(kind);
            }
            let input = input(self.drive, &self.zeros, rec);
            let (forced, basis) = (&mut self.forced, &mut self.basis);
            let mut power = [[1.0, 0.0], [0.0, 1.0]];
            let run = sim.simulate_with(&SVector::zeros(), &input, |i, s| {
                if i > 0 {
                    power = product(power, phi);
                }
                let s = [s[0], s[1]];
                for (ch, map) in rec.maps.iter().enumerate() {
                    let row = rec.start + ch * rec.len + i;
                    forced[row] = map.value(s, input.values[i]);
                    basis[row] = [
                        map.c[0] * power[0][0] + map.c[1] * power[1][0],
                        map.c[0] * power[0][1] + map.c[1] * power[1][1],
                    ];
                }
            });
            ok = ok && run.is_ok();
            rec.linear = None;
            if ok && self.linear_count(rec.maps.len()) > 0 {
                rec.linear = LinearSolve::new(self.gram(rec));
                ok = rec.linear.is_some();
            }
        }
        self.records = records;
        ok
    }

    /// The record's drive as the simulator takes it (zeros for a free decay).
    pub(crate) fn drive_input<'b>(&'b self, rec: &RecordRows<'b>) -> SampledInput<'b> {
        input(self.drive, &self.zeros, rec)
    }

    /// The model of one row (unweighted): f + G·β.
    pub(crate) fn model(&self, rec: &RecordRows<'_>, ch: usize, i: usize) -> f64 {
        let row = rec.start + ch * rec.len + i;
        let (state, offset) = self.fitted(&rec.beta, ch);
        let g = self.basis[row];
        self.forced[row] + g[0] * state[0] + g[1] * state[1] + offset
    }

    /// The initial state β̂ gives (at rest when it is not estimated).
    pub(crate) fn initial_state(&self, rec: &RecordRows<'_>) -> [f64; 2] {
        if self.state {
            [rec.beta[0], rec.beta[1]]
        } else {
            [0.0; 2]
        }
    }

    /// The offsets β̂ gives (zeros when they are not estimated).
    pub(crate) fn offsets(&self, rec: &RecordRows<'_>) -> Vec<f64> {
        let first = 2 * usize::from(self.state);
        (0..rec.maps.len())
            .map(|ch| {
                if self.offset {
                    rec.beta[first + ch]
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// W·(y − ŷ) into `out`.
    fn fill_residuals(&self, out: &mut [f64]) {
        for rec in &self.records {
            for (ch, channel) in rec.record.channels.iter().enumerate() {
                let w = rec.weights[ch];
                let (state, offset) = self.fitted(&rec.beta, ch);
                let rows = Self::rows_of(rec, ch);
                let model = self.forced[rows.clone()]
                    .iter()
                    .zip(&self.basis[rows.clone()]);
                for ((r, y), (f, g)) in out[rows].iter_mut().zip(&channel.samples).zip(model) {
                    *r = w * (y - f - g[0] * state[0] - g[1] * state[1] - offset);
                }
            }
        }
    }

    /// Kaufman's Jacobian of the residuals in the log-parameters (see the module doc),
    /// at θ and each record's β (after [`prepare`](Self::prepare) at θ).
    pub(crate) fn fill_jacobian(&self, theta: [f64; 3], out: &mut DMatrix<f64>) -> Result<()> {
        debug_assert_eq!(out.shape(), (self.rows, self.free.len()));
        let plant = Plant {
            theta,
            drive: self.drive,
        };
        let sim = plant.sensitivities(self.dt, self.hold)?;
        let m = self.rows;
        for rec in &self.records {
            let mut z0 = SVector::<f64, 8>::zeros();
            [z0[0], z0[1]] = self.initial_state(rec);
            let input = input(self.drive, &self.zeros, rec);
            let coefficients = self.jacobian_coefficients(&rec.maps, theta, &rec.weights);
            let cols = out.as_mut_slice();
            sim.simulate_with(&z0, &input, |i, z| {
                let u = input.values[i];
                for (ch, by_column) in coefficients.iter().enumerate() {
                    let row = rec.start + ch * rec.len + i;
                    for (col, k) in by_column.iter().enumerate() {
                        let dot: f64 = (0..8).map(|j| k[j] * z[j]).sum();
                        cols[col * m + row] = dot + k[8] * u;
                    }
                }
            })?;
            for col in 0..self.free.len() {
                self.project(rec, &mut out.as_mut_slice()[col * m..(col + 1) * m]);
            }
        }
        Ok(())
    }

    /// Each free parameter's ∂y/∂ln θ_p of the model of `rec` (unweighted, one series
    /// per channel) at θ from the initial state `state`, by the sensitivity system:
    /// exact, where differences of two responses carry their step's error.
    pub(crate) fn output_sensitivities(
        &self,
        rec: &RecordRows<'_>,
        theta: [f64; 3],
        state: [f64; 2],
    ) -> Result<Vec<Vec<Vec<f64>>>> {
        let plant = Plant {
            theta,
            drive: self.drive,
        };
        let sim = plant.sensitivities(self.dt, self.hold)?;
        let mut z0 = SVector::<f64, 8>::zeros();
        [z0[0], z0[1]] = state;
        let input = input(self.drive, &self.zeros, rec);
        // The outputs at θ (the prepared ones may be another θ's); weight −1: the
        // coefficients give θ_p·∂y/∂θ_p itself.
        let maps: Vec<OutputMap> = rec.kinds.iter().map(|k| plant.output(*k)).collect();
        let coefficients = self.jacobian_coefficients(&maps, theta, &vec![-1.0; maps.len()]);
        let mut out = vec![vec![vec![0.0; rec.len]; rec.maps.len()]; self.free.len()];
        sim.simulate_with(&z0, &input, |i, z| {
            let u = input.values[i];
            for (ch, by_column) in coefficients.iter().enumerate() {
                for (col, k) in by_column.iter().enumerate() {
                    let dot: f64 = (0..8).map(|j| k[j] * z[j]).sum();
                    out[col][ch][i] = dot + k[8] * u;
                }
            }
        })?;
        Ok(out)
    }

    /// Per channel (its output `maps`, weighted by `weights`) and free parameter p, the
    /// row k with −w·θ_p·∂y/∂θ_p = k·(z, u), z the 8 states of the sensitivity system:
    /// ∂y/∂θ_p = C·s_p + C_p·s + D_p·u.
    fn jacobian_coefficients(
        &self,
        maps: &[OutputMap],
        theta: [f64; 3],
        weights: &[f64],
    ) -> Vec<Vec<[f64; 9]>> {
        maps.iter()
            .zip(weights)
            .map(|(map, &w)| {
                self.free
                    .iter()
                    .map(|&p| {
                        let scale = -w * theta[p];
                        let mut k = [0.0; 9];
                        k[0] = scale * map.dc[p][0];
                        k[1] = scale * map.dc[p][1];
                        k[2 + 2 * p] = scale * map.c[0];
                        k[3 + 2 * p] = scale * map.c[1];
                        k[8] = scale * map.dd[p];
                        k
                    })
                    .collect()
            })
            .collect()
    }

    /// Each channel of the first record with the correlation of its (projected) data
    /// with the response from rest of the prepared plant: near −1 for a sensor whose
    /// sign is reversed (after [`prepare`](Self::prepare)).
    pub(crate) fn channel_correlations(&self) -> Vec<(&str, f64)> {
        let (y, f) = self.projected_data_and_response();
        let rec = &self.records[0];
        rec.record
            .channels
            .iter()
            .enumerate()
            .map(|(ch, channel)| {
                let rows = rec.start + ch * rec.len..rec.start + (ch + 1) * rec.len;
                let (y, f) = (&y[rows.clone()], &f[rows]);
                let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
                let r = dot(y, f) / (dot(y, y) * dot(f, f)).sqrt();
                (channel.name.as_str(), r)
            })
            .collect()
    }

    /// The projected weighted data and response from rest, P⊥·W·y and P⊥·W·f, for the
    /// gain of the initial guess (after [`prepare`](Self::prepare)).
    pub(crate) fn projected_data_and_response(&self) -> (Vec<f64>, Vec<f64>) {
        let (mut y, mut f) = (vec![0.0; self.rows], vec![0.0; self.rows]);
        for rec in &self.records {
            for (ch, channel) in rec.record.channels.iter().enumerate() {
                for (i, v) in channel.samples.iter().enumerate() {
                    let row = rec.start + ch * rec.len + i;
                    y[row] = rec.weights[ch] * v;
                    f[row] = rec.weights[ch] * self.forced[row];
                }
            }
            self.project(rec, &mut y);
            self.project(rec, &mut f);
        }
        (y, f)
    }
}

impl LeastSquaresProblem for Joint<'_> {
    fn residual_count(&self) -> usize {
        self.rows
    }

    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> bool {
        let theta = self.theta(x);
        if !theta.iter().all(|v| v.is_finite() && *v > 0.0) {
            return false;
        }
        self.evaluations += 1;
        if !self.prepare(theta) {
            return false;
        }
        self.solve_linear();
        self.fill_residuals(out);
        out.iter().all(|r| r.is_finite())
    }

    fn jacobian(&mut self, x: &[f64], out: &mut DMatrix<f64>) -> bool {
        let theta = self.theta(x);
        // Levenberg–Marquardt checks the entries' finiteness itself.
        self.fill_jacobian(theta, out).is_ok()
    }
}

/// The record's drive as the simulator's input (zeros for a free decay).
fn input<'b>(drive: Drive, zeros: &'b [f64], rec: &RecordRows<'b>) -> SampledInput<'b> {
    match drive {
        Drive::None => SampledInput::smooth(&zeros[..rec.len]),
        _ => SampledInput {
            values: rec.record.excitation.samples(),
            breakpoints: rec.record.excitation.breakpoints(),
        },
    }
}

/// Φⁱ·Φ.
#[inline(always)]
fn product(a: [[f64; 2]; 2], b: [[f64; 2]; 2]) -> [[f64; 2]; 2] {
    [
        [
            a[0][0] * b[0][0] + a[0][1] * b[1][0],
            a[0][0] * b[0][1] + a[0][1] * b[1][1],
        ],
        [
            a[1][0] * b[0][0] + a[1][1] * b[1][0],
            a[1][0] * b[0][1] + a[1][1] * b[1][1],
        ],
    ]
}
