//! `scenalog`: mine Argoverse 2 driving logs for scenarios written as Datalog rules.
//!
//! The command joins the workspace's crates; each subcommand lives in its own module under
//! [`cli`] and returns the process exit code.

use scenalog::cli;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Mine Argoverse 2 driving logs for scenarios written as Datalog rules.
#[derive(Parser)]
#[command(name = "scenalog", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Print the catalog of relations rules can use (name, typed columns, doc).
    Catalog(cli::catalog::Args),
    /// Summarise a log directory, or print one relation extracted from it.
    Facts(cli::facts::Args),
    /// Check rule files and print diagnostics (exit 0 clean, 1 errors, 2 unreadable).
    Check(cli::check::Args),
    /// Evaluate a program on its own ground facts, with no log.
    Run(cli::run::Args),
    /// Mine logs with rule programs and write predictions (no arguments: the library on the sample logs).
    Mine(cli::mine::Args),
    /// Explain why a track matched a program (or why it did not).
    Explain(cli::explain::Args),
    /// Score predictions against ground truth with the official scenario-mining metrics.
    Eval(cli::eval::Args),
    /// Write a rule program from a description with an LLM, repairing it on diagnostics.
    Synth(cli::synth::Args),
    /// Translate programs of another system into Scenalog programs (`import refav DIR -o OUT`).
    Import(cli::import::Args),
    /// Serve the Language Server Protocol over standard input and output, for editors
    /// (diagnostics as you type, hover documentation, completion, quick fixes).
    Lsp(cli::lsp::Args),
    /// Open a local web app to write a rule and watch its matches on a map as you type
    /// (127.0.0.1 only unless asked).
    Studio(cli::studio::Args),
}

/// A file grown past `ulimit -f` raises SIGXFSZ, whose default action kills the process without
/// a word; ignored, the write fails with EFBIG instead, and every writer reports that as an error
/// naming its file (and publishes nothing half-written: outputs are renamed into place whole).
#[cfg(unix)]
fn report_oversized_writes() {
    // SAFETY: setting a standard signal's disposition to "ignore" before any thread starts; no
    // handler runs, so nothing async-signal-unsafe can happen.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

fn main() -> ExitCode {
    #[cfg(unix)]
    report_oversized_writes();
    let cli = Cli::parse();
    let code = match cli.command {
        Command::Catalog(a) => cli::catalog::run(a),
        Command::Facts(a) => cli::facts::run(a),
        Command::Check(a) => cli::check::run(a),
        Command::Run(a) => cli::run::run(a),
        Command::Mine(a) => cli::mine::run(a),
        Command::Explain(a) => cli::explain::run(a),
        Command::Eval(a) => cli::eval::run(a),
        Command::Synth(a) => cli::synth::run(a),
        Command::Import(a) => cli::import::run(a),
        Command::Lsp(a) => cli::lsp::run(a),
        Command::Studio(a) => cli::studio::run(a),
    };
    cli::stdout::exit_code(code)
}
