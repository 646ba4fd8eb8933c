//! The integration tests of scenalog-synth in one binary (one link instead of one per file): a module
//! per concern, each saying what it tests. Run one with `cargo test -p scenalog-synth --test it MODULE::`.

mod batch;
mod conventions;
mod evaluation;
mod never_panics;
mod repair;
mod support;
