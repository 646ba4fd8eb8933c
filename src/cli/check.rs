//! `scenalog check FILE.dl…`: parse and check rule programs against the catalog and print the
//! diagnostics. Exit 0 when no file has an error (warnings allowed), 1 when some file has an
//! error, 2 when some input cannot be read.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use crate::api::check::{check, fix, write_fixed, CheckRequest, ProgramSource};

/// Arguments of `scenalog check`.
#[derive(clap::Args)]
pub struct Args {
    /// Rule programs to check; `-` reads one from standard input.
    #[arg(required = true)]
    pub files: Vec<String>,
    /// Print one JSON array of {"file", "diagnostics"} objects instead of text.
    #[arg(long)]
    pub json: bool,
    /// Do not require a `referred` rule (for programs run with `scenalog run`).
    #[arg(long)]
    pub no_referred: bool,
    /// Apply every fix the diagnostics carry (units written where a bare number was read in
    /// one, Soufflé habits, …) and write each file back; with `-`, print the fixed program.
    #[arg(long)]
    pub fix: bool,
}

/// Checks every file and prints the diagnostics.
pub fn run(args: Args) -> ExitCode {
    let color = !args.json && std::io::stdout().is_terminal();
    let mut unreadable = false;
    let mut errors = false;
    let mut json = Vec::new();
    for file in &args.files {
        let display = if file == "-" {
            "<stdin>"
        } else {
            file.as_str()
        };
        let request = CheckRequest {
            source: ProgramSource::File(PathBuf::from(file)),
            require_referred: !args.no_referred,
        };
        let result = if args.fix {
            fix(&request).and_then(|f| {
                if f.applied > 0 && file != "-" {
                    write_fixed(std::path::Path::new(file), &f.checked.text)?;
                }
                if file == "-" {
                    out!("{}", f.checked.text);
                } else if !args.json {
                    outln!("{display}: {} fix(es) applied", f.applied);
                }
                Ok(f.checked)
            })
        } else {
            check(&request)
        };
        let checked = match result {
            Ok(c) => c,
            Err(e) => {
                eprintln!("scenalog check: {}", e.flags());
                unreadable = true;
                continue;
            }
        };
        errors |= !checked.is_clean();
        if args.json {
            json.push(serde_json::json!({
                "file": display,
                "diagnostics": checked.diagnostics_json(),
            }));
        } else if args.fix && file == "-" {
            // The fixed program is on standard output.
            eprint!("{}", checked.diagnostics_text(display, false));
            let (n_err, n_warn) = checked.counts();
            eprintln!("{display}: {n_err} error(s), {n_warn} warning(s)");
        } else {
            out!("{}", checked.diagnostics_text(display, color));
            let (n_err, n_warn) = checked.counts();
            outln!("{display}: {n_err} error(s), {n_warn} warning(s)");
        }
    }
    if args.json {
        outln!("{:#}", serde_json::Value::Array(json));
    }
    if unreadable {
        ExitCode::from(2)
    } else if errors {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
