//! `scenalog run`: not built yet.

use std::process::ExitCode;

/// Arguments of `scenalog run` (none yet).
#[derive(clap::Args)]
pub struct Args {}

/// Runs the subcommand.
pub fn run(_args: Args) -> ExitCode {
    super::not_built("run")
}
