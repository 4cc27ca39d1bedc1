//! The design's cost and its exact gradient: the criterion of the relative Fisher
//! information over the plants, plus twice the log of a smooth peak ratio, so that it
//! does not change when the amplitudes are scaled (the information grows as the square
//! of the force, the peaks as the force).
//!
//! ## The smooth peak
//! r = (Σᵢ |eᵢ|^p)^{1/p} over the force samples over the peak force, the displacement
//! samples of the prior plant (or of every plant) over the stroke, and the RMS force
//! over its limit: an upper
//! bound of the largest ratio, within the factor (count)^{1/p} of it. The design is
//! scaled by the exact largest ratio at the end, so the limits hold on the samples.

use super::basis::{Layout, PlantBasis, Transform, add_free, project_free};
use super::{Aggregate, Criterion};
use nalgebra::Matrix3;
use rustfft::num_complex::Complex64;

/// The limits the smooth peak divides by.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Limits {
    pub force: f64,
    pub stroke: f64,
    pub rms_force: Option<f64>,
    pub min_step: f64,
    /// The stroke is limited on the first `stroke_plants` plants (1: the prior).
    pub stroke_plants: usize,
}

/// The cost of a design: what to evaluate it on and its buffers.
pub(crate) struct Objective<'a> {
    pub layout: &'a Layout,
    pub plants: &'a [PlantBasis],
    pub limits: Limits,
    pub criterion: Criterion,
    pub aggregate: Aggregate,
    /// The exponent p of the smooth maxima.
    pub sharpness: f64,
    /// Per plant: the unit of each relative standard error (1 for the prior's values).
    pub units: Vec<[f64; 3]>,
    transform: Transform,
    force: Vec<f64>,
    /// The displacement of each plant the stroke is limited on, the prior first.
    strokes: Vec<Vec<f64>>,
    /// Per plant: m·x_m, c·x_c, k·x_k.
    sens: Vec<[Vec<f64>; 3]>,
    adjoint: [Vec<f64>; 3],
    p: Vec<Complex64>,
    q: Vec<Complex64>,
    /// Per plant: log v and dΦ/dFIM.
    parts: Vec<(f64, Matrix3<f64>)>,
}

/// The exponent of the soft maximum of the penalty on a step below its minimum.
const STEP_PENALTY: f64 = 50.0;

impl<'a> Objective<'a> {
    pub fn new(
        layout: &'a Layout,
        plants: &'a [PlantBasis],
        limits: Limits,
        criterion: Criterion,
        aggregate: Aggregate,
    ) -> Self {
        let n = layout.kept.len();
        Self {
            layout,
            plants,
            limits,
            criterion,
            aggregate,
            sharpness: 8.0,
            units: vec![[1.0; 3]; plants.len()],
            transform: Transform::new(layout.period),
            force: vec![0.0; n],
            strokes: vec![vec![0.0; n]; limits.stroke_plants.clamp(1, plants.len())],
            sens: plants
                .iter()
                .map(|_| std::array::from_fn(|_| vec![0.0; n]))
                .collect(),
            adjoint: std::array::from_fn(|_| vec![0.0; n]),
            p: vec![Complex64::default(); layout.lines.len()],
            q: vec![Complex64::default(); layout.lines.len()],
            parts: Vec::with_capacity(plants.len()),
        }
    }

    /// The force and the prior plant's displacement of `w` (and the displacements of
    /// the other plants the stroke is limited on).
    pub fn signals(&mut self, w: &[f64]) -> (&[f64], &[f64]) {
        let (layout, basis) = (self.layout, &self.plants[0]);
        let transform = &mut self.transform;
        let (force, strokes) = (&mut self.force, &mut self.strokes);
        force.fill(0.0);
        strokes.iter_mut().for_each(|x| x.fill(0.0));
        for (s, &(a, b)) in layout.segments.iter().enumerate() {
            let pair = |l: usize| {
                let amplitude = layout.amplitude(w, s, l);
                [amplitude, basis.line_outputs[l][0] * amplitude]
            };
            transform.add_lines(layout, pair, (a, b), force, Some(&mut strokes[0]));
            for (p, (basis, x)) in self.plants.iter().zip(strokes.iter_mut()).enumerate() {
                if p > 0 {
                    let one = |l: usize| {
                        let x = basis.line_outputs[l][0] * layout.amplitude(w, s, l);
                        [x, Complex64::default()]
                    };
                    transform.add_lines(layout, one, (a, b), x, None);
                }
                free_edges(layout, basis, w, s, &[0], std::slice::from_mut(x));
            }
        }
        if let Some(n_s) = layout.step {
            let d = layout.step_amplitude(w);
            let from = layout.kept_within(n_s, layout.samples).start;
            force[from..].iter_mut().for_each(|u| *u += d);
            for (basis, x) in self.plants.iter().zip(strokes.iter_mut()) {
                step((layout, basis), d, n_s, &[0], std::slice::from_mut(x));
            }
        }
        (&self.force, &self.strokes[0])
    }

    /// The relative Fisher information (up to 1/σ²) of `w` on plant `p`.
    pub fn information(&mut self, w: &[f64], p: usize) -> Matrix3<f64> {
        let (layout, basis) = (self.layout, &self.plants[p]);
        let outs = &mut self.sens[p];
        outs.iter_mut().for_each(|o| o.fill(0.0));
        for (s, &window) in layout.segments.iter().enumerate() {
            let t = |o: usize, l: usize| basis.line_outputs[l][o] * layout.amplitude(w, s, l);
            let [first, second, third] = outs;
            self.transform
                .add_lines(layout, |l| [t(1, l), t(2, l)], window, first, Some(second));
            self.transform.add_lines(
                layout,
                |l| [t(3, l), Complex64::default()],
                window,
                third,
                None,
            );
            free_edges(layout, basis, w, s, &SENSITIVITIES, outs);
        }
        if let Some(n_s) = layout.step {
            let d = layout.step_amplitude(w);
            step((layout, basis), d, n_s, &SENSITIVITIES, outs);
        }
        gram(&self.sens[p], &layout.weights)
    }

    /// The cost at `w` and its gradient into `grad`.
    pub fn evaluate(&mut self, w: &[f64], grad: &mut [f64]) -> f64 {
        grad.fill(0.0);
        self.parts.clear();
        for p in 0..self.plants.len() {
            let d = Matrix3::from_diagonal(&self.units[p].into());
            let fim = d * self.information(w, p) * d;
            let (value, g) = criterion(self.criterion, &fim, self.sharpness);
            self.parts.push((value, d * g * d));
        }
        let (value, weights) = aggregate(self.aggregate, &self.parts, self.sharpness);
        for (p, weight) in weights.iter().enumerate() {
            let g = 2.0 * weight * self.parts[p].1;
            let sens = &self.sens[p];
            for n in 0..self.layout.kept.len() {
                let j = [sens[0][n], sens[1][n], sens[2][n]];
                for (o, adjoint) in self.adjoint.iter_mut().enumerate() {
                    adjoint[n] = (0..3).map(|c| g[(o, c)] * j[c]).sum();
                }
            }
            self.sensitivity_adjoint(w, p, grad);
        }
        value + self.peak_term(w, grad)
    }

    /// 2·log r (and the step's penalty), its gradient added into `grad`.
    fn peak_term(&mut self, w: &[f64], grad: &mut [f64]) -> f64 {
        let Limits {
            force: f_max,
            stroke: x_max,
            rms_force,
            min_step,
            ..
        } = self.limits;
        let _ = self.signals(w);
        let (n, weights) = (self.layout.samples as f64, &self.layout.weights);
        let rms = (self.force.iter().zip(weights))
            .map(|(u, w)| w * u * u)
            .sum::<f64>()
            / n;
        let rms = rms.sqrt();
        let rho = rms_force.map(|r| rms / r);
        let p = self.sharpness;
        let largest = (self.force.iter().map(|u| u.abs() / f_max))
            .chain(self.strokes.iter().flatten().map(|x| x.abs() / x_max))
            .chain(rho)
            .fold(0.0f64, f64::max);
        if !(largest > 0.0 && largest.is_finite()) {
            return f64::INFINITY;
        }
        let ratio = |e: f64, limit: f64| (e.abs() / limit / largest).powf(p);
        let sum = (self.force.iter().zip(weights))
            .map(|(u, w)| w * ratio(*u, f_max))
            .chain(
                self.strokes
                    .iter()
                    .flat_map(|x| x.iter().zip(weights).map(|(x, w)| w * ratio(*x, x_max))),
            )
            .chain(rho.map(|r| ratio(r, 1.0)))
            .sum::<f64>();
        let r = largest * sum.powf(1.0 / p);
        // dΦ/d log r: 2, plus the step penalty's share.
        let d = self.layout.step_amplitude(w);
        let shortfall = if min_step > 0.0 {
            (min_step * r / d.abs()).ln().max(0.0)
        } else {
            0.0
        };
        let scale = 2.0 + 2.0 * STEP_PENALTY * shortfall;
        if shortfall > 0.0 {
            grad[w.len() - 1] -= 2.0 * STEP_PENALTY * shortfall / d;
        }
        // d log r / d eᵢ = (|eᵢ|/r)^{p−1}·sign(eᵢ)/r.
        let soft = |e: f64| (e.abs() / r).powf(p - 1.0) * e.signum() / r;
        let [force, stroke, _] = &mut self.adjoint;
        for (a, u) in force.iter_mut().zip(&self.force) {
            *a = scale * soft(u / f_max) / f_max;
        }
        if let (Some(rho), Some(limit)) = (rho, rms_force) {
            let d_rho = scale * soft(rho);
            for (a, u) in force.iter_mut().zip(&self.force) {
                *a += d_rho * u / (n * rho * limit * limit);
            }
        }
        for (a, x) in stroke.iter_mut().zip(&self.strokes[0]) {
            *a = scale * soft(x / x_max) / x_max;
        }
        self.signal_adjoint(w, grad);
        for p in 1..self.strokes.len() {
            let [_, _, other] = &mut self.adjoint;
            for (a, x) in other.iter_mut().zip(&self.strokes[p]) {
                *a = scale * soft(x / x_max) / x_max;
            }
            self.stroke_adjoint(w, p, grad);
        }
        2.0 * r.ln() + STEP_PENALTY * shortfall * shortfall
    }
}

/// Σₙ J(n) J(n)ᵀ of the three sensitivity series (each kept sample with its weight).
fn gram(s: &[Vec<f64>; 3], weights: &[f64]) -> Matrix3<f64> {
    let mut g = [0.0; 6];
    for (((a, b), c), w) in s[0].iter().zip(&s[1]).zip(&s[2]).zip(weights) {
        let wa = w * a;
        g[0] += wa * a;
        g[1] += wa * b;
        g[2] += wa * c;
        g[3] += w * b * b;
        g[4] += w * b * c;
        g[5] += w * c * c;
    }
    Matrix3::new(g[0], g[1], g[2], g[1], g[3], g[4], g[2], g[4], g[5])
}

/// log v and dlog v/dFIM for one plant, v in variance units (it scales as 1/force²):
/// D: det(FIM⁻¹)^{1/3}; A: trace(FIM⁻¹)/3; minimax: the soft maximum of diag(FIM⁻¹).
pub(crate) fn criterion(criterion: Criterion, fim: &Matrix3<f64>, p: f64) -> (f64, Matrix3<f64>) {
    let Some(inv) = fim.try_inverse().filter(|_| fim.determinant() > 0.0) else {
        return (f64::INFINITY, Matrix3::zeros());
    };
    match criterion {
        Criterion::DOptimal => (-fim.determinant().ln() / 3.0, -inv / 3.0),
        Criterion::AOptimal => {
            let trace = inv.trace();
            ((trace / 3.0).ln(), -(inv * inv) / trace)
        }
        Criterion::Minimax => {
            let d = inv.diagonal();
            let top = d.max();
            let sum: f64 = d.iter().map(|v| (v / top).powf(p)).sum();
            let mut g = Matrix3::zeros();
            for i in 0..3 {
                let share = (d[i] / top).powf(p) / sum / d[i];
                let c = inv.column(i);
                g -= share * c * c.transpose();
            }
            (top.ln() + sum.ln() / p, g)
        }
    }
}

/// The plants' log v combined, and each one's weight in it.
fn aggregate(how: Aggregate, parts: &[(f64, Matrix3<f64>)], p: f64) -> (f64, Vec<f64>) {
    let n = parts.len() as f64;
    match how {
        Aggregate::Average => (
            parts.iter().map(|v| v.0).sum::<f64>() / n,
            vec![1.0 / n; parts.len()],
        ),
        Aggregate::Worst => {
            let top = parts.iter().map(|v| v.0).fold(f64::NEG_INFINITY, f64::max);
            let e: Vec<f64> = parts.iter().map(|v| (p * (v.0 - top)).exp()).collect();
            let sum: f64 = e.iter().sum();
            (top + sum.ln() / p, e.iter().map(|x| x / sum).collect())
        }
    }
}

/// The state at sample `n` of segment `s`'s steady state: Re Σ_l Z_l a_sl e^{iω_l n dt}.
fn boundary_state(layout: &Layout, basis: &PlantBasis, w: &[f64], s: usize, n: usize) -> [f64; 8] {
    let mut z = [0.0; 8];
    for l in 0..layout.lines.len() {
        let e = rotation(layout, l, n) * layout.amplitude(w, s, l);
        for (zi, state) in z.iter_mut().zip(&basis.line_states[l]) {
            *zi += (state * e).re;
        }
    }
    z
}

/// e^{iω_l n dt}, from the exact phase (j·n mod M)/M.
fn rotation(layout: &Layout, l: usize, n: usize) -> Complex64 {
    let m = layout.period;
    let turn = ((layout.lines[l] * n) % m) as f64 / m as f64;
    Complex64::from_polar(1.0, std::f64::consts::TAU * turn)
}

/// The outputs of the three relative sensitivities.
const SENSITIVITIES: [usize; 3] = [1, 2, 3];

impl Objective<'_> {
    /// grad += (d(m·x_m, c·x_c, k·x_k) on plant `p` / d w)ᵀ·(the adjoint series).
    fn sensitivity_adjoint(&mut self, w: &[f64], p: usize, grad: &mut [f64]) {
        let (layout, basis) = (self.layout, &self.plants[p]);
        let [first, second, third] = &self.adjoint;
        for (s, &window) in layout.segments.iter().enumerate() {
            let (pp, qq) = (&mut self.p, &mut self.q);
            self.transform
                .project_lines(layout, (first, Some(second)), window, pp, qq);
            add_line_gradient(layout, s, |l| basis.line_outputs[l][1], pp, grad);
            add_line_gradient(layout, s, |l| basis.line_outputs[l][2], qq, grad);
            self.transform
                .project_lines(layout, (third, None), window, pp, qq);
            add_line_gradient(layout, s, |l| basis.line_outputs[l][3], pp, grad);
            free_edges_adjoint(layout, basis, s, &SENSITIVITIES, &self.adjoint, grad);
        }
        if let Some(n_s) = layout.step {
            let v = &self.adjoint;
            grad[w.len() - 1] += step_adjoint((layout, basis), n_s, &SENSITIVITIES, v);
        }
    }

    /// grad += (d(force, prior displacement) / d w)ᵀ·(adjoint[0], adjoint[1]).
    fn signal_adjoint(&mut self, w: &[f64], grad: &mut [f64]) {
        let (layout, basis) = (self.layout, &self.plants[0]);
        let [force, stroke, _] = &self.adjoint;
        for (s, &window) in layout.segments.iter().enumerate() {
            let (pp, qq) = (&mut self.p, &mut self.q);
            self.transform
                .project_lines(layout, (force, Some(stroke)), window, pp, qq);
            add_line_gradient(layout, s, |_| Complex64::new(1.0, 0.0), pp, grad);
            add_line_gradient(layout, s, |l| basis.line_outputs[l][0], qq, grad);
            free_edges_adjoint(layout, basis, s, &[0], std::slice::from_ref(stroke), grad);
        }
        if let Some(n_s) = layout.step {
            let steady = weighted_sum(layout, n_s, force);
            grad[w.len() - 1] +=
                steady + step_adjoint((layout, basis), n_s, &[0], std::slice::from_ref(stroke));
        }
    }

    /// grad += (d(plant `p`'s displacement) / d w)ᵀ·adjoint[2].
    fn stroke_adjoint(&mut self, w: &[f64], p: usize, grad: &mut [f64]) {
        let (layout, basis) = (self.layout, &self.plants[p]);
        let [_, _, v] = &self.adjoint;
        for (s, &window) in layout.segments.iter().enumerate() {
            let (pp, qq) = (&mut self.p, &mut self.q);
            self.transform
                .project_lines(layout, (v, None), window, pp, qq);
            add_line_gradient(layout, s, |l| basis.line_outputs[l][0], pp, grad);
            free_edges_adjoint(layout, basis, s, &[0], std::slice::from_ref(v), grad);
        }
        if let Some(n_s) = layout.step {
            grad[w.len() - 1] += step_adjoint((layout, basis), n_s, &[0], std::slice::from_ref(v));
        }
    }
}

/// The free responses of outputs `os` from segment `s`'s edges: −F(n − a)·z_a from its
/// start a, +F(n − b)·z_b from its end b (when inside the record).
fn free_edges(
    layout: &Layout,
    basis: &PlantBasis,
    w: &[f64],
    s: usize,
    os: &[usize],
    outs: &mut [Vec<f64>],
) {
    let (a, b) = layout.segments[s];
    add_free(
        (layout, &basis.free),
        os,
        &boundary_state(layout, basis, w, s, a),
        a,
        -1.0,
        outs,
    );
    if b < layout.samples {
        add_free(
            (layout, &basis.free),
            os,
            &boundary_state(layout, basis, w, s, b),
            b,
            1.0,
            outs,
        );
    }
}

/// grad += the adjoint of [`free_edges`] for the series `v` of outputs `os`.
fn free_edges_adjoint(
    layout: &Layout,
    basis: &PlantBasis,
    s: usize,
    os: &[usize],
    v: &[Vec<f64>],
    grad: &mut [f64],
) {
    let (a, b) = layout.segments[s];
    let lines = layout.lines.len();
    for (n, sign) in [(a, -1.0), (b, 1.0)] {
        if n >= layout.samples {
            continue;
        }
        let mut zeta = [0.0; 8];
        project_free((layout, &basis.free), os, v, n, &mut zeta);
        for l in 0..lines {
            // z = Re Σ Z a e: dz/dRe a = Re(Z e), dz/dIm a = −Im(Z e).
            let e = rotation(layout, l, n);
            let (mut re, mut im) = (0.0, 0.0);
            for (zi, state) in zeta.iter().zip(&basis.line_states[l]) {
                let ze = state * e;
                re += zi * ze.re;
                im -= zi * ze.im;
            }
            grad[2 * (s * lines + l)] += sign * re;
            grad[2 * (s * lines + l) + 1] += sign * im;
        }
    }
}

/// outs += d·(steady − free) of a step of height d at sample n_s, for outputs `os`.
fn step(
    (layout, basis): (&Layout, &PlantBasis),
    d: f64,
    n_s: usize,
    os: &[usize],
    outs: &mut [Vec<f64>],
) {
    let from = layout.kept_within(n_s, layout.samples).start;
    for (out, &o) in outs.iter_mut().zip(os) {
        out[from..]
            .iter_mut()
            .for_each(|y| *y += d * basis.dc_outputs[o]);
    }
    add_free((layout, &basis.free), os, &basis.dc_state, n_s, -d, outs);
}

/// d(Σ v·outputs)/d(step height), the adjoint of [`step`].
fn step_adjoint(
    (layout, basis): (&Layout, &PlantBasis),
    n_s: usize,
    os: &[usize],
    v: &[Vec<f64>],
) -> f64 {
    let mut zeta = [0.0; 8];
    project_free((layout, &basis.free), os, v, n_s, &mut zeta);
    let free: f64 = zeta.iter().zip(&basis.dc_state).map(|(a, b)| a * b).sum();
    let steady: f64 = v
        .iter()
        .zip(os)
        .map(|(v, &o)| weighted_sum(layout, n_s, v) * basis.dc_outputs[o])
        .sum();
    steady - free
}

/// Σ_{n ≥ from} v[n] over the record: the kept samples from `from`, each with its weight.
fn weighted_sum(layout: &Layout, from: usize, v: &[f64]) -> f64 {
    let kept = layout.kept_within(from, layout.samples);
    v[kept.clone()]
        .iter()
        .zip(&layout.weights[kept])
        .map(|(v, w)| w * v)
        .sum()
}

/// grad += d(Σ_n v·Re(T_l a_l e^{iω_l n dt}))/d(Re a, Im a) = (Re(T q), −Im(T q)), with
/// q_l the projection of v on line l.
fn add_line_gradient(
    layout: &Layout,
    s: usize,
    transfer: impl Fn(usize) -> Complex64,
    q: &[Complex64],
    grad: &mut [f64],
) {
    let lines = layout.lines.len();
    for l in 0..lines {
        let t = transfer(l) * q[l];
        grad[2 * (s * lines + l)] += t.re;
        grad[2 * (s * lines + l) + 1] -= t.im;
    }
}
