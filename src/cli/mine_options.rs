//! The flags of `scenalog mine` ([`Options`]) and what both of its runs make of them: one
//! pair's limits, the synthesis settings, the error exit. [`crate::cli::mine`] (programs on
//! logs) and [`crate::cli::split`] (`--log-prompts`) both read them; neither calls the
//! other's functions.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::api::synth::Synthesis;
use crate::api::Limits;
use crate::cli::synth::{synth_config, SynthArgs};

/// What `scenalog mine` prints on standard output.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// A table of matched tracks per program and log, the time per stage, the score.
    Text,
    /// One JSON object: `matches` (log, description, track, category, first/last second),
    /// `failures`, and `score` (null without ground truth).
    Json,
}

/// The options of `scenalog mine`.
#[derive(clap::Args)]
pub struct Options {
    /// Rule programs: `.dl` files, or directories of them [default: the scenario library].
    #[arg(long, value_name = "R.dl", num_args = 1..)]
    pub rules: Vec<PathBuf>,
    /// Log directories, or directories of logs [default: the bundled sample logs].
    #[arg(long, value_name = "DIR", num_args = 1..)]
    pub logs: Vec<PathBuf>,
    /// Output directory [default: target/scenalog-mine in the workspace, else ./scenalog-out].
    #[arg(long, value_name = "OUT")]
    pub out: Option<PathBuf>,
    /// Also synthesize a program for every description of this file (one a line) with the LLM,
    /// into OUT/programs (reusing programs already there and the completion cache), and mine them.
    #[arg(long, value_name = "FILE.txt")]
    pub descriptions: Option<PathBuf>,
    /// Skip (log, program) pairs an earlier run into the same OUT already wrote.
    #[arg(long)]
    pub resume: bool,
    /// Worker threads [default: one per core].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// What to print on standard output.
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub format: Format,
    /// Also write OUT/predictions.pkl, the official pickle of the whole run (a submission; by
    /// default only the compressed Arrow table; with --gt, OUT/scored.pkl is written anyway).
    #[arg(long)]
    pub pickle: bool,
    /// Ground truth (official pickle or Arrow table) to score the run against at the end.
    #[arg(long, value_name = "G")]
    pub gt: Option<PathBuf>,
    /// Output timestamps per log: a JSON object {"<log_id>": [timestamp_ns, …]}.
    #[arg(long, value_name = "FILE.json")]
    pub eval_timestamps: Option<PathBuf>,
    /// Most tuples one (log, program) pair may hold, across all its relations (extracted and
    /// derived); a pair past it fails, naming the relation, and the other pairs run on
    /// [default: half the machine's memory shared by the threads, at 256 bytes a tuple].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_tuples: Option<u64>,
    /// Longest one (log, program) pair may take to extract and evaluate, in milliseconds; a pair
    /// past it fails, naming the relation being built, and the other pairs run [default: 120000].
    #[arg(long, value_name = "MS", value_parser = clap::value_parser!(u64).range(1..))]
    pub timeout_ms: Option<u64>,
    /// Descriptions synthesized at once with `--descriptions`.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub jobs: u32,
    /// Also write a browsable report of the run, OUT/report/index.html (a static page with
    /// pictures of the matches; opens from disk, works offline).
    #[arg(long)]
    pub report: bool,
    /// Also write the run's matches as a Rerun recording, OUT/matches.rrd: per log the map, every
    /// box per frame, each program's referred and related objects (needs a build with
    /// `--features rerun`).
    #[arg(long)]
    pub rerun: bool,
    /// Most matches the report pictures, never fewer than the first match of every program
    /// that matched (the rest are listed with the command that pictures them).
    #[arg(long, default_value_t = 40, value_name = "N")]
    pub report_max_pictures: usize,
    /// The LLM server, the cache and the prompt (for `--descriptions`).
    #[command(flatten, next_help_heading = "Synthesis (--descriptions)")]
    pub synth: SynthArgs,
    /// A split's (log, prompt) pairs, `{"<log_id>": ["prompt", …]}`: mine those and only those
    /// into OUT/submission.pkl (needs --dataset-dir).
    #[arg(long, value_name = "FILE.json", help_heading = "A split's pairs")]
    pub log_prompts: Option<PathBuf>,
    /// The AV2 split directory (`SPLIT/<log_id>/`: ego poses, map, and annotations when there is
    /// no --tracks).
    #[arg(long, value_name = "SPLIT", help_heading = "A split's pairs")]
    pub dataset_dir: Option<PathBuf>,
    /// A 3D tracker's output (the AV2 tracking-submission pickle) to mine instead of annotations.
    #[arg(long, value_name = "TRACKER.pkl", help_heading = "A split's pairs")]
    pub tracks: Option<PathBuf>,
    /// Programs for the prompts, matched by their `// description:` line (before the library).
    #[arg(long, value_name = "DIR", help_heading = "A split's pairs")]
    pub programs: Option<PathBuf>,
    /// Synthesize a program with the LLM for each prompt that has none (cached, resumable).
    #[arg(long, help_heading = "A split's pairs")]
    pub synthesize: bool,
    /// Keep every tracker track (by default RefAV's confidence filter drops one-frame tracks
    /// scoring at most 0.05 and longer ones whose lowest score is at most 0.005).
    #[arg(long, help_heading = "A split's pairs")]
    pub no_confidence_filter: bool,
}

/// Prints `scenalog mine: MESSAGE` on stderr; exit code 2 (the run cannot start).
pub(crate) fn fail(message: impl std::fmt::Display) -> ExitCode {
    eprintln!("scenalog mine: {message}");
    ExitCode::from(2)
}

/// How `--descriptions` and `--synthesize` synthesize: the LLM flags, `--jobs`; completions
/// cached in `--cache-dir`, else in `OUT/.llm-cache`.
pub(crate) fn synthesis(args: &Options) -> Result<Synthesis, String> {
    Ok(Synthesis {
        config: synth_config(&args.synth, None, &args.logs)?,
        jobs: args.jobs as usize,
    })
}

/// One pair's limits: `--max-tuples`, `--timeout-ms`.
pub(crate) fn limits(args: &Options) -> Limits {
    Limits {
        max_tuples: args.max_tuples,
        timeout_ms: args.timeout_ms,
    }
}
