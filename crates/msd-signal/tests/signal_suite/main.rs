//! The crate's one integration-test binary.

mod errors;
mod frf;
mod input_noise;
mod limits;
mod line_correlation;
mod multisine_prbs;
mod noise;
mod preprocess;
mod properties;
mod serde_toml;
mod signals;
mod spectral;
