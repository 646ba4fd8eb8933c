//! `scenalog facts LOG_DIR`: load one Argoverse 2 log and summarise it (text or `--json`).

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
    let summary = SceneSummary::of(&scene);
    if args.json {
        let mut json = summary.to_json();
        json["load_ms"] = serde_json::json!(load_ms);
        println!("{json:#}");
    } else {
        print!("{}", summary.to_text());
        println!("  loaded in {load_ms:.1} ms");
    }
    ExitCode::SUCCESS
}
