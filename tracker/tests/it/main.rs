//! The integration tests of scenalog-tracker in one binary (one link instead of one per file): a module
//! per concern, each saying what it tests. Run one with `cargo test -p scenalog-tracker --test it MODULE::`.

mod equivalence;
mod input;
mod python_pickles;
