//! One module per subcommand: its clap `Args` and a `run` returning the exit code.

pub mod catalog;
pub mod check;
pub mod eval;
pub mod explain;
pub mod facts;
pub mod import;
pub mod mine;
pub mod run;
pub mod synth;
