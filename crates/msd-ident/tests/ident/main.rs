//! Integration tests of msd-ident: one test binary, one module per topic.

mod common;
mod data;
mod diagnostics;
mod error_paths;
mod estimation;
mod nonlinear;
mod nonlinear_fast;
mod serialize;
mod stress;
