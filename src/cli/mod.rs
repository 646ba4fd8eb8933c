//! One module per subcommand: its clap `Args` and a `run` returning the exit code.

pub mod catalog;
pub mod check;
pub mod eval;
pub mod explain;
pub mod facts;
pub mod mine;
pub mod run;
pub mod synth;

use std::process::ExitCode;

/// Exit code for a subcommand whose issue has not landed yet: says so on stderr.
pub fn not_built(name: &str) -> ExitCode {
    eprintln!("scenalog {name}: not built yet (see the project's open issues)");
    ExitCode::from(2)
}
