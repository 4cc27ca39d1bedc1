//! msd-opt (placeholder while the crate is being built).
