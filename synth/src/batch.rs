//! Many descriptions at once: one `.dl` per description in an output directory, a bounded number
//! of descriptions in flight, a progress bar on a terminal, resumable, with a summary.
//!
//! For a description whose slug is `s`, the directory gets `s.dl` (the last program, clean or
//! not), `s.transcript.json` (every round) and, when the program did not check clean,
//! `s.dl.diagnostics.json`. A description whose `s.dl` exists and checks clean is skipped. The
//! whole report (every item and the counts) goes to `summary.json`.

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

use scenalog_rules::{check, CheckOptions};
use serde::Serialize;

use crate::cache::write_atomic;
use crate::extract::one_line;
use crate::repair::{Outcome, Transcript};
use crate::slug::unique_slugs;
use crate::usage::Usage;
use crate::{SynthError, Synthesizer};

/// How to run a batch.
#[derive(Debug, Clone)]
pub struct BatchOptions {
    /// Where the programs go (created if needed).
    pub out_dir: PathBuf,
    /// How many descriptions are synthesized at once (at least 1).
    pub jobs: usize,
    /// Show a progress bar (drawn only when stderr is a terminal).
    pub progress: bool,
}

/// How one description ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum ItemStatus {
    /// Its `.dl` already existed and checks clean: not synthesized again.
    Resumed,
    /// Checked clean in this round.
    Clean {
        /// The round (1-based).
        round: usize,
    },
    /// The rounds ran out; the last attempt and its diagnostics are written.
    Failed,
    /// The server could not be reached.
    Unreachable {
        /// The client's error.
        error: String,
    },
    /// The token budget was spent before a program checked clean.
    OverBudget {
        /// What was spent.
        error: String,
    },
    /// Not attempted: the server had already proved unreachable in this batch, or the token
    /// budget was spent.
    Skipped,
}

/// One description's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BatchItem {
    /// The description (on one line).
    pub description: String,
    /// Its `.dl` file.
    pub path: PathBuf,
    /// How it ended.
    pub status: ItemStatus,
    /// The program written to `path` (`None` when no round produced one).
    pub program: Option<String>,
    /// The tokens the server reported for this description's completions.
    pub usage: Usage,
    /// After a search (`--candidates K`), every candidate program that checked clean, the kept
    /// one included (their agreement becomes the boxes' scores when mined); empty otherwise.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub candidates: Vec<String>,
}

/// Counts of a batch.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct Summary {
    /// Descriptions in the batch.
    pub total: usize,
    /// Skipped because their program was already there and clean.
    pub resumed: usize,
    /// `clean_by_round[i]`: checked clean in round `i + 1`.
    pub clean_by_round: Vec<usize>,
    /// The rounds ran out.
    pub failed: usize,
    /// The server could not be reached.
    pub unreachable: usize,
    /// Not attempted after the server proved unreachable or the token budget was spent.
    pub skipped: usize,
    /// Stopped by the token budget before a program checked clean.
    pub over_budget: usize,
    /// Completions the server answered.
    pub requests: usize,
    /// Completions the cache answered.
    pub cache_hits: usize,
    /// The tokens the server reported, over every description.
    pub usage: Usage,
}

impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let clean: usize = self.clean_by_round.iter().sum();
        write!(
            f,
            "{} descriptions: {} clean ({}), {} already done, {} failed",
            self.total,
            clean,
            self.clean_by_round
                .iter()
                .enumerate()
                .map(|(i, n)| format!("round {}: {n}", i + 1))
                .collect::<Vec<_>>()
                .join(", "),
            self.resumed,
            self.failed
        )?;
        if self.unreachable + self.skipped > 0 {
            write!(
                f,
                ", {} unreachable, {} not attempted",
                self.unreachable, self.skipped
            )?;
        }
        if self.over_budget > 0 {
            write!(f, ", {} stopped by the token budget", self.over_budget)?;
        }
        write!(
            f,
            "; {} completions from the server, {} from the cache",
            self.requests, self.cache_hits
        )?;
        let u = &self.usage;
        write!(
            f,
            "; tokens: {} prompt ({} cached), {} completion",
            u.prompt_tokens, u.cached_tokens, u.completion_tokens
        )?;
        if u.without_usage > 0 {
            write!(f, " ({} answers reported no usage)", u.without_usage)?;
        }
        Ok(())
    }
}

/// A batch's results, in the order of the descriptions.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BatchReport {
    /// One per description.
    pub items: Vec<BatchItem>,
    /// The counts.
    pub summary: Summary,
}

/// The descriptions of a file: one a line, blank lines and lines starting with `#` skipped,
/// whitespace runs made one space, repeated descriptions kept once.
pub fn read_descriptions(path: &Path) -> Result<Vec<String>, SynthError> {
    let text = SynthError::read_text(path)?;
    let mut out: Vec<String> = Vec::new();
    for line in text.lines() {
        let d = one_line(line);
        if d.is_empty() || d.starts_with('#') || out.contains(&d) {
            continue;
        }
        out.push(d);
    }
    if out.is_empty() {
        return Err(SynthError::Invalid {
            path: path.to_path_buf(),
            message:
                "no descriptions (expected one a line; blank lines and # comments are skipped)"
                    .into(),
        });
    }
    Ok(out)
}

/// Whether the file exists and holds a program that checks clean.
fn checks_clean(path: &Path) -> Option<String> {
    let source = SynthError::read_text(path).ok()?;
    let outcome = check(
        &source,
        &CheckOptions {
            require_referred: true,
        },
    );
    outcome.program.map(|_| source)
}

/// Writes a transcript's program, diagnostics (when not clean) and the transcript itself next to
/// `dl` (`dl`, `dl.diagnostics.json`, `<stem>.transcript.json`), creating the directory if
/// needed. Writes nothing for the program when no round produced one.
pub fn write_outputs(dl: &Path, transcript: &Transcript) -> Result<(), SynthError> {
    if let Some(parent) = dl.parent().filter(|p| !p.as_os_str().is_empty()) {
        fs::create_dir_all(parent).map_err(|e| SynthError::io(parent, e))?;
    }
    if let Some(program) = transcript.program() {
        write_atomic(dl, program.as_bytes())?;
    }
    let diag_path = diagnostics_path(dl);
    if transcript.is_clean() {
        if diag_path.exists() {
            fs::remove_file(&diag_path).map_err(|e| SynthError::io(&diag_path, e))?;
        }
    } else if transcript.program().is_some() {
        let json = serde_json::to_string_pretty(&transcript.diagnostics()).unwrap_or_default();
        write_atomic(&diag_path, json.as_bytes())?;
    }
    write_atomic(&transcript_path(dl), transcript.to_json().as_bytes())
}

/// `FILE.dl.diagnostics.json` for `FILE.dl`.
pub fn diagnostics_path(dl: &Path) -> PathBuf {
    let mut s = dl.as_os_str().to_os_string();
    s.push(".diagnostics.json");
    PathBuf::from(s)
}

/// `FILE.transcript.json` for `FILE.dl`.
pub fn transcript_path(dl: &Path) -> PathBuf {
    dl.with_extension("transcript.json")
}

/// Synthesizes every description into `options.out_dir`. Errors only when the directory or an
/// output file cannot be written; each description's own fate is in its item.
pub fn run(
    synth: &Synthesizer,
    descriptions: &[String],
    options: &BatchOptions,
) -> Result<BatchReport, SynthError> {
    let out_dir = &options.out_dir;
    fs::create_dir_all(out_dir).map_err(|e| SynthError::io(out_dir, e))?;
    let descriptions: Vec<String> = descriptions.iter().map(|d| one_line(d)).collect();
    let slugs = unique_slugs(&descriptions);
    let n = descriptions.len();
    let bar = if options.progress {
        indicatif::ProgressBar::new(n as u64)
    } else {
        indicatif::ProgressBar::hidden()
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed} {wide_msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let stats_before = synth.stats();
    let next = AtomicUsize::new(0);
    let down = AtomicBool::new(false);
    let results: Mutex<Vec<Option<Result<BatchItem, SynthError>>>> =
        Mutex::new((0..n).map(|_| None).collect());
    let worker = || loop {
        let i = next.fetch_add(1, Ordering::Relaxed);
        if i >= n {
            break;
        }
        let description = &descriptions[i];
        let path = out_dir.join(format!("{}.dl", slugs[i]));
        bar.set_message(description.clone());
        let item = one(synth, description, path, &down);
        if let Ok(mut r) = results.lock() {
            r[i] = Some(item);
        }
        bar.inc(1);
    };
    let jobs = options.jobs.clamp(1, n.max(1));
    std::thread::scope(|s| {
        for _ in 0..jobs {
            s.spawn(worker);
        }
    });
    bar.finish_and_clear();
    let results = results.into_inner().unwrap_or_else(|e| e.into_inner());
    let mut items = Vec::with_capacity(n);
    for r in results {
        match r {
            Some(item) => items.push(item?),
            None => {
                return Err(SynthError::Invalid {
                    path: out_dir.clone(),
                    message: "a synthesis worker stopped without a result".into(),
                })
            }
        }
    }
    let stats = synth.stats();
    let mut summary = Summary {
        total: n,
        clean_by_round: vec![0; synth.config().rounds.max(1)],
        requests: stats.requests - stats_before.requests,
        cache_hits: stats.cache_hits - stats_before.cache_hits,
        ..Summary::default()
    };
    for item in &items {
        summary.usage = summary.usage.add(&item.usage);
        match &item.status {
            ItemStatus::Resumed => summary.resumed += 1,
            ItemStatus::Clean { round } => {
                if summary.clean_by_round.len() < *round {
                    summary.clean_by_round.resize(*round, 0);
                }
                summary.clean_by_round[round - 1] += 1;
            }
            ItemStatus::Failed => summary.failed += 1,
            ItemStatus::Unreachable { .. } => summary.unreachable += 1,
            ItemStatus::OverBudget { .. } => summary.over_budget += 1,
            ItemStatus::Skipped => summary.skipped += 1,
        }
    }
    let report = BatchReport { items, summary };
    let json = serde_json::to_string_pretty(&report).unwrap_or_default();
    write_atomic(&out_dir.join("summary.json"), json.as_bytes())?;
    Ok(report)
}

fn one(
    synth: &Synthesizer,
    description: &str,
    path: PathBuf,
    down: &AtomicBool,
) -> Result<BatchItem, SynthError> {
    if let Some(program) = checks_clean(&path) {
        let candidates = search_candidates_on_disk(&path);
        return Ok(BatchItem {
            description: description.to_string(),
            path,
            status: ItemStatus::Resumed,
            program: Some(program),
            usage: Usage::default(),
            candidates,
        });
    }
    if down.load(Ordering::Relaxed) {
        return Ok(BatchItem {
            description: description.to_string(),
            path,
            status: ItemStatus::Skipped,
            program: None,
            usage: Usage::default(),
            candidates: Vec::new(),
        });
    }
    let transcript = synth.synthesize(description);
    write_outputs(&path, &transcript)?;
    let status = match &transcript.outcome {
        Outcome::Clean { round } => ItemStatus::Clean { round: *round },
        Outcome::Failed => ItemStatus::Failed,
        Outcome::Unreachable { error } => {
            down.store(true, Ordering::Relaxed);
            ItemStatus::Unreachable {
                error: error.clone(),
            }
        }
        Outcome::OverBudget { error } => {
            down.store(true, Ordering::Relaxed);
            ItemStatus::OverBudget {
                error: error.clone(),
            }
        }
    };
    Ok(BatchItem {
        description: description.to_string(),
        path,
        program: transcript.program().map(str::to_string),
        status,
        usage: transcript.usage(),
        candidates: transcript
            .search
            .as_ref()
            .map(crate::search::Search::clean_programs)
            .unwrap_or_default(),
    })
}

/// The clean candidates of the search recorded in the transcript beside `dl` (a resumed
/// program's); none when there is no readable transcript or it holds no search.
fn search_candidates_on_disk(dl: &Path) -> Vec<String> {
    scenalog_input::read_text_file(&transcript_path(dl), scenalog_input::TEXT_LIMIT)
        .ok()
        .and_then(|text| serde_json::from_str::<Transcript>(&text).ok())
        .and_then(|t| t.search)
        .map(|search| search.clean_programs())
        .unwrap_or_default()
}
