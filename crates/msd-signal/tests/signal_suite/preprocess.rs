//! Preprocessing: exactness on functions it must reproduce, and refusal of bad data.

use std::f64::consts::TAU;

use msd_signal::{
    SignalError, decimate, detrend_linear, detrend_linear_at, moving_average, remove_mean,
    remove_offset, resample_uniform,
};

#[test]
fn detrend_removes_an_exact_linear_trend_to_rounding() {
    let n = 1001;
    let x: Vec<f64> = (0..n).map(|i| 3.7 - 0.0123 * i as f64).collect();
    let r = detrend_linear(&x).expect("valid");
    // Rounding: a few ulps of the largest value (|x| ≤ 12.3) per accumulated operation.
    let tol = 64.0 * f64::EPSILON * 12.3;
    assert!(
        r.iter().all(|v| v.abs() < tol),
        "max residual {}",
        r.iter().fold(0.0f64, |m, v| m.max(v.abs()))
    );

    // Non-uniform stamps: a line in t is removed, a sine on top survives (minus its own fit).
    let t: Vec<f64> = (0..n)
        .map(|i| i as f64 * 0.01 + 1e-4 * (i as f64).sin())
        .collect();
    let line: Vec<f64> = t.iter().map(|ti| -2.0 + 0.5 * ti).collect();
    let r = detrend_linear_at(&t, &line).expect("valid");
    assert!(r.iter().all(|v| v.abs() < 64.0 * f64::EPSILON * 5.0));
}

#[test]
fn offsets_and_means() {
    let x = [1.0, 2.0, 6.0];
    assert_eq!(remove_mean(&x).expect("valid"), vec![-2.0, -1.0, 3.0]);
    assert_eq!(remove_offset(&x, 1.0).expect("valid"), vec![0.0, 1.0, 5.0]);
    assert!(matches!(
        remove_offset(&x, f64::NAN),
        Err(SignalError::InvalidParameter { .. })
    ));
}

#[test]
fn moving_average_of_a_constant_is_the_constant() {
    let c = 0.1; // not exactly representable: the average must still round back to it
    let x = vec![c; 257];
    for w in [1, 3, 11, 257] {
        let y = moving_average(&x, w).expect("valid");
        assert_eq!(y.len(), x.len());
        // Summing w copies and dividing: relative error ≤ w·ε.
        assert!(
            y.iter()
                .all(|v| (v - c).abs() <= w as f64 * f64::EPSILON * c),
            "window {w}"
        );
    }
    // A straight line is unchanged away from the ends (the centred window is symmetric).
    let line: Vec<f64> = (0..50).map(|i| i as f64).collect();
    let y = moving_average(&line, 5).expect("valid");
    assert!(
        y[2..48]
            .iter()
            .zip(&line[2..48])
            .all(|(a, b)| (a - b).abs() < 1e-12)
    );
    assert_eq!(y[0], 1.0, "edge: mean of x[0..=2]");
}

#[test]
fn resampling_a_linear_function_is_exact() {
    // Irregular but increasing stamps.
    let t: Vec<f64> = (0..200)
        .map(|i| i as f64 * 0.05 + 0.01 * ((i * 7 % 5) as f64))
        .collect();
    let f = |t: f64| 1.5 - 4.0 * t;
    let x: Vec<f64> = t.iter().map(|&ti| f(ti)).collect();
    let (tn, xn) = resample_uniform(&t, &x, 0.01).expect("valid");
    assert_eq!(tn[0], t[0]);
    assert!(*tn.last().expect("non-empty") <= t[t.len() - 1]);
    assert!(t[t.len() - 1] - tn[tn.len() - 1] < 0.01);
    for (i, (ti, xi)) in tn.iter().zip(&xn).enumerate() {
        assert!((ti - (t[0] + i as f64 * 0.01)).abs() < 1e-12);
        assert!(
            (xi - f(*ti)).abs() < 1e-12 * 50.0,
            "t = {ti}: {xi} vs {}",
            f(*ti)
        );
    }
}

#[test]
fn decimation_keeps_the_band_and_rejects_aliases() {
    let (fs, factor) = (500.0, 5); // new rate 100 Hz, Nyquist 50 Hz, cut-off 40 Hz
    let n = 5000;
    let low = |t: f64| (TAU * 3.0 * t).sin();
    let high = |t: f64| (TAU * 70.0 * t).sin(); // 0.7 × the new Nyquist… above it: aliases to 30 Hz
    let x: Vec<f64> = (0..n)
        .map(|i| low(i as f64 / fs) + high(i as f64 / fs))
        .collect();
    let y = decimate(&x, factor).expect("valid");
    assert_eq!(y.len(), n / factor);
    // Interior (away from the 40-tap half-length): low passes (Hamming ripple ≲ 0.2 %),
    // the alias is attenuated beyond −40 dB.
    for (j, v) in y.iter().enumerate().skip(20).take(y.len() - 40) {
        let t = (j * factor) as f64 / fs;
        assert!(
            (v - low(t)).abs() < 0.01 + 0.003,
            "t = {t}: {v} vs {}",
            low(t)
        );
    }
    let c = decimate(&vec![4.0; 103], 4).expect("valid");
    assert_eq!(c.len(), 26);
    assert!(c.iter().all(|v| (v - 4.0).abs() < 1e-12));
    assert_eq!(decimate(&x, 1).expect("valid"), x);
}

#[test]
fn bad_data_is_refused_with_specific_errors() {
    assert!(matches!(
        remove_mean(&[]),
        Err(SignalError::EmptyData { name: "x" })
    ));
    assert!(matches!(
        detrend_linear(&[1.0]),
        Err(SignalError::TooShort { len: 1, min: 2, .. })
    ));
    assert!(matches!(
        moving_average(&[1.0, 2.0, f64::NAN, 4.0], 3),
        Err(SignalError::NonFinite {
            name: "x",
            index: 2,
            ..
        })
    ));
    assert!(matches!(
        remove_mean(&[1.0, f64::INFINITY]),
        Err(SignalError::NonFinite { index: 1, value, .. }) if value == f64::INFINITY
    ));
    assert!(matches!(
        moving_average(&[1.0, 2.0, 3.0], 5),
        Err(SignalError::WindowTooLong { window: 5, len: 3 })
    ));
    assert!(matches!(
        moving_average(&[1.0, 2.0, 3.0], 2),
        Err(SignalError::InvalidParameter { .. })
    ));
    assert!(matches!(
        moving_average(&[1.0, 2.0, 3.0], 0),
        Err(SignalError::InvalidParameter { .. })
    ));
    assert!(matches!(
        decimate(&[1.0, 2.0], 0),
        Err(SignalError::InvalidParameter { .. })
    ));
    assert!(matches!(
        decimate(&[1.0, 2.0], 3),
        Err(SignalError::WindowTooLong { window: 3, len: 2 })
    ));
    let x = [0.0, 1.0, 2.0];
    assert!(matches!(
        resample_uniform(&[0.0, 1.0], &x, 0.1),
        Err(SignalError::LengthMismatch {
            left_len: 2,
            right_len: 3,
            ..
        })
    ));
    assert!(matches!(
        resample_uniform(&[0.0, 1.0, 1.0], &x, 0.1),
        Err(SignalError::NonMonotonicTime { index: 2, .. })
    ));
    assert!(matches!(
        resample_uniform(&[0.0, 2.0, 1.0], &x, 0.1),
        Err(SignalError::NonMonotonicTime { index: 2, previous, current }) if previous == 2.0 && current == 1.0
    ));
    assert!(matches!(
        resample_uniform(&[0.0, f64::NAN, 1.0], &x, 0.1),
        Err(SignalError::NonFinite {
            name: "t",
            index: 1,
            ..
        })
    ));
    assert!(matches!(
        resample_uniform(&[0.0, 1.0, 2.0], &x, -0.1),
        Err(SignalError::InvalidParameter { .. })
    ));
    assert!(matches!(
        resample_uniform(&[0.0, 1.0, 2.0], &x, 0.0),
        Err(SignalError::InvalidParameter { .. })
    ));
    assert!(matches!(
        detrend_linear_at(&[0.0, 1.0], &x),
        Err(SignalError::LengthMismatch { .. })
    ));
}
