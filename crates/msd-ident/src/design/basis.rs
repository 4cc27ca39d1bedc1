//! The responses of a design's building blocks on one plant, computed once, and the
//! linear maps from the design's amplitudes to the force, the displacement and the
//! relative sensitivities (and back, for the gradient).
//!
//! ## The method
//! The response and its sensitivities obey one 8-state linear system z' = A z + b u
//! (see `sensitivity.rs`). For the force Re(a·e^{iωτ}) switched on at τ_a from rest,
//! the state is exactly the steady state Re(Z a e^{iωτ}), Z = (iωI − A)⁻¹b, minus the free
//! response e^{A(τ−τ_a)} Re(Z a e^{iωτ_a}); a tone windowed on [τ_a, τ_b) adds the free
//! response from τ_b; a step d at τ_s gives d·(z_dc − e^{A(τ−τ_s)} z_dc), z_dc = −A⁻¹b.
//! So per plant only Z per line, z_dc and the free responses C·e^{A n dt} (n = 0, 1, … until
//! they settle) are needed, and the steady-state sums over the lines of the multisine's
//! frequency grid (j/(M·dt), M its period: the record's N − 1 samples, or less for a long
//! record that repeats it) are one inverse FFT of length M per output. Exact in
//! continuous time; the sampled force differs from the continuous one only by the hold
//! between samples. Between the edges, once the free responses have settled, every series
//! repeats with period M: only the samples of one period are kept there (see [`Layout`]).

use crate::{error::Result, params::Parameters};
use msd_ode::{ExactSimulator, Hold, SMatrix, SVector};
use rustfft::Fft;
use rustfft::num_complex::Complex64;
use std::sync::Arc;

/// The outputs read from the 8 states: x, m·x_m, c·x_c, k·x_k (relative sensitivities).
pub(crate) const OUTPUTS: usize = 4;
const STATE_OF_OUTPUT: [usize; OUTPUTS] = [0, 2, 4, 6];

/// Where the design's amplitudes sit, on which grid, and which samples stand for the
/// record.
///
/// ## Kept samples
/// After the free responses of the segment edges and the step have died out, every
/// series is periodic (period M) between two edges. So only the samples up to one period
/// past each edge's settling are kept; a kept sample after the settling stands for
/// itself and its repetitions every M samples up to the next edge (its weight), and every
/// sum over the record is a weighted sum over the kept samples. Without repetitions (a
/// record of one period) every sample is kept, with weight 1.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Layout {
    /// Samples N of the record.
    pub samples: usize,
    /// Sampling interval, s.
    pub dt: f64,
    /// The multisine's period M, in samples: N − 1 (the record) or less.
    pub period: usize,
    /// The excited lines, as indices j of the grid j/(M·dt).
    pub lines: Vec<usize>,
    /// The segments' sample windows [a, b); the last ends at N.
    pub segments: Vec<(usize, usize)>,
    /// The sample of the step, if any.
    pub step: Option<usize>,
    /// The kept samples, ascending.
    pub kept: Vec<usize>,
    /// How many samples of the record each kept sample stands for.
    pub weights: Vec<f64>,
}

impl Layout {
    /// ω of line `l`, rad/s.
    pub fn omega(&self, l: usize) -> f64 {
        std::f64::consts::TAU * self.lines[l] as f64 / (self.period as f64 * self.dt)
    }

    /// Keeps, between consecutive edges (the segments' ends and the step), the first
    /// `settle` samples (where a free response may be alive) and one period after them;
    /// the samples of that period stand for their repetitions up to the next edge.
    pub fn keep(&mut self, settle: usize) {
        let mut edges: Vec<usize> = self.segments.iter().map(|s| s.0).collect();
        edges.extend(self.step);
        edges.push(self.samples);
        edges.sort_unstable();
        edges.dedup();
        let (m, span) = (self.period, settle.saturating_add(self.period));
        self.kept.clear();
        self.weights.clear();
        for edge in edges.windows(2) {
            let (u, v) = (edge[0], edge[1]);
            for n in u..v.min(u.saturating_add(span)) {
                self.kept.push(n);
                let repeats = if n - u < settle {
                    1
                } else {
                    (v - 1 - n) / m + 1
                };
                self.weights.push(repeats as f64);
            }
        }
        debug_assert_eq!(
            self.weights.iter().sum::<f64>(),
            self.samples as f64,
            "the kept samples stand for the record"
        );
    }

    /// The kept samples' indices in `lo..hi`.
    pub fn kept_within(&self, lo: usize, hi: usize) -> std::ops::Range<usize> {
        self.kept.partition_point(|&n| n < lo)..self.kept.partition_point(|&n| n < hi)
    }

    /// Number of design variables: (Re, Im) per line and segment, then the step.
    pub fn variables(&self) -> usize {
        2 * self.lines.len() * self.segments.len() + usize::from(self.step.is_some())
    }

    /// The complex amplitude of line `l` in segment `s` within `w`.
    pub fn amplitude(&self, w: &[f64], s: usize, l: usize) -> Complex64 {
        let i = 2 * (s * self.lines.len() + l);
        Complex64::new(w[i], w[i + 1])
    }

    /// The step's amplitude within `w` (0 without a step).
    pub fn step_amplitude(&self, w: &[f64]) -> f64 {
        if self.step.is_some() {
            w[w.len() - 1]
        } else {
            0.0
        }
    }
}

/// The building blocks' responses on one plant.
pub(crate) struct PlantBasis {
    /// Per line: the steady-state complex amplitude of each output for the force e^{iωτ}.
    pub line_outputs: Vec<[Complex64; OUTPUTS]>,
    /// Per line: the steady-state complex state Z.
    pub line_states: Vec<[Complex64; 8]>,
    /// The outputs and state of the static response to a unit force.
    pub dc_outputs: [f64; OUTPUTS],
    /// The static state z_dc = −A⁻¹b.
    pub dc_state: [f64; 8],
    /// C·e^{A n dt}, n = 0, 1, …: each output's free response to each initial state, up
    /// to N − 1 or until e^{A n dt} has fallen below 10⁻¹⁶ of its largest norm (the
    /// responses' settling).
    pub free: Vec<[[f64; 8]; OUTPUTS]>,
}

/// The free responses are cut where ‖e^{A n dt}‖ has fallen below this share of its
/// largest value: what is left is below the rounding of the sums it enters.
const SETTLED: f64 = 1e-16;

impl PlantBasis {
    /// The blocks of `plant` on `layout`'s grid.
    pub fn new(plant: &Parameters, layout: &Layout) -> Result<Self> {
        let model = crate::sensitivity::sensitivity_model(plant);
        let scale = [1.0, plant.mass, plant.damping, plant.stiffness];
        let phi = *ExactSimulator::new(&model, layout.dt, Hold::Zero)?.transition();
        let mut row = [[0.0; 8]; OUTPUTS];
        for (o, r) in row.iter_mut().enumerate() {
            r[STATE_OF_OUTPUT[o]] = scale[o];
        }
        let mut free = Vec::new();
        let (mut power, mut largest) = (SMatrix::<f64, 8, 8>::identity(), 0.0f64);
        for _ in 0..layout.samples {
            let norm = power.norm();
            largest = largest.max(norm);
            if norm < SETTLED * largest {
                break;
            }
            free.push(row);
            row = row.map(|r| std::array::from_fn(|j| (0..8).map(|i| r[i] * phi[(i, j)]).sum()));
            power *= phi;
        }
        let dc = model.a.lu().solve(&model.b).map(|z| -z);
        let dc_state: [f64; 8] = std::array::from_fn(|i| dc.map_or(0.0, |z| z[i]));
        let mut line_outputs = Vec::with_capacity(layout.lines.len());
        let mut line_states = Vec::with_capacity(layout.lines.len());
        for l in 0..layout.lines.len() {
            let z = steady_state(&model.a, &model.b, layout.omega(l));
            line_outputs.push(std::array::from_fn(|o| z[STATE_OF_OUTPUT[o]] * scale[o]));
            line_states.push(z);
        }
        Ok(Self {
            line_outputs,
            line_states,
            dc_outputs: std::array::from_fn(|o| dc_state[STATE_OF_OUTPUT[o]] * scale[o]),
            dc_state,
            free,
        })
    }
}

/// Z = (iωI − A)⁻¹b, from the real system [−A −ωI; ωI −A]·[Re Z; Im Z] = [b; 0].
fn steady_state(a: &SMatrix<f64, 8, 8>, b: &SVector<f64, 8>, omega: f64) -> [Complex64; 8] {
    let mut m = SMatrix::<f64, 16, 16>::zeros();
    let mut rhs = SVector::<f64, 16>::zeros();
    for i in 0..8 {
        for j in 0..8 {
            m[(i, j)] = -a[(i, j)];
            m[(i + 8, j + 8)] = -a[(i, j)];
        }
        m[(i, i + 8)] = -omega;
        m[(i + 8, i)] = omega;
        rhs[i] = b[i];
    }
    let z = m.lu().solve(&rhs).unwrap_or_else(SVector::zeros);
    std::array::from_fn(|i| Complex64::new(z[i], z[i + 8]))
}

/// The FFT and its buffers, allocated once.
pub(crate) struct Transform {
    fft: Arc<dyn Fft<f64>>,
    buffer: Vec<Complex64>,
    scratch: Vec<Complex64>,
}

impl Transform {
    /// For a grid of period `m` samples.
    pub fn new(m: usize) -> Self {
        let fft = crate::fft::inverse(m);
        let scratch = vec![Complex64::default(); fft.get_inplace_scratch_len()];
        Self {
            fft,
            buffer: vec![Complex64::default(); m],
            scratch,
        }
    }

    /// a[n] += Re Σ_l c_l e^{iω_l n dt} and b[n] += Re Σ_l d_l e^{iω_l n dt} for the kept
    /// n in `lo..hi`, with (c_l, d_l) = `coefficients(l)`: one FFT for two real series, c at
    /// bin j and its conjugate at M − j for the real part, d the same for the imaginary.
    pub fn add_lines(
        &mut self,
        layout: &Layout,
        coefficients: impl Fn(usize) -> [Complex64; 2],
        (lo, hi): (usize, usize),
        a: &mut [f64],
        b: Option<&mut [f64]>,
    ) {
        let m = self.buffer.len();
        let i = Complex64::new(0.0, 1.0);
        self.buffer.fill(Complex64::default());
        for (l, &j) in layout.lines.iter().enumerate() {
            let [c, d] = coefficients(l);
            self.buffer[j] = 0.5 * (c + i * d);
            self.buffer[m - j] = 0.5 * (c.conj() + i * d.conj());
        }
        self.fft
            .process_with_scratch(&mut self.buffer, &mut self.scratch);
        let kept = layout.kept_within(lo, hi);
        for (&n, o) in layout.kept[kept.clone()].iter().zip(&mut a[kept.clone()]) {
            *o += self.buffer[n % m].re;
        }
        if let Some(b) = b {
            for (&n, o) in layout.kept[kept.clone()].iter().zip(&mut b[kept]) {
                *o += self.buffer[n % m].im;
            }
        }
    }

    /// p_l = Σ_{n in lo..hi} a[n] e^{iω_l n dt} and q_l the same of b, for every line (each
    /// kept sample with its weight): one
    /// FFT of a + i·b, split by conjugate symmetry.
    pub fn project_lines(
        &mut self,
        layout: &Layout,
        (a, b): (&[f64], Option<&[f64]>),
        (lo, hi): (usize, usize),
        p: &mut [Complex64],
        q: &mut [Complex64],
    ) {
        let m = self.buffer.len();
        self.buffer.fill(Complex64::default());
        for i in layout.kept_within(lo, hi) {
            let weight = layout.weights[i];
            self.buffer[layout.kept[i] % m] +=
                weight * Complex64::new(a[i], b.map_or(0.0, |b| b[i]));
        }
        self.fft
            .process_with_scratch(&mut self.buffer, &mut self.scratch);
        for (l, &j) in layout.lines.iter().enumerate() {
            let (z, w) = (self.buffer[j], self.buffer[m - j].conj());
            p[l] = 0.5 * (z + w);
            q[l] = Complex64::new(0.0, -0.5) * (z - w);
        }
    }
}

/// outs[k][n] += sign·F_{os[k]}(n − a)·z for the kept samples n ≥ a while the free
/// response lasts: the outputs' free response from the state z at sample a, in one pass
/// over the free responses (a kept sample within it stands for itself only).
pub(crate) fn add_free(
    (layout, free): (&Layout, &[[[f64; 8]; OUTPUTS]]),
    os: &[usize],
    z: &[f64; 8],
    a: usize,
    sign: f64,
    outs: &mut [Vec<f64>],
) {
    each_free(layout, free, a, |i, f| {
        for (out, &o) in outs.iter_mut().zip(os) {
            out[i] += sign * dot8(&f[o], z);
        }
    });
}

/// ζ += Σ_k Σ_{n ≥ a} v[k][n]·F_{os[k]}(n − a): the adjoint of [`add_free`] (without its
/// sign).
pub(crate) fn project_free(
    (layout, free): (&Layout, &[[[f64; 8]; OUTPUTS]]),
    os: &[usize],
    v: &[Vec<f64>],
    a: usize,
    zeta: &mut [f64; 8],
) {
    each_free(layout, free, a, |i, f| {
        debug_assert_eq!(
            layout.weights[i], 1.0,
            "a free response on a repeated sample"
        );
        for (v, &o) in v.iter().zip(os) {
            let x = v[i];
            for (zeta, f) in zeta.iter_mut().zip(&f[o]) {
                *zeta += x * f;
            }
        }
    });
}

/// Calls `each(i, F(n − a))` for the kept samples i (at n) in a … a + the free response's
/// length, in order: a plain walk where they are consecutive samples (every sample kept,
/// or one interval's), by index otherwise.
#[inline(always)]
fn each_free<'f>(
    layout: &Layout,
    free: &'f [[[f64; 8]; OUTPUTS]],
    a: usize,
    mut each: impl FnMut(usize, &'f [[f64; 8]; OUTPUTS]),
) {
    let kept = layout.kept_within(a, a.saturating_add(free.len()));
    let Some(&first) = layout.kept.get(kept.start).filter(|_| !kept.is_empty()) else {
        return;
    };
    if layout.kept[kept.end - 1] - first == kept.len() - 1 {
        kept.zip(&free[first - a..]).for_each(|(i, f)| each(i, f));
    } else {
        kept.for_each(|i| each(i, &free[layout.kept[i] - a]));
    }
}

fn dot8(a: &[f64; 8], b: &[f64; 8]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}
