//! Mining programs on logs (`scenalog mine --rules … --logs …`, `scenalog.mine(rules, logs)`):
//! a [`MineRequest`] is planned ([`plan`]: the defaults, the ground truth, the timestamps, the
//! programs checked, synthesis) and run ([`run`]: every (log, program) pair, the score, the
//! report, published as one generation); [`mine`] does both. The outcome carries what the run
//! published ([`Outputs`]: every file's path) and every failure in one list
//! ([`MineOutcome::failures`]), so a caller neither knows the output layout nor gathers the
//! failures itself.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use crate::api::error::{Error, Field, Message, Names};
use crate::api::inputs::{
    bundled, check_threads, create_out, default_out, log_dirs, read_timestamps, rule_files,
    scenarios_of, LIBRARY, MANIFEST_DIR, SAMPLE_GT, SAMPLE_LOGS,
};
use crate::api::limits::Limits;
use crate::api::outputs::Outputs;
use crate::api::synth::{check_jobs, synthesize, Synthesis};
use crate::pipeline::output::{OutputNames, MATCHES_RRD, SCORED_PICKLE};
use crate::pipeline::report::write_run_report;
use crate::pipeline::run::{pairs_json, run_unpublished, PairStatus, RunOptions};
use crate::pipeline::scenario::{load_scenario, scenario_from_source};
use crate::pipeline::studio_link::{studio_command, studio_url};
use crate::pipeline::summary::{render_score, render_table, score};

pub use crate::pipeline::output::Match;
pub use crate::pipeline::run::{LogInput, PairResult, RunReport};
pub use crate::pipeline::scenario::Scenario;
pub use crate::pipeline::summary::Scored;

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
    /// Also write the run's matches as a Rerun recording, `OUT/matches.rrd` (needs the `rerun`
    /// feature; without it the plan is refused).
    pub rerun: bool,
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
            rerun: false,
            progress: false,
            cancel: None,
        }
    }
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
    if request.rerun && !cfg!(feature = "rerun") {
        return Err(Error::about(Field::Rerun, WITHOUT_RERUN));
    }
    if let Some(d) = &request.descriptions {
        check_jobs(d.synthesis.jobs)?;
    }
    let no_arguments =
        request.rules.is_empty() && request.logs.is_empty() && request.descriptions.is_none();
    let rule_paths = if request.rules.is_empty() && request.descriptions.is_none() {
        match bundled(LIBRARY) {
            Some(p) => vec![p],
            None => {
                return Err(Error::mentioning(
                    "no ",
                    Field::Rules,
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
                    Field::Logs,
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
            Err(e) => return Err(Error::about(Field::Gt, e)),
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
        let candidates = synthesized.candidates;
        loaded.extend(synthesized.programs.into_iter().map(|(p, s)| {
            let s = scenario_from_source(&p, s).map(|mut scenario| {
                scenario.candidates = checked_candidates(candidates.get(&p));
                scenario
            });
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

/// The candidates of a search, checked (they checked clean when synthesized; one that no
/// longer does is left out).
fn checked_candidates(sources: Option<&Vec<String>>) -> Vec<scenalog_rules::CheckedProgram> {
    sources
        .into_iter()
        .flatten()
        .filter_map(|s| {
            scenalog_rules::check(
                s,
                &scenalog_rules::CheckOptions {
                    require_referred: true,
                },
            )
            .program
        })
        .collect()
}

/// The run's options for a plan: resume, threads, the engine's limits, progress, the cancel
/// flag; the submission is kept in memory when there is ground truth to score.
pub fn run_options(request: &MineRequest, plan: &MinePlan) -> RunOptions {
    RunOptions {
        out: plan.out.clone(),
        resume: request.resume,
        timestamps: plan.timestamps.clone(),
        threads: request.threads,
        engine: request.limits.for_run(request.threads),
        progress: request.progress,
        names: OutputNames {
            write_pickle: request.pickle,
            ..Default::default()
        },
        keep_submission: plan.gt.is_some(),
        cancel: request.cancel.clone(),
    }
}

impl MinePlan {
    /// Why the plan cannot run, when it cannot: no program or no log to mine, and the problems
    /// that left none (empty when there was nothing to begin with: the command's exit 2, else 1).
    pub fn nothing_to_mine(&self) -> Option<(&'static str, Vec<Message>)> {
        let causes = |c: &[String]| c.iter().map(Message::text).collect();
        if self.scenarios.is_empty() {
            Some(("no program to mine", causes(&self.failures)))
        } else if self.logs.is_empty() {
            Some(("no log to mine", causes(&self.log_problems)))
        } else {
            None
        }
    }
}

/// `message`, followed by the problems that caused it, one a line.
pub(crate) fn with_causes(message: &str, causes: &[Message]) -> Error {
    let mut out = Message::text(message);
    for c in causes {
        out = out.then("\n  ").append(c);
    }
    Error::from(out)
}

/// What a run of programs on logs gave, published (or not: see [`MineOutcome::published`]).
pub struct MineOutcome {
    /// Every pair's result.
    pub report: RunReport,
    /// The programs mined (names unique).
    pub scenarios: Vec<Scenario>,
    /// The logs mined.
    pub logs: Vec<LogInput>,
    /// Every failure, the rest having run: programs that do not check (or repeat a
    /// description), failed syntheses, logs left out or unreadable, and failed pairs (a log that
    /// could not be read listed once, not once per pair).
    pub failures: Vec<Message>,
    /// The score against the plan's ground truth (`None` without ground truth, when no mined
    /// sequence is in it, or when scoring failed).
    pub scored: Option<Scored>,
    /// The ground truth scored against, when there was one.
    pub gt: Option<PathBuf>,
    /// Scoring failed, or `scored.pkl` could not be written: the messages.
    pub score_errors: Vec<String>,
    /// With a report: the page's path, or why it could not be written.
    pub report_page: Option<Result<PathBuf, String>>,
    /// With `rerun`: the recording's path and the logs or programs it had to leave out, or why
    /// it could not be written.
    pub recording: Option<Result<(PathBuf, Vec<String>), String>>,
    /// Whether the outputs were published (the generation switched in), or why not.
    pub published: Result<(), String>,
    /// The files published.
    pub outputs: Outputs,
}

impl MineOutcome {
    /// Whether a program, synthesis, log or pair failed (the command's exit 1).
    pub fn any_failed(&self) -> bool {
        !self.failures.is_empty()
    }

    /// Every match of every finished pair, in pair order (`matches.json`).
    pub fn matches(&self) -> Vec<&Match> {
        self.report.matches()
    }

    /// Each pair's record as `summary.json` holds it, a failed pair's error rendered with
    /// `names`.
    pub fn pairs_json(&self, names: Names) -> Vec<serde_json::Value> {
        pairs_json(&self.report, &self.scenarios, names)
    }

    /// The table `scenalog mine` prints: matched tracks per program and log, totals, the time
    /// per stage.
    pub fn table_text(&self) -> String {
        render_table(&self.report, &self.scenarios, &self.logs)
    }

    /// The score as `scenalog mine` prints it (the headline numbers and per prompt), when the
    /// run was scored.
    pub fn score_text(&self) -> Option<String> {
        self.scored.as_ref().map(render_score)
    }

    /// The `scenalog studio` command for the run's programs and logs, and the address that
    /// opens its first match (by program, then log) there.
    pub fn studio_hint(&self) -> Option<(String, String)> {
        let pair = self.first_matched_pair()?;
        let m = pair.matches.first()?;
        let scenario = &self.scenarios[pair.scenario];
        Some((
            studio_command(
                self.scenarios.iter().map(|s| s.path.as_path()),
                self.logs.iter().map(|l| l.dir.as_path()),
            ),
            studio_url(&scenario.name, &m.log_id, &m.track_uuid, m.first_s),
        ))
    }

    /// The pair of the run's first match, by program, then log.
    fn first_matched_pair(&self) -> Option<&crate::pipeline::run::PairResult> {
        let logs = &self.logs;
        self.report
            .pairs
            .iter()
            .filter(|p| !p.matches.is_empty())
            .min_by_key(|p| (p.scenario, logs.iter().position(|l| l.log_id == p.log_id)))
    }

    /// A `scenalog explain` command for the run's first match (by program, then log).
    pub fn explain_hint(&self) -> Option<String> {
        let (scenarios, logs) = (&self.scenarios, &self.logs);
        let pair = self.first_matched_pair()?;
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
}

/// Mines a plan: every (log, program) pair, then the score (`scored.pkl`) and the report,
/// published with the predictions as one generation. An error means nothing was published (no
/// program or log to mine, a thread pool, the output folder's lock, a cancelled run).
pub fn run(request: &MineRequest, plan: MinePlan) -> Result<MineOutcome, Error> {
    if let Some((what, causes)) = plan.nothing_to_mine() {
        return Err(with_causes(what, &causes));
    }
    let options = run_options(request, &plan);
    let (report, generation) = run_unpublished(&plan.scenarios, &plan.logs, &options)?;
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
    let mut scored_written = false;
    if let Some(s) = &scored {
        let path = generation.path(SCORED_PICKLE);
        match scenalog_eval::write_pickle(&s.predictions, &path) {
            Ok(()) => scored_written = true,
            Err(e) => score_errors.push(e.to_string()),
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
    let recording = request
        .rerun
        .then(|| write_recording(&generation.path(MATCHES_RRD), &plan, &report, &options));
    let published = generation.publish();
    let page = report_page.as_ref().and_then(|r| r.as_ref().ok().cloned());
    let mut outputs = Outputs::of(&plan.out, &options.names, scored_written, page);
    if matches!(recording, Some(Ok(_))) {
        outputs.rerun = Some(plan.out.join(MATCHES_RRD));
    }
    let recording = recording.map(|r| r.map(|notes| (plan.out.join(MATCHES_RRD), notes)));
    let failures = rolled_up(&plan, &report);
    let MinePlan {
        scenarios,
        logs,
        gt,
        ..
    } = plan;
    Ok(MineOutcome {
        report,
        scenarios,
        logs,
        failures,
        scored,
        gt: gt.map(|(p, _)| p),
        score_errors,
        report_page,
        recording,
        published,
        outputs,
    })
}

/// The run's matches written as a Rerun recording at `path` (the programs evaluated again on
/// each log with matches, within one pair's limits); the logs or programs left out.
#[cfg(feature = "rerun")]
fn write_recording(
    path: &Path,
    plan: &MinePlan,
    report: &crate::pipeline::run::RunReport,
    options: &RunOptions,
) -> Result<Vec<String>, String> {
    crate::pipeline::recording::write_run_recording(
        path,
        &plan.scenarios,
        &plan.logs,
        &report.pairs,
        &options.engine,
    )
}

#[cfg(not(feature = "rerun"))]
fn write_recording(
    _: &Path,
    _: &MinePlan,
    _: &crate::pipeline::run::RunReport,
    _: &RunOptions,
) -> Result<Vec<String>, String> {
    Err(WITHOUT_RERUN.to_string())
}

/// What a request for a Rerun recording gets from a build without the `rerun` feature.
pub const WITHOUT_RERUN: &str =
    "this scenalog was built without Rerun: build it with `--features rerun` \
     (cargo install --locked --path . --features rerun)";

/// Plans and runs a request ([`plan`], then [`run`]).
pub fn mine(request: &MineRequest) -> Result<MineOutcome, Error> {
    run(request, plan(request)?)
}

/// The plan's failures (programs, syntheses, logs left out), then the run's (logs that could not
/// be read, then failed pairs of the other logs).
fn rolled_up(plan: &MinePlan, report: &RunReport) -> Vec<Message> {
    let mut all: Vec<Message> = plan.failures.iter().map(Message::text).collect();
    all.extend(plan.log_problems.iter().map(Message::text));
    all.extend(report.log_failures.iter().map(|(_, e)| e.clone()));
    all.extend(pair_failures(report));
    all
}

/// The failures of a run's pairs, a log that could not be read listed once (as the log, in
/// the report's `log_failures`) rather than once per pair.
pub fn pair_failures(report: &RunReport) -> Vec<Message> {
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
