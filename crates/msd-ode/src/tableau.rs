//! The Dormand–Prince 5(4) Butcher tableau and its continuous extension.
//!
//! Coefficients are exact rationals written as `num / den` from J. R. Dormand and
//! P. J. Prince, "A family of embedded Runge–Kutta formulae", J. Comput. Appl. Math. 6
//! (1980) 19–26, in the form MATLAB's `ode45` uses (L. F. Shampine and M. W. Reichelt,
//! "The MATLAB ODE Suite", SIAM J. Sci. Comput. 18 (1997) 1–22). The dense-output matrix
//! [`INTERPOLANT`] is the one of MATLAB's `ntrp45`.

/// Nodes c₁…c₇ (stage times as fractions of the step).
pub const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];

/// Strictly lower triangular coupling matrix a_ij (row i = stage i+1).
pub const A: [[f64; 6]; 7] = [
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];

/// Fifth-order weights b (the solution that is propagated; equal to the last row of
/// [`A`], which makes the method first-same-as-last).
pub const B: [f64; 7] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
    0.0,
];

/// Embedded fourth-order weights b̂.
pub const B_HAT: [f64; 7] = [
    5179.0 / 57600.0,
    0.0,
    7571.0 / 16695.0,
    393.0 / 640.0,
    -92097.0 / 339200.0,
    187.0 / 2100.0,
    1.0 / 40.0,
];

/// Error weights E = b − b̂, exactly as MATLAB's `ode45` writes them.
pub const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Continuous extension (MATLAB's `ntrp45` matrix `BI`): with s = (t − tₙ)/h,
/// y(t) = yₙ + h · Σᵢ fᵢ · (BIᵢ₀ s + BIᵢ₁ s² + BIᵢ₂ s³ + BIᵢ₃ s⁴).
/// A fourth-order interpolant that reproduces y_{n+1} at s = 1.
pub const INTERPOLANT: [[f64; 4]; 7] = [
    [1.0, -183.0 / 64.0, 37.0 / 12.0, -145.0 / 128.0],
    [0.0, 0.0, 0.0, 0.0],
    [0.0, 1500.0 / 371.0, -1000.0 / 159.0, 1000.0 / 371.0],
    [0.0, -125.0 / 32.0, 125.0 / 12.0, -375.0 / 64.0],
    [0.0, 9477.0 / 3392.0, -729.0 / 106.0, 25515.0 / 6784.0],
    [0.0, -11.0 / 7.0, 11.0 / 3.0, -55.0 / 28.0],
    [0.0, 3.0 / 2.0, -4.0, 5.0 / 2.0],
];
