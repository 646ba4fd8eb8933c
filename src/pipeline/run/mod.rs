//! A mining run: every (log, program) pair evaluated, turned into prediction tracks and written.
//!
//! Logs run in parallel (rayon), and so do the programs of one log, which share one
//! [`Extractor`] (its per-scene cache computes each relation once for all of them). Results are
//! gathered by index, so the output is the same whatever the thread count. A log that cannot be
//! read, or a program that fails on a log, is reported and skipped; the rest of the run goes on.
//! Each finished pair is written at once under `OUT/pairs/` (see [`super::output`]), so with
//! `resume` a rerun skips what a crashed or interrupted one finished, when its fingerprint (tool
//! version, the log's input files, program text, output timestamps) is unchanged.
//!
//! A log's scene comes from its directory's annotations, or from a tracker's output
//! ([`LogInput::tracker`]) with the directory giving ego poses and map. Outputs are streamed: as
//! soon as a log is done its predictions are written to a part file in a staging directory and
//! dropped, so memory holds the logs in flight, not the run; at the end the parts are joined into
//! the run's Arrow table (and its pickle, when asked for) and every output file is moved into
//! place together.

use std::collections::{BTreeMap, BTreeSet};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use rayon::prelude::*;
use scenalog_engine::Options;
use scenalog_eval::{FrameData, Submission};
use scenalog_extractors::cache::Extractor;
use scenalog_facts::relation::Value;
use scenalog_facts::{Frame, Scene, TrackId};

use super::output::{self, Match, PairRecord};
use super::predictions::{to_frames, Agreement, BoxScores};
use super::scenario::{evaluate_on, limits_after_check, Scenario};
use super::tracks::{eval_frames, label_frames};
use crate::message::{Message, Names};

mod pair;
mod resume;

pub(crate) use pair::referred_tuples;
pub use pair::short_id;
use pair::*;
use resume::*;

/// One log to mine: its directory, its id (the directory's name), where its objects come from
/// and which programs to run on it.
#[derive(Debug, Clone)]
pub struct LogInput {
    /// The log directory.
    pub dir: PathBuf,
    /// The log id.
    pub log_id: String,
    /// The tracker output its objects come from (`None`: the directory's annotations).
    pub tracker: Option<Arc<TrackerInput>>,
    /// The indices of the scenarios to run on it (`None`: every one).
    pub programs: Option<Vec<usize>>,
}

/// A tracker's output shared by the logs of a run.
pub struct TrackerInput {
    /// The parsed tracking pickle.
    pub pickle: scenalog_tracker::TrackerPickle,
    /// The confidence filter.
    pub filter: scenalog_tracker::Filter,
    /// A fingerprint of the file's bytes and the filter (part of each pair's resume key).
    pub fingerprint: String,
}

impl std::fmt::Debug for TrackerInput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "TrackerInput({}, {:?})", self.pickle.file(), self.filter)
    }
}

impl LogInput {
    /// A log directory; its id is the directory's name: the path's last component when it is a
    /// plain name, else (a path ending in `..` or `.`) the name of the directory it resolves to.
    /// The id is joined to output paths, so it must pass [`scenalog_input::check_log_id`].
    ///
    /// # Errors
    /// The directory cannot be resolved, or its name is not a valid log id (the message says
    /// which and why).
    pub fn new(dir: PathBuf) -> Result<LogInput, String> {
        let log_id = log_id_of_dir(&dir)?;
        Ok(LogInput::with_id(dir, log_id))
    }

    /// A log directory with an id already checked by the caller (a split's key).
    pub fn with_id(dir: PathBuf, log_id: String) -> LogInput {
        LogInput {
            dir,
            log_id,
            tracker: None,
            programs: None,
        }
    }

    /// The scenario indices to run on this log, out of `n`.
    pub fn program_indices(&self, n: usize) -> Vec<usize> {
        match &self.programs {
            Some(p) => p.iter().copied().filter(|&i| i < n).collect(),
            None => (0..n).collect(),
        }
    }
}

/// The log id of a log directory (see [`LogInput::new`]).
fn log_id_of_dir(dir: &Path) -> Result<String, String> {
    let name = match dir.components().next_back() {
        Some(std::path::Component::Normal(n)) => n.to_string_lossy().into_owned(),
        _ => {
            let real = std::fs::canonicalize(dir)
                .map_err(|e| format!("cannot resolve log directory `{}`: {e}", dir.display()))?;
            real.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        }
    };
    scenalog_input::check_log_id(&name)
        .map_err(|e| format!("log directory `{}`: {e}", dir.display()))?;
    Ok(name)
}

/// How to run.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// The output directory.
    pub out: PathBuf,
    /// Skip pairs whose record under `OUT/pairs/` matches this run (same program text, same
    /// description, same output timestamps).
    pub resume: bool,
    /// Output timestamps per log id; logs not listed get every 5th frame from the first.
    pub timestamps: BTreeMap<String, Vec<i64>>,
    /// Threads (`None`: rayon's default, one per core).
    pub threads: Option<usize>,
    /// The engine's limits.
    pub engine: Options,
    /// Draw a progress bar (only when stderr is a terminal) and print each failure on stderr as
    /// it happens, naming the command's flags (the command does; a library caller gets them in
    /// the report).
    pub progress: bool,
    /// The file names of the run's pickle and Arrow table.
    pub names: output::OutputNames,
    /// Read the run's predictions back into [`RunReport::submission`] (for scoring); without it
    /// the submission there is empty and memory stays bounded by the logs in flight.
    pub keep_submission: bool,
    /// Set from another thread to stop the run: logs and pairs not started yet are not started,
    /// those in flight finish, and the run ends with an error without publishing its outputs
    /// (the pairs already written stay under `OUT/pairs/` for `resume`). `None` for the
    /// command, which Ctrl-C ends.
    pub cancel: Option<Arc<AtomicBool>>,
}

/// The error of a run stopped through [`RunOptions::cancel`].
pub const CANCELLED: &str = "the run was cancelled";

/// How failures printed as they happen ([`RunOptions::progress`], the command's) name fields.
const PROGRESS_NAMES: Names = Names::Flags;

/// Whether the run was asked to stop.
fn cancelled(options: &RunOptions) -> bool {
    options
        .cancel
        .as_ref()
        .is_some_and(|c| c.load(Ordering::Relaxed))
}

/// How one pair ended.
#[derive(Debug, Clone, PartialEq)]
pub enum PairStatus {
    /// Evaluated and written in this run.
    Done,
    /// Already written by an earlier run (`resume`).
    Resumed,
    /// Could not be evaluated or written: the reason (naming the request's fields, such as the
    /// tuple budget to raise).
    Failed(Message),
}

/// One (log, program) pair's outcome.
#[derive(Debug, Clone)]
pub struct PairResult {
    /// The log id.
    pub log_id: String,
    /// The program's index in the run's scenarios.
    pub scenario: usize,
    /// How it ended.
    pub status: PairStatus,
    /// The prediction frames (empty when failed; [`run`] moves them into
    /// [`RunReport::submission`]).
    pub frames: Vec<FrameData>,
    /// The referred tracks.
    pub matches: Vec<Match>,
    /// Time spent extracting and evaluating.
    pub evaluate: Duration,
    /// Time spent turning tuples into frames.
    pub tracks: Duration,
    /// Time spent writing the pair's files.
    pub write: Duration,
}

/// Times per stage, summed over threads (and the run's wall-clock time).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Timings {
    /// Reading logs.
    pub load: Duration,
    /// Extracting relations and evaluating programs.
    pub evaluate: Duration,
    /// Dilation, labelling and building prediction frames.
    pub tracks: Duration,
    /// Writing the per-pair files and the run's outputs.
    pub write: Duration,
    /// Wall-clock time of the whole run.
    pub wall: Duration,
}

/// What a run did.
#[derive(Debug, Clone)]
pub struct RunReport {
    /// One per (log, program), logs in input order, programs in input order within a log.
    pub pairs: Vec<PairResult>,
    /// Logs that could not be read (or whose output timestamps do not fit), with the reason.
    pub log_failures: Vec<(String, Message)>,
    /// The run's predictions, keyed `(log_id, description)` (finished pairs only), when
    /// [`RunOptions::keep_submission`]; else empty.
    pub submission: Submission,
    /// Times per stage.
    pub timings: Timings,
    /// The number of threads used.
    pub threads: usize,
}

impl RunReport {
    /// Whether any log or pair failed.
    pub fn any_failed(&self) -> bool {
        !self.log_failures.is_empty()
            || self
                .pairs
                .iter()
                .any(|p| matches!(p.status, PairStatus::Failed(_)))
    }

    /// How many pairs were resumed from an earlier run.
    pub fn resumed(&self) -> usize {
        self.pairs
            .iter()
            .filter(|p| p.status == PairStatus::Resumed)
            .count()
    }

    /// How many pairs referred at least one track.
    pub fn with_matches(&self) -> usize {
        self.pairs.iter().filter(|p| !p.matches.is_empty()).count()
    }

    /// Every match of every finished pair, in pair order.
    pub fn matches(&self) -> Vec<&Match> {
        self.pairs.iter().flat_map(|p| &p.matches).collect()
    }
}

/// Runs every scenario on every log and writes the outputs under `options.out`, published as one
/// generation ([`output`]). Errors only when the run's own outputs cannot be written or the
/// thread pool cannot be made; a log or pair that fails is in the report.
pub fn run(
    scenarios: &[Scenario],
    logs: &[LogInput],
    options: &RunOptions,
) -> Result<RunReport, String> {
    let (report, generation) = run_unpublished(scenarios, logs, options)?;
    generation.publish()?;
    Ok(report)
}

/// [`run`] without the publication: the outputs are complete in the returned generation, which
/// the caller may add to (`scored.pkl`, the report) and must publish
/// ([`output::Staging::publish`]); dropped unpublished, it is removed and `OUT/` is unchanged.
pub fn run_unpublished(
    scenarios: &[Scenario],
    logs: &[LogInput],
    options: &RunOptions,
) -> Result<(RunReport, output::Staging), String> {
    let start = Instant::now();
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = options.threads {
        builder = builder.num_threads(n.max(1));
    }
    let pool = builder
        .build()
        .map_err(|e| format!("cannot start the thread pool: {e}"))?;
    std::fs::create_dir_all(&options.out).map_err(|e| {
        format!(
            "cannot create output directory `{}`: {e}",
            options.out.display()
        )
    })?;
    // The folder is held before anything in it is touched: a second run into it stops here.
    let mut staging = output::Staging::new(&options.out)?;
    staging.set_contents(
        table_dictionaries(scenarios, logs),
        options.names.write_pickle,
    );
    if let Some(holder) = staging.took_over() {
        eprintln!(
            "scenalog: took over the lock of `{}` left by a run no longer running ({holder})",
            options.out.display()
        );
    }
    output::clean_orphans(&options.out);
    let total: u64 = logs
        .iter()
        .map(|l| l.program_indices(scenarios.len()).len() as u64)
        .sum();
    let bar = if options.progress && std::io::stderr().is_terminal() {
        let bar = indicatif::ProgressBar::new(total);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:30} {pos}/{len} pairs {elapsed} {wide_msg}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    } else {
        indicatif::ProgressBar::hidden()
    };
    let load_time = Mutex::new(Duration::ZERO);
    let without_attributes = AtomicUsize::new(0);
    type LogOutcome = (Vec<PairResult>, Option<Message>, Result<(), String>);
    let per_log: Vec<LogOutcome> = pool.install(|| {
        logs.par_iter()
            .enumerate()
            .map(|(i, log)| {
                let sink = PartSink {
                    staging: &staging,
                    log: i,
                };
                let (pairs, failure, load, part) =
                    mine_log(log, scenarios, options, &bar, &sink, &without_attributes);
                if let Ok(mut t) = load_time.lock() {
                    *t += load;
                }
                (pairs, failure, part)
            })
            .collect()
    });
    bar.finish_and_clear();
    if cancelled(options) {
        return Err(CANCELLED.to_string());
    }
    no_attributes_note(without_attributes.into_inner(), logs.len(), options);
    let mut pairs = Vec::with_capacity(total as usize);
    let mut log_failures = Vec::new();
    for (log, (p, failure, part)) in logs.iter().zip(per_log) {
        pairs.extend(p);
        part?;
        if let Some(f) = failure {
            log_failures.push((log.log_id.clone(), f));
        }
    }
    let write_start = Instant::now();
    let mut order = staging.written_parts();
    order.sort_by(|&(la, sa), &(lb, sb)| {
        (&logs[la].log_id, &scenarios[sa].description)
            .cmp(&(&logs[lb].log_id, &scenarios[sb].description))
    });
    staging.join_parts(&order, &options.names)?;
    let matches: Vec<&Match> = pairs.iter().flat_map(|p| &p.matches).collect();
    output::write_json(&staging.path(output::MATCHES_JSON), &matches, true)?;
    let mut timings = Timings {
        load: load_time.into_inner().unwrap_or_else(|e| e.into_inner()),
        ..Timings::default()
    };
    for p in &pairs {
        timings.evaluate += p.evaluate;
        timings.tracks += p.tracks;
        timings.write += p.write;
    }
    let mut report = RunReport {
        pairs,
        log_failures,
        submission: Submission::default(),
        timings,
        threads: pool.current_num_threads(),
    };
    report.timings.write += write_start.elapsed();
    report.timings.wall = start.elapsed();
    output::write_json(
        &staging.path(output::SUMMARY_JSON),
        &summary_json(&report, scenarios, SUMMARY_NAMES),
        true,
    )?;
    if options.keep_submission {
        // Read back from the table; a pair with no frame (no row in the table) is an empty
        // sequence, as in the pickle.
        let path = staging.path(options.names.table);
        report.submission = scenalog_eval::read_table(&path).map_err(|e| e.to_string())?;
        for p in &report.pairs {
            if !matches!(p.status, PairStatus::Failed(_)) {
                let key = (p.log_id.clone(), scenarios[p.scenario].description.clone());
                report.submission.sequences.entry(key).or_default();
            }
        }
    }
    Ok((report, staging))
}

/// How `summary.json` names the request's fields in its errors: it is the command's file, so
/// with the command's flags (the Python package's `pairs` name its keywords: [`pairs_json`]).
const SUMMARY_NAMES: Names = Names::Flags;

/// `summary.json`: the stage times, the failed logs and every pair's status, messages rendered
/// with `names`.
fn summary_json(report: &RunReport, scenarios: &[Scenario], names: Names) -> serde_json::Value {
    let t = &report.timings;
    serde_json::json!({
        "threads": report.threads,
        "seconds": {
            "load": t.load.as_secs_f64(),
            "extract_evaluate": t.evaluate.as_secs_f64(),
            "tracks": t.tracks.as_secs_f64(),
            "write": t.write.as_secs_f64(),
            "wall": t.wall.as_secs_f64(),
        },
        "failed_logs": report.log_failures.iter()
            .map(|(l, e)| serde_json::json!({"log_id": l, "error": e.render(names)}))
            .collect::<Vec<_>>(),
        "pairs": pairs_json(report, scenarios, names),
    })
}

/// Every pair of a run as JSON, in pair order: its log, program, description, status
/// (`done`, `resumed`, `failed`), error (rendered with `names`), number of matches and
/// evaluation time; the `pairs` of `summary.json` (and of the Python package's `mine`).
pub fn pairs_json(
    report: &RunReport,
    scenarios: &[Scenario],
    names: Names,
) -> Vec<serde_json::Value> {
    report
        .pairs
        .iter()
        .map(|p| {
            let (status, error) = match &p.status {
                PairStatus::Done => ("done", None),
                PairStatus::Resumed => ("resumed", None),
                PairStatus::Failed(e) => ("failed", Some(e.render(names))),
            };
            serde_json::json!({
                "log_id": p.log_id,
                "program": scenarios[p.scenario].name,
                "description": scenarios[p.scenario].description,
                "status": status,
                "error": error,
                "matches": p.matches.len(),
                "evaluate_s": p.evaluate.as_secs_f64(),
            })
        })
        .collect()
}

/// Says once per log, when one of its programs reads RefAV's colour cache (`refav_color`, what
/// an imported `is_color` becomes) and the log has none, that `is_color` keeps every object
/// there, as RefAV does without a cache.
fn no_color_cache_note(
    log: &LogInput,
    scene: &Scene,
    scenarios: &[Scenario],
    indices: &[usize],
    bar: &indicatif::ProgressBar,
) {
    let reads = |i: &usize| scenarios[*i].program.predicates.contains_key("refav_color");
    if scene.color_cache == scenalog_facts::ColorCache::Absent && indices.iter().any(reads) {
        bar.suspend(|| {
            eprintln!(
                "scenalog mine: log `{}` has no RefAV colour cache (`{}`): is_color keeps every object there, as RefAV does without one",
                log.log_id,
                scenalog_facts::color::COLOR_CACHE_FILE
            )
        });
    }
}

/// Whether a program of the log reads `attribute` and the log has nothing it is read from (no
/// `attributes.csv`, no RefAV colour cache): the relation is empty there.
fn lacks_attributes(scene: &Scene, scenarios: &[Scenario], indices: &[usize]) -> bool {
    let reads = |i: &usize| scenarios[*i].program.predicates.contains_key("attribute");
    scene.attributes == scenalog_facts::Attributes::Absent
        && scene.color_cache == scenalog_facts::ColorCache::Absent
        && indices.iter().any(reads)
}

/// Says once per run, after it, on how many logs `attribute` was empty for want of a file.
fn no_attributes_note(without: usize, logs: usize, options: &RunOptions) {
    if without > 0 && options.progress {
        eprintln!(
            "scenalog mine: `attribute` is empty on {without} of {logs} logs: they have no `{}` (nor RefAV's colour cache), so what only a camera shows is not known there (the README's \"Attributes from outside\" says how to write one)",
            scenalog_facts::attributes::ATTRIBUTES_FILE
        );
    }
}

/// A log's scene and, for tracker input, each box's score (`scores[track][box]`).
type LoadedLog = (Scene, Option<Vec<Vec<f32>>>);

/// The log's scene and, for tracker input, each box's score.
fn load_log(log: &LogInput) -> Result<LoadedLog, String> {
    match &log.tracker {
        // Annotations, or RefAV's per-log form of a tracker's output (scores in a column).
        None => {
            let read = |e| format!("cannot read log `{}`: {e}", log.dir.display());
            let scene = scenalog_facts::load_scene(&log.dir).map_err(read)?;
            let scores = scenalog_facts::box_scores(&log.dir, &scene).map_err(read)?;
            Ok((scene, scores))
        }
        Some(t) => {
            let frames = t.pickle.frames(&log.log_id).map_err(|e| e.to_string())?;
            let tracked = scenalog_tracker::tracked_log(
                &log.log_id,
                &frames,
                &log.dir,
                t.filter,
                t.pickle.file(),
            )
            .map_err(|e| e.to_string())?;
            Ok((tracked.scene, Some(tracked.scores)))
        }
    }
}

/// The log's predictions (its finished pairs' frames, moved out of `pairs`).
/// The dictionaries of the run's table: every log id and description of the run, and the
/// three label names.
fn table_dictionaries(
    scenarios: &[Scenario],
    logs: &[LogInput],
) -> scenalog_eval::arrow_table::TableDictionaries {
    use super::tracks::Label;
    scenalog_eval::arrow_table::TableDictionaries {
        log_ids: logs.iter().map(|l| l.log_id.clone()).collect(),
        prompts: scenarios.iter().map(|s| s.description.clone()).collect(),
        names: [Label::Referred, Label::Related, Label::Other]
            .into_iter()
            .map(|l| super::predictions::label_name(l).to_string())
            .collect(),
    }
}

/// Where a log's pairs send their predictions: the run's staging folder, one part a pair.
struct PartSink<'a> {
    staging: &'a output::Staging,
    /// The log's index in the run.
    log: usize,
}

impl PartSink<'_> {
    /// Writes a finished pair's predictions (its frames leave memory); a failed pair has none.
    fn write(
        &self,
        log: &LogInput,
        scenarios: &[Scenario],
        p: &mut PairResult,
    ) -> Result<(), String> {
        if matches!(p.status, PairStatus::Failed(_)) {
            return Ok(());
        }
        let mut part = Submission::default();
        part.sequences.insert(
            (
                log.log_id.clone(),
                scenarios[p.scenario].description.clone(),
            ),
            std::mem::take(&mut p.frames),
        );
        self.staging.write_part((self.log, p.scenario), &part)
    }
}

fn failed(log: &LogInput, index: usize, reason: impl Into<Message>) -> PairResult {
    PairResult {
        log_id: log.log_id.clone(),
        scenario: index,
        status: PairStatus::Failed(reason.into()),
        frames: Vec::new(),
        matches: Vec::new(),
        evaluate: Duration::ZERO,
        tracks: Duration::ZERO,
        write: Duration::ZERO,
    }
}

/// Mines one log with every scenario: the pairs (in scenario order), the log's own failure if it
/// could not be read, the time spent reading it, and whether every pair's predictions were
/// written to `sink` as the pair finished (the first write error otherwise). Resumed pairs are
/// rebuilt from their records' tuples (which needs the scene, so the log is read even when every
/// pair is resumed).
fn mine_log(
    log: &LogInput,
    scenarios: &[Scenario],
    options: &RunOptions,
    bar: &indicatif::ProgressBar,
    sink: &PartSink,
    without_attributes: &AtomicUsize,
) -> (
    Vec<PairResult>,
    Option<Message>,
    Duration,
    Result<(), String>,
) {
    let t0 = Instant::now();
    let indices = log.program_indices(scenarios.len());
    if cancelled(options) {
        let pairs = indices
            .iter()
            .map(|&i| failed(log, i, CANCELLED.to_string()))
            .collect();
        return (pairs, None, Duration::ZERO, Ok(()));
    }
    let scene = load_log(log).map_err(Message::text);
    let load = t0.elapsed();
    let frames = scene.and_then(|(scene, scores)| {
        let frames = output_frames(&scene, options.timestamps.get(&log.log_id))?;
        Ok((scene, scores, frames))
    });
    let (scene, scores, frames) = match frames {
        Ok(x) => x,
        Err(e) => {
            if options.progress {
                bar.suspend(|| eprintln!("scenalog mine: {}", e.render(PROGRESS_NAMES)));
            }
            bar.inc(indices.len() as u64);
            let pairs = indices.iter().map(|&i| failed(log, i, e.clone())).collect();
            return (pairs, Some(e), load, Ok(()));
        }
    };
    let log_fp = log_fingerprint(log);
    let extractor = Extractor::new(&scene);
    if options.progress {
        no_color_cache_note(log, &scene, scenarios, &indices, bar);
    }
    if lacks_attributes(&scene, scenarios, &indices) {
        without_attributes.fetch_add(1, Ordering::Relaxed);
    }
    let ctx = PairContext {
        log,
        scene: &scene,
        scores: scores.as_deref(),
        frames: &frames,
        options,
    };
    let pairs: Vec<(PairResult, Result<(), String>)> = indices
        .par_iter()
        .map(|&i| {
            let s = &scenarios[i];
            bar.set_message(format!("{} on {}", s.name, short_id(&log.log_id)));
            if cancelled(options) {
                return (failed(log, i, CANCELLED.to_string()), Ok(()));
            }
            let fingerprint = pair_fingerprint(&log_fp, s, options.timestamps.get(&log.log_id));
            let mut r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                let earlier = resumable(log, s, options, &fingerprint)
                    .and_then(|r| resume_pair(&ctx, &extractor, s, i, r));
                earlier.unwrap_or_else(|| mine_pair(&ctx, &extractor, s, i, &fingerprint))
            }))
            .unwrap_or_else(|_| {
                failed(
                    log,
                    i,
                    format!("program `{}` panicked on log {}", s.name, log.log_id),
                )
            });
            if let PairStatus::Failed(e) = &r.status {
                if options.progress {
                    bar.suspend(|| eprintln!("scenalog mine: {}", e.render(PROGRESS_NAMES)));
                }
            }
            bar.inc(1);
            let written = sink.write(log, scenarios, &mut r);
            (r, written)
        })
        .collect();
    let mut written = Ok(());
    let pairs = pairs
        .into_iter()
        .map(|(r, w)| {
            if written.is_ok() {
                written = w;
            }
            r
        })
        .collect();
    (pairs, None, load, written)
}
