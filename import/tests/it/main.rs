//! The integration tests of scenalog-import in one binary (one link instead of one per file): a module
//! per concern, each saying what it tests. Run one with `cargo test -p scenalog-import --test it MODULE::`.

mod agreement;
mod coverage;
mod translate;
