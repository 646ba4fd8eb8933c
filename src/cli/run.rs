//! `scenalog run FILE.dl [--print REL]… [--json] [--max-tuples N] [--timeout-ms N]`: evaluate a
//! program on its own ground facts, with no log, within `mine`'s limits by default. Checker diagnostics come first; then each
//! requested relation's tuples, one per line in the program's syntax, sorted (`--json`: one object
//! of relation name -> array of tuples); without `--print`, the size of every derived relation.
//! Exit 0 when it ran, 1 on check or evaluation errors, 2 when the input cannot be read.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use crate::api::check::ProgramSource;
use crate::api::run::{run as run_program, RunRequest};
use crate::api::Limits;

/// Arguments of `scenalog run`.
#[derive(clap::Args)]
pub struct Args {
    /// The rule program; `-` reads it from standard input.
    pub file: String,
    /// Print this relation's tuples (repeatable); default: sizes of all derived relations. Only
    /// the relations printed are read: the others may be inlined or derived only for what those
    /// need, as Soufflé computes for its outputs.
    #[arg(long = "print", value_name = "REL")]
    pub print: Vec<String>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Stop when the program's relations together (its facts and every derived relation) hold
    /// more tuples than this (default: `mine`'s, sized to the machine's memory).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_tuples: Option<u64>,
    /// Stop when evaluation runs longer than this many milliseconds (default: `mine`'s,
    /// 120,000).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub timeout_ms: Option<u64>,
}

/// Checks and evaluates the program and prints what was asked.
pub fn run(args: Args) -> ExitCode {
    let display = if args.file == "-" {
        "<stdin>"
    } else {
        args.file.as_str()
    };
    let request = RunRequest {
        source: ProgramSource::File(PathBuf::from(&args.file)),
        display: display.to_string(),
        print: args.print.clone(),
        limits: Limits {
            max_tuples: args.max_tuples,
            timeout_ms: args.timeout_ms,
        },
    };
    let ran = match run_program(&request) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("scenalog run: {}", e.flags());
            return ExitCode::from(2);
        }
    };
    let checked = &ran.checked;
    if !checked.outcome.diagnostics.is_empty() {
        if args.json && !checked.is_clean() {
            outln!(
                "{:#}",
                serde_json::json!({ "diagnostics": checked.diagnostics_json() })
            );
        } else {
            let color = std::io::stderr().is_terminal();
            eprint!("{}", checked.diagnostics_text(display, color));
        }
    }
    let evaluated = match ran.evaluation {
        None => return ExitCode::from(1),
        Some(Err(e)) => {
            eprintln!("scenalog run: {}", e.flags());
            return ExitCode::from(1);
        }
        Some(Ok(evaluated)) => evaluated,
    };
    if args.json {
        outln!("{:#}", evaluated.json());
    } else {
        out!("{}", evaluated.text());
    }
    ExitCode::SUCCESS
}
