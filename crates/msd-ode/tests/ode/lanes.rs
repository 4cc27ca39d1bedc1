//! ode45 lanes against the single-lane stepper: every lane's values and statistics the
//! same bits, however the grid is cut, whatever the other lanes do (different
//! parameters, rejected steps, failures, lanes left out), and the same errors.

use msd_ode::{
    LaneSystem, Ode45Lanes, Ode45Options, Ode45Stepper, OdeError, SVector, Stats, TimeGrid,
};

const B: usize = 8;

/// The paper's validation force (chirp 0.2 → 3 Hz + step at 1 s) on a plant per lane;
/// lane l's force turns NaN from `poison[l]` on (a blow-up at a known time).
#[derive(Clone, Copy)]
struct Plants {
    m: [f64; B],
    c: [f64; B],
    k: [f64; B],
    poison: [f64; B],
}

fn force(t: f64) -> f64 {
    let chirp = 2.5 * (std::f64::consts::TAU * (0.2 * t + 2.8 / 30.0 * t * t)).sin();
    chirp + if t >= 1.0 { 1.0 } else { 0.0 }
}

impl Plants {
    fn rhs(&self, lane: usize) -> impl FnMut(f64, &SVector<f64, 2>, &mut SVector<f64, 2>) {
        let (m, c, k, poison) = (self.m[lane], self.c[lane], self.k[lane], self.poison[lane]);
        move |t, y, d| {
            let f = if t >= poison { f64::NAN } else { force(t) };
            d[0] = y[1];
            d[1] = (f - c * y[1] - k * y[0]) / m;
        }
    }
}

impl LaneSystem<2, B> for Plants {
    fn rhs(&mut self, active: &[bool; B], t: &[f64; B], y: &[[f64; B]; 2], d: &mut [[f64; B]; 2]) {
        let mut f = [0.0; B];
        for l in (0..B).filter(|&l| active[l]) {
            f[l] = if t[l] >= self.poison[l] {
                f64::NAN
            } else {
                force(t[l])
            };
        }
        for l in 0..B {
            d[0][l] = y[1][l];
            d[1][l] = (f[l] - self.c[l] * y[1][l] - self.k[l] * y[0][l]) / self.m[l];
        }
    }
}

/// Eight plants ±30 % around the paper's, one nearly undamped, one stiff (many steps).
fn plants() -> Plants {
    let scale = [1.0, 0.7, 1.3, 0.9, 1.15, 0.8, 1.05, 1.25];
    Plants {
        m: scale.map(|s| 2.5 * s),
        c: std::array::from_fn(|l| if l == 3 { 1e-4 } else { 1.8 / scale[l] }),
        k: std::array::from_fn(|l| {
            if l == 6 {
                4.0e4
            } else {
                120.0 * scale[(l + 3) % B]
            }
        }),
        poison: [f64::INFINITY; B],
    }
}

fn options() -> Ode45Options {
    Ode45Options {
        rel_tol: 1e-6,
        abs_tol: 1e-9,
        ..Ode45Options::default()
    }
}

/// Lane `lane` alone: its outputs of `component` (NaN where none), statistics, error.
fn alone(
    plants: &Plants,
    lane: usize,
    times: &[f64],
    component: usize,
    options: &Ode45Options,
) -> (Vec<f64>, Stats, Option<OdeError>) {
    let mut f = plants.rhs(lane);
    let grid = TimeGrid::new(times).unwrap();
    let mut out = vec![f64::NAN; times.len()];
    let y0 = SVector::<f64, 2>::new(0.01 * lane as f64, 0.0);
    let mut stepper = match Ode45Stepper::new(&mut f, grid, &y0, options) {
        Ok(s) => s,
        Err(e) => return (out, Stats::default(), Some(e)),
    };
    let result = stepper.advance(&mut f, times.len(), |i, y| out[i] = y[component]);
    (out, stepper.stats(), result.err())
}

/// Outputs (time-major), statistics, errors, and how often each point was handed out.
type Together = (
    Vec<[f64; B]>,
    Vec<Stats>,
    Vec<Option<OdeError>>,
    Vec<[u32; B]>,
);

/// All lanes through `cuts`; outputs (NaN where none), statistics, errors, and how
/// often each point was handed out.
fn together(
    plants: &mut Plants,
    used: [bool; B],
    times: &[f64],
    component: usize,
    cuts: &[usize],
    options: &Ode45Options,
) -> Together {
    let grid = TimeGrid::new(times).unwrap();
    let y0 = [std::array::from_fn(|l| 0.01 * l as f64), [0.0; B]];
    let mut lanes = Ode45Lanes::new(plants, grid, &y0, used, options);
    let mut out = vec![[f64::NAN; B]; times.len()];
    let mut calls = vec![[0; B]; times.len()];
    for &until in cuts {
        let good = lanes.advance(plants, until, component, |l, i, v| {
            out[i][l] = v;
            calls[i][l] += 1;
        });
        assert_eq!(good, lanes.good());
    }
    let stats = (0..B).map(|l| lanes.stats(l)).collect();
    let errors = (0..B).map(|l| lanes.error(l).cloned()).collect();
    (out, stats, errors, calls)
}

fn bits(v: f64) -> u64 {
    if v.is_nan() { u64::MAX } else { v.to_bits() }
}

fn assert_lanes_equal_alone(plants: Plants, times: &[f64], cuts: &[usize], options: &Ode45Options) {
    for component in [0, 1] {
        let mut p = plants;
        let (out, stats, errors, calls) =
            together(&mut p, [true; B], times, component, cuts, options);
        for lane in 0..B {
            let (expected, expected_stats, expected_error) =
                alone(&plants, lane, times, component, options);
            for (i, e) in expected.iter().enumerate() {
                assert_eq!(
                    bits(out[i][lane]),
                    bits(*e),
                    "lane {lane}, point {i}, cuts {cuts:?}"
                );
                assert_eq!(
                    calls[i][lane],
                    u32::from(!e.is_nan()),
                    "lane {lane}, point {i}"
                );
            }
            assert_eq!(errors[lane], expected_error, "lane {lane}");
            if expected_error.is_none() {
                assert_eq!(stats[lane], expected_stats, "lane {lane}");
            }
        }
    }
}

/// Cuts at every kind of place: index 0 and 1, inside steps, repeated and decreasing
/// `until`s (no-ops), past the end; the stiff lane rejects steps.
#[test]
fn every_lane_is_the_single_stepper_bit_for_bit_however_the_grid_is_cut() {
    let times: Vec<f64> = (0..7501).map(|i| i as f64 * 0.002).collect();
    let mut rejected = 0;
    for cuts in [
        &[7501][..],
        &[0, 1, 2, 3, 5, 8, 13, 21, 34, 55, 89, 144, 7501],
        &[100, 100, 50, 3000, 2999, 7000, 9999],
        &(46..7600).step_by(46).collect::<Vec<_>>(),
    ] {
        assert_lanes_equal_alone(plants(), &times, cuts, &options());
    }
    for lane in 0..B {
        rejected += alone(&plants(), lane, &times, 0, &options())
            .1
            .rejected_steps;
    }
    assert!(rejected > 20, "the reject path is exercised: {rejected}");
}

/// Steps longer and shorter than the grid spacing, backward time, other tolerances, a
/// maximum and an initial step.
#[test]
fn coarse_fine_and_backward_grids_and_other_options() {
    let grids = [
        (0..31).map(|i| i as f64 * 0.5).collect::<Vec<_>>(),
        (0..20001).map(|i| i as f64 * 0.00075).collect(),
        (0..1500).map(|i| 15.0 - i as f64 * 0.01).collect(),
    ];
    let others = [
        options(),
        Ode45Options::default(),
        Ode45Options {
            rel_tol: 1e-10,
            abs_tol: 1e-12,
            max_step: Some(0.05),
            initial_step: Some(1e-4),
            ..Ode45Options::default()
        },
    ];
    for times in &grids {
        for options in &others {
            let cuts: Vec<usize> = (7..times.len() + 7).step_by(7).collect();
            assert_lanes_equal_alone(plants(), times, &cuts, options);
        }
    }
}

/// A lane whose force turns NaN fails with the single stepper's error at the same
/// time, after the same outputs, and the others go on untouched; so does a lane that
/// runs out of steps; lanes left out are failed without an error.
#[test]
fn failures_stay_in_their_lane() {
    let times: Vec<f64> = (0..7501).map(|i| i as f64 * 0.002).collect();
    let mut poisoned = plants();
    poisoned.poison[2] = 4.321;
    poisoned.poison[5] = 0.0; // f(t0, y0) is not finite: fails at the start
    let cuts: Vec<usize> = (46..7600).step_by(46).collect();
    assert_lanes_equal_alone(poisoned, &times, &cuts, &options());
    let (_, _, errors, _) = together(
        &mut poisoned.clone(),
        [true; B],
        &times,
        0,
        &cuts,
        &options(),
    );
    assert!(matches!(errors[2], Some(OdeError::NonFiniteState { t, .. }) if t > 4.0 && t < 4.33));
    assert!(matches!(
        errors[5],
        Some(OdeError::NonFiniteState {
            t: 0.0,
            component: 1
        })
    ));

    let few = Ode45Options {
        max_steps: 300,
        ..options()
    };
    assert_lanes_equal_alone(plants(), &times, &cuts, &few);
    let (_, _, errors, _) = together(&mut plants(), [true; B], &times, 0, &[7501], &few);
    assert!(matches!(
        errors[6],
        Some(OdeError::TooManySteps { steps: 300, .. })
    ));

    let mut used = [true; B];
    used[1] = false;
    used[7] = false;
    let (out, stats, errors, _) = together(&mut plants(), used, &times, 0, &[7501], &options());
    for lane in [1, 7] {
        assert!(out.iter().all(|o| o[lane].is_nan()) && errors[lane].is_none());
        assert_eq!(stats[lane], Stats::default());
    }
    let (expected, _, _) = alone(&plants(), 4, &times, 0, &options());
    assert!(out.iter().zip(&expected).all(|(o, e)| o[4] == *e));
}

#[test]
fn bad_options_and_initial_states_fail_the_lanes_by_name() {
    let times: Vec<f64> = (0..100).map(|i| i as f64 * 0.01).collect();
    let grid = TimeGrid::new(&times).unwrap();
    let mut p = plants();
    let bad = Ode45Options {
        rel_tol: 0.0,
        ..options()
    };
    let lanes = Ode45Lanes::new(&mut p, grid, &[[0.0; B]; 2], [true; B], &bad);
    assert_eq!(lanes.good(), [false; B]);
    assert!((0..B).all(|l| matches!(
        lanes.error(l),
        Some(OdeError::InvalidOption {
            name: "rel_tol",
            ..
        })
    )));
    let mut y0 = [[0.0; B]; 2];
    y0[1][3] = f64::INFINITY;
    let mut lanes = Ode45Lanes::new(&mut p, grid, &y0, [true; B], &options());
    assert!(matches!(
        lanes.error(3),
        Some(OdeError::NonFiniteInitialState { index: 1, value }) if *value == f64::INFINITY
    ));
    let good = lanes.advance(&mut p, 100, 0, |l, _, _| assert_ne!(l, 3));
    assert_eq!(good, std::array::from_fn(|l| l != 3));
}
