//! `scenalog import refav FILE.py|DIR -o OUT`: translate RefAV scenario programs into Scenalog
//! programs (scenalog-import does the work). Prints one line per program that did not import,
//! naming the line and construct, and a summary. Exit 0 when every program imported except those
//! RefAV itself fails on, 1 when some program failed on Scenalog's side, 2 when the input cannot
//! be read or the output cannot be written.

use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `scenalog import`.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    source: Source,
}

#[derive(clap::Subcommand)]
enum Source {
    /// RefAV programs (Python over RefAV's atomic functions), a file or a directory of them.
    Refav {
        /// A RefAV program (`.py` or `.txt`), or a directory of them.
        input: PathBuf,
        /// Where to write the Scenalog programs (one `.dl` per program; created if missing).
        #[arg(short, long)]
        out: PathBuf,
        /// Print one JSON object per program instead of text.
        #[arg(long)]
        json: bool,
        /// Whose definitions the programs target where RefAV's and Scenalog's differ:
        /// Scenalog's catalog relations, or RefAV's (`refav_*` relations, to reproduce RefAV's
        /// output; see import/README.md, "RefAV semantics").
        #[arg(long, value_enum, default_value_t = SemanticsArg::Scenalog)]
        semantics: SemanticsArg,
        /// With `--semantics refav`: which of RefAV's defects to reproduce, `all` (the default:
        /// RefAV's answers as its code gives them), `none` (RefAV's definitions as meant) or a
        /// comma-separated list of ego-back-edge, crossing-direction, reverse-carry-over, crosswalk-loop, turning-spikes (see
        /// import/README.md, "RefAV's defects").
        #[arg(long, value_name = "all|none|LIST")]
        defects: Option<String>,
    },
}

/// `--semantics`.
#[derive(Clone, Copy, clap::ValueEnum)]
enum SemanticsArg {
    /// Scenalog's definitions (the default).
    Scenalog,
    /// RefAV's definitions where the catalog has them.
    Refav,
}

/// Imports and prints the report.
pub fn run(args: Args) -> ExitCode {
    let Source::Refav {
        input,
        out,
        json,
        semantics,
        defects,
    } = args.source;
    let semantics = match (semantics, defects) {
        (SemanticsArg::Scenalog, None) => scenalog_import::Semantics::Scenalog,
        (SemanticsArg::Scenalog, Some(_)) => {
            eprintln!(
                "scenalog import: --defects chooses which of RefAV's defects RefAV's definitions reproduce; add --semantics refav"
            );
            return ExitCode::from(2);
        }
        (SemanticsArg::Refav, None) => {
            scenalog_import::Semantics::Refav(scenalog_import::Defects::ALL)
        }
        (SemanticsArg::Refav, Some(text)) => match scenalog_import::Defects::parse(&text) {
            Ok(d) => scenalog_import::Semantics::Refav(d),
            Err(e) => {
                eprintln!("scenalog import: --defects: {e}");
                return ExitCode::from(2);
            }
        },
    };
    // One import writes a folder at a time (held until the report is printed).
    let _held = match crate::pipeline::lock::OutputLock::acquire(&out) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("scenalog import: {e}");
            return ExitCode::from(2);
        }
    };
    let report = match scenalog_import::import_path_with(&input, &out, semantics) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("scenalog import: {e}");
            return ExitCode::from(2);
        }
    };
    if json {
        let rows: Vec<serde_json::Value> = report
            .files
            .iter()
            .map(|f| {
                serde_json::json!({
                    "source": f.source.display().to_string(),
                    "output": f.output.as_ref().map(|p| p.display().to_string()),
                    "refav_broken": f.refav_broken(),
                    "refav_api": if f.first_api { "first" } else { "current" },
                    "notes": f.notes,
                    "errors": f.errors.iter().map(|e| serde_json::json!({
                        "line": e.line, "construct": e.construct, "message": e.message,
                        "refav_broken": e.refav_broken,
                    })).collect::<Vec<_>>(),
                })
            })
            .collect();
        outln!("{}", serde_json::Value::Array(rows));
    } else {
        for f in &report.files {
            for e in &f.errors {
                let kind = if e.refav_broken {
                    "broken in RefAV"
                } else {
                    "not imported"
                };
                outln!(
                    "{}:{}: {kind}: {}: {}",
                    f.source.display(),
                    e.line,
                    e.construct,
                    e.message
                );
            }
        }
        outln!(
            "{} programs: {} imported and checked clean into {} ({} written against RefAV's first API), {} broken in RefAV itself, {} not imported",
            report.files.len(),
            report.imported(),
            out.display(),
            report.first_api(),
            report.refav_broken(),
            report.failed_here()
        );
    }
    if report.failed_here() > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
