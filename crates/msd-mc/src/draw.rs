//! Per-sample random generators and parameter draws.
//!
//! Sample i of a run with seed s draws from `ChaCha8Rng::seed_from_u64(s)` switched to
//! stream i (`set_stream(i)`): its draw depends on (s, i) only, never on the thread that
//! runs it or how the samples are chunked.

use crate::{
    error::{McError, Result},
    options::Sampling,
};
use msd_ident::Parameters;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// How many times a non-physical covariance draw is redrawn before the sample fails.
pub const MAX_REDRAWS: usize = 100;

/// The generator of sample (or row, or resample) `stream` of a run seeded with `seed`.
///
/// ```
/// use rand::Rng;
/// let a: f64 = msd_mc::sample_rng(7, 3).random();
/// let b: f64 = msd_mc::sample_rng(7, 3).random();
/// assert_eq!(a, b);
/// ```
pub fn sample_rng(seed: u64, stream: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    rng
}

/// A lower-triangular L with L Lᵀ = covariance, tolerating zero pivots (fixed
/// parameters): a pivot within 1e-12 of the diagonal's scale counts as zero and its
/// column below is set to zero.
pub(crate) fn cholesky(covariance: &[[f64; 3]; 3]) -> Result<[[f64; 3]; 3]> {
    let scale = (0..3).map(|i| covariance[i][i].abs()).fold(0.0, f64::max);
    for (r, c) in (0..3).flat_map(|r| (0..3).map(move |c| (r, c))) {
        let (a, b) = (covariance[r][c], covariance[c][r]);
        if !a.is_finite() || (a - b).abs() > 1e-12 * scale.max(f64::MIN_POSITIVE) {
            return Err(McError::NotPositiveSemidefinite {
                pivot: r,
                value: a - b,
            });
        }
    }
    let tolerance = 1e-12 * scale;
    let mut l = [[0.0; 3]; 3];
    for j in 0..3 {
        let d = covariance[j][j] - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>();
        if d < -tolerance || d.is_nan() {
            return Err(McError::NotPositiveSemidefinite { pivot: j, value: d });
        }
        if d <= tolerance {
            continue;
        }
        l[j][j] = d.sqrt();
        for i in (j + 1)..3 {
            let s = covariance[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>();
            l[i][j] = s / l[j][j];
        }
    }
    Ok(l)
}

/// A prepared sampler: the nominal values and either the uniform half-width or L.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Sampler {
    Uniform { nominal: [f64; 3], fraction: f64 },
    Normal { nominal: [f64; 3], l: [[f64; 3]; 3] },
}

impl Sampler {
    pub(crate) fn new(nominal: &Parameters, sampling: &Sampling) -> Result<Self> {
        let nominal = nominal.to_array();
        Ok(match *sampling {
            Sampling::Uniform { percent } => Sampler::Uniform {
                nominal,
                fraction: percent / 100.0,
            },
            Sampling::Covariance { covariance, scale } => {
                let mut l = cholesky(&covariance)?;
                l.iter_mut().flatten().for_each(|v| *v *= scale);
                Sampler::Normal { nominal, l }
            }
        })
    }

    /// The parameters of sample `index`, or `None` when every redraw was non-physical.
    pub(crate) fn draw(&self, seed: u64, index: usize) -> Option<Parameters> {
        let mut rng = sample_rng(seed, index as u64);
        match *self {
            Sampler::Uniform { nominal, fraction } => {
                let theta =
                    nominal.map(|v| v * (1.0 + fraction * (2.0 * rng.random::<f64>() - 1.0)));
                Some(Parameters::from_array(theta))
            }
            Sampler::Normal { nominal, l } => (0..=MAX_REDRAWS).find_map(|_| {
                let z: [f64; 3] = std::array::from_fn(|_| rng.sample(StandardNormal));
                let theta: [f64; 3] = std::array::from_fn(|r| {
                    nominal[r] + (0..=r).map(|c| l[r][c] * z[c]).sum::<f64>()
                });
                let p = Parameters::from_array(theta);
                p.validate().is_ok().then_some(p)
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_reproduces_the_covariance_and_tolerates_a_fixed_parameter() {
        let cov = [[4.0, 0.0, 2.0], [0.0, 0.0, 0.0], [2.0, 0.0, 5.0]];
        let l = cholesky(&cov).unwrap();
        for r in 0..3 {
            for c in 0..3 {
                let v: f64 = (0..3).map(|k| l[r][k] * l[c][k]).sum();
                assert!((v - cov[r][c]).abs() < 1e-14, "({r},{c})");
            }
        }
        let bad = [[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert!(matches!(
            cholesky(&bad),
            Err(McError::NotPositiveSemidefinite { pivot: 1, .. })
        ));
    }

    #[test]
    fn uniform_draws_stay_within_the_band() {
        let sampler =
            Sampler::new(&Parameters::PAPER, &Sampling::Uniform { percent: 10.0 }).unwrap();
        for i in 0..500 {
            let p = sampler.draw(3, i).unwrap().to_array();
            for (v, n) in p.iter().zip(Parameters::PAPER.to_array()) {
                assert!((v / n - 1.0).abs() <= 0.1);
            }
        }
    }
}
