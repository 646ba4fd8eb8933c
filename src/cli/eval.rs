//! `scenalog eval`: score predictions against ground truth with the official scenario-mining metrics.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::api::eval::{evaluate_counted, EvalRequest, Frames, SubmissionSource};

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
    /// Write `temporal_metrics.json` and `spatiotemporal_metrics.json` (as the official code) and
    /// `paper_metrics.json` (HOTA-Temporal of related and other objects, the tracker's HOTA) into
    /// this directory.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Score only the ground truth's sequences the predictions hold, as `scenalog mine --gt`
    /// scores a run (its `OUT/scored.pkl` holds the sequences it mined); the number left out is
    /// printed. Without it a ground-truth sequence missing from the predictions is an error, as
    /// in the official evaluation.
    #[arg(long)]
    only_predicted: bool,
    /// Evaluate at this rate (Hz, e.g. 2 or 10): every k-th frame of each ground-truth sequence,
    /// k its own rate over this one; the predictions keep the frames at those timestamps.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..), conflicts_with = "timestamps")]
    rate: Option<u32>,
    /// Evaluate at the timestamps this JSON file lists per log (`{log_id: [timestamp_ns, ...]}`,
    /// as RefAV's `eval_timestamps.json`).
    #[arg(long)]
    timestamps: Option<PathBuf>,
}

/// Runs the subcommand: exit 0 on success, 2 on unreadable or inconsistent input.
pub fn run(args: Args) -> ExitCode {
    let frames = match (&args.rate, &args.timestamps) {
        (Some(hz), _) => Frames::Rate(*hz),
        (None, Some(path)) => Frames::TimestampsFile(path.clone()),
        (None, None) => Frames::All,
    };
    let request = EvalRequest {
        pred: SubmissionSource::File(args.pred.clone()),
        gt: SubmissionSource::File(args.gt.clone()),
        max_range_m: args.max_range_m,
        dataset_dir: args.dataset_dir.clone(),
        frames,
        only_predicted: args.only_predicted,
    };
    let evaluated = match evaluate_counted(&request) {
        Ok(done) => done,
        Err(e) => {
            eprintln!("scenalog eval: {}", e.flags());
            if let Some(hint) = &e.hint {
                eprintln!("  {}", hint.flags());
            }
            return ExitCode::from(2);
        }
    };
    if evaluated.left_out > 0 {
        eprintln!(
            "scenalog eval: --only-predicted: {} of the ground truth's {} sequences are not in \
             the predictions and are not scored",
            evaluated.left_out, evaluated.gt_sequences
        );
    }
    if let Some(dir) = &args.out {
        if let Err(e) = evaluated.write_metrics(dir) {
            eprintln!("scenalog eval: {}", e.flags());
            return ExitCode::from(2);
        }
    }
    for w in &evaluated.report.further.warnings {
        eprintln!("scenalog eval: warning: {w}");
    }
    if args.json {
        outln!("{:#}", evaluated.report.to_json());
    } else {
        out!("{}", evaluated.text(args.per_prompt));
    }
    ExitCode::SUCCESS
}
