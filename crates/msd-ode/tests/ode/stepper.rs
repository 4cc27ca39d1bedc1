//! The resumable ode45 stepper against ode45_with: the same bits however the grid is cut,
//! the same errors, and no re-checking of a shared grid.

use msd_ode::{Ode45Options, Ode45Stepper, OdeError, SVector, TimeGrid, ode45_with};

/// The paper's plant under the paper's validation force (chirp 0.2 → 3 Hz + step at 1 s):
/// a jump, a sweep through resonance, hundreds of steps.
fn paper_rhs(m: f64, c: f64, k: f64) -> impl FnMut(f64, &SVector<f64, 2>, &mut SVector<f64, 2>) {
    move |t, y, d| {
        let chirp = 2.5 * (std::f64::consts::TAU * (0.2 * t + 2.8 / 30.0 * t * t)).sin();
        let step = if t >= 1.0 { 1.0 } else { 0.0 };
        d[0] = y[1];
        d[1] = (chirp + step - c * y[1] - k * y[0]) / m;
    }
}

fn paper_options() -> Ode45Options {
    Ode45Options {
        rel_tol: 1e-6,
        abs_tol: 1e-9,
        ..Ode45Options::default()
    }
}

fn whole(times: &[f64], options: &Ode45Options) -> (Vec<[f64; 2]>, msd_ode::Stats) {
    let mut f = paper_rhs(2.5, 1.8, 120.0);
    let mut out = Vec::new();
    let stats = ode45_with(&mut f, times, &SVector::zeros(), options, |_, y| {
        out.push([y[0], y[1]])
    })
    .unwrap();
    (out, stats)
}

/// Cuts at every kind of place: index 0 and 1, inside a step (several grid points per
/// step at dt = 2 ms), repeated and decreasing `until`s (no-ops), and past the end.
#[test]
fn any_cutting_of_the_grid_gives_the_same_bits_and_statistics() {
    let times: Vec<f64> = (0..7501).map(|i| i as f64 * 0.002).collect();
    let options = paper_options();
    let (reference, stats) = whole(&times, &options);
    let cuts: [&[usize]; 4] = [
        &[7501],
        &[0, 1, 2, 3, 5, 8, 13, 21, 34, 55, 89, 144, 7501],
        &[100, 100, 50, 3000, 2999, 7000, 9999],
        &[1; 1],
    ];
    for cut in cuts {
        let mut f = paper_rhs(2.5, 1.8, 120.0);
        let grid = TimeGrid::new(&times).unwrap();
        let mut stepper = Ode45Stepper::new(&mut f, grid, &SVector::zeros(), &options).unwrap();
        let mut out = vec![[f64::NAN; 2]; times.len()];
        let mut calls = 0;
        for &until in cut {
            let before = stepper.next_index();
            stepper
                .advance(&mut f, until, |i, y| {
                    out[i] = [y[0], y[1]];
                    calls += 1;
                })
                .unwrap();
            assert_eq!(stepper.next_index(), until.clamp(before, times.len()));
        }
        let done = stepper.next_index();
        assert_eq!(calls, done, "each grid point exactly once");
        assert_eq!(out[..done], reference[..done], "cut {cut:?}");
        if done == times.len() {
            assert!(stepper.is_finished());
            assert_eq!(stepper.stats(), stats);
        }
    }
}

/// Steps may be longer than the grid spacing or shorter: both sides of it.
#[test]
fn coarse_and_fine_grids_and_backward_time() {
    let options = paper_options();
    for times in [
        (0..31).map(|i| i as f64 * 0.5).collect::<Vec<_>>(),
        (0..20001).map(|i| i as f64 * 0.00075).collect(),
        (0..1500).map(|i| 15.0 - i as f64 * 0.01).collect(),
    ] {
        let (reference, _) = whole(&times, &options);
        let mut f = paper_rhs(2.5, 1.8, 120.0);
        let grid = TimeGrid::new(&times).unwrap();
        let mut stepper = Ode45Stepper::new(&mut f, grid, &SVector::zeros(), &options).unwrap();
        let mut out = vec![[f64::NAN; 2]; times.len()];
        for until in (7..times.len() + 7).step_by(7) {
            stepper
                .advance(&mut f, until, |i, y| out[i] = [y[0], y[1]])
                .unwrap();
        }
        assert_eq!(out, reference);
    }
}

#[test]
fn errors_are_those_of_ode45_with() {
    let times: Vec<f64> = (0..7501).map(|i| i as f64 * 0.002).collect();
    let options = Ode45Options {
        max_steps: 40,
        ..paper_options()
    };
    let mut f = paper_rhs(2.5, 1.8, 120.0);
    let expected = ode45_with(&mut f, &times, &SVector::zeros(), &options, |_, _| {}).unwrap_err();
    assert!(matches!(expected, OdeError::TooManySteps { steps: 40, .. }));
    let grid = TimeGrid::new(&times).unwrap();
    let mut stepper = Ode45Stepper::new(&mut f, grid, &SVector::zeros(), &options).unwrap();
    stepper.advance(&mut f, 10, |_, _| {}).unwrap();
    let got = stepper.advance(&mut f, 7501, |_, _| {}).unwrap_err();
    assert_eq!(got, expected);

    let bad = Ode45Options {
        rel_tol: 0.0,
        ..paper_options()
    };
    assert!(matches!(
        Ode45Stepper::new(&mut f, grid, &SVector::zeros(), &bad),
        Err(OdeError::InvalidOption {
            name: "rel_tol",
            ..
        })
    ));
    assert!(matches!(
        Ode45Stepper::new(
            &mut f,
            grid,
            &SVector::<f64, 2>::new(f64::NAN, 0.0),
            &options
        ),
        Err(OdeError::NonFiniteInitialState { index: 0, .. })
    ));
    let mut blows_up =
        |_t: f64, _y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| d.fill(f64::INFINITY);
    assert!(matches!(
        Ode45Stepper::new(&mut blows_up, grid, &SVector::zeros(), &options),
        Err(OdeError::NonFiniteState { component: 0, .. })
    ));
    for (span, index) in [
        (&[0.0][..], 0),
        (&[0.0, f64::NAN][..], 1),
        (&[1.0, 1.0][..], 1),
    ] {
        assert!(
            matches!(TimeGrid::new(span), Err(OdeError::InvalidTimeSpan { index: i, .. }) if i == index),
            "{span:?}"
        );
    }
}
