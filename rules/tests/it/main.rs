//! The integration tests of scenalog-rules in one binary (one link instead of one per file): a module
//! per concern, each saying what it tests. Run one with `cargo test -p scenalog-rules --test it MODULE::`.

mod codes;
mod grammar;
mod hints;
mod library;
mod no_panic;
mod parse;
mod render;
mod roundtrip;
mod scale;
mod strata;
