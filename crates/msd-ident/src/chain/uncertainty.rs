//! The uncertainty of a chain at a point θ from the weighted Jacobian there: the
//! intervals of every m, c, k, the modes, the delays, and what the records cannot tell
//! apart. Shared by the fit (σ̂² from its residuals) and the plan (σ² = 1: the Jacobian is
//! weighted by the true noise levels).

use super::modes::modes_with_intervals;
use super::problem::Layout;
use super::setup::{ChainParameters, ChainSetup};
use crate::uncertainty::t_975;
use msd_modal_core::Mode;
use msd_opt::statistics::Interval;
use msd_opt::statistics::{Linearization, SINGULAR_CONDITION, correlation};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// m_i, c_i and k_i with their 95 % intervals (a known mass with a zero standard error).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainIntervals {
    /// The masses, kg.
    pub masses: Vec<Interval>,
    /// The dampers, N·s/m.
    pub dampers: Vec<Interval>,
    /// The springs, N/m.
    pub springs: Vec<Interval>,
    /// The extra dampers to the ground, N·s/m (none when the chain has none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub ground_dampers: Vec<Interval>,
    /// The extra springs to the ground, N/m, likewise.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub ground_springs: Vec<Interval>,
}

/// The uncertainty of a chain's parameters at one point: from a fit's records
/// ([`ChainFit`](super::ChainFit)) or predicted before the test ([`predict_chain`](super::predict_chain)).
///
/// Displays every m, c, k with its interval (or what is lost), the modes, the delays,
/// then the degrees of freedom and the condition number.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainUncertainty {
    /// The intervals, when the records identify every parameter; `None` otherwise (see
    /// `unidentifiable`).
    pub intervals: Option<ChainIntervals>,
    /// The combinations of parameters the records cannot tell apart, in words (empty when
    /// all are identified).
    pub unidentifiable: Vec<String>,
    /// The modes, by frequency, with intervals (delta method). They are identified even
    /// where the physical parameters are not.
    pub modes: Vec<Mode>,
    /// Each sensor's estimated delay, s (`None` where it is not estimated).
    pub delays: Vec<Option<Interval>>,
    /// Each sensor's estimated filter cut-off, Hz (`None` where it is not estimated).
    pub cutoffs: Vec<Option<Interval>>,
    /// The estimated quantities ("m1", "c2", "delay1", …), in the order of `correlation`.
    pub names: Vec<String>,
    /// Their correlation (of the logarithms for m, c, k).
    pub correlation: Vec<Vec<f64>>,
    /// Condition number of the column-scaled JᵀJ.
    pub condition_number: f64,
    /// Samples × channels − estimated quantities.
    pub degrees_of_freedom: usize,
}

impl std::fmt::Display for ChainUncertainty {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.intervals {
            Some(iv) => {
                for (i, ((m, c), k)) in iv
                    .masses
                    .iter()
                    .zip(&iv.dampers)
                    .zip(&iv.springs)
                    .enumerate()
                {
                    writeln!(f, "m{} = {m:.6} kg", i + 1)?;
                    writeln!(f, "c{} = {c:.6} N·s/m", i + 1)?;
                    writeln!(f, "k{} = {k:.6} N/m", i + 1)?;
                }
                for i in 0..iv.masses.len() {
                    let (c, k) = (iv.ground_dampers.get(i), iv.ground_springs.get(i));
                    if let Some(c) = c.filter(|c| c.value > 0.0) {
                        writeln!(f, "cg{} = {c:.6} N·s/m (to the ground)", i + 1)?;
                    }
                    if let Some(k) = k.filter(|k| k.value > 0.0) {
                        writeln!(f, "kg{} = {k:.6} N/m (to the ground)", i + 1)?;
                    }
                }
            }
            None => {
                writeln!(f, "m, c, k: not identified from these records")?;
                for reason in &self.unidentifiable {
                    writeln!(f, "  {reason}")?;
                }
            }
        }
        for (i, mode) in self.modes.iter().enumerate() {
            writeln!(f, "mode {}: {mode}", i + 1)?;
        }
        for (i, delay) in self.delays.iter().enumerate() {
            if let Some(d) = delay {
                writeln!(f, "delay of sensor {} = {d:.6} s", i + 1)?;
            }
        }
        for (i, cutoff) in self.cutoffs.iter().enumerate() {
            if let Some(c) = cutoff {
                writeln!(f, "filter cut-off of sensor {} = {c:.4} Hz", i + 1)?;
            }
        }
        write!(
            f,
            "{} degrees of freedom, condition number {:.3e}",
            self.degrees_of_freedom, self.condition_number
        )
    }
}

/// A point θ of a chain's fit: the layout and what θ does not hold.
pub(crate) struct Point<'a> {
    pub setup: &'a ChainSetup,
    pub layout: &'a Layout,
    pub theta: &'a [f64],
    pub base: &'a ChainParameters,
    pub delays: &'a [f64],
}

/// The uncertainty at `at` from the weighted `jacobian` there, σ² = `s2` and `dof`; or,
/// where the records identify every quantity and `reported` is given, from that
/// covariance of θ with a t of its degrees of freedom (a noise model's sandwich).
pub(crate) fn uncertainty_at(
    at: &Point<'_>,
    jacobian: &DMatrix<f64>,
    s2: f64,
    dof: usize,
    reported: Option<(&DMatrix<f64>, usize)>,
) -> ChainUncertainty {
    let layout = at.layout;
    let (parameters, delays) = layout.unpack(at.theta, at.base, at.delays);
    let t = t_975(reported.map_or(dof, |(_, nu)| nu));
    let (covariance, condition_number, unidentifiable) = match Linearization::new(jacobian) {
        Ok(lin) => (
            reported.map_or_else(|| lin.covariance(s2), |(c, _)| c.clone()),
            lin.condition_number,
            Vec::new(),
        ),
        Err(_) => pseudo_covariance(jacobian, s2, layout),
    };
    let se = |j: usize| covariance[(j, j)].max(0.0).sqrt();
    let mut unidentifiable = unidentifiable;
    unidentifiable.extend(loose(layout, &covariance));
    let intervals = unidentifiable
        .is_empty()
        .then(|| intervals(layout, &parameters, &se, t));
    let delay_intervals = (0..at.setup.sensors.len())
        .map(|ch| {
            layout.delayed.iter().position(|&d| d == ch).map(|j| {
                let col = layout.simulated() + j;
                Interval::new(delays[ch], se(col), t)
            })
        })
        .collect();
    let setup = layout.setup_at(at.theta, at.setup);
    let cutoffs = (0..at.setup.sensors.len())
        .map(|ch| {
            let j = layout.cutoffs.iter().position(|&(c, _)| c == ch)?;
            let hz = setup.sensors[ch].low_pass?.cutoff_hz;
            Some(Interval::positive(hz, hz * se(layout.free.len() + j), t))
        })
        .collect();
    let mut modes = modes_with_intervals(layout, at.theta, at.base, at.delays, &covariance, t);
    let all = modes.len();
    modes.retain(bounded);
    if modes.len() < all {
        unidentifiable.push(format!(
            "{} of the {all} modes have intervals that are not finite, or no width at all: the records do not fix them; not reported",
            all - modes.len()
        ));
    }
    let correlation = correlation(&covariance);
    ChainUncertainty {
        intervals,
        unidentifiable,
        modes,
        delays: delay_intervals,
        cutoffs,
        names: (0..layout.len()).map(|j| layout.name(j)).collect(),
        // Not computable where a variance is not finite: empty, never NaN.
        correlation: if correlation.iter().all(|v| v.is_finite()) {
            (correlation.row_iter())
                .map(|r| r.iter().copied().collect())
                .collect()
        } else {
            Vec::new()
        },
        condition_number,
        degrees_of_freedom: dof,
    }
}

/// The largest standard error of a logarithm an identified parameter may have: its 95 %
/// interval then spans a factor e^±20 (5e8) already; beyond, nothing is fixed.
const MAX_LOG_SE: f64 = 10.0;

/// The parameters the records do not fix, in words: a variance not finite, or a standard
/// error of the logarithm above [`MAX_LOG_SE`].
fn loose(layout: &Layout, covariance: &DMatrix<f64>) -> Option<String> {
    let names: Vec<String> = (0..layout.free.len())
        .filter(|&j| {
            let v = covariance[(j, j)];
            v.is_nan() || v > MAX_LOG_SE * MAX_LOG_SE
        })
        .map(|j| layout.name(j))
        .collect();
    (!names.is_empty()).then(|| {
        format!(
            "the records do not fix {}: the standard errors of their logarithms exceed {MAX_LOG_SE} or are not finite (the sensors see too little of them)",
            names.join(", ")
        )
    })
}

/// Whether every number of a mode's intervals is finite, and its frequency and damping
/// ratio are fixed by the records (a standard error of exactly zero under the
/// pseudo-inverse means the mode moves only along directions the records lose).
fn bounded(mode: &Mode) -> bool {
    let finite = |iv: &Interval| {
        iv.value.is_finite()
            && iv.standard_error.is_finite()
            && iv.standard_error > 0.0
            && iv.ci95.iter().all(|v| v.is_finite())
    };
    finite(&mode.natural_frequency_hz)
        && finite(&mode.damping_ratio)
        && (mode.shape.iter()).all(|e| {
            e.re.is_finite()
                && e.im.is_finite()
                && e.standard_error
                    .is_none_or(|se| se.iter().all(|v| v.is_finite()))
        })
}

/// Every m, c, k with its interval, computed on its logarithm (a known mass exact).
fn intervals(
    layout: &Layout,
    parameters: &ChainParameters,
    se: &dyn Fn(usize) -> f64,
    t: f64,
) -> ChainIntervals {
    use super::model::Family::{self, Damper, GroundDamper, GroundSpring, Mass, Spring};
    let each = |family: Family, values: &[f64]| {
        values
            .iter()
            .enumerate()
            .map(
                |(i, &value)| match layout.free.iter().position(|&c| c == (family, i)) {
                    // A spring or damper to the ground may be absent: its interval is on
                    // the value itself and stops at zero, so that it can reach it.
                    Some(j) if matches!(family, GroundDamper | GroundSpring) => {
                        let mut iv = Interval::new(value, value * se(j), t);
                        iv.ci95[0] = iv.ci95[0].max(0.0);
                        iv
                    }
                    // The log's standard error times the value; the interval on the log.
                    Some(j) => Interval::positive(value, value * se(j), t),
                    None => Interval::new(value, 0.0, t),
                },
            )
            .collect()
    };
    ChainIntervals {
        masses: each(Mass, &parameters.masses),
        dampers: each(Damper, &parameters.dampers),
        springs: each(Spring, &parameters.springs),
        ground_dampers: each(GroundDamper, &parameters.ground_dampers),
        ground_springs: each(GroundSpring, &parameters.ground_springs),
    }
}

/// The covariance on the identifiable subspace (the pseudo-inverse), the condition
/// number, and the lost directions in words: first whether scaling every m, c and k
/// together is among them (a base drive with no known mass), then each other one.
fn pseudo_covariance(
    jacobian: &DMatrix<f64>,
    s2: f64,
    layout: &Layout,
) -> (DMatrix<f64>, f64, Vec<String>) {
    let p = jacobian.ncols();
    let norms: Vec<f64> = (0..p)
        .map(|j| jacobian.column(j).norm().max(f64::MIN_POSITIVE))
        .collect();
    let scaled = DMatrix::from_fn(jacobian.nrows(), p, |r, c| jacobian[(r, c)] / norms[c]);
    let svd = scaled.svd(false, true);
    let Some(v_t) = svd.v_t else {
        return (
            DMatrix::zeros(p, p),
            f64::INFINITY,
            vec!["the sensitivities cannot be decomposed".into()],
        );
    };
    let largest = svd.singular_values.max();
    let cutoff = largest / SINGULAR_CONDITION.sqrt();
    let mut covariance = DMatrix::zeros(p, p);
    let mut null: Vec<DVector<f64>> = Vec::new();
    for (i, &sv) in svd.singular_values.iter().enumerate() {
        let v = v_t.row(i).transpose();
        if sv > cutoff {
            for r in 0..p {
                for c in 0..p {
                    covariance[(r, c)] += s2 * v[r] * v[c] / (sv * sv * norms[r] * norms[c]);
                }
            }
        } else {
            null.push(v);
        }
    }
    let smallest = svd.singular_values.min();
    let condition = (largest / smallest).powi(2);
    (covariance, condition, lost_in_words(null, &norms, layout))
}

/// The null directions (orthonormal, in column-scaled coordinates) in words.
pub(super) fn lost_in_words(
    mut null: Vec<DVector<f64>>,
    norms: &[f64],
    layout: &Layout,
) -> Vec<String> {
    let free = layout.free.len();
    // The common scale: δ(ln p) = 1 for every free m, c, k.
    let mut scale = DVector::from_fn(norms.len(), |j, _| if j < free { norms[j] } else { 0.0 });
    scale /= scale.norm();
    let captured: f64 = null.iter().map(|v| v.dot(&scale).powi(2)).sum();
    let mut words = Vec::new();
    if (captured - 1.0).abs() < 1e-6 {
        words.push(
            "every free m, c and k scaled by one factor leaves the records unchanged: give a known mass (known_masses) to set the scale".to_string(),
        );
        // The rest of the null space, orthogonal to the scale.
        let projected: Vec<DVector<f64>> =
            null.iter().map(|v| v - &scale * v.dot(&scale)).collect();
        let basis = DMatrix::from_columns(&projected);
        let svd = basis.svd(true, false);
        null = match svd.u {
            Some(u) => (0..svd.singular_values.len())
                .filter(|&i| svd.singular_values[i] > 0.5)
                .map(|i| u.column(i).clone_owned())
                .collect(),
            None => Vec::new(),
        };
    }
    for v in null {
        let theta: Vec<f64> = v.iter().zip(norms).map(|(x, n)| x / n).collect();
        words.push(direction_in_words(&theta, layout));
    }
    words
}

/// A direction δθ (in logarithms) along which the records do not change, as the
/// product of powers it leaves unfixed: "m1^1.00 · k2^-0.50 …".
fn direction_in_words(v: &[f64], layout: &Layout) -> String {
    let top = v.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let terms: Vec<String> = v
        .iter()
        .enumerate()
        .filter(|(_, x)| x.abs() > 1e-2 * top)
        .map(|(j, x)| format!("{}^{:.2}", layout.name(j), x / top))
        .collect();
    format!(
        "the records do not change when these move together (each by one factor to the power shown): {}",
        terms.join(" · ")
    )
}
