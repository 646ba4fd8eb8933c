//! The `scenalog` command's tests, one binary: each module tests one subcommand or concern
//! through the built binary (`util::scenalog`), on the real sample logs and fixture.
//!
//! Run one module with `cargo test --test cli mine::`, one test by its name.

#[path = "../../synth/tests/it/support/server.rs"]
mod server;
mod util;

mod catalog;
mod check;
mod eval;
mod explain;
mod facts;
mod hostile;
mod hostile_input;
mod import;
mod lsp;
mod mine;
mod out_confined;
mod output_folder;
mod pictures;
mod rerun;
mod run;
mod split;
mod studio;
mod synth;
mod tracker_rates;
