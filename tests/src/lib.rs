//! Cross-crate end-to-end tests of the msd toolkit.
//!
//! The library part is intentionally empty; the tests live in `tests/tests/`.
