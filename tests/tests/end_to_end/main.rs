//! End-to-end tests of the toolkit (one test binary; the property tests are another,
//! `cargo test -p msd-tests --test properties`).

mod bad_input;
mod bad_sets;
mod chain_experiment;
mod determinism;
mod docs;
mod emps;
mod experiment;
mod faults;
mod files;
mod frf_compare;
mod frf_experiment;
mod golden;
mod init;
mod nonlinear_experiment;
mod oma_experiment;
mod summary_format;
