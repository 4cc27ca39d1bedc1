//! Integration tests of the xtask binary and its bench: one test binary.

mod bench;
mod cli;
