//! `scenalog facts`: not built yet.

use std::process::ExitCode;

/// Arguments of `scenalog facts` (none yet).
#[derive(clap::Args)]
pub struct Args {}

/// Runs the subcommand.
pub fn run(_args: Args) -> ExitCode {
    super::not_built("facts")
}
