//! The batch simulator: every lane, streamed in any stretches, is bit for bit the single
//! simulation of its parameters, for both backends; failed lanes are reported and +∞.

use super::*;
use msd_ident::{PaperExperiment, simulate};

fn validation_input() -> Excitation {
    PaperExperiment::generate(0)
        .expect("the paper's experiment")
        .validation
        .excitation
}

/// Eight different plants ±10 % around the paper's, one lane empty, one invalid.
fn lanes() -> [Option<Parameters>; LANES] {
    let mut sets = [None; LANES];
    for (lane, set) in sets.iter_mut().enumerate().take(6) {
        let f = 0.9 + 0.04 * lane as f64;
        *set = Some(Parameters::new(2.5 * f, 1.8 / f, 120.0 * (2.0 - f)).unwrap());
    }
    sets[7] = Some(Parameters {
        mass: -1.0,
        damping: 1.8,
        stiffness: 120.0,
    });
    sets
}

fn check(backend: Backend, cuts: &[usize]) {
    let input = validation_input();
    assert_eq!(input.len(), 7501);
    let initial = InitialState {
        displacement: 1e-3,
        velocity: -0.02,
    };
    let batch = BatchSimulator::new(&input, &backend).unwrap();
    let sets = lanes();
    let mut run = batch.start(&sets, initial);
    let mut out = vec![f64::NAN; 7501 * LANES];
    let mut ok = [true; LANES];
    for &until in cuts {
        let from = run.next;
        let got = run.advance_strided(&batch, until, &mut out[from * LANES..], LANES);
        assert_eq!(run.next, until.clamp(from, 7501));
        ok = got;
    }
    assert_eq!(ok, [true, true, true, true, true, true, false, false]);
    for (lane, set) in sets.iter().enumerate() {
        let column: Vec<f64> = (0..7501).map(|t| out[t * LANES + lane]).collect();
        match set {
            Some(p) if ok[lane] => {
                let alone = simulate(p, &input, initial, &backend).unwrap();
                assert_eq!(column, alone, "{} lane {lane}", backend.name());
            }
            _ => assert!(column.iter().all(|&v| v == f64::INFINITY), "lane {lane}"),
        }
    }
}

#[test]
fn exact_lanes_streamed_equal_single_simulations() {
    for hold in [Hold::Zero, Hold::First, Hold::Cubic] {
        check(Backend::Exact { hold }, &[7501]);
        check(
            Backend::Exact { hold },
            &[0, 1, 2, 500, 499, 3001, 7000, 7501, 9000],
        );
    }
}

#[test]
fn ode45_lanes_streamed_equal_single_simulations() {
    check(Backend::PAPER, &[7501]);
    check(Backend::PAPER, &[1, 2, 333, 334, 4096, 4000, 7500, 7501]);
}

/// With a stride, the lanes' values at one time land `stride` apart: a run written into
/// the second half of a two-run-wide table equals the same run written alone.
#[test]
fn a_strided_run_writes_what_a_packed_run_writes() {
    let input = Excitation::from_samples(0.0, 0.01, vec![1.0; 100]).unwrap();
    for backend in [Backend::EXACT, Backend::PAPER] {
        let batch = BatchSimulator::new(&input, &backend).unwrap();
        let sets = [Some(Parameters::PAPER); LANES];
        let mut table = vec![0.0; 100 * 2 * LANES];
        let mut run = batch.start(&sets, InitialState::REST);
        run.advance_strided(&batch, 100, &mut table[LANES..], 2 * LANES);
        let mut alone = vec![0.0; 100 * LANES];
        let mut run = batch.start(&sets, InitialState::REST);
        run.advance_strided(&batch, 100, &mut alone, LANES);
        for t in 0..100 {
            assert_eq!(table[t * 2 * LANES..][..LANES], [0.0; LANES]);
            assert_eq!(
                table[t * 2 * LANES + LANES..][..LANES],
                alone[t * LANES..][..LANES]
            );
        }
        assert!(alone.iter().any(|&v| v != 0.0), "{}", backend.name());
    }
}

/// A force of 1e10 N on a plant of 1e-300 kg overflows the state: that lane fails (for good)
/// in the stretch where it overflows, with either backend; the other lanes go on.
#[test]
fn a_lane_that_overflows_fails_from_then_on() {
    let mut force = vec![0.0; 2001];
    force[1000..].fill(1e10);
    let input = Excitation::from_samples(0.0, 0.002, force).unwrap();
    let soft = Parameters::new(1e-300, 0.0, 1e-300).unwrap(); // acceleration 1e310
    let mut sets = [Some(Parameters::PAPER); LANES];
    sets[3] = Some(soft);
    for backend in [Backend::EXACT, Backend::PAPER] {
        let batch = BatchSimulator::new(&input, &backend).unwrap();
        let mut run = batch.start(&sets, InitialState::REST);
        let mut out = vec![0.0; 2001 * LANES];
        let first = run.advance_strided(&batch, 900, &mut out, LANES);
        assert!(
            first.iter().all(|&g| g),
            "{}: all good before the force",
            backend.name()
        );
        let second = run.advance_strided(&batch, 2001, &mut out[900 * LANES..], LANES);
        assert!(!second[3], "{}", backend.name());
        assert_eq!(second.iter().filter(|&&g| g).count(), LANES - 1);
        assert!((900..2001).all(|t| out[t * LANES + 3] == f64::INFINITY));
        assert!((0..2001).all(|t| out[t * LANES].is_finite()));
    }
}

#[test]
fn bad_backend_options_are_refused() {
    let input = validation_input();
    let bad = Backend::Ode45 {
        rel_tol: -1.0,
        abs_tol: 1e-9,
    };
    assert!(matches!(
        BatchSimulator::new(&input, &bad),
        Err(crate::McError::Ident(IdentError::Ode(
            msd_ode::OdeError::InvalidOption {
                name: "rel_tol",
                ..
            }
        )))
    ));
}
