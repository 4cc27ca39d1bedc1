//! Integration tests of msd-opt: one test binary, one module per topic.

mod faults;
mod levenberg_marquardt;
mod mgh;
mod multistart;
mod nelder_mead;
