//! # msd-signal
//!
//! Everything the mass–spring–damper toolkit knows about signals, in one leaf crate:
//!
//! * [`Signal`]: excitation signals (constant, step, windowed sine, the paper's stepped
//!   sine, linear/logarithmic chirp, multisine, PRBS, sums and scaled copies) that can be
//!   evaluated at any t, sampled on a grid and asked for their [`Breakpoint`]s, and that
//!   describe themselves in TOML; [`paper_identification_input`] and
//!   [`paper_validation_input`] are the paper experiment's two inputs.
//! * [`noise`]: seeded Gaussian white noise in named, independent ChaCha streams.
//! * [`pair`]: strict `[low, high]` pairs for configs read with serde.
//! * [`quantity`]: [`ResponseQuantity`], what a sensor measures.
//! * [`recording`]: [`Recording`], one test run as every engine reads it: a uniform
//!   grid, the measured inputs and the response [`Channel`]s with their [`Quantity`],
//!   unit, scale and [`Dof`].
//! * [`preprocess`]: mean/offset and trend removal, moving average, decimation,
//!   resampling onto a uniform grid, each refusing bad data with a clear error.
//! * [`spectral`]: Welch PSD, cross spectrum, H1 frequency-response estimate and
//!   coherence on top of rustfft.
//! * [`frf`]: frequency responses from records (H1, H2, Hv with the coherence, averaged
//!   over records and segments; the force and exponential windows of an impact test),
//!   measured tables, receptance/mobility/accelerance.
//!
//! ## Signals in TOML
//! Every [`Signal`] is a table tagged by `kind`; the [`paper`] module shows both paper
//! inputs in full. For example, the validation input:
//! ```
//! let u: msd_signal::Signal = toml::from_str(r#"
//!     kind = "sum"
//!     [[terms]]
//!     kind = "chirp"
//!     amplitude = 2.5
//!     f0 = 0.2
//!     f1 = 3.0
//!     duration = 15.0
//!     [[terms]]
//!     kind = "step"
//!     amplitude = 1.0
//!     time = 1.0
//! "#)?;
//! u.validate()?;
//! assert_eq!(u, msd_signal::paper_validation_input());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Example: the paper's identification data, seeded
//! ```
//! use msd_signal::{gaussian_noise, h1_estimate, paper_identification_input, WelchOptions};
//!
//! let (dt, n) = (0.002, 7501);
//! let u = paper_identification_input();
//! u.validate()?;
//! let force = u.sample(0.0, dt, n);
//! assert_eq!(force[250], 6.0); // t = 0.5 s, right at the step: H(0) = 1
//!
//! // The simulator must not smooth over these:
//! let jumps: Vec<f64> = u.breakpoints(0.0, 15.0).iter().map(|b| b.time).collect();
//! assert_eq!(jumps, [0.5, 3.0, 9.0]);
//!
//! // Measurement noise from the run's seed, in the identification data set's own stream.
//! let noise = gaussian_noise(2024, "identification", 0.0025, n)?;
//! assert_eq!(noise, gaussian_noise(2024, "identification", 0.0025, n)?);
//!
//! // A frequency-domain look (here: the force through a pure gain of 2).
//! let y: Vec<f64> = force.iter().zip(&noise).map(|(f, e)| 2.0 * f + e).collect();
//! let frf = h1_estimate(&force, &y, 1.0 / dt, &WelchOptions::default())?;
//! assert_eq!(frf.averages, 1); // the default: the whole record as one segment
//! # Ok::<(), msd_signal::SignalError>(())
//! ```

pub mod error;
pub mod frf;
pub mod lowpass;
pub mod noise;
pub mod pair;
pub mod paper;
pub mod preprocess;
pub mod quantity;
pub mod recording;
pub mod signal;
pub mod spectral;

pub use error::{Result, SignalError};
pub use frf::{
    Estimator, FrfKind, FrfOptions, ImpactWindows, LineCorrelation, REPEATING, Record, UNEXCITED,
    force_channel_noise, frf_estimate, resolve_window,
};
pub use lowpass::{central_difference, lowpass_zero_phase};
pub use noise::{NoiseStream, gaussian_noise, stream_id, stream_rng};
pub use paper::{paper_identification_input, paper_validation_input};
pub use preprocess::{
    decimate, detrend_linear, detrend_linear_at, moving_average, remove_mean, remove_offset,
    resample_uniform,
};
pub use quantity::ResponseQuantity;
pub use recording::{Channel, Dof, Frame, Quantity, Recording};
pub use rustfft::num_complex::Complex64;
pub use signal::{
    Breakpoint, ClippingOptions, LineSelection, Multisine, MultisineSpec, PhaseScheme, Prbs,
    PrbsSpec, PreparedSignal, Signal, SineSegment, Sweep,
};
pub use spectral::{
    CrossSpectrum, Detrend, DftPair, FrequencyResponseEstimate, Spectrum, WelchOptions, Window,
    coherence, cross_spectrum, h1_estimate, welch_psd,
};
