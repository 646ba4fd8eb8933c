//! One module per subcommand: its clap `Args` turned into a request of [`crate::api`], the
//! result printed, and a `run` returning the exit code; `flags` (parsers for float flags) and
//! `stdout` (output that ends quietly on a closed pipe) serve them all. The subcommands call
//! only [`crate::api`] (and std, clap, serde_json): a test (`tests/tidy.rs`) reads these files
//! and fails on an import past it.

#[macro_use]
pub mod stdout;

pub mod catalog;
pub mod check;
pub mod eval;
pub mod explain;
pub mod facts;
pub mod flags;
pub mod import;
pub mod lsp;
pub mod mine;
pub mod mine_options;
pub mod run;
pub mod split;
pub mod studio;
pub mod synth;
