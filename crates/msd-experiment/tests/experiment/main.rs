//! Integration tests of msd-experiment: one test binary, one module per topic.

mod cli;
mod in_memory;
