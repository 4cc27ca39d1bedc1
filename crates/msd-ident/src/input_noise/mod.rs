//! The errors-in-variables noise model shared by every time-domain fit of a measured
//! drive (one mass, repeats, chains): white sensor noise on every channel plus white
//! noise on the measured drive, seen through the plant.
//!
//! ## Why
//! The output-error fit assumes the residuals are white. When the drive is measured with
//! noise (a load cell, a base accelerometer), the plant feels u = u_m − n while the model
//! is driven by u_m, so each channel's residual is v = e − g∗n: its sensor's white noise
//! plus the drive's noise filtered by the plant (and by the sensor's own delay and
//! filter), largest near resonance and shared by the channels of one record. The
//! white-noise covariance then understates the spread of c and ζ several times over
//! (1 % force noise: 2–5×).
//!
//! ## The method
//! At θ̂, each channel's impulse response g (the model's response to one unit drive
//! sample, hold included) gives G_a(ω). The residuals' cross-spectrum is modelled as
//! S_ab(ω) = δ_ab·σ²_a + σ²_u·G_a(ω)·G_b(ω)*, one σ_a per sensor group and one σ_u for the
//! drive. σ²_a and σ²_u maximise the Whittle likelihood of the residuals' DFTs at the
//! record's own lines (independent for stationary noise; a one-factor model per line,
//! [`maximise`], by Fisher scoring), each line's spectrum taken as the fit left it: the residual is the
//! noise less what the fit absorbed, most at the resonance lines where the drive's noise
//! is largest, and the restricted likelihood ([`restricted`]) accounts for that (σ̂_u
//! 0.30 % for 0.30 % instead of 0.23–0.25 %; 3.00 % for 3 % on a chain instead of 2.86 %).
//! A likelihood-ratio test against σ_u = 0 says whether the drive's noise
//! shows. The covariance of θ is the sandwich A⁻¹·B·A⁻¹ of the Gauss–Newton matrix
//! A = JᵀJ of the weighted Jacobian and B = Jᵀ·W·Σ·W·J, computed line by line in the
//! frequency domain ([`middle_matrix`], zero-padded to ≥ 2N so that the circular
//! products are the linear ones): the intervals of the estimate that was made, under the
//! noise it was made with. With σ̂_u = 0 it is the white-noise covariance.
//!
//! Where the drive's noise shows (the test's p < 0.01), the output-error estimate is not
//! efficient — it counts the resonance's lines as the sensor's noise alone, where the
//! drive's noise makes them worth least — and its equations carry the errors-in-variables
//! bias of least squares (σ²_u·Σ Re(∂G·Ḡ), second order). A joint fit of records then
//! reports the weighted estimate instead (`records::weighted`: the frequency-domain
//! maximum likelihood of this model, each line weighted by S_k⁻¹, the variances as
//! found), with the sandwich of its own estimating equations; [`NoiseModelFit`] keeps
//! the output-error estimate's efficiency beside it. (Chains keep the output-error
//! estimate and its sandwich for now.) Where the drive's noise shows, the standard
//! errors rest on estimated variances: Satterthwaite's degrees of freedom
//! ([`satterthwaite`]) widen the t quantile.
//!
//! Over 100 simulated load-cell records (1.7 kg, 950 N/m, ζ 0.04, a 0.2–15 Hz multisine
//! at 1 kHz, an accelerometer at 0.05 m/s²) the weighted estimate's 95 % intervals of
//! m, c, k, fn and ζ cover the truth 0.95–0.98 at 1 % and 3 % force noise, where the
//! white-noise ones cover 0.19–0.50 (`cargo xtask noise-study` repeats this over 400
//! seeds and more setups, the two-storey chain among them).

mod bound;
mod fit;
mod middle;
mod psd;
mod restricted;
mod satterthwaite;
mod scoring;
mod spectral;

pub(crate) use bound::{efficiency, restricted_fit};
pub(crate) use fit::notes;
pub use fit::{NoiseModel, NoiseModelFit, ResidualWhiteness};
pub(crate) use middle::{MiddleRecord, middle_matrix};
pub use psd::ResidualSpectrum;
pub(crate) use psd::residual_spectrum_bands;
pub(crate) use restricted::Sensitivity;
pub(crate) use satterthwaite::satterthwaite;
pub(crate) use spectral::{
    Lines, SpectralModel, concentrate, impulse_spectrum, likelihood_lines, residual_spectrum,
    spectra, spectrum, whitened_ljung_box,
};

/// The level of the test for the drive's noise (and of the whiteness tests by default).
pub(crate) const WHITENESS_LEVEL: f64 = 0.01;
