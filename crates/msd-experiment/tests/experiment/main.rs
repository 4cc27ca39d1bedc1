//! Integration tests of msd-experiment: one test binary, one module per topic.

mod cli;
mod design;
#[cfg(feature = "download")]
mod download;
mod fetch;
mod frf_beam;
mod frf_coverage;
mod frf_modes_coverage;
mod frf_set;
mod frf_table;
mod frf_uff;
mod in_memory;
mod plan;
mod plan_setups;
mod setups;
mod unused_sections;
