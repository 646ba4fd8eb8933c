//! `scenalog eval`: score predictions against ground truth with the official scenario-mining metrics.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

use scenalog_eval::{evaluate, read_any, EvalOptions, RoiMaps};

/// Arguments of `scenalog eval`.
#[derive(clap::Args)]
pub struct Args {
    /// Predictions: official pickle or long Arrow table.
    #[arg(long)]
    pred: PathBuf,
    /// Ground truth: official pickle or long Arrow table.
    #[arg(long)]
    gt: PathBuf,
    /// Objects farther than this from the ego (x-y) are not evaluated (a finite number of
    /// metres greater than 0).
    #[arg(long, default_value_t = 50.0, value_parser = crate::cli::flags::positive_finite)]
    max_range_m: f64,
    /// Dataset directory holding one directory per log id (`<log_id>/map/log_map_archive_*.json`):
    /// objects outside the drivable area grown by 5 m are not evaluated (the official `--dataset_dir`).
    #[arg(long)]
    dataset_dir: Option<PathBuf>,
    /// Print one JSON object (full precision) instead of text.
    #[arg(long)]
    json: bool,
    /// Also print per-prompt values.
    #[arg(long)]
    per_prompt: bool,
    /// Write `temporal_metrics.json` and `spatiotemporal_metrics.json` (as the official code) into this directory.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Runs the subcommand: exit 0 on success, 2 on unreadable or inconsistent input.
pub fn run(args: Args) -> ExitCode {
    let loaded = read_any(&args.pred).and_then(|p| read_any(&args.gt).map(|g| (p, g)));
    let (pred, gt) = match loaded {
        Ok(x) => x,
        Err(e) => {
            eprintln!("scenalog eval: {e}");
            return ExitCode::from(2);
        }
    };
    let roi = match &args.dataset_dir {
        None => None,
        Some(dir) => {
            let ids = gt.sequences.keys().chain(pred.sequences.keys());
            match RoiMaps::load(dir, ids.map(|k| k.0.as_str())) {
                Ok(m) => Some(Arc::new(m)),
                Err(e) => {
                    eprintln!("scenalog eval: --dataset-dir: {e}");
                    return ExitCode::from(2);
                }
            }
        }
    };
    let opts = EvalOptions {
        max_range_m: args.max_range_m,
        roi,
    };
    let report = match evaluate(&pred, &gt, &opts) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("scenalog eval: {e}");
            return ExitCode::from(2);
        }
    };
    if let Some(dir) = &args.out {
        let (temporal, spatio) = report.official_json();
        let mut files = vec![("temporal_metrics.json", temporal)];
        if let Some(s) = spatio {
            files.push(("spatiotemporal_metrics.json", s));
        }
        let written = std::fs::create_dir_all(dir).and_then(|()| {
            files
                .iter()
                .try_for_each(|(name, v)| std::fs::write(dir.join(name), format!("{v:#}\n")))
        });
        if let Err(e) = written {
            eprintln!("scenalog eval: {}: {e}", dir.display());
            return ExitCode::from(2);
        }
    }
    if args.json {
        outln!("{:#}", report.to_json());
        return ExitCode::SUCCESS;
    }
    outln!("HOTA-Temporal: {}", report.hota_temporal);
    outln!("HOTA-Track: {}", report.hota_track);
    outln!("Timestamp-level Balanced Accuracy: {}", report.timestamp_ba);
    outln!("Log-level Balanced Accuracy: {}", report.log_ba);
    if args.per_prompt {
        outln!();
        outln!("prompt\tHOTA-Temporal\tHOTA-Track\ttimestamp BA\tlog BA");
        for (prompt, ts) in &report.timestamp_ba_by_prompt {
            let ht = report
                .hota_temporal_by_prompt
                .get(prompt)
                .map_or(0.0, |h| h.value);
            let hk = report
                .hota_track_by_prompt
                .get(prompt)
                .map_or(0.0, |h| h.value);
            let lb = report
                .log_ba_by_prompt
                .get(prompt)
                .copied()
                .unwrap_or(f64::NAN);
            outln!("{prompt}\t{ht}\t{hk}\t{ts}\t{lb}");
        }
    }
    ExitCode::SUCCESS
}
