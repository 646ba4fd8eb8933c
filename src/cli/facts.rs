//! `scenalog facts LOG_DIR`: load one Argoverse 2 log and summarise it (text or `--json`), or
//! extract one relation (`--relation`) within `mine`'s limits (`--max-tuples`, `--timeout-ms`).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use scenalog_facts::{load_scene, SceneSummary};

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

/// Loads the log and prints its summary; exit 2 with a message on stderr if it cannot be read.
pub fn run(args: Args) -> ExitCode {
    let start = Instant::now();
    let scene = match load_scene(&args.log_dir) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("scenalog facts: {e}");
            return ExitCode::from(2);
        }
    };
    let load_ms = start.elapsed().as_secs_f64() * 1e3;
    if let Some(name) = &args.relation {
        let limits = crate::pipeline::limits::pair_limits(args.max_tuples, args.timeout_ms, 1);
        return print_relation(&scene, name, (args.json, args.columns), &limits);
    }
    let summary = SceneSummary::of(&scene);
    if args.json {
        let mut json = summary.to_json();
        json["load_ms"] = serde_json::json!(load_ms);
        outln!("{json:#}");
    } else {
        out!("{}", summary.to_text());
        outln!("  loaded in {load_ms:.1} ms");
    }
    ExitCode::SUCCESS
}

/// Extracts one relation within `limits` (its tuple budget and time limit, `mine`'s by default)
/// and prints its count (text) or its tuples (`--json`; with `--columns` named, see [`Args`]).
fn print_relation(
    scene: &scenalog_facts::Scene,
    name: &str,
    (json, columns): (bool, bool),
    limits: &scenalog_engine::Options,
) -> ExitCode {
    let Some(spec) = scenalog_facts::catalog::relation(name) else {
        eprintln!(
            "scenalog facts: `{name}` is not a relation of the catalog (see `scenalog catalog`)"
        );
        return ExitCode::from(2);
    };
    let start = Instant::now();
    let request = scenalog_facts::relation::Request::all(name);
    let budget = scenalog_extractors::Budget::new(limits.max_tuples, start, limits.timeout);
    let extractor = scenalog_extractors::cache::Extractor::new(scene);
    let data = match extractor.extract_within(&request, &budget) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("scenalog facts: extracting {name}: {e}");
            return ExitCode::from(2);
        }
    };
    let ms = start.elapsed().as_secs_f64() * 1e3;
    if json {
        let mut json = scenalog_extractors::relation_json(scene, &data);
        if columns {
            let named: Vec<serde_json::Value> = spec
                .column_names()
                .into_iter()
                .zip(spec.types())
                .map(|(n, t)| serde_json::json!({"name": n, "type": t.to_string()}))
                .collect();
            json = serde_json::json!({"relation": name, "columns": named, "tuples": json});
        }
        crate::cli::stdout::write_with(|out| {
            serde_json::to_writer(&mut *out, &json)?;
            std::io::Write::write_all(out, b"\n")
        });
    } else {
        outln!(
            "{}: {name}: {} tuples ({ms:.1} ms)",
            scene.log_id,
            data.len()
        );
    }
    ExitCode::SUCCESS
}
