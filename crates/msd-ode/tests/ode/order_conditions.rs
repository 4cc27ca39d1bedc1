//! The Dormand–Prince tableau satisfies the Runge–Kutta order conditions: all 17 up to
//! order 5 for the propagated weights b, all 8 up to order 4 for the embedded b̂ (and b̂
//! violates at least one fifth-order condition, as an embedded lower-order formula must).

#![allow(clippy::needless_range_loop)] // index loops mirror the tableau notation

use msd_ode::tableau::{A, B, B_HAT, C, E, INTERPOLANT};

const TOL: f64 = 1e-15;

fn a(i: usize, j: usize) -> f64 {
    if j < 6 { A[i][j] } else { 0.0 }
}

/// (A v)_i
fn a_times(v: &[f64; 7]) -> [f64; 7] {
    std::array::from_fn(|i| (0..7).map(|j| a(i, j) * v[j]).sum())
}

fn dot(w: &[f64; 7], v: &[f64; 7]) -> f64 {
    w.iter().zip(v).map(|(x, y)| x * y).sum()
}

fn pow(p: i32) -> [f64; 7] {
    std::array::from_fn(|i| C[i].powi(p))
}

fn mul(u: &[f64; 7], v: &[f64; 7]) -> [f64; 7] {
    std::array::from_fn(|i| u[i] * v[i])
}

/// The 17 order conditions up to order 5 as (order, value, exact).
fn conditions(w: &[f64; 7]) -> Vec<(u32, f64, f64)> {
    let ones = [1.0; 7];
    let c = pow(1);
    let c2 = pow(2);
    let c3 = pow(3);
    let c4 = pow(4);
    let ac = a_times(&c);
    let ac2 = a_times(&c2);
    let ac3 = a_times(&c3);
    let aac = a_times(&ac);
    let aac2 = a_times(&ac2);
    let aaac = a_times(&aac);
    let a_cac = a_times(&mul(&c, &ac));
    vec![
        (1, dot(w, &ones), 1.0),
        (2, dot(w, &c), 1.0 / 2.0),
        (3, dot(w, &c2), 1.0 / 3.0),
        (3, dot(w, &ac), 1.0 / 6.0),
        (4, dot(w, &c3), 1.0 / 4.0),
        (4, dot(w, &mul(&c, &ac)), 1.0 / 8.0),
        (4, dot(w, &ac2), 1.0 / 12.0),
        (4, dot(w, &aac), 1.0 / 24.0),
        (5, dot(w, &c4), 1.0 / 5.0),
        (5, dot(w, &mul(&c2, &ac)), 1.0 / 10.0),
        (5, dot(w, &mul(&c, &ac2)), 1.0 / 15.0),
        (5, dot(w, &mul(&c, &aac)), 1.0 / 30.0),
        (5, dot(w, &mul(&ac, &ac)), 1.0 / 20.0),
        (5, dot(w, &ac3), 1.0 / 20.0),
        (5, dot(w, &a_cac), 1.0 / 40.0),
        (5, dot(w, &aac2), 1.0 / 60.0),
        (5, dot(w, &aaac), 1.0 / 120.0),
    ]
}

#[test]
fn row_sums_equal_nodes() {
    for i in 0..7 {
        let sum: f64 = (0..7).map(|j| a(i, j)).sum();
        assert!((sum - C[i]).abs() <= TOL, "row {i}: {sum} vs c = {}", C[i]);
    }
}

#[test]
fn fifth_order_weights_satisfy_all_conditions_to_order_five() {
    let conds = conditions(&B);
    assert_eq!(conds.len(), 17);
    for (k, (order, value, exact)) in conds.iter().enumerate() {
        assert!(
            (value - exact).abs() <= TOL,
            "condition {k} (order {order}): {value} vs {exact}"
        );
    }
}

#[test]
fn embedded_weights_are_fourth_order_exactly() {
    let conds = conditions(&B_HAT);
    for (k, (order, value, exact)) in conds.iter().enumerate().filter(|(_, c)| c.0 <= 4) {
        assert!(
            (value - exact).abs() <= TOL,
            "condition {k} (order {order}): {value} vs {exact}"
        );
    }
    let worst_fifth = conds
        .iter()
        .filter(|c| c.0 == 5)
        .map(|c| (c.1 - c.2).abs())
        .fold(0.0, f64::max);
    assert!(worst_fifth > 1e-6, "b̂ should not be fifth order");
}

#[test]
fn first_same_as_last_and_error_weights() {
    for j in 0..6 {
        assert_eq!(A[6][j], B[j], "FSAL: last row of A equals b");
        assert!((E[j] - (B[j] - B_HAT[j])).abs() <= TOL);
    }
    assert!((E[6] - (B[6] - B_HAT[6])).abs() <= TOL);
}

#[test]
fn interpolant_reproduces_the_step_end_and_is_consistent() {
    // At s = 1 the continuous extension equals the fifth-order solution: Σⱼ BIᵢⱼ = bᵢ.
    for i in 0..7 {
        let sum: f64 = INTERPOLANT[i].iter().sum();
        assert!((sum - B[i]).abs() <= TOL, "stage {i}");
    }
    // Its derivative at s = 0 is f(tₙ, yₙ): only the first stage contributes, with weight 1.
    for i in 0..7 {
        assert_eq!(INTERPOLANT[i][0], if i == 0 { 1.0 } else { 0.0 });
    }
}
