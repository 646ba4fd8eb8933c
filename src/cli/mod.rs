//! One module per subcommand: its clap `Args` and a `run` returning the exit code; `flags`
//! (parsers for float flags) and `stdout` (output that ends quietly on a closed pipe) serve them
//! all.

#[macro_use]
pub mod stdout;

pub mod catalog;
pub mod check;
pub mod eval;
pub mod explain;
pub mod facts;
pub mod flags;
pub mod import;
pub mod mine;
pub mod mine_options;
pub mod run;
pub mod split;
pub mod synth;
pub mod synth_fixture;
