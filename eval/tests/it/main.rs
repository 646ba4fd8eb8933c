//! The integration tests of scenalog-eval in one binary (one link instead of one per file): a module
//! per concern, each saying what it tests. Run one with `cargo test -p scenalog-eval --test it MODULE::`.

mod arrow_io;
mod bad_input;
mod fixture;
mod further;
mod holdout;
mod pickle_io;
