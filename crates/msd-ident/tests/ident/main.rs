//! Integration tests of msd-ident: one test binary, one module per topic.

mod common;
mod data;
mod diagnostics;
mod error_paths;
mod estimation;
mod frf;
mod nonlinear;
mod serialize;
mod stress;
