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
    let report = match evaluate_counted(&request) {
        Ok(done) => {
            if done.left_out > 0 {
                eprintln!(
                    "scenalog eval: --only-predicted: {} of the ground truth's {} sequences are \
                     not in the predictions and are not scored",
                    done.left_out, done.gt_sequences
                );
            }
            done.report
        }
        Err(e) => {
            eprintln!("scenalog eval: {}", e.flags());
            if e.flags().contains("not in the predictions") {
                eprintln!(
                    "  (to score only the sequences the predictions hold, as `scenalog mine --gt` \
                     does, add --only-predicted)"
                );
            }
            return ExitCode::from(2);
        }
    };
    if let Some(dir) = &args.out {
        let (temporal, spatio) = report.official_json();
        let mut files = vec![("temporal_metrics.json", temporal)];
        if let Some(s) = spatio {
            files.push(("spatiotemporal_metrics.json", s));
        }
        files.push(("paper_metrics.json", report.paper_json()));
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
    for w in &report.further.warnings {
        eprintln!("scenalog eval: warning: {w}");
    }
    if args.json {
        outln!("{:#}", report.to_json());
        return ExitCode::SUCCESS;
    }
    let f = &report.further;
    outln!("HOTA-Temporal: {}", report.hota_temporal);
    outln!("HOTA-Track: {}", report.hota_track);
    outln!("Timestamp-level Balanced Accuracy: {}", report.timestamp_ba);
    outln!("Log-level Balanced Accuracy: {}", report.log_ba);
    outln!(
        "HOTA-Temporal (related objects): {}",
        shown(f.related.value(), "no related object in the ground truth")
    );
    outln!(
        "HOTA-Temporal (other objects): {}",
        shown(f.other.value(), "no other object in the ground truth")
    );
    outln!(
        "HOTA (tracker, every object): {}",
        shown(f.tracker.value(), "no object in the ground truth")
    );
    if args.per_prompt {
        outln!();
        outln!("prompt\tHOTA-Temporal\tHOTA-Track\ttimestamp BA\tlog BA\tHOTA-Temporal related\tHOTA-Temporal other\tHOTA");
        let by = |c: &scenalog_eval::ClassHota, prompt: &str| {
            let v = c
                .by_prompt
                .get(prompt)
                .and_then(|h| h.as_ref().map(|h| h.value));
            v.map_or_else(|| "-".to_string(), |v| v.to_string())
        };
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
            let (rel, oth, trk) = (
                by(&f.related, prompt),
                by(&f.other, prompt),
                by(&f.tracker, prompt),
            );
            outln!("{prompt}\t{ht}\t{hk}\t{ts}\t{lb}\t{rel}\t{oth}\t{trk}");
        }
    }
    ExitCode::SUCCESS
}

/// A value, or `-` and why there is none.
fn shown(v: Option<f64>, why_none: &str) -> String {
    v.map_or_else(|| format!("- ({why_none})"), |v| v.to_string())
}
