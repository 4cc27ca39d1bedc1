//! Placeholder while the estimators land.
fn main() {}
