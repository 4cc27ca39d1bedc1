//! Integration tests of msd-opt: one test binary, one module per topic.

mod levenberg_marquardt;
mod mgh;
mod nelder_mead;
