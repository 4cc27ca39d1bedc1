//! Multisine lines and crest factors; PRBS period and balance.

use msd_signal::{
    ClippingOptions, LineSelection, Multisine, MultisineSpec, PhaseScheme, Prbs, PrbsSpec, Signal,
    WelchOptions, Window, welch_psd,
};

fn spec(phases: PhaseScheme, lines: LineSelection, seed: u64) -> MultisineSpec {
    MultisineSpec {
        base_frequency: 0.5,
        f_min: 1.0,
        f_max: 20.0,
        rms: 2.0,
        phases,
        lines,
        seed,
        ..Default::default()
    }
}

/// Periodogram of exactly `periods` periods of `u` sampled at `fs`: the lines fall on bins.
fn line_power(u: &Signal, fs: f64, period: f64, periods: usize) -> Vec<f64> {
    let n = (fs * period).round() as usize * periods;
    let x = u.sample(0.0, 1.0 / fs, n);
    let opts = WelchOptions {
        window: Window::Rectangular,
        detrend: msd_signal::Detrend::None,
        ..Default::default()
    };
    welch_psd(&x, fs, &opts).expect("valid record").values
}

#[test]
fn multisine_energy_is_on_exactly_the_requested_lines() {
    let fs = 64.0;
    for lines in [
        LineSelection::All,
        LineSelection::Odd,
        LineSelection::RandomOdd,
    ] {
        let ms = Multisine::new(spec(PhaseScheme::Random, lines, 11)).expect("valid spec");
        let harmonics = ms.harmonics().to_vec();
        match lines {
            LineSelection::All => assert_eq!(harmonics, (2..=40).collect::<Vec<u32>>()),
            LineSelection::Odd => assert_eq!(harmonics, (3..=39).step_by(2).collect::<Vec<u32>>()),
            LineSelection::RandomOdd => {
                // 19 odd lines 3 … 39: six full groups of three lose one each, the last one stays.
                assert_eq!(harmonics.len(), 19 - 6);
                assert!(harmonics.iter().all(|k| k % 2 == 1));
                for group in (3..=37).step_by(6).map(|s| [s, s + 2, s + 4]) {
                    assert_eq!(
                        group.iter().filter(|k| harmonics.contains(k)).count(),
                        2,
                        "{group:?}"
                    );
                }
            }
        }
        let period = ms.period();
        let u = Signal::Multisine(ms);
        let periods = 3;
        let p = line_power(&u, fs, period, periods);
        let total: f64 = p.iter().sum();
        for (bin, &power) in p.iter().enumerate() {
            let is_line = bin % periods == 0 && harmonics.contains(&((bin / periods) as u32));
            if is_line {
                // Each line carries 1/K of the power: rms² = 4.
                let share = power / total;
                assert!(
                    (share - 1.0 / harmonics.len() as f64).abs() < 1e-9,
                    "{lines:?} bin {bin}"
                );
            } else {
                // Round-off only: ~(1e-16)² relative.
                assert!(
                    power < 1e-20 * total,
                    "{lines:?}: energy at bin {bin}: {power}"
                );
            }
        }
        // Parseval: Σ P·Δf = rms².
        let df = fs / p.len().saturating_sub(1).max(1) as f64 / 2.0;
        assert!((total * df - 4.0).abs() < 1e-9, "{} vs 4", total * df);
    }
}

#[test]
fn schroeder_beats_median_of_random_phases_and_clipping_helps() {
    let schroeder =
        Multisine::new(spec(PhaseScheme::Schroeder, LineSelection::All, 0)).expect("valid");
    let mut random: Vec<f64> = (0..15)
        .map(|seed| {
            Multisine::new(spec(PhaseScheme::Random, LineSelection::All, seed))
                .expect("valid")
                .crest_factor()
        })
        .collect();
    random.sort_by(f64::total_cmp);
    let median = random[random.len() / 2];
    assert!(
        schroeder.crest_factor() < median,
        "Schroeder {} vs median random {median}",
        schroeder.crest_factor()
    );
    // The crest factor of any signal is at least 1 (and √2 for a single sine).
    assert!(schroeder.crest_factor() >= 1.0);

    let clipped_spec = MultisineSpec {
        crest_factor_reduction: Some(ClippingOptions::default()),
        ..spec(PhaseScheme::Random, LineSelection::All, 3)
    };
    let plain = Multisine::new(spec(PhaseScheme::Random, LineSelection::All, 3)).expect("valid");
    let clipped = Multisine::new(clipped_spec).expect("valid");
    assert!(clipped.crest_factor() < plain.crest_factor());
    assert_eq!(clipped.harmonics(), plain.harmonics());
    // The reported crest factor is the true one of the evaluated signal.
    let u = Signal::Multisine(clipped.clone());
    let n = 20_000;
    let x = u.sample(0.0, clipped.period() / n as f64, n);
    let peak = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let rms = (x.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
    assert!((rms - 2.0).abs() < 1e-9, "rms {rms}");
    // The crate samples N = 1024 points per period (16 per period of the top line, k = 40);
    // between grid points the peak can rise by at most ~(π/16)²/2 ≈ 2 %.
    let cf = peak / rms;
    assert!(cf >= clipped.crest_factor() - 1e-9 && cf < 1.03 * clipped.crest_factor());
}

#[test]
fn multisine_starts_at_t_start_and_is_periodic() {
    let ms = Multisine::new(MultisineSpec {
        t_start: 2.0,
        ..spec(PhaseScheme::Schroeder, LineSelection::Odd, 0)
    })
    .expect("valid");
    let period = ms.period();
    let u = Signal::Multisine(ms);
    assert_eq!(u.value(1.999), 0.0);
    let bps = u.breakpoints(0.0, 10.0);
    assert_eq!(bps.len(), 1);
    assert_eq!(bps[0].time, 2.0);
    assert_eq!(bps[0].right, u.value(2.0));
    for &t in &[2.0, 2.3, 3.77] {
        assert!((u.value(t) - u.value(t + 3.0 * period)).abs() < 1e-9);
    }
}

#[test]
fn prbs_is_maximum_length_for_every_order() {
    for order in 2..=24u32 {
        let p = Prbs::new(PrbsSpec {
            order,
            clock_period: 1.0,
            amplitude: 1.0,
            t_start: 0.0,
        })
        .expect("valid order");
        let period = (1usize << order) - 1;
        assert_eq!(p.period_chips(), period);
        let high = (0..period).filter(|&i| p.chip(i)).count();
        let low = period - high;
        assert_eq!(high, low + 1, "order {order}: {high} high, {low} low");
        // Every non-zero n-bit window occurs exactly once per period (so the sequence
        // has period exactly 2^n − 1 and no shorter one).
        let mut seen = vec![false; period + 1];
        let mut window = 0usize;
        for i in 0..order as usize - 1 {
            window = (window << 1) | p.chip(i) as usize;
        }
        let mask = period; // 2^n − 1
        for i in 0..period {
            window = ((window << 1) | p.chip(i + order as usize - 1) as usize) & mask;
            assert!(window != 0, "order {order}: zero window");
            assert!(
                !seen[window],
                "order {order}: window {window:#b} repeats at {i}"
            );
            seen[window] = true;
        }
    }
}

#[test]
fn prbs_values_and_breakpoints() {
    let (tc, amp, t0) = (0.05, 2.5, 0.2);
    let p = Prbs::new(PrbsSpec {
        order: 6,
        clock_period: tc,
        amplitude: amp,
        t_start: t0,
    })
    .expect("valid");
    let period = p.period_chips();
    let u = Signal::Prbs(p.clone());
    assert_eq!(u.value(0.19), 0.0);
    for i in [0usize, 1, 5, 62, 63, 64, 130] {
        let level = if p.chip(i) { amp } else { -amp };
        let mid = t0 + (i as f64 + 0.5) * tc;
        assert_eq!(u.value(mid), level, "chip {i}");
    }
    // Periodic in time with period (2^n − 1)·Tc.
    assert_eq!(
        u.value(t0 + 0.5 * tc),
        u.value(t0 + (period as f64 + 0.5) * tc)
    );
    let bps = u.breakpoints(0.0, t0 + period as f64 * tc);
    assert_eq!(bps[0].time, t0);
    assert_eq!(bps[0].left, 0.0);
    for b in &bps[1..] {
        assert!(b.left != b.right, "only level changes are listed");
        assert_eq!(b.right, u.value(b.time));
        assert_eq!(b.left, u.value(b.time - tc / 2.0));
        assert_eq!(b.right, u.value(b.time + tc / 2.0));
    }
    // Number of level changes in one period: runs of an m-sequence number 2^(n−1).
    let changes = (1..=period).filter(|&i| p.chip(i) != p.chip(i - 1)).count();
    assert_eq!(changes, 1 << 5);
    assert_eq!(bps.len(), 1 + changes);
}
