//! The stabilization diagram: the poles of every model order, flagged where they agree
//! with the order before, and the modes that stay stable.

use std::f64::consts::TAU;

use msd_signal::{Complex64, FrequencyResponseEstimate};

use crate::lscf::{Lscf, roots_of};
use crate::options::ModalOptions;
use msd_modal_core::diagram::{DiagramOrder, DiagramPole, StabilizationDiagram, StableColumn};
use msd_modal_core::error::{ModalError, Result};
use msd_modal_core::lines::{Lines, prepare};

/// The stabilization diagram of `frf` and the modes selected from it (see
/// [`ModalOptions`] for the orders, the tolerances and the selection).
///
/// ## The method
/// Poles by LSCF (the least-squares complex-frequency estimator: a common-denominator
/// model in e^{jωΔt} with real coefficients, solved from its reduced normal equations)
/// at every order; the physical ones are kept. A pole is stable in frequency (in damping)
/// when the nearest pole of the order before has fn (ζ) within the tolerance; stable
/// when both. The stable poles, sorted by frequency, form a new group where the gap to
/// the previous one exceeds the frequency tolerance; a group is a mode when it is
/// stable at `min_stable_share` of the orders (or, with `mode_count`, the groups
/// stable at the most orders). A mode's fn and ζ are the medians of its poles.
///
/// Errors: too few lines for the largest order, bad options, `Variance` weighting
/// without variances, fewer stable modes than `mode_count`
/// ([`ModalError::TooFewModes`](ModalError::TooFewModes), which keeps the diagram).
///
/// ```
/// use msd_modal::{ModalOptions, stabilization_diagram, ModalParameters};
/// use msd_signal::FrequencyResponseEstimate;
/// let modes = [(8.0, 0.02, 1.0), (17.0, 0.01, -0.5)].map(|(f, z, a)| ModalParameters {
///     natural_frequency_hz: f, damping_ratio: z, modal_constant: a, modal_constant_imaginary: 0.0 });
/// let f: Vec<f64> = (1..=1000).map(|i| 0.025 * i as f64).collect();
/// let h = f.iter().map(|&f| modes.iter().map(|m| m.receptance(f)).sum()).collect();
/// let diagram = stabilization_diagram(&FrequencyResponseEstimate::new(f, h)?, &ModalOptions::default())?;
/// assert_eq!(diagram.modes.len(), 2);
/// assert!((diagram.modes[1].natural_frequency_hz / 17.0 - 1.0).abs() < 1e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// Order by order, a pole of the diagram:
///
/// ```
/// use msd_modal::{ModalOptions, stabilization_diagram, synthetic_frequency_response, ModalParameters};
/// let mode = ModalParameters { natural_frequency_hz: 5.0, damping_ratio: 0.03,
///     modal_constant: 1.0, modal_constant_imaginary: 0.0 };
/// let f: Vec<f64> = (1..=200).map(|i| 0.05 * i as f64).collect();
/// let frf = synthetic_frequency_response(&f, 0.0, 1, |f| mode.receptance(f))?;
/// let diagram = stabilization_diagram(&frf, &ModalOptions { orders: [2, 10], ..ModalOptions::default() })?;
/// // The z-domain model needs a little more than the mode's two poles: order 2 puts it
/// // at 5.003 Hz (ζ = 0.0286), order 4 at 4.9997 Hz (ζ = 0.03002: stable in frequency,
/// // not yet in damping), order 6 at 5.00002 Hz, the first stable in both.
/// let order_6 = &diagram.orders[2];
/// assert_eq!(order_6.order, 6);
/// let pole = order_6.poles.iter().find(|p| p.stable).expect("the mode is stable");
/// assert!((pole.natural_frequency_hz / 5.0 - 1.0).abs() < 1e-4);
/// assert!(diagram.orders[1].poles.iter().all(|p| p.stable_frequency && !p.stable));
/// assert_eq!(diagram.modes.len(), 1);
/// assert_eq!(diagram.modes[0].stable_orders, 4); // stable in frequency at orders 4 to 10
/// # Ok::<(), msd_modal::ModalError>(())
/// ```
///
/// Displayed (one line per selected mode) and serialized with every order's poles:
///
/// ```
/// use msd_modal::{ModalOptions, stabilization_diagram, synthetic_frequency_response, ModalParameters};
/// let mode = ModalParameters { natural_frequency_hz: 5.0, damping_ratio: 0.03,
///     modal_constant: 1.0, modal_constant_imaginary: 0.0 };
/// let f: Vec<f64> = (1..=200).map(|i| 0.05 * i as f64).collect();
/// let frf = synthetic_frequency_response(&f, 0.01, 1, |f| mode.receptance(f))?;
/// let diagram = stabilization_diagram(&frf, &ModalOptions::default())?;
/// assert!(diagram.to_string().starts_with("stabilization diagram, orders 2–40"));
/// let json = serde_json::to_value(&diagram).expect("serializable");
/// assert_eq!(json["orders"].as_array().map(Vec::len), Some(20));
/// # Ok::<(), msd_modal::ModalError>(())
/// ```
pub fn stabilization_diagram(
    frf: &FrequencyResponseEstimate,
    options: &ModalOptions,
) -> Result<StabilizationDiagram> {
    options.validate()?;
    let lines = prepare(
        frf,
        options.band_hz,
        options.weighting,
        options.orders[1] + 1,
    )?;
    diagram_of(&lines, options)
}

/// The diagram of prepared lines (options validated, enough lines).
pub(crate) fn diagram_of(lines: &Lines, options: &ModalOptions) -> Result<StabilizationDiagram> {
    let lscf = Lscf::new(lines, options.orders[1]);
    diagram_from(
        |order, warm| lscf.roots(order, warm),
        lscf.dt(),
        lines,
        options,
    )
}

/// The diagram of several frequency responses sharing one denominator (their lines on
/// one axis): the poles of the summed reduced normal matrices; `peaks` the lines whose
/// magnitude shows the modes (the sum of the responses' magnitudes).
pub(crate) fn diagram_of_set(
    lines: &[Lines],
    peaks: &Lines,
    options: &ModalOptions,
) -> Result<StabilizationDiagram> {
    let lscfs: Vec<Lscf> = lines
        .iter()
        .map(|l| Lscf::new(l, options.orders[1]))
        .collect();
    let dt = lscfs[0].dt();
    let roots = |order: usize, warm: Option<&[Complex64]>| {
        let mut sum = lscfs[0].reduced(order)?;
        for l in &lscfs[1..] {
            sum += l.reduced(order)?;
        }
        roots_of(sum, order, warm)
    };
    diagram_from(roots, dt, peaks, options)
}

/// The diagram from the denominator's roots z of each order (each order's from the
/// roots of the order before, when there is one), the poles ln(z)/Δt; `lines` give the
/// band and the peaks.
fn diagram_from(
    roots_at: impl Fn(usize, Option<&[Complex64]>) -> Option<Vec<Complex64>>,
    dt: f64,
    lines: &Lines,
    options: &ModalOptions,
) -> Result<StabilizationDiagram> {
    let mut orders: Vec<DiagramOrder> = Vec::new();
    let mut previous_roots: Option<Vec<Complex64>> = None;
    for order in (options.orders[0]..=options.orders[1]).step_by(options.order_step) {
        let Some(roots) = roots_at(order, previous_roots.as_deref()) else {
            continue;
        };
        let mut poles: Vec<DiagramPole> = roots
            .iter()
            .filter_map(|&z| physical(z.ln() / dt, lines.band_hz, options.max_damping_ratio))
            .collect();
        previous_roots = Some(roots);
        poles.sort_by(|a, b| a.natural_frequency_hz.total_cmp(&b.natural_frequency_hz));
        if let Some(previous) = orders.last() {
            flag(&mut poles, &previous.poles, options);
        }
        orders.push(DiagramOrder { order, poles });
    }
    if orders.is_empty() {
        return Err(ModalError::NotIdentifiable {
            reason: "the LSCF normal equations are singular at every order".into(),
        });
    }
    let (candidates, modes, shortfall) = select(&orders, lines, options);
    let diagram = StabilizationDiagram {
        orders,
        candidates,
        modes,
        band_hz: lines.band_hz,
    };
    match shortfall {
        Some(reason) => Err(ModalError::TooFewModes {
            reason,
            diagram: Box::new(diagram),
        }),
        None => Ok(diagram),
    }
}

/// The pole λ as a diagram pole (unflagged) if it is physical.
fn physical(lambda: Complex64, band_hz: [f64; 2], max_damping: f64) -> Option<DiagramPole> {
    let f = lambda.norm() / TAU;
    let zeta = -lambda.re / lambda.norm();
    let inside = f >= band_hz[0] && f <= band_hz[1];
    (lambda.im > 0.0 && zeta > 0.0 && zeta <= max_damping && inside).then_some(DiagramPole {
        natural_frequency_hz: f,
        damping_ratio: zeta,
        stable_frequency: false,
        stable_damping: false,
        stable: false,
        mode: None,
    })
}

/// Flags each pole against the nearest pole (in frequency) of the order before.
fn flag(poles: &mut [DiagramPole], previous: &[DiagramPole], options: &ModalOptions) {
    for pole in poles {
        let nearest = previous.iter().min_by(|a, b| {
            let da = (a.natural_frequency_hz - pole.natural_frequency_hz).abs();
            let db = (b.natural_frequency_hz - pole.natural_frequency_hz).abs();
            da.total_cmp(&db)
        });
        if let Some(p) = nearest {
            let df = (pole.natural_frequency_hz / p.natural_frequency_hz - 1.0).abs();
            let dz = (pole.damping_ratio / p.damping_ratio - 1.0).abs();
            pole.stable_frequency = df <= options.frequency_tolerance;
            pole.stable_damping = dz <= options.damping_tolerance;
            pole.stable = pole.stable_frequency && pole.stable_damping;
        }
    }
}

/// Groups the poles stable in frequency into modes and selects those the data show:
/// the candidates, the selected modes, and why they are too few for `mode_count`.
fn select(
    orders: &[DiagramOrder],
    lines: &Lines,
    options: &ModalOptions,
) -> (Vec<StableColumn>, Vec<StableColumn>, Option<String>) {
    let mut stable: Vec<(usize, DiagramPole)> = orders
        .iter()
        .flat_map(|o| {
            o.poles
                .iter()
                .filter(|p| p.stable_frequency)
                .map(move |p| (o.order, *p))
        })
        .collect();
    stable.sort_by(|a, b| {
        a.1.natural_frequency_hz
            .total_cmp(&b.1.natural_frequency_hz)
    });
    let groups = columns(&stable, options.frequency_tolerance);
    let mut candidates: Vec<StableColumn> = groups.iter().map(|g| summarise(g)).collect();
    for m in &mut candidates {
        m.at_peak = lines.has_peak(m.natural_frequency_hz, m.damping_ratio);
    }
    let mut modes: Vec<StableColumn> = candidates.iter().copied().filter(|m| m.at_peak).collect();
    let mut shortfall = None;
    match options.mode_count {
        Some(count) if modes.len() < count => {
            shortfall = Some(format!(
                "the stabilization diagram has {} stable modes at a peak of the data, {count} were asked for{}",
                modes.len(),
                explain(&candidates, orders.len(), options)
            ));
        }
        Some(count) => {
            modes.sort_by_key(|m| std::cmp::Reverse(m.stable_orders));
            modes.truncate(count);
        }
        None => {
            let needed = (options.min_stable_share * orders.len() as f64).ceil() as usize;
            modes.retain(|m| m.stable_orders >= needed.max(1));
        }
    }
    modes.sort_by(|a, b| a.natural_frequency_hz.total_cmp(&b.natural_frequency_hz));
    (candidates, modes, shortfall)
}

/// The columns of the diagram: poles (sorted by frequency) gathered around seeds, the
/// densest first. A pole's density is the number of orders with a pole within `tolerance`
/// of it; each unassigned pole, densest first (then least damped), takes every unassigned
/// pole within `tolerance`, and keeps the nearest of each order. Unlike chaining poles
/// whose gaps are below the tolerance, a real mode's column is not merged with the
/// scattered poles of noise around it.
fn columns(poles: &[(usize, DiagramPole)], tolerance: f64) -> Vec<Vec<(usize, DiagramPole)>> {
    let f = |i: usize| poles[i].1.natural_frequency_hz;
    let window = |i: usize| {
        let lo = poles.partition_point(|p| p.1.natural_frequency_hz < f(i) * (1.0 - tolerance));
        let hi = poles.partition_point(|p| p.1.natural_frequency_hz <= f(i) * (1.0 + tolerance));
        lo..hi
    };
    let distinct_orders = |members: &mut Vec<usize>| {
        members.sort_unstable();
        members.dedup();
        members.len()
    };
    let density: Vec<usize> = (0..poles.len())
        .map(|i| distinct_orders(&mut window(i).map(|j| poles[j].0).collect()))
        .collect();
    let mut seeds: Vec<usize> = (0..poles.len()).collect();
    seeds.sort_by(|&a, &b| {
        density[b]
            .cmp(&density[a])
            .then(
                poles[a]
                    .1
                    .damping_ratio
                    .total_cmp(&poles[b].1.damping_ratio),
            )
            .then(a.cmp(&b))
    });
    let mut taken = vec![false; poles.len()];
    let mut groups = Vec::new();
    for seed in seeds {
        if taken[seed] {
            continue;
        }
        let mut nearest: Vec<(usize, usize)> = Vec::new(); // (order, pole index)
        for j in window(seed) {
            if taken[j] {
                continue;
            }
            taken[j] = true;
            let distance = |k: usize| (f(k) - f(seed)).abs();
            match nearest.iter_mut().find(|(o, _)| *o == poles[j].0) {
                Some(entry) if distance(j) < distance(entry.1) => entry.1 = j,
                Some(_) => {}
                None => nearest.push((poles[j].0, j)),
            }
        }
        let mut group: Vec<(usize, DiagramPole)> = nearest.iter().map(|&(_, j)| poles[j]).collect();
        group.sort_by_key(|(order, _)| *order);
        groups.push(group);
    }
    groups.sort_by(|a, b| {
        a[0].1
            .natural_frequency_hz
            .total_cmp(&b[0].1.natural_frequency_hz)
    });
    groups
}

/// Why a selection found too few modes: the candidate columns, where they are, and the
/// keys that change the outcome.
fn explain(candidates: &[StableColumn], orders: usize, options: &ModalOptions) -> String {
    let at_peaks: Vec<StableColumn> = candidates.iter().copied().filter(|m| m.at_peak).collect();
    let needed = (options.min_stable_share * orders as f64).ceil() as usize;
    let list = |modes: &[StableColumn]| {
        let mut v: Vec<&StableColumn> = modes.iter().collect();
        v.sort_by_key(|m| std::cmp::Reverse(m.stable_orders));
        v.iter()
            .take(8)
            .map(|m| {
                format!(
                    "{:.4} Hz ({} orders)",
                    m.natural_frequency_hz, m.stable_orders
                )
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut text = format!(
        " ({orders} orders {}–{}; a mode needs poles within frequency_tolerance = {} at {needed} of them (min_stable_share = {}) and a peak of the data within its half-power band): {} candidate columns",
        options.orders[0],
        options.orders[1],
        options.frequency_tolerance,
        options.min_stable_share,
        candidates.len(),
    );
    if !candidates.is_empty() {
        text += &format!(" [{}]", list(candidates));
    }
    text += &format!(", {} of them at a peak of the data", at_peaks.len());
    if !at_peaks.is_empty() {
        text += &format!(" [{}]", list(&at_peaks));
    }
    text += ". Likely causes: lightly damped modes need higher orders (raise orders[1], e.g. to 120), noisy lines need a weighting that fits them (weighting = \"uniform\" weights the measured quantity equally), or the band holds no mode (band_hz); mode_count = N selects the N most stable columns";
    text
}

/// A group's median fn and ζ and its number of distinct orders.
fn summarise(group: &[(usize, DiagramPole)]) -> StableColumn {
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        let n = v.len();
        if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        }
    };
    let mut orders: Vec<usize> = group.iter().map(|(o, _)| *o).collect();
    orders.sort_unstable();
    orders.dedup();
    // The poles stable in damping too, when there are any: a lightly damped mode's ζ
    // settles only at the higher orders.
    let both: Vec<&DiagramPole> = group.iter().map(|(_, p)| p).filter(|p| p.stable).collect();
    let poles: Vec<&DiagramPole> = if both.is_empty() {
        group.iter().map(|(_, p)| p).collect()
    } else {
        both
    };
    StableColumn {
        natural_frequency_hz: median(poles.iter().map(|p| p.natural_frequency_hz).collect()),
        damping_ratio: median(poles.iter().map(|p| p.damping_ratio).collect()),
        stable_orders: orders.len(),
        at_peak: false,
    }
}

/// Why `diagram` selected no mode (or too few): the candidate columns, where they are,
/// the likely causes and the keys to change (for an error message).
///
/// ```
/// use msd_modal::{ModalOptions, stabilization_diagram};
/// use msd_signal::{Complex64, FrequencyResponseEstimate};
/// // A smooth response with no mode in it.
/// let f: Vec<f64> = (1..=200).map(|i| i as f64).collect();
/// let h = f.iter().map(|&f| Complex64::new(1.0 + 1e-3 * f, 0.0)).collect();
/// let options = ModalOptions::default();
/// let diagram = stabilization_diagram(&FrequencyResponseEstimate::new(f, h)?, &options)?;
/// assert!(diagram.modes.is_empty());
/// assert!(msd_modal::why_too_few(&diagram, &options).contains("orders[1]"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn why_too_few(diagram: &StabilizationDiagram, options: &ModalOptions) -> String {
    explain(&diagram.candidates, diagram.orders.len(), options)
}
