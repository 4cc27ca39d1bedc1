//! Integration tests of msd-opt: one test binary, one module per topic.

mod mgh;
mod nelder_mead;
