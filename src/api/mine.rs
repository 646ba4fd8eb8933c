//! Mining programs on logs (`scenalog mine --rules … --logs …`, `scenalog.mine(rules, logs)`):
//! a [`MineRequest`] is planned ([`plan`]: the defaults, the ground truth, the timestamps, the
//! programs checked, synthesis) and run ([`run`]: every (log, program) pair, the score, the
//! report, published as one generation). The pieces the split's run shares ([`rule_files`],
//! [`synthesize`], [`engine_options`], the bundled paths) are here too.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use scenalog_synth::SynthConfig;

use crate::api::error::{Arg, Error, ErrorKind};
use crate::pipeline::limits::pair_limits;
use crate::pipeline::output::{OutputNames, SCORED_PICKLE};
use crate::pipeline::report::write_run_report;
use crate::pipeline::run::{run_unpublished, LogInput, PairStatus, RunOptions, RunReport};
use crate::pipeline::scenario::{load_scenario, scenario_from_source, Scenario};
use crate::pipeline::summary::{score, Scored};

/// Where the workspace was built: the bundled library and sample logs are found from here.
const MANIFEST_DIR: &str = env!("CARGO_MANIFEST_DIR");
/// The scenario library, relative to the workspace.
pub const LIBRARY: &str = "rules/library";
/// The bundled sample logs, relative to the workspace.
const SAMPLE_LOGS: &str = "tests/data/av2/logs";
/// The bundled ground truth of the sample logs, relative to the workspace.
pub const SAMPLE_GT: &str = "tests/data/av2/eval/combined_gt_dev.pkl";

/// One pair's limits: its tuple budget and its time limit (`None`: the defaults of
/// [`crate::pipeline::limits`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Limits {
    /// Most tuples one (log, program) pair may hold, across all its relations (at least 1).
    pub max_tuples: Option<u64>,
    /// Longest one pair may take to extract and evaluate, in milliseconds (at least 1).
    pub timeout_ms: Option<u64>,
}

impl Limits {
    /// The limits checked: each at least 1.
    pub fn check(&self) -> Result<(), Error> {
        for (value, arg) in [
            (self.max_tuples, Arg::MaxTuples),
            (self.timeout_ms, Arg::TimeoutMs),
        ] {
            if value == Some(0) {
                return Err(invalid(arg, "expected at least 1, got 0"));
            }
        }
        Ok(())
    }
}

/// An out-of-range value of a field.
pub(crate) fn invalid(arg: Arg, message: impl std::fmt::Display) -> Error {
    Error::about(arg, message).of_kind(ErrorKind::Invalid)
}

/// How to synthesize programs with the LLM.
pub struct Synthesis {
    /// The server, the cache, the rounds, the examples; a `cache_dir` of `None` caches in
    /// `OUT/.llm-cache`.
    pub config: SynthConfig,
    /// Descriptions synthesized at once (1 to 64).
    pub jobs: usize,
}

/// Descriptions to synthesize programs for and mine with the others.
pub struct Descriptions {
    /// The descriptions, one a line.
    pub file: PathBuf,
    /// How.
    pub synthesis: Synthesis,
}

/// A run of programs on logs.
pub struct MineRequest {
    /// Rule programs: `.dl` files or directories of them (empty, and no `descriptions`: the
    /// scenario library).
    pub rules: Vec<PathBuf>,
    /// Log directories or directories of logs (empty: the bundled sample logs).
    pub logs: Vec<PathBuf>,
    /// The output directory (`None`: [`default_out`]).
    pub out: Option<PathBuf>,
    /// Also synthesize programs for these descriptions into `OUT/programs` and mine them.
    pub descriptions: Option<Descriptions>,
    /// Skip (log, program) pairs an earlier run into the same output already wrote.
    pub resume: bool,
    /// Worker threads, 1 to 1024 (`None`: one per core).
    pub threads: Option<usize>,
    /// Also write `OUT/predictions.pkl`, the official pickle of the whole run (a submission); by
    /// default only the compressed Arrow table (with `gt`, `OUT/scored.pkl` is written anyway).
    pub pickle: bool,
    /// Ground truth to score the run against (`None`, with no rules, logs or descriptions:
    /// the sample logs' ground truth).
    pub gt: Option<PathBuf>,
    /// Output timestamps per log: a JSON file `{"<log_id>": [timestamp_ns, …]}`.
    pub eval_timestamps: Option<PathBuf>,
    /// One pair's limits.
    pub limits: Limits,
    /// Also write the report `OUT/report/index.html`, picturing at most this many matches.
    pub report: Option<usize>,
    /// Draw a progress bar and print failures on stderr as they happen (the command).
    pub progress: bool,
    /// Set from another thread to stop the run without publishing it.
    pub cancel: Option<Arc<AtomicBool>>,
}

impl Default for MineRequest {
    /// The command with no arguments: the library on the sample logs, scored.
    fn default() -> MineRequest {
        MineRequest {
            rules: Vec::new(),
            logs: Vec::new(),
            out: None,
            descriptions: None,
            resume: false,
            threads: None,
            pickle: false,
            gt: None,
            eval_timestamps: None,
            limits: Limits::default(),
            report: None,
            progress: false,
            cancel: None,
        }
    }
}

/// A bundled path: under the workspace the binary was built from, else under the current
/// directory; `None` when neither exists.
pub fn bundled(rel: &str) -> Option<PathBuf> {
    [Path::new(MANIFEST_DIR).join(rel), PathBuf::from(rel)]
        .into_iter()
        .find(|p| p.exists())
}

/// `target/scenalog-mine` in the workspace the binary was built from (ignored by git, even when
/// the build itself went to another `CARGO_TARGET_DIR`), else `./scenalog-out` when the binary
/// runs away from its sources.
pub fn default_out() -> PathBuf {
    let workspace = Path::new(MANIFEST_DIR);
    if workspace.join("Cargo.toml").is_file() {
        workspace.join("target").join("scenalog-mine")
    } else {
        PathBuf::from("scenalog-out")
    }
}

/// Worker threads checked: 1 to 1024.
pub(crate) fn check_threads(threads: Option<usize>) -> Result<(), Error> {
    match threads {
        Some(n) if !(1..=1024).contains(&n) => Err(invalid(
            Arg::Threads,
            format!("expected 1 to 1024, got {n}"),
        )),
        _ => Ok(()),
    }
}

/// Synthesis jobs checked: 1 to 64.
pub(crate) fn check_jobs(synthesis: &Synthesis) -> Result<(), Error> {
    if !(1..=64).contains(&synthesis.jobs) {
        return Err(Error::plain(format!(
            "synthesis jobs: expected 1 to 64, got {}",
            synthesis.jobs
        ))
        .of_kind(ErrorKind::Invalid));
    }
    Ok(())
}

/// A run of programs on logs ready to start: what [`plan`] read and decided from the request
/// before mining.
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
    /// The synthesis's one-line summary, when there were descriptions.
    pub synthesis_summary: Option<String>,
}

/// Reads and checks everything a run needs before it starts (defaults for missing rules and
/// logs, the ground truth, the timestamps, the programs, synthesis); an error means the run
/// cannot start (the command's exit 2).
pub fn plan(request: &MineRequest) -> Result<MinePlan, Error> {
    check_threads(request.threads)?;
    request.limits.check()?;
    if let Some(d) = &request.descriptions {
        check_jobs(&d.synthesis)?;
    }
    let no_arguments =
        request.rules.is_empty() && request.logs.is_empty() && request.descriptions.is_none();
    let rule_paths = if request.rules.is_empty() && request.descriptions.is_none() {
        match bundled(LIBRARY) {
            Some(p) => vec![p],
            None => {
                return Err(Error::mentioning(
                    "no ",
                    Arg::Rules,
                    format!(
                        " given and the scenario library is not in {MANIFEST_DIR}/{LIBRARY} or \
                         ./{LIBRARY}"
                    ),
                ))
            }
        }
    } else {
        request.rules.clone()
    };
    let log_paths = if request.logs.is_empty() {
        match bundled(SAMPLE_LOGS) {
            Some(p) => vec![p],
            None => {
                return Err(Error::mentioning(
                    "no ",
                    Arg::Logs,
                    format!(
                        " given and the sample logs are not in {MANIFEST_DIR}/{SAMPLE_LOGS} or \
                         ./{SAMPLE_LOGS}"
                    ),
                ))
            }
        }
    } else {
        request.logs.clone()
    };
    let gt_path = match &request.gt {
        Some(g) => Some(g.clone()),
        None if no_arguments => bundled(SAMPLE_GT),
        None => None,
    };
    let out = request.out.clone().unwrap_or_else(default_out);

    // Everything that can make the run pointless is checked before it starts.
    let gt = match &gt_path {
        Some(p) => match scenalog_eval::read_any(p) {
            Ok(g) => Some(g),
            Err(e) => return Err(Error::about(Arg::Gt, e)),
        },
        None => None,
    };
    let timestamps = match &request.eval_timestamps {
        Some(p) => read_timestamps(p)?,
        None => BTreeMap::new(),
    };
    let files = rule_files(&rule_paths)?;
    let (logs, log_problems) = log_dirs(&log_paths)?;
    create_out(&out)?;

    let mut failures: Vec<String> = Vec::new();
    let mut loaded: Vec<(PathBuf, Result<Scenario, String>)> = files
        .into_iter()
        .map(|p| {
            let s = load_scenario(&p);
            (p, s)
        })
        .collect();
    let mut synthesis_summary = None;
    if let Some(d) = &request.descriptions {
        let synthesized = synthesize(&d.file, &out, &d.synthesis, request.progress)?;
        loaded.extend(synthesized.programs.into_iter().map(|(p, s)| {
            let s = scenario_from_source(&p, s);
            (p, s)
        }));
        failures.extend(synthesized.problems);
        synthesis_summary = Some(synthesized.summary);
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
        synthesis_summary,
    })
}

/// Creates the output directory.
pub(crate) fn create_out(out: &Path) -> Result<(), Error> {
    std::fs::create_dir_all(out).map_err(|e| {
        Error::plain(format!(
            "cannot create output directory `{}`: {e}",
            out.display()
        ))
    })
}

/// The run's options for a plan: resume, threads, the engine's limits, progress, the cancel
/// flag; the submission is kept in memory when there is ground truth to score.
pub fn run_options(request: &MineRequest, plan: &MinePlan) -> RunOptions {
    RunOptions {
        out: plan.out.clone(),
        resume: request.resume,
        timestamps: plan.timestamps.clone(),
        threads: request.threads,
        engine: engine_options(request.threads, &request.limits),
        progress: request.progress,
        names: OutputNames {
            write_pickle: request.pickle,
            ..Default::default()
        },
        keep_submission: plan.gt.is_some(),
        cancel: request.cancel.clone(),
    }
}

/// What a run of programs on logs gave, published (or not: see [`MineOutcome::published`]).
pub struct MineOutcome {
    /// Every pair's result.
    pub report: RunReport,
    /// The failed pairs' messages, a log that could not be read listed once (in the report's
    /// `log_failures`) rather than once per pair.
    pub pair_failures: Vec<String>,
    /// The score against the plan's ground truth (`None` without ground truth, when no mined
    /// sequence is in it, or when scoring failed).
    pub scored: Option<Scored>,
    /// Scoring failed, or `scored.pkl` could not be written: the messages.
    pub score_errors: Vec<String>,
    /// With a report: the page's path, or why it could not be written.
    pub report_page: Option<Result<PathBuf, String>>,
    /// Whether the outputs were published (the generation switched in), or why not.
    pub published: Result<(), String>,
}

/// Mines a plan: every (log, program) pair, then the score (`scored.pkl`) and the report,
/// published with the predictions as one generation. An error means nothing was published (a
/// thread pool, the output folder's lock, a cancelled run).
pub fn run(request: &MineRequest, plan: &MinePlan) -> Result<MineOutcome, Error> {
    let options = run_options(request, plan);
    let (report, generation) = run_unpublished(&plan.scenarios, &plan.logs, &options)?;
    let pair_failures = pair_failures(&report);
    let mut score_errors = Vec::new();
    let scored = match &plan.gt {
        Some((_, g)) => match score(&report.submission, g) {
            Ok(s) => s,
            Err(e) => {
                score_errors.push(format!("scoring against the ground truth failed: {e}"));
                None
            }
        },
        None => None,
    };
    if let Some(s) = &scored {
        let path = generation.path(SCORED_PICKLE);
        if let Err(e) = scenalog_eval::write_pickle(&s.predictions, &path) {
            score_errors.push(e.to_string());
        }
    }
    let report_page = request.report.map(|max_pictures| {
        write_run_report(
            generation.dir(),
            &plan.out,
            &report,
            &plan.scenarios,
            &plan.logs,
            max_pictures,
            &crate::pipeline::report::scored_prompts(plan.gt.as_ref().map(|(_, g)| g)),
        )
    });
    let published = generation.publish();
    Ok(MineOutcome {
        report,
        pair_failures,
        scored,
        score_errors,
        report_page,
        published,
    })
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

/// Reads the output timestamps: `{"<log_id>": [timestamp_ns, …], …}`.
pub fn read_timestamps(path: &Path) -> Result<BTreeMap<String, Vec<i64>>, Error> {
    let text = crate::input::read_text(path).map_err(|e| Error::about(Arg::EvalTimestamps, e))?;
    let timestamps: BTreeMap<String, Vec<i64>> = serde_json::from_str(&text).map_err(|e| {
        Error::about(
            Arg::EvalTimestamps,
            format!(
                "`{}`: expected a JSON object mapping log ids to lists of integer timestamps \
                 (ns): {e}",
                path.display()
            ),
        )
    })?;
    for log in timestamps.keys() {
        scenalog_input::check_log_id(log)
            .map_err(|e| Error::about(Arg::EvalTimestamps, format!("`{}`: {e}", path.display())))?;
    }
    Ok(timestamps)
}

/// The `.dl` files of rule paths: files as given, directories' `.dl` files sorted by name.
pub fn rule_files(paths: &[PathBuf]) -> Result<Vec<PathBuf>, Error> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut files: Vec<PathBuf> = std::fs::read_dir(p)
                .map_err(|e| {
                    Error::about(
                        Arg::Rules,
                        format!("cannot read directory `{}`: {e}", p.display()),
                    )
                })?
                .filter_map(|e| e.ok().map(|e| e.path()))
                // Anything named *.dl but a directory is kept, so a FIFO or a dangling link
                // is reported when read rather than skipped in silence.
                .filter(|f| !f.is_dir() && f.extension().is_some_and(|x| x == "dl"))
                .collect();
            files.sort();
            if files.is_empty() {
                return Err(Error::about(
                    Arg::Rules,
                    format!("no .dl file in `{}`", p.display()),
                ));
            }
            out.extend(files);
        } else {
            match scenalog_input::regular_file(p) {
                Ok(_) => out.push(p.clone()),
                Err(problem) => {
                    let kind = match problem {
                        scenalog_input::FileProblem::NotFound => ErrorKind::NotFound,
                        _ => ErrorKind::Failed,
                    };
                    return Err(
                        Error::about(Arg::Rules, format!("`{}` {problem}", p.display()))
                            .of_kind(kind),
                    );
                }
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

/// The logs of log paths (a log directory, or a directory whose subdirectories are logs,
/// sorted by name), and the duplicates left out (same log id twice).
pub fn log_dirs(paths: &[PathBuf]) -> Result<(Vec<LogInput>, Vec<String>), Error> {
    let mut dirs = Vec::new();
    for p in paths {
        if !p.is_dir() {
            let kind = if p.exists() {
                ErrorKind::Failed
            } else {
                ErrorKind::NotFound
            };
            return Err(
                Error::about(Arg::Logs, format!("`{}` is not a directory", p.display()))
                    .of_kind(kind),
            );
        }
        if is_log_dir(p) {
            dirs.push(p.clone());
            continue;
        }
        let mut subs: Vec<PathBuf> = std::fs::read_dir(p)
            .map_err(|e| {
                Error::about(
                    Arg::Logs,
                    format!("cannot read directory `{}`: {e}", p.display()),
                )
            })?
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
            return Err(Error::about(
                Arg::Logs,
                format!(
                    "`{}` is neither a log directory nor a directory of logs",
                    p.display()
                ),
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

/// Programs synthesized from descriptions.
pub struct Synthesized {
    /// The programs that check clean: their file and text.
    pub programs: Vec<(PathBuf, String)>,
    /// A message per description that gave none.
    pub problems: Vec<String>,
    /// The batch's one-line summary.
    pub summary: String,
}

/// Synthesizes the descriptions of `file` into OUT/programs (see `scenalog synth
/// --descriptions`), caching completions in `OUT/.llm-cache` unless the configuration names a
/// cache: the programs that check clean, and a failure per description that did not.
pub fn synthesize(
    file: &Path,
    out: &Path,
    synthesis: &Synthesis,
    progress: bool,
) -> Result<Synthesized, Error> {
    let mut config = synthesis.config.clone();
    if config.cache_dir.is_none() {
        config.cache_dir = Some(out.join(".llm-cache"));
    }
    let dir = out.join("programs");
    let report =
        scenalog_synth::programs_for_descriptions(file, &dir, config, synthesis.jobs, progress)
            .map_err(|e| Error::about(Arg::Descriptions, e))?;
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
    Ok(Synthesized {
        programs,
        problems,
        summary: report.summary.to_string(),
    })
}

/// The engine's limits for one pair: the tuple budget (default sized to the machine's memory
/// and the worker threads) and the time limit (default
/// [`crate::pipeline::limits::DEFAULT_TIMEOUT`]).
pub fn engine_options(threads: Option<usize>, limits: &Limits) -> scenalog_engine::Options {
    let threads = threads.unwrap_or_else(rayon::current_num_threads);
    pair_limits(limits.max_tuples, limits.timeout_ms, threads)
}
