//! A mining run: every (log, program) pair evaluated, turned into prediction tracks and written.
//!
//! Logs run in parallel (rayon), and so do the programs of one log, which share one
//! [`Extractor`] (its per-scene cache computes each relation once for all of them). Results are
//! gathered by index, so the output is the same whatever the thread count. A log that cannot be
//! read, or a program that fails on a log, is reported and skipped; the rest of the run goes on.
//! Each finished pair is written at once under `OUT/pairs/` (see [`super::output`]), so with
//! `resume` a rerun skips what a crashed or interrupted one finished.

use std::collections::{BTreeMap, BTreeSet};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use rayon::prelude::*;
use scenalog_engine::Options;
use scenalog_eval::{FrameData, Submission};
use scenalog_extractors::cache::Extractor;
use scenalog_facts::relation::Value;
use scenalog_facts::{Frame, Scene, TrackId};

use super::output::{self, Match, PairRecord};
use super::predictions::to_frames;
use super::scenario::{evaluate_on, Scenario};
use super::tracks::{eval_frames, label_frames};

/// One log to mine: its directory and its id (the directory's name).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LogInput {
    /// The log directory.
    pub dir: PathBuf,
    /// The log id.
    pub log_id: String,
}

impl LogInput {
    /// A log directory; its id is the directory's name.
    pub fn new(dir: PathBuf) -> LogInput {
        let log_id = dir
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| dir.display().to_string());
        LogInput { dir, log_id }
    }
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
    /// Draw a progress bar (only when stderr is a terminal).
    pub progress: bool,
}

/// How one pair ended.
#[derive(Debug, Clone, PartialEq)]
pub enum PairStatus {
    /// Evaluated and written in this run.
    Done,
    /// Already written by an earlier run (`resume`).
    Resumed,
    /// Could not be evaluated or written: the reason.
    Failed(String),
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
    pub log_failures: Vec<(String, String)>,
    /// The run's predictions, keyed `(log_id, description)` (finished pairs only).
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

    /// Every match of every finished pair, in pair order.
    pub fn matches(&self) -> Vec<&Match> {
        self.pairs.iter().flat_map(|p| &p.matches).collect()
    }
}

/// Runs every scenario on every log and writes the outputs under `options.out`. Errors only
/// when the run's own outputs cannot be written or the thread pool cannot be made; a log or
/// pair that fails is in the report.
pub fn run(
    scenarios: &[Scenario],
    logs: &[LogInput],
    options: &RunOptions,
) -> Result<RunReport, String> {
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
    let total = (logs.len() * scenarios.len()) as u64;
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
    let per_log: Vec<(Vec<PairResult>, Option<String>)> = pool.install(|| {
        logs.par_iter()
            .map(|log| {
                let (pairs, failure, load) = mine_log(log, scenarios, options, &bar);
                if let Ok(mut t) = load_time.lock() {
                    *t += load;
                }
                (pairs, failure)
            })
            .collect()
    });
    bar.finish_and_clear();
    let mut pairs = Vec::with_capacity(total as usize);
    let mut log_failures = Vec::new();
    for (log, (p, failure)) in logs.iter().zip(per_log) {
        pairs.extend(p);
        if let Some(f) = failure {
            log_failures.push((log.log_id.clone(), f));
        }
    }
    let mut submission = Submission::default();
    for p in &mut pairs {
        if !matches!(p.status, PairStatus::Failed(_)) {
            submission.sequences.insert(
                (p.log_id.clone(), scenarios[p.scenario].description.clone()),
                std::mem::take(&mut p.frames),
            );
        }
    }
    let write_start = Instant::now();
    // The two big files are written at once.
    let (pickled, tabled) = pool.install(|| {
        rayon::join(
            || {
                scenalog_eval::write_pickle(
                    &submission,
                    &options.out.join(output::PREDICTIONS_PICKLE),
                )
            },
            || {
                scenalog_eval::write_table(
                    &submission,
                    &options.out.join(output::PREDICTIONS_TABLE),
                )
            },
        )
    });
    pickled.map_err(|e| e.to_string())?;
    tabled.map_err(|e| e.to_string())?;
    let matches: Vec<&Match> = pairs.iter().flat_map(|p| &p.matches).collect();
    output::write_json(&options.out.join(output::MATCHES_JSON), &matches, true)?;
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
        submission,
        timings,
        threads: pool.current_num_threads(),
    };
    report.timings.write += write_start.elapsed();
    report.timings.wall = start.elapsed();
    output::write_json(
        &options.out.join(output::SUMMARY_JSON),
        &summary_json(&report, scenarios),
        true,
    )?;
    Ok(report)
}

/// `summary.json`: the stage times, the failed logs and every pair's status.
fn summary_json(report: &RunReport, scenarios: &[Scenario]) -> serde_json::Value {
    let t = &report.timings;
    let pairs: Vec<serde_json::Value> = report
        .pairs
        .iter()
        .map(|p| {
            let (status, error) = match &p.status {
                PairStatus::Done => ("done", None),
                PairStatus::Resumed => ("resumed", None),
                PairStatus::Failed(e) => ("failed", Some(e.clone())),
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
        .collect();
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
            .map(|(l, e)| serde_json::json!({"log_id": l, "error": e}))
            .collect::<Vec<_>>(),
        "pairs": pairs,
    })
}

/// A pair's earlier record, when `resume` is on and the record matches this run (same program
/// text, description and output timestamps).
fn resumable(log: &LogInput, scenario: &Scenario, options: &RunOptions) -> Option<PairRecord> {
    if !options.resume {
        return None;
    }
    let path = output::pair_path(&options.out, &log.log_id, &scenario.name);
    let record = output::read_record(&path)?;
    let same = record.log_id == log.log_id
        && record.description == scenario.description
        && record.source == scenario.source
        && record.timestamps.as_ref() == options.timestamps.get(&log.log_id);
    same.then_some(record)
}

fn failed(log: &LogInput, index: usize, reason: String) -> PairResult {
    PairResult {
        log_id: log.log_id.clone(),
        scenario: index,
        status: PairStatus::Failed(reason),
        frames: Vec::new(),
        matches: Vec::new(),
        evaluate: Duration::ZERO,
        tracks: Duration::ZERO,
        write: Duration::ZERO,
    }
}

/// Mines one log with every scenario: the pairs (in scenario order), the log's own failure if it
/// could not be read, and the time spent reading it. Resumed pairs are rebuilt from their
/// records' tuples (which needs the scene, so the log is read even when every pair is resumed).
fn mine_log(
    log: &LogInput,
    scenarios: &[Scenario],
    options: &RunOptions,
    bar: &indicatif::ProgressBar,
) -> (Vec<PairResult>, Option<String>, Duration) {
    let t0 = Instant::now();
    let scene = scenalog_facts::load_scene(&log.dir)
        .map_err(|e| format!("cannot read log `{}`: {e}", log.dir.display()));
    let load = t0.elapsed();
    let frames = scene.and_then(|scene| {
        let frames = output_frames(&scene, options.timestamps.get(&log.log_id))?;
        Ok((scene, frames))
    });
    let (scene, frames) = match frames {
        Ok(x) => x,
        Err(e) => {
            bar.suspend(|| eprintln!("scenalog mine: {e}"));
            bar.inc(scenarios.len() as u64);
            let pairs = (0..scenarios.len())
                .map(|i| failed(log, i, e.clone()))
                .collect();
            return (pairs, Some(e), load);
        }
    };
    let extractor = Extractor::new(&scene);
    let indices: Vec<usize> = (0..scenarios.len()).collect();
    let pairs: Vec<PairResult> = indices
        .par_iter()
        .map(|&i| {
            let s = &scenarios[i];
            bar.set_message(format!("{} on {}", s.name, short_id(&log.log_id)));
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                let earlier =
                    resumable(log, s, options).and_then(|r| resume_pair(&scene, s, i, &frames, r));
                earlier
                    .unwrap_or_else(|| mine_pair(log, &scene, &extractor, s, i, &frames, options))
            }))
            .unwrap_or_else(|_| {
                failed(
                    log,
                    i,
                    format!("program `{}` panicked on log {}", s.name, log.log_id),
                )
            });
            if let PairStatus::Failed(e) = &r.status {
                bar.suspend(|| eprintln!("scenalog mine: {e}"));
            }
            bar.inc(1);
            r
        })
        .collect();
    (pairs, None, load)
}

/// Rebuilds a finished pair from its record; `None` when the record's tuples do not fit the
/// scene (the log changed), so the pair is mined again.
fn resume_pair(
    scene: &Scene,
    scenario: &Scenario,
    index: usize,
    frames: &[Frame],
    record: PairRecord,
) -> Option<PairResult> {
    let t = Instant::now();
    let n_tracks = scene.tracks.len();
    let n_frames = scene.num_frames();
    let track = |i: u32| ((i as usize) < n_tracks).then_some(TrackId(i));
    let frame = |f: Frame| ((f as usize) < n_frames).then_some(f);
    let referred: Vec<(TrackId, Frame)> = record
        .referred
        .iter()
        .map(|&(v, f)| Some((track(v)?, frame(f)?)))
        .collect::<Option<_>>()?;
    let related: Vec<(TrackId, TrackId, Frame)> = record
        .related
        .iter()
        .map(|&(v, o, f)| Some((track(v)?, track(o)?, frame(f)?)))
        .collect::<Option<_>>()?;
    if record.tracks != n_tracks {
        return None;
    }
    let (out, matches) = build_pair(scene, scenario, &referred, &related, frames);
    Some(PairResult {
        log_id: scene.log_id.clone(),
        scenario: index,
        status: PairStatus::Resumed,
        frames: out,
        matches,
        evaluate: Duration::ZERO,
        tracks: t.elapsed(),
        write: Duration::ZERO,
    })
}

/// The prediction frames and matches of a pair from its tuples.
fn build_pair(
    scene: &Scene,
    scenario: &Scenario,
    referred: &[(TrackId, Frame)],
    related: &[(TrackId, TrackId, Frame)],
    frames: &[Frame],
) -> (Vec<FrameData>, Vec<Match>) {
    let labelled = label_frames(scene, referred, related, frames);
    let out = to_frames(scene, &scenario.description, &labelled);
    (out, matches_of(scene, scenario, referred, related))
}

/// The first 8 characters of a log id, for messages and tables.
pub fn short_id(log_id: &str) -> &str {
    log_id.get(..8).unwrap_or(log_id)
}

/// The frames predictions are emitted at: the given timestamps (each must be a frame of the
/// log), or every 5th frame from the first.
fn output_frames(scene: &Scene, given: Option<&Vec<i64>>) -> Result<Vec<Frame>, String> {
    let Some(given) = given else {
        return Ok(eval_frames(scene));
    };
    let mut frames = Vec::with_capacity(given.len());
    for &ns in given {
        let f = scene.timeline.frame_of(ns).ok_or_else(|| {
            format!(
                "--eval-timestamps: {ns} is not an annotation timestamp of log {}",
                scene.log_id
            )
        })?;
        frames.push(f);
    }
    frames.sort_unstable();
    frames.dedup();
    Ok(frames)
}

/// Evaluates one program on one log and writes the pair's files.
fn mine_pair(
    log: &LogInput,
    scene: &Scene,
    extractor: &Extractor<'_>,
    scenario: &Scenario,
    index: usize,
    frames: &[Frame],
    options: &RunOptions,
) -> PairResult {
    let t0 = Instant::now();
    let evaluation = match evaluate_on(extractor, &scenario.program, &options.engine) {
        Ok(e) => e,
        Err(e) => {
            return failed(
                log,
                index,
                format!(
                    "program `{}` failed on log {}: {e}",
                    scenario.name, log.log_id
                ),
            )
        }
    };
    let evaluate = t0.elapsed();
    let t1 = Instant::now();
    let referred = referred_tuples(&evaluation);
    let related = related_tuples(&evaluation);
    let (frames, matches) = build_pair(scene, scenario, &referred, &related, frames);
    let tracks = t1.elapsed();
    let t2 = Instant::now();
    let written = write_pair(log, scene, scenario, &referred, &related, options);
    let write = t2.elapsed();
    let status = match written {
        Ok(()) => PairStatus::Done,
        Err(e) => PairStatus::Failed(e),
    };
    PairResult {
        log_id: log.log_id.clone(),
        scenario: index,
        status,
        frames,
        matches,
        evaluate,
        tracks,
        write,
    }
}

/// Writes the pair's record (its tuples, from which `--resume` rebuilds it).
fn write_pair(
    log: &LogInput,
    scene: &Scene,
    scenario: &Scenario,
    referred: &[(TrackId, Frame)],
    related: &[(TrackId, TrackId, Frame)],
    options: &RunOptions,
) -> Result<(), String> {
    let record = PairRecord {
        log_id: log.log_id.clone(),
        description: scenario.description.clone(),
        program: scenario.name.clone(),
        source: scenario.source.clone(),
        timestamps: options.timestamps.get(&log.log_id).cloned(),
        tracks: scene.tracks.len(),
        referred: referred.iter().map(|&(v, f)| (v.0, f)).collect(),
        related: related.iter().map(|&(v, o, f)| (v.0, o.0, f)).collect(),
    };
    let path = output::pair_path(&options.out, &log.log_id, &scenario.name);
    output::write_json(&path, &record, false)
}

/// `referred(Track, Time)` tuples.
fn referred_tuples(e: &scenalog_engine::Evaluation) -> Vec<(TrackId, Frame)> {
    e.tuples("referred")
        .unwrap_or_default()
        .iter()
        .filter_map(|t| match t.as_slice() {
            [Value::Track(v), Value::Time(f)] => Some((*v, *f)),
            _ => None,
        })
        .collect()
}

/// `related(Track, Other, Time)` tuples.
fn related_tuples(e: &scenalog_engine::Evaluation) -> Vec<(TrackId, TrackId, Frame)> {
    e.tuples("related")
        .unwrap_or_default()
        .iter()
        .filter_map(|t| match t.as_slice() {
            [Value::Track(v), Value::Track(o), Value::Time(f)] => Some((*v, *o, *f)),
            _ => None,
        })
        .collect()
}

/// One [`Match`] per referred track, in track order (tracks are sorted by uuid).
fn matches_of(
    scene: &Scene,
    scenario: &Scenario,
    referred: &[(TrackId, Frame)],
    related: &[(TrackId, TrackId, Frame)],
) -> Vec<Match> {
    let mut frames: BTreeMap<TrackId, BTreeSet<Frame>> = BTreeMap::new();
    for &(t, f) in referred {
        frames.entry(t).or_default().insert(f);
    }
    let mut rel: BTreeMap<TrackId, BTreeSet<&str>> = BTreeMap::new();
    for &(t, o, _) in related {
        rel.entry(t)
            .or_default()
            .insert(scene.track(o).uuid.as_str());
    }
    frames
        .into_iter()
        .filter_map(|(t, fs)| {
            let first = *fs.first()?;
            let last = *fs.last()?;
            let track = scene.track(t);
            Some(Match {
                log_id: scene.log_id.clone(),
                description: scenario.description.clone(),
                program: scenario.name.clone(),
                track_uuid: track.uuid.clone(),
                category: track.category.clone(),
                first_s: round_ms(scene.timeline.seconds(first).unwrap_or(0.0)),
                last_s: round_ms(scene.timeline.seconds(last).unwrap_or(0.0)),
                frames: fs.len(),
                related: rel
                    .get(&t)
                    .map(|s| s.iter().map(|u| u.to_string()).collect())
                    .unwrap_or_default(),
            })
        })
        .collect()
}

/// Seconds rounded to the millisecond (frames are 0.1 s apart; the rest is clock noise).
fn round_ms(s: f64) -> f64 {
    (s * 1000.0).round() / 1000.0
}
