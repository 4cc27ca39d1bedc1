//! msd-signal with wild parameters: a signal that validates is finite wherever it is
//! evaluated on a record's time span, and so are its breakpoints; a signal that does not
//! validate names the parameter by its path (e.g. `terms[1].segments[0].t_off`).

use crate::{cases, wild_count, wild_f64};
use msd_signal::{
    ClippingOptions, LineSelection, Multisine, MultisineSpec, PhaseScheme, Prbs, PrbsSpec, Signal,
    SignalError, SineSegment, Sweep,
};
use proptest::prelude::*;

fn sweep() -> impl Strategy<Value = Sweep> {
    prop_oneof![Just(Sweep::Linear), Just(Sweep::Logarithmic)]
}

fn segment() -> impl Strategy<Value = SineSegment> {
    (
        wild_f64(),
        wild_f64(),
        wild_f64(),
        proptest::option::of(wild_f64()),
        wild_f64(),
    )
        .prop_map(|(frequency, amplitude, t_on, t_off, phase)| SineSegment {
            frequency,
            amplitude,
            t_on,
            t_off,
            phase,
        })
}

fn leaf() -> impl Strategy<Value = Signal> {
    prop_oneof![
        wild_f64().prop_map(|value| Signal::Constant { value }),
        (wild_f64(), wild_f64()).prop_map(|(amplitude, time)| Signal::Step { amplitude, time }),
        (
            wild_f64(),
            wild_f64(),
            wild_f64(),
            wild_f64(),
            proptest::option::of(wild_f64())
        )
            .prop_map(|(amplitude, frequency, phase, t_on, t_off)| Signal::Sine {
                amplitude,
                frequency,
                phase,
                t_on,
                t_off,
            }),
        prop::collection::vec(segment(), 0..4)
            .prop_map(|segments| Signal::SteppedSine { segments }),
        (
            (wild_f64(), wild_f64(), wild_f64()),
            (wild_f64(), wild_f64(), sweep(), wild_f64())
        )
            .prop_map(|((amplitude, f0, f1), (duration, phase, sweep, t_start))| {
                Signal::Chirp {
                    amplitude,
                    f0,
                    f1,
                    duration,
                    phase,
                    sweep,
                    t_start,
                }
            }),
    ]
}

/// Sums and scaled copies of leaves, up to three levels deep.
fn signal() -> impl Strategy<Value = Signal> {
    leaf().prop_recursive(3, 12, 4, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..4).prop_map(|terms| Signal::Sum { terms }),
            (wild_f64(), inner).prop_map(|(gain, s)| s.scaled(gain)),
        ]
    })
}

/// The parameter path of a validation error (every variant that has one).
fn parameter_of(e: &SignalError) -> Option<String> {
    match e {
        SignalError::InvalidParameter { parameter, .. }
        | SignalError::ReversedWindow { parameter, .. }
        | SignalError::OverlappingSegments { parameter, .. } => Some(parameter.clone()),
        SignalError::EmptyData { name } => Some((*name).to_string()),
        _ => None,
    }
}

/// The bits of `x`, every NaN counted as one.
fn bits(x: f64) -> u64 {
    if x.is_nan() {
        f64::NAN.to_bits()
    } else {
        x.to_bits()
    }
}

/// Every value on [t0, t1] (2001 points plus the breakpoints) and every breakpoint is
/// finite; the breakpoints are sorted.
fn finite_on(u: &Signal, t0: f64, t1: f64) -> Result<(), TestCaseError> {
    for i in 0..=2000 {
        let t = t0 + (t1 - t0) * i as f64 / 2000.0;
        let (v, l) = (u.value(t), u.left_limit(t));
        prop_assert!(
            v.is_finite() && l.is_finite(),
            "u({t}) = {v}, u({t}⁻) = {l}"
        );
    }
    // A fast PRBS over the span would list ~span/clock edges: the bound says so first.
    let bound = u.max_breakpoints(t0, t1);
    prop_assert!(bound >= 0.0, "bound {bound}");
    if bound > 1e6 {
        return Ok(());
    }
    let bps = u.breakpoints(t0, t1);
    prop_assert!(
        bps.len() as f64 <= bound,
        "{} breakpoints, bound {bound}",
        bps.len()
    );
    for w in bps.windows(2) {
        prop_assert!(w[0].time < w[1].time, "unsorted breakpoints {:?}", bps);
    }
    for b in &bps {
        prop_assert!(
            b.time.is_finite() && b.left.is_finite() && b.right.is_finite(),
            "{b:?}"
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(cases(1024))]

    /// A prepared signal computes exactly what the signal does, bit for bit, for any
    /// parameters (valid or not: NaN where the signal gives NaN, its sign and payload
    /// being the compiler's to choose) at any time, one time or several at once.
    #[test]
    fn prepared_signals_equal_the_signal_bit_for_bit(
        u in signal(),
        times in prop::collection::vec(wild_f64(), 1..40),
    ) {
        let prepared = u.prepare();
        for chunk in times.chunks_exact(4) {
            let lanes: [f64; 4] = std::array::from_fn(|l| chunk[l]);
            let active = [true, chunk[0] < chunk[1], true, false];
            let mut out = [0.5; 4];
            prepared.values(&lanes, &active, &mut out);
            for l in 0..4 {
                let expected = if active[l] { u.value(lanes[l]) } else { 0.5 };
                prop_assert_eq!(bits(out[l]), bits(expected), "lane {} at {}", l, lanes[l]);
            }
        }
        for t in times.into_iter().chain((0..=200).map(|i| -1.0 + 0.1 * i as f64)) {
            prop_assert_eq!(bits(prepared.value(t)), bits(u.value(t)), "u({})", t);
            prop_assert_eq!(bits(prepared.left_limit(t)), bits(u.left_limit(t)), "u({}⁻)", t);
        }
    }

    /// validate() decides: an accepted signal is finite over any record that starts
    /// where its times are (a 20 s span from its earliest time and from 0), and a refused
    /// one names the parameter.
    #[test]
    fn signals_are_finite_or_refused_by_name(u in signal()) {
        match u.validate() {
            Ok(()) => {
                finite_on(&u, -1.0, 20.0)?;
                // The documented domain: finite for every |t| ≤ 1e280 s.
                for t in [1e6, -1e9, 1e12, 1e100, 1e280, -1e280] {
                    prop_assert!(u.value(t).is_finite() && u.left_limit(t).is_finite(), "u({t}) = {}", u.value(t));
                }
                let msg = format!("{u:?}");
                prop_assert!(!msg.is_empty());
                // On a sampled grid as msd-ident uses it: finite samples, or a specific
                // error (e.g. a grid too long).
                if let Err(e) = msd_ident::Excitation::from_signal(u.clone(), 0.0, 0.01, 1001) {
                    prop_assert!(!matches!(e, msd_ident::IdentError::NonFiniteSample { .. }),
                        "validated signal sampled to a non-finite value: {e}");
                }
            }
            Err(e) => {
                let text = e.to_string();
                let parameter = parameter_of(&e);
                prop_assert!(parameter.as_ref().is_some_and(|p| !p.is_empty() && text.contains(p.as_str())),
                    "error without a parameter path: {text}");
            }
        }
    }

    /// Multisines are checked when built: an accepted one is finite and has a finite
    /// crest factor; a refused one names its parameter or the band.
    #[test]
    fn multisines_are_finite_or_refused_by_name(
        base_frequency in wild_f64(), f_min in wild_f64(), f_max in wild_f64(),
        rms in wild_f64(), t_start in wild_f64(), seed in any::<u64>(),
        random in any::<bool>(), lines in 0u8..3,
        clipping in proptest::option::of((0usize..20, wild_f64())),
    ) {
        let spec = MultisineSpec {
            base_frequency, f_min, f_max, rms, t_start, seed,
            phases: if random { PhaseScheme::Random } else { PhaseScheme::Schroeder },
            lines: [LineSelection::All, LineSelection::Odd, LineSelection::RandomOdd][lines as usize],
            crest_factor_reduction: clipping.map(|(iterations, clip_ratio)| ClippingOptions { iterations, clip_ratio }),
        };
        // Keep each case cheap: 4096 to 65 536 lines (the crate's limit) would synthesise
        // long periods; more are refused before any work.
        if (4096.0..=65_536.0).contains(&(f_max / base_frequency)) {
            return Ok(());
        }
        match Multisine::new(spec) {
            Ok(m) => {
                prop_assert!(m.crest_factor().is_finite(), "crest factor {}", m.crest_factor());
                let start = if t_start.is_finite() { t_start } else { 0.0 };
                finite_on(&Signal::Multisine(m), start - 1.0, start + 20.0)?;
            }
            Err(e) => {
                let text = e.to_string();
                let named = parameter_of(&e).is_some_and(|p| text.contains(p.as_str()))
                    || matches!(e, SignalError::NoMultisineLines { .. } | SignalError::TooManyLines { .. });
                prop_assert!(named, "unspecific error: {text}");
            }
        }
    }

    /// PRBS: an accepted one is ±amplitude everywhere; a refused one names the order or
    /// the parameter.
    #[test]
    fn prbs_is_finite_or_refused_by_name(
        order in prop_oneof![2u32..=12, any::<u32>()], clock_period in wild_f64(),
        amplitude in wild_f64(), t_start in wild_f64(),
    ) {
        match Prbs::new(PrbsSpec { order, clock_period, amplitude, t_start }) {
            Ok(p) => {
                let start = t_start;
                finite_on(&Signal::Prbs(p), start - 1.0, start + 20.0)?;
            }
            Err(e) => {
                let text = e.to_string();
                let named = parameter_of(&e).is_some_and(|p| text.contains(p.as_str()))
                    || matches!(e, SignalError::PrbsOrder { .. });
                prop_assert!(named, "unspecific error: {text}");
            }
        }
    }

    /// Noise streams: a non-negative finite σ gives finite noise of that size, anything
    /// else is refused naming `sigma`.
    #[test]
    fn noise_levels_are_checked(sigma in wild_f64(), n in wild_count()) {
        let n = n.min(10_000);
        match msd_signal::gaussian_noise(3, "p", sigma, n) {
            Ok(e) => {
                prop_assert!(sigma.is_finite() && sigma >= 0.0, "σ = {sigma} accepted");
                prop_assert!(e.iter().all(|v| v.is_finite()), "σ = {sigma}: non-finite noise");
            }
            Err(e) => prop_assert!(e.to_string().contains("sigma"), "{e}"),
        }
    }
}
