//! The exact LTI simulator against analytic solutions and against DP5(4).

use crate::common::{Plant, paper_grid, paper_input, paper_input_left};
use msd_ode::{
    Breakpoint, Complex, ExactSimulator, Hold, LtiModel, Ode45Options, SMatrix, SVector,
    SampledInput, ode45,
};

const DT: f64 = 0.002;

fn simulate(plant: Plant, hold: Hold, values: &[f64], breakpoints: &[Breakpoint]) -> Vec<f64> {
    let sim = ExactSimulator::new(&plant.model(), DT, hold).expect("valid model");
    sim.simulate(
        &SVector::zeros(),
        &SampledInput {
            values,
            breakpoints,
        },
    )
    .expect("simulates")
    .iter()
    .map(|x| x[0])
    .collect()
}

/// Breakpoints of the paper's identification input on its grid: the 6 N step at 0.5 s
/// (sample 250), the kink where the 0.5 Hz sine starts at 3 s (1500), and the switch to
/// the 1.4 Hz sine at 9 s (4500), where the force jumps.
fn paper_breakpoints() -> Vec<Breakpoint> {
    [250usize, 1500, 4500]
        .iter()
        .map(|&i| {
            let t = i as f64 * DT;
            Breakpoint {
                index: i,
                left: paper_input_left(t),
                right: paper_input(t),
            }
        })
        .collect()
}

/// Reference: ode45 at RelTol 1e-12, restarted at each breakpoint so that no step straddles
/// a jump or a kink (each piece's input is smooth, evaluated one-sidedly).
fn piecewise_reference(plant: Plant) -> Vec<f64> {
    let grid = paper_grid();
    let cuts = [0usize, 250, 1500, 4500, 7500];
    let opts = Ode45Options {
        rel_tol: 1e-12,
        abs_tol: 1e-15,
        ..Ode45Options::default()
    };
    let mut state = SVector::<f64, 2>::zeros();
    let mut out = vec![0.0; grid.len()];
    for w in cuts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (ta, tb) = (grid[a], grid[b]);
        // One-sided input on the open piece: evaluate with the formula valid inside it.
        let inside = move |t: f64| {
            if t <= ta {
                paper_input(ta)
            } else if t >= tb {
                paper_input_left(tb)
            } else {
                paper_input(t)
            }
        };
        let mut rhs = |t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| {
            d[0] = y[1];
            d[1] = (inside(t) - plant.c * y[1] - plant.k * y[0]) / plant.m;
        };
        let sol = ode45(&mut rhs, &grid[a..=b], &state, &opts).expect("solves");
        for (j, y) in sol.y.iter().enumerate() {
            out[a + j] = y[0];
        }
        state = *sol.y.last().expect("non-empty");
    }
    out
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

#[test]
fn every_hold_is_exact_for_a_constant_input() {
    for zeta in [0.05, 1.0, 3.0] {
        let plant = Plant::with_damping_ratio(zeta);
        let values = vec![6.0; 2001];
        for hold in [Hold::Zero, Hold::First, Hold::Cubic] {
            let x = simulate(plant, hold, &values, &[]);
            let worst = x
                .iter()
                .enumerate()
                .map(|(i, xi)| (xi - plant.step_response(6.0, i as f64 * DT).0).abs())
                .fold(0.0, f64::max);
            // Only rounding: ~2000 steps of a few ulps of 0.05 m.
            assert!(worst < 1e-12, "{hold:?}, ζ = {zeta}: {worst:e}");
        }
    }
}

#[test]
fn first_and_cubic_holds_are_exact_for_a_ramp() {
    let plant = Plant::PAPER;
    let values: Vec<f64> = (0..2001).map(|i| 4.0 * i as f64 * DT).collect();
    for hold in [Hold::First, Hold::Cubic] {
        let x = simulate(plant, hold, &values, &[]);
        let worst = x
            .iter()
            .enumerate()
            .map(|(i, xi)| (xi - plant.ramp_response(4.0, i as f64 * DT).0).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12, "{hold:?}: {worst:e}");
    }
}

#[test]
fn a_jump_on_a_sample_instant_is_exact_with_its_breakpoint() {
    let plant = Plant::PAPER;
    let values: Vec<f64> = (0..3001)
        .map(|i| if i >= 250 { 6.0 } else { 0.0 })
        .collect();
    let jump = [Breakpoint {
        index: 250,
        left: 0.0,
        right: 6.0,
    }];
    let exact = |i: usize| {
        if i < 250 {
            0.0
        } else {
            plant.step_response(6.0, (i - 250) as f64 * DT).0
        }
    };
    for hold in [Hold::Zero, Hold::First, Hold::Cubic] {
        let x = simulate(plant, hold, &values, &jump);
        let worst = x
            .iter()
            .enumerate()
            .map(|(i, xi)| (xi - exact(i)).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12, "{hold:?}: {worst:e}");
    }
    // Without the breakpoint the cubic smears the jump over its stencil: a visible error.
    let smeared = simulate(plant, Hold::Cubic, &values, &[]);
    let worst = smeared
        .iter()
        .enumerate()
        .map(|(i, xi)| (xi - exact(i)).abs())
        .fold(0.0, f64::max);
    assert!(worst > 1e-7, "the breakpoint should matter: {worst:e}");
}

#[test]
fn cubic_hold_matches_dp45_on_the_paper_input_to_1e_8_relative() {
    let plant = Plant::PAPER;
    let grid = paper_grid();
    let values: Vec<f64> = grid.iter().map(|&t| paper_input(t)).collect();
    let exact = simulate(plant, Hold::Cubic, &values, &paper_breakpoints());
    let reference = piecewise_reference(plant);
    let relative = max_abs_diff(&exact, &reference) / max_abs(&reference);
    assert!(relative < 1e-8, "relative error {relative:e}");

    // Also against ode45 at RelTol 1e-10 straight through the jumps, as the paper runs it.
    let mut rhs = |t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| {
        d[0] = y[1];
        d[1] = (paper_input(t) - plant.c * y[1] - plant.k * y[0]) / plant.m;
    };
    let opts = Ode45Options {
        rel_tol: 1e-10,
        abs_tol: 1e-13,
        ..Ode45Options::default()
    };
    let sol = ode45(&mut rhs, &grid, &SVector::zeros(), &opts).expect("solves");
    let straight: Vec<f64> = sol.y.iter().map(|y| y[0]).collect();
    let relative = max_abs_diff(&exact, &straight) / max_abs(&reference);
    assert!(
        relative < 1e-8,
        "relative error against straight ode45 {relative:e}"
    );
}

#[test]
fn first_order_hold_error_stays_within_its_dt_squared_bound() {
    // Linear interpolation errs by at most dt²/8·max|u''| on a smooth piece, and the
    // displacement error is that input error filtered by the plant, so
    // |Δx| ≤ dt²/8 · max|u''| · ∫|g|, with g the displacement impulse response.
    let plant = Plant::PAPER;
    let grid = paper_grid();
    let values: Vec<f64> = grid.iter().map(|&t| paper_input(t)).collect();
    let reference = piecewise_reference(plant);
    let first = simulate(plant, Hold::First, &values, &paper_breakpoints());
    let error = max_abs_diff(&first, &reference);
    let u2 = (3.0 * (std::f64::consts::PI).powi(2))
        .max(2.5 * (2.0 * std::f64::consts::PI * 1.4).powi(2));
    let fine = 1e-4;
    let g_l1: f64 = (0..150_000)
        .map(|i| plant.velocity_decay(i as f64 * fine).0.abs() / plant.m * fine)
        .sum();
    let bound = DT * DT / 8.0 * u2 * g_l1 * 1.01;
    assert!(
        error <= bound,
        "first-order hold error {error:e} above bound {bound:e}"
    );
    // And the bound is not vacuous: the error is of the predicted order, well above the
    // cubic hold's.
    assert!(
        error > bound / 100.0,
        "error {error:e} suspiciously small for O(dt²), bound {bound:e}"
    );
    let cubic = simulate(plant, Hold::Cubic, &values, &paper_breakpoints());
    assert!(max_abs_diff(&cubic, &reference) < error / 100.0);
    // A zero-order hold is far worse still (O(dt)).
    let zero = simulate(plant, Hold::Zero, &values, &paper_breakpoints());
    assert!(max_abs_diff(&zero, &reference) > 10.0 * error);
}

#[test]
fn short_pieces_fall_back_to_lower_order_stencils() {
    // Breakpoints two and three samples apart force the quadratic and linear stencils;
    // a ramp is still reproduced exactly.
    let plant = Plant::PAPER;
    let values: Vec<f64> = (0..41).map(|i| 4.0 * i as f64 * DT).collect();
    let kinks: Vec<Breakpoint> = [3usize, 5, 8, 9, 12]
        .iter()
        .map(|&i| Breakpoint {
            index: i,
            left: values[i],
            right: values[i],
        })
        .collect();
    let x = simulate(plant, Hold::Cubic, &values, &kinks);
    for (i, xi) in x.iter().enumerate() {
        let exact = plant.ramp_response(4.0, i as f64 * DT).0;
        assert!((xi - exact).abs() < 1e-14, "sample {i}: {xi} vs {exact}");
    }
}

#[test]
fn transition_matrix_is_the_matrix_exponential() {
    let plant = Plant::PAPER;
    let sim = ExactSimulator::new(&plant.model(), DT, Hold::Cubic).expect("valid");
    let expected = (plant.matrix() * DT).exp();
    assert!((sim.transition() - expected).abs().max() < 1e-15);
    assert_eq!(sim.dt(), DT);
    assert_eq!(sim.hold(), Hold::Cubic);
}

/// Lanes stepped together give each simulator's own result bit for bit, for every hold,
/// through the paper input's jumps and kinks and a breakpoint close to the end (short
/// pieces: quadratic and linear stencils), stopping and resuming mid-record.
#[test]
fn lockstep_lanes_equal_single_simulations_bit_for_bit() {
    use msd_ode::{InputSchedule, Lockstep};
    let grid = paper_grid();
    let values: Vec<f64> = grid.iter().map(|&t| paper_input(t)).collect();
    let mut breakpoints = paper_breakpoints();
    breakpoints.push(Breakpoint {
        index: values.len() - 3,
        left: 0.5,
        right: -0.25,
    });
    let input = SampledInput {
        values: &values,
        breakpoints: &breakpoints,
    };
    let plants = [0.5, 1.0, 1.7].map(|scale| Plant {
        k: Plant::PAPER.k * scale,
        c: Plant::PAPER.c / scale,
        ..Plant::PAPER
    });
    let x0 = [
        SVector::zeros(),
        SVector::<f64, 2>::new(0.01, -0.2),
        SVector::<f64, 2>::new(-0.003, 0.0),
    ];
    for hold in [Hold::Zero, Hold::First, Hold::Cubic] {
        let sims = plants.map(|p| ExactSimulator::new(&p.model(), DT, hold).expect("model"));
        let schedule = InputSchedule::new(&input, hold).expect("schedule");
        assert_eq!(schedule.samples(), values.len());
        let mut lanes = Lockstep::new([&sims[0], &sims[1], &sims[2]], x0).expect("lanes");
        let mut got = vec![[[0.0; 3]; 2]; values.len()];
        got[0] = *lanes.state();
        lanes.advance(&schedule, 3000, |i, x| got[i] = *x);
        assert_eq!(lanes.sample(), 3000);
        lanes.advance(&schedule, usize::MAX, |i, x| got[i] = *x);
        assert_eq!(lanes.sample(), values.len() - 1);
        for (lane, sim) in sims.iter().enumerate() {
            let alone = sim.simulate(&x0[lane], &input).expect("simulates");
            for (i, x) in alone.iter().enumerate() {
                for r in 0..2 {
                    assert_eq!(
                        got[i][r][lane].to_bits(),
                        x[r].to_bits(),
                        "{hold:?}, lane {lane}, sample {i}, component {r}"
                    );
                }
            }
        }
    }
    // Lanes of different steps are refused.
    let other = ExactSimulator::new(&Plant::PAPER.model(), 2.0 * DT, Hold::Cubic).expect("model");
    let same = ExactSimulator::new(&Plant::PAPER.model(), DT, Hold::Cubic).expect("model");
    assert!(Lockstep::new([&same, &other], [SVector::<f64, 2>::zeros(); 2]).is_err());
}

/// The hold polynomials are the input the exact simulator integrates: ode45 at RelTol
/// 1e-12 driven by them, restarted at each sample so that no step straddles a kink,
/// agrees with the exact simulation for every hold, breakpoints included.
#[test]
fn hold_polynomials_are_what_the_exact_simulator_integrates() {
    let grid = paper_grid();
    let values: Vec<f64> = grid.iter().map(|&t| paper_input(t)).collect();
    let breakpoints = paper_breakpoints();
    let input = SampledInput {
        values: &values,
        breakpoints: &breakpoints,
    };
    let plant = Plant::PAPER;
    let opts = Ode45Options {
        rel_tol: 1e-12,
        abs_tol: 1e-15,
        ..Ode45Options::default()
    };
    for hold in [Hold::Zero, Hold::First, Hold::Cubic] {
        let polynomials = input.hold_polynomials(hold).expect("valid input");
        assert_eq!(polynomials.len(), values.len() - 1);
        let exact = simulate(plant, hold, &values, &breakpoints);
        let mut state = SVector::<f64, 2>::zeros();
        let (mut worst, mut steps) = (0.0f64, 0usize);
        // The first 600 samples cover the step at 250 and plenty of smooth intervals.
        for (i, a) in polynomials.iter().enumerate().take(600) {
            let mut rhs = |t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| {
                let s = t / DT;
                let u = a[0] + s * (a[1] + s * (a[2] + s * a[3]));
                d[0] = y[1];
                d[1] = (u - plant.c * y[1] - plant.k * y[0]) / plant.m;
            };
            let sol = ode45(&mut rhs, &[0.0, DT], &state, &opts).expect("solves");
            state = *sol.y.last().expect("non-empty");
            steps += sol.stats.accepted_steps;
            worst = worst.max((state[0] - exact[i + 1]).abs());
        }
        // Each ode45 step errs by at most RelTol·|x| + AbsTol, and the damped plant does
        // not amplify earlier errors: over these steps at most their sum.
        let bound = steps as f64 * (opts.rel_tol * max_abs(&exact[..=600]) + opts.abs_tol);
        assert!(worst < bound, "{hold:?}: {worst:e} vs {bound:e}");
    }
}

/// Each hold polynomial starts at its interval's right value and, but for the zero
/// hold, ends at the next sample's left value; the cubic hold reproduces a cubic in
/// every interval, one-sided stencils at the ends included.
#[test]
fn hold_polynomials_interpolate_and_reproduce_their_degree() {
    let cubic = |t: f64| 1.0 - 2.0 * t + 0.5 * t * t - 0.25 * t * t * t;
    let values: Vec<f64> = (0..12).map(|i| cubic(i as f64)).collect();
    let breakpoints = [Breakpoint {
        index: 6,
        left: 7.0,
        right: values[6],
    }];
    let input = SampledInput {
        values: &values,
        breakpoints: &breakpoints,
    };
    for hold in [Hold::Zero, Hold::First, Hold::Cubic] {
        let p = input.hold_polynomials(hold).expect("valid input");
        for (i, a) in p.iter().enumerate() {
            let end = if i + 1 == 6 { 7.0 } else { values[i + 1] };
            let at_end = a.iter().sum::<f64>();
            assert!((a[0] - values[i]).abs() < 1e-12, "{hold:?} {i}: {a:?}");
            if hold != Hold::Zero {
                assert!((at_end - end).abs() < 1e-12, "{hold:?} {i}: {a:?}");
            }
        }
    }
    let smooth = SampledInput::smooth(&values)
        .hold_polynomials(Hold::Cubic)
        .expect("valid input");
    for (i, a) in smooth.iter().enumerate() {
        for s in [0.25, 0.5, 0.75] {
            let u = a[0] + s * (a[1] + s * (a[2] + s * a[3]));
            let truth = cubic(i as f64 + s);
            assert!((u - truth).abs() < 1e-12, "{i} at {s}: {u} vs {truth}");
        }
    }
    let err = SampledInput::smooth(&[0.0, f64::NAN])
        .hold_polynomials(Hold::First)
        .unwrap_err();
    assert!(matches!(
        err,
        msd_ode::OdeError::InvalidInput { index: 1, .. }
    ));
}

/// The frequency response is the DFT of the response to one unit input sample placed
/// where no one-sided stencil reaches it (sample 4), for every hold, at lines from the
/// lowest to near Nyquist: the impulse response decays to 1e-15 of its peak within the
/// record, so they agree to rounding (a DFT's: n·ε·Σ|x|).
#[test]
fn the_frequency_response_is_the_impulse_responses_dft() {
    let plant = Plant::PAPER;
    for hold in [Hold::Zero, Hold::First, Hold::Cubic] {
        let sim = ExactSimulator::new(&plant.model(), DT, hold).expect("valid model");
        impulse_against_response(&sim, hold);
    }
    // Three states (elimination, where two take the adjugate): the plant behind a
    // first-order sensor filter at 50 rad/s.
    let filtered = behind_a_sensor_filter(&plant);
    let sim = ExactSimulator::new(&filtered, DT, Hold::Cubic).expect("valid model");
    impulse_against_response(&sim, Hold::Cubic);
}

/// The plant behind a first-order sensor filter at 50 rad/s: three states.
fn behind_a_sensor_filter(plant: &Plant) -> LtiModel<3> {
    let two = plant.model();
    let (a, b) = (two.a, two.b);
    #[rustfmt::skip]
    let filtered = LtiModel {
        a: SMatrix::<f64, 3, 3>::new(
            a[(0, 0)], a[(0, 1)], 0.0,
            a[(1, 0)], a[(1, 1)], 0.0,
            50.0, 0.0, -50.0,
        ),
        b: SVector::<f64, 3>::new(b[0], b[1], 0.0),
    };
    filtered
}

fn impulse_against_response<const N: usize>(sim: &ExactSimulator<N>, hold: Hold) {
    let n = 40_000; // 80 s: e^(−ζωn·t) < 1e-15
    let mut unit = vec![0.0; n];
    unit[4] = 1.0;
    let x = sim
        .simulate(&SVector::zeros(), &SampledInput::smooth(&unit))
        .expect("simulates");
    for line in [1usize, 37, 400, 5_000, 19_999] {
        let z = Complex::from_polar(1.0, 2.0 * std::f64::consts::PI * line as f64 / n as f64);
        let mut dft = [Complex::new(0.0, 0.0); N];
        for (t, s) in x.iter().enumerate() {
            // The phase reduced in integers: w·t rounds to 1e-11 rad at t = 40 000.
            let turns = (line * (t + n - 4)) % n;
            let e = Complex::from_polar(1.0, -2.0 * std::f64::consts::PI * turns as f64 / n as f64);
            for (d, v) in dft.iter_mut().zip(s.iter()) {
                *d += e * v;
            }
        }
        let response = sim.frequency_response(z).expect("regular");
        // The same response from the hold's interior transforms (one resolvent).
        let resolvent = sim.resolvent(z).expect("regular");
        let held = (resolvent.held_response(&hold.interior_transforms(z))).expect("regular");
        for i in 0..N {
            // Near Nyquist the sum cancels to 1e-4 of its terms: its rounding, about
            // n·ε·Σ|x|, is the floor.
            let floor = n as f64 * f64::EPSILON * x.iter().map(|s| s[i].abs()).sum::<f64>();
            let scale = dft[i].norm() + floor / 1e-9;
            for (how, r) in [("stencil weights", response), ("interior transforms", held)] {
                assert!(
                    (r[i] - dft[i]).norm() < 1e-9 * scale,
                    "{hold:?} by its {how}, {N} states, line {line}, state {i}: {} against {}",
                    r[i],
                    dft[i]
                );
            }
        }
    }
}

/// A record's state spectrum in closed form is its DFT, for every hold, on a record
/// with jumps (breakpoints, the stencils' one-sided variants around them), a nonzero
/// initial state, odd and even lengths and 2 and 3 states, at lines from the lowest to
/// Nyquist's: the identity is exact, so they agree to the DFT's rounding.
#[test]
fn the_state_spectrum_is_the_records_dft() {
    let plant = Plant::PAPER;
    for hold in [Hold::Zero, Hold::First, Hold::Cubic] {
        let sim = ExactSimulator::new(&plant.model(), DT, hold).expect("valid model");
        for n in [501usize, 800] {
            state_spectrum_against_dft(&sim, hold, n, SVector::from([2e-3, -0.05]));
        }
    }
    let filtered = behind_a_sensor_filter(&plant);
    let sim = ExactSimulator::new(&filtered, DT, Hold::Cubic).expect("valid model");
    state_spectrum_against_dft(&sim, Hold::Cubic, 640, SVector::from([1e-3, 0.0, 0.2]));
}

fn state_spectrum_against_dft<const N: usize>(
    sim: &ExactSimulator<N>,
    hold: Hold,
    n: usize,
    x0: SVector<f64, N>,
) {
    // A multisine with a step up at sample 100 and a kink at 300.
    let values: Vec<f64> = (0..n)
        .map(|t| {
            let s = (0.07 * t as f64).sin() + 0.4 * (0.31 * t as f64).cos();
            s + if t >= 100 { 3.0 } else { 0.0 } + 0.01 * (t.max(300) - 300) as f64
        })
        .collect();
    let jumps = [
        Breakpoint {
            index: 100,
            left: values[99] + (values[99] - values[98]),
            right: values[100],
        },
        Breakpoint {
            index: 300,
            left: values[300],
            right: values[300],
        },
    ];
    let input = SampledInput {
        values: &values,
        breakpoints: &jumps,
    };
    let x = sim.simulate(&x0, &input).expect("simulates");
    let holds = input.hold_polynomials(hold).expect("valid input");
    let phase = |line: usize, t: usize| {
        let turns = (line * t) % n;
        Complex::from_polar(1.0, -2.0 * std::f64::consts::PI * turns as f64 / n as f64)
    };
    for line in [1usize, 7, n / 5, n / 2 - 1, n / 2] {
        let z = Complex::from_polar(1.0, 2.0 * std::f64::consts::PI * line as f64 / n as f64);
        let m: [Complex<f64>; 4] =
            std::array::from_fn(|j| (1..n).map(|t| holds[t - 1][j] * phase(line, t)).sum());
        let closed = sim.state_spectrum(z, &x0, &x[n - 1], &m).expect("regular");
        for i in 0..N {
            let dft: Complex<f64> = (0..n).map(|t| x[t][i] * phase(line, t)).sum();
            let floor = n as f64 * f64::EPSILON * x.iter().map(|s| s[i].abs()).sum::<f64>();
            assert!(
                (closed[i] - dft).norm() < 1e-9 * dft.norm() + 100.0 * floor,
                "{hold:?}, n {n}, {N} states, line {line}, state {i}: {} against {dft}",
                closed[i]
            );
        }
    }
}
