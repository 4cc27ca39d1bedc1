//! Seeded Gaussian white noise in named, independent streams.
//!
//! ## The algorithm
//! A run has one `u64` seed; each data set draws from its own *named stream*. The pair
//! (seed, stream name) selects a ChaCha20 generator (rand_chacha's `ChaCha20Rng`):
//!
//! * the 256-bit key is four successive outputs of SplitMix64 started at `seed`
//!   (Steele, Lea & Flood 2014; constants 0x9E3779B97F4A7C15, 0xBF58476D1CE4E5B9,
//!   0x94D049BB133111EB), little-endian;
//! * the 64-bit ChaCha stream (nonce) is [`stream_id`]`(name)`, the FNV-1a 64-bit hash of
//!   the name's UTF-8 bytes (offset basis 0xcbf29ce484222325, prime 0x100000001b3),
//!   set with `ChaCha20Rng::set_stream`.
//!
//! Both are written out here, so they never change with the Rust or rand version, and
//! ChaCha20 is platform independent: **(seed, stream) fully determines the uniform
//! draws on every platform**. Gaussian samples are σ × rand_distr's `StandardNormal`
//! (Ziggurat), fixed for the pinned rand_distr 0.5 line. Different names give different
//! ChaCha streams, so identification and validation noise are independent and adding a
//! new stream elsewhere never changes existing ones.
//!
//! ```
//! use msd_signal::{NoiseStream, gaussian_noise};
//!
//! let e_id = gaussian_noise(42, "identification", 0.0025, 7501)?;
//! let e_val = gaussian_noise(42, "validation", 0.0025, 7501)?;
//! assert_ne!(e_id, e_val);
//! assert_eq!(e_id, gaussian_noise(42, "identification", 0.0025, 7501)?);
//!
//! // The same samples, streamed in pieces:
//! let mut s = NoiseStream::new(42, "identification", 0.0025)?;
//! let mut head = [0.0; 10];
//! s.fill(&mut head);
//! assert_eq!(&head[..], &e_id[..10]);
//! # Ok::<(), msd_signal::SignalError>(())
//! ```

use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;
use rand_distr::{Distribution, StandardNormal};

use crate::error::{Result, SignalError, non_negative};

/// FNV-1a 64-bit hash of `name`'s UTF-8 bytes: the ChaCha stream number of a named stream.
///
/// ```
/// assert_eq!(msd_signal::stream_id(""), 0xcbf29ce484222325);
/// assert_eq!(msd_signal::stream_id("a"), 0xaf63dc4c8601ec8c);
/// ```
pub fn stream_id(name: &str) -> u64 {
    const OFFSET_BASIS: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    name.bytes()
        .fold(OFFSET_BASIS, |h, b| (h ^ u64::from(b)).wrapping_mul(PRIME))
}

/// One SplitMix64 step.
fn splitmix64(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The ChaCha20 generator of (seed, stream name), as described in the [module docs](self).
///
/// Use it for any other seeded draw (e.g. random phases) so that it follows the same
/// stream discipline.
pub fn stream_rng(seed: u64, stream: &str) -> ChaCha20Rng {
    let mut state = seed;
    let mut key = [0u8; 32];
    for chunk in key.chunks_exact_mut(8) {
        chunk.copy_from_slice(&splitmix64(&mut state).to_le_bytes());
    }
    let mut rng = ChaCha20Rng::from_seed(key);
    rng.set_stream(stream_id(stream));
    rng
}

/// A stream of N(0, σ²) samples drawn from [`stream_rng`]`(seed, stream)`.
#[derive(Debug, Clone)]
pub struct NoiseStream {
    rng: ChaCha20Rng,
    sigma: f64,
}

impl NoiseStream {
    /// Largest σ accepted: a standard normal draw never exceeds 16 in magnitude (the
    /// ziggurat's tail from a 53-bit uniform), so σ·z stays finite with a wide margin.
    pub const MAX_SIGMA: f64 = 1e300;

    /// A new stream; `sigma` must be finite, ≥ 0 and at most [`NoiseStream::MAX_SIGMA`]
    /// (σ = 0 gives zeros).
    pub fn new(seed: u64, stream: &str, sigma: f64) -> Result<Self> {
        non_negative(|| "sigma".into(), sigma)?;
        if sigma > Self::MAX_SIGMA {
            return Err(SignalError::InvalidParameter {
                parameter: "sigma".into(),
                value: sigma,
                expected: "a finite value in 0 ..= 1e300",
            });
        }
        Ok(NoiseStream {
            rng: stream_rng(seed, stream),
            sigma,
        })
    }

    /// The standard deviation σ.
    pub fn sigma(&self) -> f64 {
        self.sigma
    }

    /// The next sample.
    pub fn next_sample(&mut self) -> f64 {
        let z: f64 = StandardNormal.sample(&mut self.rng);
        self.sigma * z
    }

    /// Overwrites `out` with the next `out.len()` samples.
    pub fn fill(&mut self, out: &mut [f64]) {
        for o in out {
            *o = self.next_sample();
        }
    }

    /// Adds the next `out.len()` samples to `out` (e.g. to a simulated output).
    pub fn add_to(&mut self, out: &mut [f64]) {
        for o in out {
            *o += self.next_sample();
        }
    }
}

/// `n` samples of N(0, σ²) white noise from stream `stream` of `seed`.
///
/// Errors if `sigma` is NaN, infinite, negative or above [`NoiseStream::MAX_SIGMA`].
///
/// ```
/// let e = msd_signal::gaussian_noise(7, "identification", 0.0025, 4)?;
/// assert_eq!(e.len(), 4);
/// assert!(matches!(msd_signal::gaussian_noise(7, "x", -1.0, 4),
///     Err(msd_signal::SignalError::InvalidParameter { .. })));
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
pub fn gaussian_noise(seed: u64, stream: &str, sigma: f64, n: usize) -> Result<Vec<f64>> {
    let mut s = NoiseStream::new(seed, stream, sigma)?;
    let mut out = vec![0.0; n];
    s.fill(&mut out);
    Ok(out)
}
