//! The integration tests of scenalog-view in one binary (one link instead of one per file): a module
//! per concern, each saying what it tests. Run one with `cargo test -p scenalog-view --test it MODULE::`.

mod errors;
mod layout;
mod pixels;
