//! Integration tests of msd-ode: one test binary, one module per topic.

mod analytic;
mod common;
mod convergence;
mod errors;
mod exact;
mod lanes;
mod order_conditions;
mod overflow;
mod stepper;
mod units;
