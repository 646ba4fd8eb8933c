//! One module per subcommand: its clap `Args` and a `run` returning the exit code.

pub mod catalog;
pub mod check;
pub mod eval;
pub mod explain;
pub mod facts;
pub mod mine;
pub mod mine_pairs;
pub mod run;
pub mod synth;
