//! One FFT planner per thread for the crate's transforms.
//!
//! rustfft plans are costly to make for lengths with large prime factors (7501 = 13·577)
//! and are reused across calls on the same thread.

use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlannerScalar};
use std::cell::RefCell;
use std::sync::Arc;

thread_local! {
    static PLANNER: RefCell<FftPlannerScalar<f64>> = RefCell::new(FftPlannerScalar::new());
}

/// The forward FFT of length `len` (unnormalised: X_k = Σ x_t e^{−2πikt/N}).
pub(crate) fn forward(len: usize) -> Arc<dyn Fft<f64>> {
    PLANNER.with(|p| p.borrow_mut().plan_fft_forward(len))
}

/// The inverse FFT of length `len` (unnormalised: no 1/N).
pub(crate) fn inverse(len: usize) -> Arc<dyn Fft<f64>> {
    PLANNER.with(|p| p.borrow_mut().plan_fft_inverse(len))
}

/// Two real sequences' DFTs at line k from the one DFT Z of z = x + i·y, by conjugate
/// symmetry: X_k = (Z_k + Z̄_(N−k))/2 and Y_k = (Z_k − Z̄_(N−k))/(2i), with `zk` = Z_k
/// and `mirror` = Z_(N−k) (Z_0 at k = 0).
pub(crate) fn split(zk: Complex64, mirror: Complex64) -> (Complex64, Complex64) {
    let x = (zk + mirror.conj()) * 0.5;
    let y = (zk - mirror.conj()) * Complex64::new(0.0, -0.5);
    (x, y)
}
