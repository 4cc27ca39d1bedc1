//! Integration tests of msd-experiment: one test binary, one module per topic.

mod cli;
mod download;
mod fetch;
mod in_memory;
