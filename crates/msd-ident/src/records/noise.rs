//! The sensors' noise levels: a first guess from the data alone, then the maximum
//! likelihood estimate from the residuals, each sensor its share of the degrees of
//! freedom.

use super::ChannelNoise;
use super::problem::Joint;

/// A first noise level per sensor from the median absolute second difference (its
/// variance is 6σ² for white noise on a smooth signal), so that sensors in different
/// units start with sensible weights.
pub(super) fn initial_sigmas(problem: &Joint<'_>) -> Vec<f64> {
    (0..problem.group_names.len())
        .map(|g| {
            let mut d2 = Vec::new();
            let mut scale = 0.0f64;
            for rec in &problem.records {
                for (ch, channel) in rec.record.channels.iter().enumerate() {
                    if rec.groups[ch] == g {
                        d2.extend(
                            channel
                                .samples
                                .windows(3)
                                .map(|w| (w[2] - 2.0 * w[1] + w[0]).abs()),
                        );
                        scale = channel.samples.iter().fold(scale, |s, v| s.max(v.abs()));
                    }
                }
            }
            let mid = d2.len() / 2;
            let median = *d2.select_nth_unstable_by(mid, f64::total_cmp).1;
            floor(median / (0.674_489_75 * 6f64.sqrt()), scale)
        })
        .collect()
}

/// A noise level of at least 1e-12 of the channel's scale (a noise-free record would
/// otherwise give an infinite weight).
fn floor(sigma: f64, scale: f64) -> f64 {
    sigma.max(1e-12 * scale).max(f64::MIN_POSITIVE)
}

/// σ̂ of each group: √(SSE / (N·(N_total − p)/N_total)), each sensor its share of the
/// degrees of freedom.
pub(super) fn residual_sigmas(problem: &Joint<'_>, dof: usize) -> Vec<f64> {
    let groups = problem.group_names.len();
    let (mut sse, mut count, mut scale) = (
        vec![0.0; groups],
        vec![0usize; groups],
        vec![0.0f64; groups],
    );
    for rec in &problem.records {
        for (ch, channel) in rec.record.channels.iter().enumerate() {
            let g = rec.groups[ch];
            for (i, y) in channel.samples.iter().enumerate() {
                sse[g] += (y - problem.model(rec, ch, i)).powi(2);
                scale[g] = scale[g].max(y.abs());
            }
            count[g] += rec.len;
        }
    }
    let share = dof as f64 / problem.rows as f64;
    (0..groups)
        .map(|g| floor((sse[g] / (count[g] as f64 * share)).sqrt(), scale[g]))
        .collect()
}

pub(super) fn noise_levels(problem: &Joint<'_>, sigma: &[f64]) -> Vec<ChannelNoise> {
    problem
        .group_names
        .iter()
        .enumerate()
        .map(|(g, name)| ChannelNoise {
            channel: name.clone(),
            sigma: sigma[g],
            samples: problem
                .records
                .iter()
                .map(|r| r.len * r.groups.iter().filter(|&&x| x == g).count())
                .sum(),
        })
        .collect()
}
