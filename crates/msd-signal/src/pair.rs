//! `[low, high]` pairs in TOML, read strictly: exactly two values.
//!
//! Serde reads a `[T; 2]` from the first two elements of a longer array and drops the
//! rest without a word, so `bounds = { stiffness = [50.0, 200.0, 300.0] }` would run with
//! [50, 200]. These helpers, for `#[serde(deserialize_with = …)]`, refuse any other
//! length by name (the error carries the key's position).
//!
//! ```
//! #[derive(serde::Deserialize)]
//! struct Band {
//!     #[serde(deserialize_with = "msd_signal::pair::exactly_two")]
//!     band: [f64; 2],
//! }
//! assert!(toml::from_str::<Band>("band = [1.0, 2.0]").is_ok());
//! let err = toml::from_str::<Band>("band = [1.0, 2.0, 3.0]").err().unwrap();
//! assert!(err.to_string().contains("expected 2 values [low, high], got 3"), "{err}");
//! ```

use serde::{Deserialize, Deserializer, de::Error};

/// Exactly two values.
pub fn exactly_two<'de, D, T>(d: D) -> Result<[T; 2], D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    let values = Vec::<T>::deserialize(d)?;
    let got = values.len();
    <[T; 2]>::try_from(values)
        .map_err(|_| D::Error::custom(format!("expected 2 values [low, high], got {got}")))
}

/// An optional pair: absent (with `#[serde(default)]`) or exactly two values.
pub fn optional<'de, D, T>(d: D) -> Result<Option<[T; 2]>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    exactly_two(d).map(Some)
}
