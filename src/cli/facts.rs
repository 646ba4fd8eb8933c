//! `scenalog facts LOG_DIR`: load one Argoverse 2 log and summarise it (text or `--json`), or
//! extract one relation (`--relation`) within `mine`'s limits (`--max-tuples`, `--timeout-ms`);
//! [`crate::api::facts`] does the work.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::api::facts::{facts, Facts, FactsRequest};
use crate::api::Limits;

/// Arguments of `scenalog facts`.
#[derive(clap::Args)]
pub struct Args {
    /// The log directory (holding annotations*.feather, city_SE3_egovehicle.feather and map/).
    pub log_dir: PathBuf,
    /// Print one JSON object (keys log_id, city, timestamps, tracks, tracks_by_category,
    /// lane_segments, pedestrian_crossings, drivable_areas, … and load_ms) instead of text.
    #[arg(long)]
    pub json: bool,
    /// Extract one catalog relation instead of summarising: prints its tuple count (with
    /// `--json`, the tuples as a JSON array of arrays: tracks as uuids, lanes as map ids, times
    /// as frame indices, numbers as numbers).
    #[arg(long, value_name = "NAME")]
    pub relation: Option<String>,
    /// With `--relation --json`: print one object naming the columns, `{"relation": NAME,
    /// "columns": [{"name": "X", "type": "track"}, …], "tuples": [[…], …]}` (names from the
    /// catalog, as the Python package's tables), instead of the bare array of tuples.
    #[arg(long, requires = "relation")]
    pub columns: bool,
    /// Most tuples the extracted relation may hold, as `mine --max-tuples` [default: sized to
    /// the machine, as `mine`'s].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_tuples: Option<u64>,
    /// Longest the extraction may take, in milliseconds, as `mine --timeout-ms` [default:
    /// 120000].
    #[arg(long, value_name = "MS", value_parser = clap::value_parser!(u64).range(1..))]
    pub timeout_ms: Option<u64>,
}

/// Loads the log and prints its summary or the relation; exit 2 with a message on stderr if the
/// log cannot be read, the relation is not in the catalog or its extraction passes a limit.
pub fn run(args: Args) -> ExitCode {
    let request = FactsRequest {
        log: args.log_dir.clone(),
        relation: args.relation.clone(),
        limits: Limits {
            max_tuples: args.max_tuples,
            timeout_ms: args.timeout_ms,
        },
    };
    let facts = match facts(&request) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("scenalog facts: {}", e.flags());
            return ExitCode::from(2);
        }
    };
    match facts {
        Facts::Summary(summary) if args.json => outln!("{:#}", summary.json()),
        Facts::Summary(summary) => out!("{}", summary.text()),
        Facts::Relation(relation) if args.json => {
            let json = if args.columns {
                relation.columns_json()
            } else {
                relation.tuples_json()
            };
            crate::cli::stdout::write_with(|out| {
                serde_json::to_writer(&mut *out, &json)?;
                std::io::Write::write_all(out, b"\n")
            });
        }
        Facts::Relation(relation) => out!("{}", relation.text()),
    }
    ExitCode::SUCCESS
}
