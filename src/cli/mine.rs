//! `scenalog mine`: run scenario programs over logs and write predictions.
//!
//! `scenalog mine --rules R.dl… --logs DIR… --out OUT` evaluates every program on every log and
//! writes, under OUT: `predictions.pkl` (the official pickle, keyed `(log_id, description)`),
//! `predictions.feather` (the long Arrow table), `matches.json` (one entry per referred track),
//! `summary.json`, `scored.pkl` with `--gt` (the scored sequences' predictions), and one pickle and record per (log, program) pair under `pairs/` (what
//! `--resume` skips). `--rules` takes files or directories of `.dl` files; `--logs` takes log
//! directories or directories of logs.
//!
//! With no `--rules`, `--logs` or `--descriptions`, it mines the scenario library over the
//! bundled sample logs and scores the two fixture prompts against the bundled ground truth.
//!
//! `--eval-timestamps FILE.json` gives the output timestamps per log as a JSON object
//! `{"<log_id>": [timestamp_ns, …], …}` (each an annotation timestamp of that log); logs not in
//! it get every 5th frame from the first, which are the benchmark's 2 Hz timestamps.
//!
//! `--gt G` scores the run at the end: only sequences in both the predictions and G are scored;
//! predictions for (log, description) pairs not in G are written but not scored, and G's
//! sequences the run did not mine are left out of the score.
//!
//! `--max-tuples N` is one pair's budget over all its relations, extracted ones included
//! (default: half the machine's memory shared by the threads); `--timeout-ms MS` one pair's time
//! limit (default 120 s). A pair past either fails, naming the relation, and the others run.
//! `--log-prompts log_prompt_pairs.json --dataset-dir SPLIT [--tracks TRACKER.pkl]` mines a
//! split's (log, prompt) pairs and only those (see [`crate::cli::mine_pairs`]), into
//! `OUT/submission.pkl`.
//! `--report` also writes `OUT/report/index.html` after the run: the table of programs × logs
//! and, for up to `--report-max-pictures` matches, pictures over the referred span with a frame
//! scrubber and the proof (see [`crate::pipeline::report`]).
//!
//! Exit code: 0 when everything ran; 1 when a log, program, synthesis or the scoring failed
//! (the rest ran and was written); 2 when the arguments or inputs are unusable.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::cli::synth::{synth_config, SynthArgs};
use crate::pipeline::budget::pair_limits;
use crate::pipeline::output::{MATCHES_JSON, PREDICTIONS_PICKLE, PREDICTIONS_TABLE, SCORED_PICKLE};
use crate::pipeline::report::write_run_report;
use crate::pipeline::run::{run_unpublished, LogInput, PairStatus, RunOptions, RunReport};
use crate::pipeline::scenario::{load_scenario, scenario_from_source, Scenario};
use crate::pipeline::summary::{render_score, render_table, score};

/// Where the workspace was built: the bundled library and sample logs are found from here.
const MANIFEST_DIR: &str = env!("CARGO_MANIFEST_DIR");
/// The scenario library, relative to the workspace.
pub(crate) const LIBRARY: &str = "rules/library";
/// The bundled sample logs, relative to the workspace.
const SAMPLE_LOGS: &str = "tests/data/av2/logs";
/// The bundled ground truth of the sample logs, relative to the workspace.
pub(crate) const SAMPLE_GT: &str = "tests/data/av2/eval/combined_gt_dev.pkl";

/// Arguments of `scenalog mine` (boxed: they are many, and the command enum stays small).
#[derive(clap::Args)]
pub struct Args {
    /// The options.
    #[command(flatten)]
    pub options: Box<Options>,
}

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

pub(crate) fn fail(message: impl std::fmt::Display) -> ExitCode {
    eprintln!("scenalog mine: {message}");
    ExitCode::from(2)
}

/// A bundled path: under the workspace the binary was built from, else under the current
/// directory; `None` when neither exists.
pub(crate) fn bundled(rel: &str) -> Option<PathBuf> {
    [Path::new(MANIFEST_DIR).join(rel), PathBuf::from(rel)]
        .into_iter()
        .find(|p| p.exists())
}

/// `target/scenalog-mine` in the workspace the binary was built from (ignored by git, even when
/// the build itself went to another `CARGO_TARGET_DIR`), else `./scenalog-out` when the binary
/// runs away from its sources.
pub(crate) fn default_out() -> PathBuf {
    let workspace = Path::new(MANIFEST_DIR);
    if workspace.join("Cargo.toml").is_file() {
        workspace.join("target").join("scenalog-mine")
    } else {
        PathBuf::from("scenalog-out")
    }
}

/// Runs the subcommand.
pub fn run(args: Args) -> ExitCode {
    let args = *args.options;
    if args.log_prompts.is_some() {
        return crate::cli::mine_pairs::run(&args);
    }
    let plan = match plan(&args) {
        Ok(p) => p,
        Err(e) => return fail(e),
    };
    let options = run_options(&args, &plan, true);
    let MinePlan {
        scenarios,
        logs,
        failures,
        mut log_problems,
        gt,
        timestamps: _,
        out,
    } = plan;
    let (gt_path, gt) = match gt {
        Some((p, g)) => (Some(p), Some(g)),
        None => (None, None),
    };
    for f in &failures {
        eprintln!("scenalog mine: {f}");
    }
    for f in &log_problems {
        eprintln!("scenalog mine: {f}");
    }
    if scenarios.is_empty() {
        eprintln!("scenalog mine: no program to mine");
        return ExitCode::from(if failures.is_empty() { 2 } else { 1 });
    }
    if logs.is_empty() {
        eprintln!("scenalog mine: no log to mine");
        return ExitCode::from(if log_problems.is_empty() { 2 } else { 1 });
    }
    // The outputs, the scored pickle and the report are one generation, published together.
    let (report, generation) = match run_unpublished(&scenarios, &logs, &options) {
        Ok(r) => r,
        Err(e) => return fail(e),
    };
    for (_, e) in &report.log_failures {
        log_problems.push(e.clone());
    }
    let pair_failures = pair_failures(&report);

    let mut score_failed = false;
    let scored = match &gt {
        Some(g) => match score(&report.submission, g) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("scenalog mine: scoring against the ground truth failed: {e}");
                score_failed = true;
                None
            }
        },
        None => None,
    };
    if let Some(s) = &scored {
        let path = generation.path(SCORED_PICKLE);
        if let Err(e) = scenalog_eval::write_pickle(&s.predictions, &path) {
            eprintln!("scenalog mine: {e}");
            score_failed = true;
        }
    }
    let any_failed = report.any_failed() || !failures.is_empty() || !log_problems.is_empty();
    if args.report {
        let written = write_run_report(
            generation.dir(),
            &out,
            &report,
            &scenarios,
            &logs,
            args.report_max_pictures,
            &crate::pipeline::report::scored_prompts(gt.as_ref()),
        );
        match written {
            Ok(page) => eprintln!("scenalog mine: wrote the report {}", page.display()),
            Err(e) => {
                eprintln!("scenalog mine: the report: {e}");
                score_failed = true;
            }
        }
    }
    if let Err(e) = generation.publish() {
        return fail(e);
    }

    match args.format {
        Format::Json => {
            let all_failures: Vec<&String> = failures
                .iter()
                .chain(&log_problems)
                .chain(&pair_failures)
                .collect();
            let value = serde_json::json!({
                "out": out.display().to_string(),
                "matches": report.matches(),
                "failures": all_failures,
                "score": scored.as_ref().map(|s| s.report.to_json()),
            });
            match serde_json::to_string_pretty(&value) {
                Ok(text) => outln!("{text}"),
                Err(e) => return fail(format!("cannot encode the summary: {e}")),
            }
        }
        Format::Text => {
            out!("{}", render_table(&report, &scenarios, &logs));
            let all = failures.len() + log_problems.len() + pair_failures.len();
            if all > 0 {
                outln!("\nfailed ({all}):");
                for f in failures.iter().chain(&log_problems).chain(&pair_failures) {
                    let mut lines = f.trim_end().lines();
                    outln!("  {}", lines.next().unwrap_or_default());
                    for l in lines {
                        outln!("    {l}");
                    }
                }
            }
            outln!(
                "\nwrote {} (official pickle), {} (Arrow table), {} (one entry per matched \
                 track) in {}",
                PREDICTIONS_PICKLE,
                PREDICTIONS_TABLE,
                MATCHES_JSON,
                out.display()
            );
            if let Some(hint) = explain_hint(&report, &scenarios, &logs) {
                outln!("\nwhy did a track match? for example:\n  {hint}");
            }
            match (&scored, &gt_path) {
                (Some(s), Some(p)) => {
                    outln!("\nscore against {}:", p.display());
                    out!("{}", render_score(s));
                }
                (None, Some(p)) if !score_failed => outln!(
                    "\nnot scored: no mined (log, description) pair is in {}",
                    p.display()
                ),
                _ => {}
            }
        }
    }
    if any_failed || score_failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// A run of `scenalog mine` (without `--log-prompts`) ready to start: what [`plan`] read and
/// decided from the options before mining.
pub struct MinePlan {
    /// The checked programs, names unique.
    pub scenarios: Vec<Scenario>,
    /// The logs.
    pub logs: Vec<LogInput>,
    /// Programs that do not check (or repeat a description) and failed syntheses.
    pub failures: Vec<String>,
    /// Logs left out (duplicate log ids).
    pub log_problems: Vec<String>,
    /// The ground truth to score against, and where it was read from.
    pub gt: Option<(PathBuf, scenalog_eval::Submission)>,
    /// The output timestamps per log.
    pub timestamps: BTreeMap<String, Vec<i64>>,
    /// The output directory (created).
    pub out: PathBuf,
}

/// Reads and checks everything `scenalog mine` needs before it starts (defaults for missing
/// `--rules`/`--logs`, the ground truth, the timestamps, the programs, synthesis); an error is
/// the message the command prints before exiting with 2.
pub fn plan(args: &Options) -> Result<MinePlan, String> {
    for (set, flag) in [
        (args.dataset_dir.is_some(), "--dataset-dir"),
        (args.tracks.is_some(), "--tracks"),
        (args.programs.is_some(), "--programs"),
        (args.synthesize, "--synthesize"),
        (args.no_confidence_filter, "--no-confidence-filter"),
    ] {
        if set {
            return Err(format!("{flag} goes with --log-prompts"));
        }
    }
    let no_arguments = args.rules.is_empty() && args.logs.is_empty() && args.descriptions.is_none();
    let rule_paths = if args.rules.is_empty() && args.descriptions.is_none() {
        match bundled(LIBRARY) {
            Some(p) => vec![p],
            None => {
                return Err(format!(
                    "no --rules given and the scenario library is not in {MANIFEST_DIR}/{LIBRARY} \
                     or ./{LIBRARY}"
                ))
            }
        }
    } else {
        args.rules.clone()
    };
    let log_paths = if args.logs.is_empty() {
        match bundled(SAMPLE_LOGS) {
            Some(p) => vec![p],
            None => {
                return Err(format!(
                    "no --logs given and the sample logs are not in {MANIFEST_DIR}/{SAMPLE_LOGS} \
                     or ./{SAMPLE_LOGS}"
                ))
            }
        }
    } else {
        args.logs.clone()
    };
    let gt_path = match &args.gt {
        Some(g) => Some(g.clone()),
        None if no_arguments => bundled(SAMPLE_GT),
        None => None,
    };
    let out = args.out.clone().unwrap_or_else(default_out);

    // Everything that can make the run pointless is checked before it starts.
    let gt = match &gt_path {
        Some(p) => match scenalog_eval::read_any(p) {
            Ok(g) => Some(g),
            Err(e) => return Err(format!("--gt: {e}")),
        },
        None => None,
    };
    let timestamps = match &args.eval_timestamps {
        Some(p) => read_timestamps(p)?,
        None => BTreeMap::new(),
    };
    let files = rule_files(&rule_paths)?;
    let (logs, log_problems) = log_dirs(&log_paths)?;
    if let Err(e) = std::fs::create_dir_all(&out) {
        return Err(format!(
            "cannot create output directory `{}`: {e}",
            out.display()
        ));
    }

    let mut failures: Vec<String> = Vec::new();
    let mut loaded: Vec<(PathBuf, Result<Scenario, String>)> = files
        .into_iter()
        .map(|p| {
            let s = load_scenario(&p);
            (p, s)
        })
        .collect();
    if let Some(file) = &args.descriptions {
        match synthesize(file, &out, args) {
            Ok((programs, problems)) => {
                loaded.extend(programs.into_iter().map(|(p, s)| {
                    let s = scenario_from_source(&p, s);
                    (p, s)
                }));
                failures.extend(problems);
            }
            Err(e) => return Err(e),
        }
    }
    let scenarios = scenarios_of(loaded, &mut failures);
    Ok(MinePlan {
        scenarios,
        logs,
        failures,
        log_problems,
        gt: gt_path.zip(gt),
        timestamps,
        out,
    })
}

/// The run's options for a plan: `--resume`, `--threads`, the engine's limits; the submission
/// is kept in memory when there is ground truth to score.
pub fn run_options(args: &Options, plan: &MinePlan, progress: bool) -> RunOptions {
    RunOptions {
        out: plan.out.clone(),
        resume: args.resume,
        timestamps: plan.timestamps.clone(),
        threads: args.threads.map(|n| n as usize),
        engine: engine_options(args),
        progress,
        names: Default::default(),
        keep_submission: plan.gt.is_some(),
        cancel: None,
    }
}

/// The failures of a run's pairs, a log that could not be read listed once (as the log, in
/// the report's `log_failures`) rather than once per pair.
pub fn pair_failures(report: &RunReport) -> Vec<String> {
    let failed_logs: BTreeSet<&str> = report
        .log_failures
        .iter()
        .map(|(l, _)| l.as_str())
        .collect();
    report
        .pairs
        .iter()
        .filter(|p| !failed_logs.contains(p.log_id.as_str()))
        .filter_map(|p| match &p.status {
            PairStatus::Failed(e) => Some(e.clone()),
            _ => None,
        })
        .collect()
}

/// A `scenalog explain` command for the first match of the run (by program, then log).
fn explain_hint(report: &RunReport, scenarios: &[Scenario], logs: &[LogInput]) -> Option<String> {
    let pair = report
        .pairs
        .iter()
        .filter(|p| !p.matches.is_empty())
        .min_by_key(|p| (p.scenario, logs.iter().position(|l| l.log_id == p.log_id)))?;
    let m = pair.matches.first()?;
    let log = logs.iter().find(|l| l.log_id == pair.log_id)?;
    Some(format!(
        "scenalog explain --rules {} --log {} --track {} --at {}",
        scenarios[pair.scenario].path.display(),
        log.dir.display(),
        m.track_uuid,
        m.first_s
    ))
}

/// Reads `--eval-timestamps`: `{"<log_id>": [timestamp_ns, …], …}`.
pub fn read_timestamps(path: &Path) -> Result<BTreeMap<String, Vec<i64>>, String> {
    let text = crate::input::read_text(path).map_err(|e| format!("--eval-timestamps: {e}"))?;
    let timestamps: BTreeMap<String, Vec<i64>> = serde_json::from_str(&text).map_err(|e| {
        format!(
            "--eval-timestamps: `{}`: expected a JSON object mapping log ids to lists of \
             integer timestamps (ns): {e}",
            path.display()
        )
    })?;
    for log in timestamps.keys() {
        scenalog_input::check_log_id(log)
            .map_err(|e| format!("--eval-timestamps: `{}`: {e}", path.display()))?;
    }
    Ok(timestamps)
}

/// The `.dl` files named by `--rules`: files as given, directories' `.dl` files sorted by name.
pub fn rule_files(paths: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut files: Vec<PathBuf> = std::fs::read_dir(p)
                .map_err(|e| format!("--rules: cannot read directory `{}`: {e}", p.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                // Anything named *.dl but a directory is kept, so a FIFO or a dangling link
                // is reported when read rather than skipped in silence.
                .filter(|f| !f.is_dir() && f.extension().is_some_and(|x| x == "dl"))
                .collect();
            files.sort();
            if files.is_empty() {
                return Err(format!("--rules: no .dl file in `{}`", p.display()));
            }
            out.extend(files);
        } else {
            match scenalog_input::regular_file(p) {
                Ok(_) => out.push(p.clone()),
                Err(problem) => return Err(format!("--rules: `{}` {problem}", p.display())),
            }
        }
    }
    Ok(out)
}

/// Whether a directory looks like one AV2 log (rather than a directory of logs).
fn is_log_dir(p: &Path) -> bool {
    p.join("city_SE3_egovehicle.feather").exists()
        || p.join("annotations.feather").exists()
        || p.join("annotations_with_ego.feather").exists()
        || p.join("map").is_dir()
}

/// The logs named by `--logs` (a log directory, or a directory whose subdirectories are logs,
/// sorted by name), and the duplicates left out (same log id twice).
pub fn log_dirs(paths: &[PathBuf]) -> Result<(Vec<LogInput>, Vec<String>), String> {
    let mut dirs = Vec::new();
    for p in paths {
        if !p.is_dir() {
            return Err(format!("--logs: `{}` is not a directory", p.display()));
        }
        if is_log_dir(p) {
            dirs.push(p.clone());
            continue;
        }
        let mut subs: Vec<PathBuf> = std::fs::read_dir(p)
            .map_err(|e| format!("--logs: cannot read directory `{}`: {e}", p.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|d| {
                d.is_dir()
                    && !d
                        .file_name()
                        .is_some_and(|n| n.to_string_lossy().starts_with('.'))
            })
            .collect();
        subs.sort();
        if subs.is_empty() {
            return Err(format!(
                "--logs: `{}` is neither a log directory nor a directory of logs",
                p.display()
            ));
        }
        dirs.extend(subs);
    }
    let mut seen = BTreeSet::new();
    let mut logs = Vec::new();
    let mut problems = Vec::new();
    for d in dirs {
        let log = LogInput::new(d);
        if seen.insert(log.log_id.clone()) {
            logs.push(log);
        } else {
            problems.push(format!(
                "log `{}`: a log with id {} is already in the run; left out",
                log.dir.display(),
                log.log_id
            ));
        }
    }
    Ok((logs, problems))
}

/// Checks every program; those that do not check, and those whose description another program
/// already has (predictions are keyed by it), are failures. Names are made unique (`name-2`…)
/// so every pair has its own files.
pub fn scenarios_of(
    loaded: Vec<(PathBuf, Result<Scenario, String>)>,
    failures: &mut Vec<String>,
) -> Vec<Scenario> {
    let mut out: Vec<Scenario> = Vec::new();
    let mut names = BTreeSet::new();
    let mut descriptions: BTreeMap<String, String> = BTreeMap::new();
    for (path, scenario) in loaded {
        let mut s = match scenario {
            Ok(s) => s,
            Err(e) => {
                failures.push(e);
                continue;
            }
        };
        if let Some(other) = descriptions.get(&s.description) {
            failures.push(format!(
                "`{}`: its description {:?} is already that of `{other}`; left out",
                path.display(),
                s.description
            ));
            continue;
        }
        descriptions.insert(s.description.clone(), path.display().to_string());
        let base = s.name.clone();
        let mut n = 1;
        while !names.insert(s.name.clone()) {
            n += 1;
            s.name = format!("{base}-{n}");
        }
        out.push(s);
    }
    out
}

/// Synthesized programs (their file and text) and the descriptions that gave none.
pub(crate) type Synthesized = (Vec<(PathBuf, String)>, Vec<String>);

/// Synthesizes the descriptions of `file` into OUT/programs (see `scenalog synth
/// --descriptions`): the programs that check clean, and a failure per description that did not.
pub(crate) fn synthesize(file: &Path, out: &Path, args: &Options) -> Result<Synthesized, String> {
    let config = synth_config(&args.synth, Some(out.join(".llm-cache")))?;
    let dir = out.join("programs");
    let report =
        scenalog_synth::programs_for_descriptions(file, &dir, config, args.jobs as usize, true)
            .map_err(|e| format!("--descriptions: {e}"))?;
    eprintln!("scenalog mine: synthesis: {}", report.summary);
    let mut programs = Vec::new();
    let mut problems = Vec::new();
    for item in report.items {
        use scenalog_synth::ItemStatus;
        match (&item.status, item.program) {
            (ItemStatus::Clean { .. } | ItemStatus::Resumed, Some(p)) => {
                programs.push((item.path, p))
            }
            (ItemStatus::Failed, _) => problems.push(format!(
                "synthesis of {:?} gave no clean program; the last attempt is in `{}`",
                item.description,
                item.path.display()
            )),
            (ItemStatus::Unreachable { error }, _) => problems.push(format!(
                "synthesis of {:?}: the LLM could not be reached: {error}",
                item.description
            )),
            (ItemStatus::Skipped, _) => problems.push(format!(
                "synthesis of {:?}: not attempted, the LLM could not be reached",
                item.description
            )),
            (_, None) => problems.push(format!(
                "synthesis of {:?} gave no program",
                item.description
            )),
        }
    }
    Ok((programs, problems))
}

/// The engine's limits for one pair: `--max-tuples` (default sized to the machine's memory and
/// the worker threads) and `--timeout-ms` (default [`crate::pipeline::budget::DEFAULT_TIMEOUT`]).
pub fn engine_options(args: &Options) -> scenalog_engine::Options {
    let threads = args
        .threads
        .map_or_else(rayon::current_num_threads, |n| n as usize);
    pair_limits(args.max_tuples, args.timeout_ms, threads)
}
