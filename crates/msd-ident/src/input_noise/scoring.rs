//! Newton's method on the spectral model's variances, Fisher scoring where the
//! likelihood is not concave: the usual iterations for variance components (restricted
//! likelihood included), a few passes over the lines.
//!
//! Each line's covariance is linear in the variances v = (σ²_u, σ²_a…):
//! Σ_k = Σ_q v_q·M_{k,q}. The Whittle log-likelihood −Σ_k (ln det Σ_k + R_kᴴ·Σ_k⁻¹·R_k)
//! has the score s_q = Σ_k (y_kᴴ·M_q·y_k − tr Σ_k⁻¹·M_q), y_k = Σ_k⁻¹·R_k, the expected
//! information F_qr = Σ_k tr(Σ_k⁻¹·M_q·Σ_k⁻¹·M_r) and the observed one
//! H_qr = Σ_k (2·Re(y_kᴴ·M_r·Σ_k⁻¹·M_q·y_k) − tr(Σ_k⁻¹·M_q·Σ_k⁻¹·M_r)). Each step is
//! v + H⁻¹·s (F⁻¹·s where H is not positive definite), halved until the likelihood does
//! not fall, with σ²_u held at 0 where its score points below. Scoring alone converges
//! linearly where σ²_u is weakly determined (a ratio of 0.6 per step on an exact drive,
//! 40 passes); Newton's steps converge in a handful.

use super::restricted::Expected;
use super::spectral::{Lines, SpectralModel, likelihood_lines};
use nalgebra::DMatrix;
use rustfft::num_complex::Complex64;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// The likelihood at v, its score, and its expected (Fisher) and observed information
/// in v.
struct Evaluation {
    pub log_likelihood: f64,
    pub score: Vec<f64>,
    pub fisher: DMatrix<f64>,
    pub observed: DMatrix<f64>,
}

/// The most steps taken; Newton converges in far fewer (3–10 on the shipped rigs).
const MAX_STEPS: usize = 200;
/// A step below this fraction of every variance (or of its scale, for σ²_u near 0) has
/// converged: far inside the variances' standard errors.
const STEP_TOLERANCE: f64 = 1e-8;

/// σ²_a (one per group, `groups` of them) and σ²_u maximising the Whittle likelihood
/// (Fisher scoring), then the likelihood ratio against the best fit
/// with σ_u = 0.
///
/// With `expected` (one per record), the likelihood is the restricted one: each line's
/// residual cross-spectrum as the fit left it ([`super::restricted`]).
pub(crate) fn maximise(
    lines: &[Lines],
    groups: usize,
    expected: Option<&[Expected]>,
) -> SpectralModel {
    let white = white_variances(lines, groups);
    // σ²_u's scale: the drive noise that matches the first group's at the first
    // record's largest gain.
    let peak = likelihood_lines(lines[0].size)
        .map(|k| lines[0].transfer[0][k].norm_sqr())
        .fold(0.0, f64::max);
    let reference = white[0] / peak.max(f64::MIN_POSITIVE);
    let scale: Vec<f64> = std::iter::once(reference)
        .chain(white.iter().copied())
        .collect();
    let start: Vec<f64> = std::iter::once(0.0).chain(white.iter().copied()).collect();
    let (boundary, white_likelihood) = maximise_from(lines, expected, start, &scale, false);
    // From the lines' moments weighted at a quarter of σ²_u's scale (Newton on a
    // variance from far below only doubles it per step), or from there.
    let mut guess = boundary.clone();
    guess[0] = 0.25 * reference;
    let start = moments(lines, &guess).unwrap_or(guess);
    let (fitted, likelihood) = maximise_from(lines, expected, start, &scale, true);
    let (v, best) = if likelihood > white_likelihood && fitted[0] > 0.0 {
        (fitted, likelihood)
    } else {
        (boundary, white_likelihood)
    };
    let likelihood_ratio = 2.0 * (best - white_likelihood);
    let p_value = 0.5
        * ChiSquared::new(1.0)
            .map(|c| c.sf(likelihood_ratio))
            .unwrap_or(1.0);
    // The unrestricted model's information, as the sandwich's middle matrix uses.
    let covariance = evaluate(lines, None, &v).fisher.try_inverse();
    let (s_u, d) = (v[0], v[1..].to_vec());
    SpectralModel {
        sensor_variance: d,
        input_variance: s_u,
        covariance,
        likelihood_ratio,
        p_value,
    }
}

/// (σ²_u, σ²_a…) by the lines' moments, E|R_k|² = σ²_a + σ²_u·|G_k|², least squares
/// weighted by each power's variance at `at` (the periodogram's: its mean squared),
/// reweighted once at the first fit; `None` unless σ²_u and every σ²_a come out
/// positive. A start for the likelihood's maximum, not an estimate: `at` needs σ²_u
/// > 0, or the few lines at the resonance outweigh all others.
fn moments(lines: &[Lines], at: &[f64]) -> Option<Vec<f64>> {
    let mut v = at.to_vec();
    for _ in 0..2 {
        // Normal equations in (σ²_u, σ²_a…): unknowns q = 0 (drive) and 1 + group.
        let q = v.len();
        let (mut normal, mut rhs) = (DMatrix::<f64>::zeros(q, q), nalgebra::DVector::zeros(q));
        for l in lines {
            for (ch, &g) in l.groups.iter().enumerate() {
                for k in likelihood_lines(l.size) {
                    let gain = l.transfer[ch][k].norm_sqr();
                    let mean = v[1 + g] + v[0] * gain;
                    let w = 1.0 / (mean * mean).max(f64::MIN_POSITIVE);
                    let power = l.residual[ch][k].norm_sqr();
                    let x = [(0, gain), (1 + g, 1.0)];
                    for &(a, xa) in &x {
                        rhs[a] += w * xa * power;
                        for &(b, xb) in &x {
                            normal[(a, b)] += w * xa * xb;
                        }
                    }
                }
            }
        }
        let solved = normal.cholesky()?.solve(&rhs);
        if !solved.iter().all(|x| x.is_finite() && *x > 0.0) {
            return None;
        }
        v = solved.iter().copied().collect();
    }
    Some(v)
}

/// Each group's mean line power: the white model's variances.
fn white_variances(lines: &[Lines], groups: usize) -> Vec<f64> {
    let (mut power, mut members) = (vec![0.0; groups], vec![0.0; groups]);
    for l in lines {
        for (ch, &g) in l.groups.iter().enumerate() {
            for k in likelihood_lines(l.size) {
                power[g] += l.residual[ch][k].norm_sqr();
                members[g] += 1.0;
            }
        }
    }
    power
        .iter()
        .zip(&members)
        .map(|(p, m)| (p / m).max(f64::MIN_POSITIVE))
        .collect()
}

/// The variances maximising the likelihood from `start`; σ²_u (`v[0]`) held at its
/// start when `drive_free` is false. `scale` sets each variance's convergence size.
/// Returns the variances and the likelihood there.
fn maximise_from(
    lines: &[Lines],
    expected: Option<&[Expected]>,
    start: Vec<f64>,
    scale: &[f64],
    drive_free: bool,
) -> (Vec<f64>, f64) {
    let mut v = start;
    let mut at = evaluate(lines, expected, &v);
    for _ in 0..MAX_STEPS {
        let free: Vec<usize> = (0..v.len())
            .filter(|&q| q > 0 || (drive_free && (v[0] > 0.0 || at.score[0] > 0.0)))
            .collect();
        let s = nalgebra::DVector::from_iterator(free.len(), free.iter().map(|&q| at.score[q]));
        let block = |m: &DMatrix<f64>| {
            DMatrix::from_fn(free.len(), free.len(), |i, j| m[(free[i], free[j])]).cholesky()
        };
        let Some(delta) = (block(&at.observed).or_else(|| block(&at.fisher))).map(|c| c.solve(&s))
        else {
            break;
        };
        let small = free
            .iter()
            .zip(delta.iter())
            .all(|(&q, d)| d.abs() <= STEP_TOLERANCE * v[q].abs().max(scale[q]));
        if small {
            // Taken, not evaluated: Newton's next error is this step's square, so the
            // result no longer depends on the start; the likelihood moves by as little.
            for (i, &q) in free.iter().enumerate() {
                v[q] = (v[q] + delta[i]).max(if q == 0 { 0.0 } else { 0.1 * v[q] });
            }
            break;
        }
        let mut step = 1.0;
        let accepted = loop {
            let mut trial = v.clone();
            for (i, &q) in free.iter().enumerate() {
                // A variance may fall by at most nine tenths in one step (σ²_u to 0).
                let floor = if q == 0 { 0.0 } else { 0.1 * v[q] };
                trial[q] = (v[q] + step * delta[i]).max(floor);
            }
            let next = evaluate(lines, expected, &trial);
            // Rounding in a sum over thousands of lines: a step that loses less than
            // 1e-12 of the likelihood has not gone downhill.
            if next.log_likelihood >= at.log_likelihood - 1e-12 * at.log_likelihood.abs() {
                break Some((trial, next));
            }
            step *= 0.5;
            if step < 1e-6 {
                break None;
            }
        };
        let Some((trial, next)) = accepted else {
            break;
        };
        (v, at) = (trial, next);
    }
    (v, at.log_likelihood)
}

/// Reused per-line buffers (c channels, q variances).
struct Work {
    matrices: Vec<Vec<Complex64>>,
    factor: Vec<Complex64>,
    inverse: Vec<Complex64>,
    parts: Vec<Vec<Complex64>>,
    /// M_q·y and Σ⁻¹·M_q·y, per variance.
    images: Vec<Vec<Complex64>>,
    solved: Vec<Vec<Complex64>>,
    y: Vec<Complex64>,
    residual: Vec<Complex64>,
    sums: GroupSums,
}

/// The likelihood, score and Fisher information at `v` over every line of every record.
fn evaluate(lines: &[Lines], expected: Option<&[Expected]>, v: &[f64]) -> Evaluation {
    let q = v.len();
    let mut out = Evaluation {
        log_likelihood: 0.0,
        score: vec![0.0; q],
        fisher: DMatrix::zeros(q, q),
        observed: DMatrix::zeros(q, q),
    };
    let mut work = Work {
        matrices: vec![Vec::new(); q],
        factor: Vec::new(),
        inverse: Vec::new(),
        parts: vec![Vec::new(); q],
        images: vec![Vec::new(); q],
        solved: vec![Vec::new(); q],
        y: Vec::new(),
        residual: Vec::new(),
        sums: GroupSums::default(),
    };
    for (r, l) in lines.iter().enumerate() {
        for (i, k) in likelihood_lines(l.size).enumerate() {
            work.residual.clear();
            work.residual
                .extend((0..l.groups.len()).map(|ch| l.residual[ch][k]));
            if let Some(m) = expected.and_then(|e| e[r].lines[i].as_ref()) {
                for (to, from) in work.matrices.iter_mut().zip(m) {
                    to.clone_from(from);
                }
                if accumulate(v, &mut work, &mut out) {
                    continue;
                }
            }
            // The noise's own spectrum, D + σ²_u·G·Gᴴ: in closed form where there are
            // several channels (one is the scalar case).
            if l.groups.len() > 1 && accumulate_rank_one(l, k, v, &mut work.sums, &mut out) {
                continue;
            }
            noise_matrices(l, k, &mut work.matrices);
            accumulate(v, &mut work, &mut out);
        }
    }
    out
}

/// The unrestricted line matrices at line `k`: M_0 = G·Gᴴ, M_{1+g} = the diagonal of
/// group g's channels.
fn noise_matrices(l: &Lines, k: usize, matrices: &mut [Vec<Complex64>]) {
    let c = l.groups.len();
    for (q, m) in matrices.iter_mut().enumerate() {
        m.clear();
        m.extend((0..c * c).map(|i| {
            let (a, b) = (i / c, i % c);
            if q == 0 {
                l.transfer[a][k] * l.transfer[b][k].conj()
            } else if a == b && l.groups[a] == q - 1 {
                Complex64::new(1.0, 0.0)
            } else {
                Complex64::new(0.0, 0.0)
            }
        }));
    }
}

/// Adds one line's terms (Σ = Σ_q v_q·M_q from `work.matrices`, the residual in
/// `work.residual`); false, adding nothing, where Σ is not positive definite.
fn accumulate(v: &[f64], work: &mut Work, out: &mut Evaluation) -> bool {
    let c = work.residual.len();
    if c == 1 {
        return accumulate_scalar(v, work, out);
    }
    let zero = Complex64::new(0.0, 0.0);
    work.factor.clear();
    work.factor.resize(c * c, zero);
    for (m, x) in work.matrices.iter().zip(v) {
        for (f, e) in work.factor.iter_mut().zip(m) {
            *f += e * x;
        }
    }
    let Some(log_det) = cholesky(&mut work.factor, c) else {
        return false;
    };
    invert(&work.factor, c, &mut work.inverse);
    let inverse = &work.inverse;
    work.y.clear();
    work.y.extend((0..c).map(|a| {
        (0..c)
            .map(|b| inverse[a * c + b] * work.residual[b])
            .sum::<Complex64>()
    }));
    let quadratic: f64 = (0..c)
        .map(|a| (work.residual[a].conj() * work.y[a]).re)
        .sum();
    out.log_likelihood -= log_det + quadratic;
    for (part, m) in work.parts.iter_mut().zip(&work.matrices) {
        part.clear();
        part.extend((0..c * c).map(|i| {
            let (a, b) = (i / c, i % c);
            (0..c)
                .map(|e| inverse[a * c + e] * m[e * c + b])
                .sum::<Complex64>()
        }));
    }
    images_of(work);
    for (qi, part) in work.parts.iter().enumerate() {
        let trace: f64 = (0..c).map(|a| part[a * c + a].re).sum();
        let form: f64 = (0..c)
            .map(|a| (work.y[a].conj() * work.images[qi][a]).re)
            .sum();
        out.score[qi] += form - trace;
        for (qj, other) in work.parts.iter().enumerate().skip(qi) {
            let t: f64 = (0..c * c)
                .map(|i| (part[i] * other[(i % c) * c + i / c]).re)
                .sum();
            let cross: f64 = (0..c)
                .map(|a| (work.images[qj][a].conj() * work.solved[qi][a]).re)
                .sum();
            for (m, value) in [(&mut out.fisher, t), (&mut out.observed, 2.0 * cross - t)] {
                m[(qi, qj)] += value;
                if qi != qj {
                    m[(qj, qi)] += value;
                }
            }
        }
    }
    true
}

/// One line's sums per sensor group under Σ = D + σ²_u·g·gᴴ ([`accumulate_rank_one`]),
/// with h = D⁻¹·g and y = Σ⁻¹·R: Σ|h_a|², Σ h̄_a·y_a, Σ|y_a|², Σ|y_a|²/d_a, the trace
/// of Σ⁻¹ over the group's channels and Σ (1/d_a² − 2β·|h_a|²/d_a).
#[derive(Default)]
struct GroupSums {
    h2: Vec<f64>,
    u: Vec<Complex64>,
    y2: Vec<f64>,
    yd: Vec<f64>,
    trace: Vec<f64>,
    diagonal: Vec<f64>,
}

/// [`accumulate`] at an unrestricted line k of `l`, where Σ = D + σ²_u·g·gᴴ (D the
/// groups' variances on the diagonal) is diagonal plus rank one: Σ⁻¹ = D⁻¹ − β·h·hᴴ
/// with γ = gᴴ·D⁻¹·g, κ = 1 + σ²_u·γ, β = σ²_u/κ, and det Σ = κ·det D (Sherman–Morrison
/// and the determinant lemma). Every trace of [`accumulate`] then reduces to sums over
/// the channels, without a factorisation. False, adding nothing, where a variance is
/// not positive (or σ²_u negative).
fn accumulate_rank_one(
    l: &Lines,
    k: usize,
    v: &[f64],
    sums: &mut GroupSums,
    out: &mut Evaluation,
) -> bool {
    let (s, groups) = (v[0], v.len() - 1);
    let variance = |a: usize| v[1 + l.groups[a]];
    let c = l.groups.len();
    // NaN fails these too.
    let positive = |x: f64| x.partial_cmp(&0.0) == Some(std::cmp::Ordering::Greater);
    if s.is_nan() || s < 0.0 || !(0..c).all(|a| positive(variance(a))) {
        return false;
    }
    let (mut gamma, mut rho) = (0.0, Complex64::new(0.0, 0.0));
    for a in 0..c {
        let h = l.transfer[a][k] / variance(a);
        gamma += (l.transfer[a][k].conj() * h).re;
        rho += h.conj() * l.residual[a][k];
    }
    let kappa = 1.0 + s * gamma;
    let beta = s / kappa;
    for part in [
        &mut sums.h2,
        &mut sums.y2,
        &mut sums.yd,
        &mut sums.trace,
        &mut sums.diagonal,
    ] {
        part.clear();
        part.resize(groups, 0.0);
    }
    sums.u.clear();
    sums.u.resize(groups, Complex64::new(0.0, 0.0));
    let (mut log_det, mut quadratic) = (kappa.ln(), -beta * rho.norm_sqr());
    for a in 0..c {
        let (j, d, r) = (l.groups[a], variance(a), l.residual[a][k]);
        let h = l.transfer[a][k] / d;
        let y = r / d - h * (beta * rho);
        log_det += d.ln();
        quadratic += r.norm_sqr() / d;
        sums.h2[j] += h.norm_sqr();
        sums.u[j] += h.conj() * y;
        sums.y2[j] += y.norm_sqr();
        sums.yd[j] += y.norm_sqr() / d;
        sums.trace[j] += 1.0 / d - beta * h.norm_sqr();
        sums.diagonal[j] += 1.0 / (d * d) - 2.0 * beta * h.norm_sqr() / d;
    }
    out.log_likelihood -= log_det + quadratic;
    let k2 = kappa * kappa;
    out.score[0] += rho.norm_sqr() / k2 - gamma / kappa;
    for j in 0..groups {
        out.score[1 + j] += sums.y2[j] - sums.trace[j];
    }
    // Each pair's tr(P_q·P_r) and Re((M_r·y)ᴴ·Σ⁻¹·M_q·y); the observed information is
    // twice the second less the first.
    let mut add = |q: usize, r: usize, trace: f64, cross: f64| {
        for (m, value) in [
            (&mut out.fisher, trace),
            (&mut out.observed, 2.0 * cross - trace),
        ] {
            m[(q, r)] += value;
            if q != r {
                m[(r, q)] += value;
            }
        }
    };
    add(
        0,
        0,
        (gamma / kappa).powi(2),
        rho.norm_sqr() / k2 * gamma / kappa,
    );
    for j in 0..groups {
        add(0, 1 + j, sums.h2[j] / k2, (sums.u[j].conj() * rho).re / k2);
        for m in j..groups {
            let shared = beta * beta * sums.h2[j] * sums.h2[m];
            let cross = -beta * (sums.u[m].conj() * sums.u[j]).re;
            if m == j {
                add(1 + j, 1 + j, shared + sums.diagonal[j], cross + sums.yd[j]);
            } else {
                add(1 + j, 1 + m, shared, cross);
            }
        }
    }
    true
}

/// [`accumulate`] for one channel, where every matrix is a positive number: with
/// Σ = Σ_q v_q·m_q and e = |R|²/Σ, the score is (m_q/Σ)·(e − 1), the Fisher information
/// m_q·m_r/Σ² and the observed one (m_q·m_r/Σ²)·(2e − 1).
fn accumulate_scalar(v: &[f64], work: &Work, out: &mut Evaluation) -> bool {
    let sigma: f64 = work.matrices.iter().zip(v).map(|(m, x)| m[0].re * x).sum();
    if sigma.is_nan() || sigma <= 0.0 {
        return false;
    }
    let excess = work.residual[0].norm_sqr() / sigma;
    out.log_likelihood -= sigma.ln() + excess;
    let q = v.len();
    for a in 0..q {
        let pa = work.matrices[a][0].re / sigma;
        out.score[a] += pa * (excess - 1.0);
        for b in a..q {
            let t = pa * work.matrices[b][0].re / sigma;
            for (m, value) in [
                (&mut out.fisher, t),
                (&mut out.observed, t * (2.0 * excess - 1.0)),
            ] {
                m[(a, b)] += value;
                if a != b {
                    m[(b, a)] += value;
                }
            }
        }
    }
    true
}

/// M_q·y and Σ⁻¹·M_q·y (= P_q·y, P_q = Σ⁻¹·M_q in `work.parts`) for each variance.
fn images_of(work: &mut Work) {
    let c = work.y.len();
    let y = &work.y;
    for (q, (m, part)) in work.matrices.iter().zip(&work.parts).enumerate() {
        let product =
            |a: &[Complex64], i: usize| -> Complex64 { (0..c).map(|b| a[i * c + b] * y[b]).sum() };
        work.images[q].clear();
        work.images[q].extend((0..c).map(|i| product(m, i)));
        work.solved[q].clear();
        work.solved[q].extend((0..c).map(|i| product(part, i)));
    }
}

/// The Cholesky factor L (Σ = L·Lᴴ) in place in the lower triangle of the row-major
/// c×c `a`; returns ln det Σ, `None` where Σ is not positive definite.
fn cholesky(a: &mut [Complex64], c: usize) -> Option<f64> {
    let mut log_det = 0.0;
    for i in 0..c {
        for j in 0..=i {
            let mut sum = a[i * c + j];
            for k in 0..j {
                sum -= a[i * c + k] * a[j * c + k].conj();
            }
            if i == j {
                if sum.re.is_nan() || sum.re <= 0.0 {
                    return None;
                }
                let d = sum.re.sqrt();
                a[i * c + i] = Complex64::new(d, 0.0);
                log_det += 2.0 * d.ln();
            } else {
                a[i * c + j] = sum / a[j * c + j].re;
            }
        }
    }
    Some(log_det)
}

/// Σ⁻¹ = L⁻ᴴ·L⁻¹ from the Cholesky factor in the lower triangle of `l`.
fn invert(l: &[Complex64], c: usize, inverse: &mut Vec<Complex64>) {
    let zero = Complex64::new(0.0, 0.0);
    // L⁻¹ by forward substitution, column by column (lower triangular).
    let mut li = vec![zero; c * c];
    for col in 0..c {
        for i in col..c {
            let mut sum = if i == col {
                Complex64::new(1.0, 0.0)
            } else {
                zero
            };
            for k in col..i {
                sum -= l[i * c + k] * li[k * c + col];
            }
            li[i * c + col] = sum / l[i * c + i].re;
        }
    }
    inverse.clear();
    inverse.extend((0..c * c).map(|i| {
        let (a, b) = (i / c, i % c);
        (a.max(b)..c)
            .map(|k| li[k * c + a].conj() * li[k * c + b])
            .sum::<Complex64>()
    }));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The score is the likelihood's gradient and the observed information minus the
    /// score's (central differences), on two channels in two groups, and the Fisher
    /// information is positive definite there.
    #[test]
    fn the_score_is_the_likelihoods_gradient() {
        let size = 64;
        let transfer: Vec<Vec<Complex64>> = (0..2)
            .map(|ch| {
                (0..size)
                    .map(|k| Complex64::new(1.0 + 0.1 * ch as f64, 0.02 * k as f64).inv())
                    .collect()
            })
            .collect();
        let residual: Vec<Vec<Complex64>> = (0..2)
            .map(|ch| {
                (0..size)
                    .map(|k| Complex64::new(((k * (ch + 3)) as f64).sin(), (k as f64).cos()))
                    .collect()
            })
            .collect();
        let lines = [Lines {
            size,
            groups: vec![0, 1],
            residual,
            transfer,
        }];
        let v = [0.3, 0.8, 1.4];
        let at = evaluate(&lines, None, &v);
        for q in 0..3 {
            let h = 1e-6;
            let (mut up, mut down) = (v, v);
            up[q] += h;
            down[q] -= h;
            let slope = (evaluate(&lines, None, &up).log_likelihood
                - evaluate(&lines, None, &down).log_likelihood)
                / (2.0 * h);
            assert!(
                (slope - at.score[q]).abs() < 1e-5 * slope.abs().max(1.0),
                "q {q}: {slope} against {}",
                at.score[q]
            );
        }
        assert!(at.fisher.clone().cholesky().is_some());
        // The observed information is minus the score's derivative.
        for q in 0..3 {
            let h = 1e-6;
            let (mut up, mut down) = (v, v);
            up[q] += h;
            down[q] -= h;
            let (su, sd) = (evaluate(&lines, None, &up), evaluate(&lines, None, &down));
            for r in 0..3 {
                let slope = -(su.score[r] - sd.score[r]) / (2.0 * h);
                assert!(
                    (slope - at.observed[(r, q)]).abs() < 1e-5 * slope.abs().max(1.0),
                    "({r}, {q}): {slope} against {}",
                    at.observed[(r, q)]
                );
            }
        }
    }

    /// Newton's maximum does not depend on where it starts: from the lines' moments and
    /// from a drive variance a hundred times too small (seven doublings away), the
    /// variances agree to rounding, since the last step below tolerance is taken.
    #[test]
    fn the_maximum_does_not_depend_on_the_start() {
        let (size, d, s) = (1024usize, 0.5, 40.0);
        let gain = |k: usize| {
            let r = k as f64 / 80.0;
            Complex64::new(1.0 - r * r, 0.1 * r).inv()
        };
        let draws = msd_signal::gaussian_noise(7, "scoring test", 1.0, 2 * size).expect("draws");
        let residual: Vec<Complex64> = (0..size)
            .map(|k| {
                let spread = ((d + s * gain(k).norm_sqr()) / 2.0).sqrt();
                Complex64::new(draws[2 * k], draws[2 * k + 1]) * spread
            })
            .collect();
        let lines = [Lines {
            size,
            groups: vec![0],
            residual: vec![residual],
            transfer: vec![(0..size).map(gain).collect()],
        }];
        let scale = [s, d];
        let start = moments(&lines, &[0.01 * s, d]).expect("the drive's noise shows");
        let (near, near_likelihood) = maximise_from(&lines, None, start, &scale, true);
        let (far, far_likelihood) = maximise_from(&lines, None, vec![0.01 * s, d], &scale, true);
        for (a, b) in near.iter().zip(&far) {
            assert!((a - b).abs() < 1e-12 * a.abs(), "{near:?} against {far:?}");
        }
        assert!((near_likelihood - far_likelihood).abs() < 1e-12 * near_likelihood.abs());
    }

    /// The closed form of a line whose Σ is diagonal plus rank one gives the general
    /// factorisation's likelihood, score and both informations, for three channels in
    /// two groups, with and without the drive's noise.
    #[test]
    fn the_rank_one_line_is_the_general_one() {
        let size = 16;
        let wave = |k: usize, a: usize, f: f64| {
            Complex64::new((f * (k + a) as f64).sin(), (0.7 * f * (k * a) as f64).cos())
        };
        let lines = Lines {
            size,
            groups: vec![0, 1, 1],
            residual: (0..3)
                .map(|a| (0..size).map(|k| wave(k, a, 0.9)).collect())
                .collect(),
            transfer: (0..3)
                .map(|a| {
                    (0..size)
                        .map(|k| wave(k, a, 0.4) * (1.0 + a as f64))
                        .collect()
                })
                .collect(),
        };
        for v in [[0.7, 0.4, 1.3], [0.0, 0.2, 2.5]] {
            let fresh = || Evaluation {
                log_likelihood: 0.0,
                score: vec![0.0; 3],
                fisher: DMatrix::zeros(3, 3),
                observed: DMatrix::zeros(3, 3),
            };
            for k in 1..size / 2 {
                let (mut general, mut closed) = (fresh(), fresh());
                let mut work = Work {
                    matrices: vec![Vec::new(); 3],
                    factor: Vec::new(),
                    inverse: Vec::new(),
                    parts: vec![Vec::new(); 3],
                    images: vec![Vec::new(); 3],
                    solved: vec![Vec::new(); 3],
                    y: Vec::new(),
                    residual: (0..3).map(|a| lines.residual[a][k]).collect(),
                    sums: GroupSums::default(),
                };
                noise_matrices(&lines, k, &mut work.matrices);
                assert!(accumulate(&v, &mut work, &mut general));
                assert!(accumulate_rank_one(
                    &lines,
                    k,
                    &v,
                    &mut work.sums,
                    &mut closed
                ));
                let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * a.abs().max(1.0);
                assert!(
                    close(general.log_likelihood, closed.log_likelihood),
                    "line {k}"
                );
                for q in 0..3 {
                    assert!(
                        close(general.score[q], closed.score[q]),
                        "line {k}, score {q}"
                    );
                    for r in 0..3 {
                        let (f, o) = ((q, r), (q, r));
                        assert!(
                            close(general.fisher[f], closed.fisher[f]),
                            "line {k}, F {q}{r}"
                        );
                        assert!(
                            close(general.observed[o], closed.observed[o]),
                            "line {k}, O {q}{r}"
                        );
                    }
                }
            }
        }
    }
}
