//! `scenalog import refav FILE.py|DIR -o OUT`: translate RefAV scenario programs into Scenalog
//! programs (scenalog-import does the work). Prints one line per program that did not import,
//! naming the line and construct, and a summary. Exit 0 when every program imported except those
//! RefAV itself fails on, 1 when some program failed on Scenalog's side, 2 when the input cannot
//! be read or the output cannot be written.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::api::import::{import, parse_defects, Defects, ImportRequest, Semantics};

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
        (SemanticsArg::Scenalog, None) => Semantics::Scenalog,
        (SemanticsArg::Scenalog, Some(_)) => {
            eprintln!(
                "scenalog import: --defects chooses which of RefAV's defects RefAV's definitions reproduce; add --semantics refav"
            );
            return ExitCode::from(2);
        }
        (SemanticsArg::Refav, None) => Semantics::Refav(Defects::ALL),
        (SemanticsArg::Refav, Some(text)) => match parse_defects(&text) {
            Ok(d) => Semantics::Refav(d),
            Err(e) => {
                eprintln!("scenalog import: --defects: {}", e.flags());
                return ExitCode::from(2);
            }
        },
    };
    let request = ImportRequest {
        input,
        out,
        semantics,
    };
    let imported = match import(&request) {
        Ok(i) => i,
        Err(e) => {
            eprintln!("scenalog import: {}", e.flags());
            return ExitCode::from(2);
        }
    };
    if json {
        outln!("{}", imported.json());
    } else {
        out!("{}", imported.text(&request.out));
    }
    if imported.any_failed() {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
