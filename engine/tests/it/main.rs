//! The integration tests of scenalog-engine in one binary (one link instead of one per file): a module
//! per concern, each saying what it tests. Run one with `cargo test -p scenalog-engine --test it MODULE::`.

mod concepts_real_logs;
mod differential;
mod fact_scene;
mod features;
mod library;
mod library_facts;
mod meaning_real_logs;
mod naive;
mod no_panic;
mod oracle;
mod pushdown;
mod real_logs;
mod rng;
mod souffle;
mod why_not;
mod wide;
