//! What every command-line test shares: the built `scenalog` binary as a [`Command`].

use std::process::Command;

/// The `scenalog` binary this test run built, as a command to add arguments to. Variables of
/// the environment that change the command's behaviour (the LLM server, the cache, the thread
/// count) are left as the test sets them.
pub fn scenalog() -> Command {
    Command::new(env!("CARGO_BIN_EXE_scenalog"))
}
