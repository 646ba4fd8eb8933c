//! The integration tests of scenalog-facts in one binary (one link instead of one per file): a module
//! per concern, each saying what it tests. Run one with `cargo test -p scenalog-facts --test it MODULE::`.

mod bad_input;
mod real_logs;
