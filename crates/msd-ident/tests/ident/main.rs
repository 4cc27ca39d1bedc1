//! Integration tests of msd-ident: one test binary, one module per topic.

mod common;
mod data;
mod design;
mod diagnostics;
mod dynamometer;
mod error_paths;
mod estimation;
mod free_decay;
mod frf;
mod inverse_dynamics;
mod noise_model;
mod nonlinear;
mod nonlinear_fast;
mod plan;
mod records;
mod serialize;
mod stress;
mod validation;
