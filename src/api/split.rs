//! A split's (log, prompt) pairs, and only those, mined into one submission
//! (`scenalog mine --log-prompts FILE --dataset-dir SPLIT`, `scenalog.mine(log_prompts=…)`).
//!
//! The program for a prompt is the `programs` directory's file whose `// description:` is the
//! prompt, else the library's, else (with synthesis) one the LLM writes; descriptions match
//! after trimming, lower-casing and collapsing spaces, and the submission is keyed by the
//! prompt exactly as the pairs file spells it. A prompt with no program is listed and gets the
//! empty prediction (every object `OTHER_OBJECT` at the output timestamps), so the submission
//! keeps every listed key. A log missing from the tracker file or the split is an error naming
//! it; the other logs are still mined. Each log is read, and its facts extracted, once for all
//! of its prompts. Writes `OUT/submission.pkl` and `OUT/submission.feather`; the outcome
//! ([`SplitOutcome`]) carries their paths and every failure in one list. [`mine_split`] prepares
//! and runs a request.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use crate::api::error::{Error, Field, Message, Names};
use crate::api::inputs::{bundled, check_threads, create_out, default_out, rule_files, LIBRARY};
use crate::api::limits::Limits;
use crate::api::mine::{with_causes, Match};
use crate::api::outputs::Outputs;
use crate::api::synth::{check_jobs, synthesize, Synthesis};
use crate::pipeline::output::{OutputNames, SUBMISSION_PICKLE, SUBMISSION_TABLE};
use crate::pipeline::run::{
    pairs_json, run as run_mining, LogInput, PairStatus, RunOptions, RunReport, TrackerInput,
};
use crate::pipeline::scenario::{load_scenario, scenario_from_source, Scenario};

/// The program given to a prompt that has none: it checks, and refers nothing.
const EMPTY_PROGRAM: &str = "referred(X, T) :- category(X, \"ANY\"), present(X, T), T < 0.\n";

/// A split's pairs to mine.
pub struct SplitRequest {
    /// The pairs: a JSON file `{"<log_id>": ["prompt", …]}`.
    pub log_prompts: PathBuf,
    /// The AV2 split directory (`SPLIT/<log_id>/`: ego poses, map, and annotations when there
    /// are no `tracks`).
    pub dataset_dir: PathBuf,
    /// The output directory (`None`: [`default_out`]).
    pub out: Option<PathBuf>,
    /// A 3D tracker's output (the AV2 tracking-submission pickle) to mine instead of
    /// annotations.
    pub tracks: Option<PathBuf>,
    /// Apply RefAV's confidence filter to the tracker's tracks.
    pub confidence_filter: bool,
    /// Programs for the prompts, matched by their `// description:` line (before the library).
    pub programs: Option<PathBuf>,
    /// Synthesize a program with the LLM for each prompt that has none.
    pub synthesis: Option<Synthesis>,
    /// Skip pairs an earlier run into the same output already wrote.
    pub resume: bool,
    /// Worker threads, 1 to 1024 (`None`: one per core).
    pub threads: Option<usize>,
    /// One pair's limits.
    pub limits: Limits,
    /// Draw a progress bar and print failures on stderr as they happen (the command).
    pub progress: bool,
    /// Set from another thread to stop the run without publishing it.
    pub cancel: Option<Arc<AtomicBool>>,
}

impl SplitRequest {
    /// The pairs of `log_prompts` in `dataset_dir`, every other field at its default.
    pub fn new(log_prompts: PathBuf, dataset_dir: PathBuf) -> SplitRequest {
        SplitRequest {
            log_prompts,
            dataset_dir,
            out: None,
            tracks: None,
            confidence_filter: true,
            programs: None,
            synthesis: None,
            resume: false,
            threads: None,
            limits: Limits::default(),
            progress: false,
            cancel: None,
        }
    }
}

/// Reads `{"<log_id>": ["prompt", …]}`.
fn read_pairs(path: &Path) -> Result<BTreeMap<String, Vec<String>>, Error> {
    let text = crate::input::read_text(path).map_err(|e| Error::about(Field::LogPrompts, e))?;
    let pairs: BTreeMap<String, Vec<String>> = serde_json::from_str(&text).map_err(|e| {
        Error::about(
            Field::LogPrompts,
            format!(
                "`{}`: expected a JSON object mapping log ids to lists of prompts: {e}",
                path.display()
            ),
        )
    })?;
    for log in pairs.keys() {
        scenalog_input::check_log_id(log)
            .map_err(|e| Error::about(Field::LogPrompts, format!("`{}`: {e}", path.display())))?;
    }
    Ok(pairs)
}

/// A description as matched: trimmed, lower-case, single spaces.
fn normal(d: &str) -> String {
    d.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_lowercase()
}

/// Every checked program of `dir` by normalised description (the first by file name wins), and
/// the problems (programs that do not check).
fn programs_by_description(
    dir: &Path,
    problems: &mut Vec<String>,
) -> Result<BTreeMap<String, Scenario>, Error> {
    let mut out = BTreeMap::new();
    for f in rule_files(&[dir.to_path_buf()])? {
        match load_scenario(&f) {
            Ok(s) => {
                out.entry(normal(&s.description)).or_insert(s);
            }
            Err(e) => problems.push(e),
        }
    }
    Ok(out)
}

/// SHA-256 of bytes, hex.
fn sha256_hex(parts: &[&[u8]]) -> String {
    use sha2::{Digest, Sha256};
    let mut h = Sha256::new();
    for p in parts {
        h.update(p);
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// A split's pairs ready to mine: what [`prepare`] read and decided before the run.
pub struct SplitPlan {
    /// The pairs file: prompts by log id.
    pub pairs: BTreeMap<String, Vec<String>>,
    /// The output directory (created).
    pub out: PathBuf,
    /// One program per prompt, its description the prompt as written.
    pub scenarios: Vec<Scenario>,
    /// The logs to mine, each with the indices of its prompts' programs.
    pub logs: Vec<LogInput>,
    /// Programs that do not check and descriptions synthesis gave no program for.
    pub problems: Vec<String>,
    /// Logs missing from the split or the tracker file.
    pub log_problems: Vec<String>,
    /// Prompts with no program (their predictions are empty).
    pub without_program: Vec<String>,
    /// The synthesis's one-line summary, when prompts were synthesized.
    pub synthesis_summary: Option<String>,
}

/// Reads the pairs, the tracker file and the programs, and plans the run; an error means the
/// run cannot start (the command's exit 2).
pub fn prepare(request: &SplitRequest) -> Result<SplitPlan, Error> {
    check_threads(request.threads)?;
    request.limits.check()?;
    if let Some(s) = &request.synthesis {
        check_jobs(s.jobs)?;
    }
    let split = &request.dataset_dir;
    if !split.is_dir() {
        return Err(Error::about(
            Field::DatasetDir,
            format!("`{}` is not a directory", split.display()),
        ));
    }
    let pairs = read_pairs(&request.log_prompts)?;
    let out = request.out.clone().unwrap_or_else(default_out);
    create_out(&out)?;
    let tracker = match &request.tracks {
        None => None,
        Some(p) => {
            let bytes = crate::input::read_pickle(p).map_err(|e| Error::about(Field::Tracks, e))?;
            let filter = if request.confidence_filter {
                scenalog_tracker::Filter::RefAv
            } else {
                scenalog_tracker::Filter::None
            };
            let fingerprint = sha256_hex(&[&bytes, format!("{filter:?}").as_bytes()]);
            match scenalog_tracker::TrackerPickle::from_bytes(&bytes, &p.display().to_string()) {
                Ok(pickle) => Some(Arc::new(TrackerInput {
                    pickle,
                    filter,
                    fingerprint,
                })),
                Err(e) => return Err(Error::about(Field::Tracks, e)),
            }
        }
    };

    // Programs: the request's, then the library, then synthesis.
    let mut problems: Vec<String> = Vec::new();
    let mut sources: Vec<BTreeMap<String, Scenario>> = Vec::new();
    if let Some(dir) = &request.programs {
        match programs_by_description(dir, &mut problems) {
            Ok(m) => sources.push(m),
            Err(e) => return Err(e.within(Field::Programs)),
        }
    }
    if let Some(lib) = bundled(LIBRARY) {
        sources.push(programs_by_description(&lib, &mut problems)?);
    }
    let prompts: BTreeSet<&String> = pairs.values().flatten().collect();
    let find = |sources: &[BTreeMap<String, Scenario>], p: &str| {
        sources.iter().find_map(|m| m.get(&normal(p)).cloned())
    };
    let mut synthesis_summary = None;
    if let Some(synthesis) = &request.synthesis {
        let wanted: Vec<&str> = prompts
            .iter()
            .filter(|p| find(&sources, p).is_none())
            .map(|p| p.as_str())
            .collect();
        if !wanted.is_empty() {
            let file = out.join("prompts-to-synthesize.txt");
            let text: String = wanted.iter().map(|p| format!("{p}\n")).collect();
            crate::pipeline::output::write_atomic(&file, text.as_bytes(), false)?;
            let synthesized = synthesize(&file, &out, synthesis, request.progress)?;
            problems.extend(synthesized.problems);
            synthesis_summary = Some(synthesized.summary);
            let mut m = BTreeMap::new();
            for (path, source) in synthesized.programs {
                match scenario_from_source(&path, source) {
                    Ok(s) => {
                        m.entry(normal(&s.description)).or_insert(s);
                    }
                    Err(e) => problems.push(e),
                }
            }
            sources.push(m);
        }
    }
    // One scenario per prompt, keyed by the prompt as written, with a unique name.
    let mut scenarios: Vec<Scenario> = Vec::new();
    let mut index_of: BTreeMap<&str, usize> = BTreeMap::new();
    let mut without_program: Vec<String> = Vec::new();
    let mut names = BTreeSet::new();
    for p in &prompts {
        let mut s = match find(&sources, p) {
            Some(s) => s,
            None => {
                without_program.push(p.to_string());
                let source = format!("// description: {p}\n{EMPTY_PROGRAM}");
                match scenario_from_source(Path::new("no_program.dl"), source) {
                    Ok(s) => s,
                    Err(e) => {
                        return Err(Error::plain(format!("internal: the empty program: {e}")))
                    }
                }
            }
        };
        s.description = p.to_string();
        let base = s.name.clone();
        let mut n = 1;
        while !names.insert(s.name.clone()) {
            n += 1;
            s.name = format!("{base}-{n}");
        }
        index_of.insert(p, scenarios.len());
        scenarios.push(s);
    }

    // Logs: each in the split (and in the tracker file).
    let mut logs = Vec::new();
    let mut log_problems = Vec::new();
    for (log_id, ps) in &pairs {
        let dir = split.join(log_id);
        if let Some(t) = &tracker {
            if !t.pickle.contains(log_id) {
                log_problems.push(format!(
                    "log {log_id}: not in the tracker file `{}`; its {} pairs are not mined",
                    t.pickle.file(),
                    ps.len()
                ));
                continue;
            }
        }
        if !dir.is_dir() {
            log_problems.push(format!(
                "log {log_id}: no directory `{}` in the split; its {} pairs are not mined",
                dir.display(),
                ps.len()
            ));
            continue;
        }
        let mut programs: Vec<usize> = ps
            .iter()
            .filter_map(|p| index_of.get(p.as_str()).copied())
            .collect();
        programs.sort_unstable();
        programs.dedup();
        logs.push(LogInput {
            tracker: tracker.clone(),
            programs: Some(programs),
            ..LogInput::with_id(dir, log_id.clone())
        });
    }
    Ok(SplitPlan {
        pairs,
        out,
        scenarios,
        logs,
        problems,
        log_problems,
        without_program,
        synthesis_summary,
    })
}

/// The run's options for a plan: its output directory and names, threads, resume, the
/// engine's limits, progress, the cancel flag.
pub fn run_options(request: &SplitRequest, plan: &SplitPlan) -> RunOptions {
    RunOptions {
        out: plan.out.clone(),
        resume: request.resume,
        timestamps: BTreeMap::new(),
        threads: request.threads,
        engine: request.limits.for_run(request.threads),
        progress: request.progress,
        names: OutputNames {
            pickle: SUBMISSION_PICKLE,
            table: SUBMISSION_TABLE,
            write_pickle: true,
        },
        keep_submission: false,
        cancel: request.cancel.clone(),
    }
}

impl SplitPlan {
    /// The pairs the pairs file lists, each (log, prompt) once.
    pub fn listed_pairs(&self) -> usize {
        self.pairs
            .values()
            .map(|v| v.iter().collect::<BTreeSet<_>>().len())
            .sum()
    }
}

/// What a split's run gave, published.
pub struct SplitOutcome {
    /// Every pair's result.
    pub report: RunReport,
    /// One program per prompt.
    pub scenarios: Vec<Scenario>,
    /// The logs mined.
    pub logs: usize,
    /// The pairs the pairs file lists, each (log, prompt) once.
    pub listed: usize,
    /// Every failure, the rest having run: programs that do not check, prompts synthesis gave
    /// no program for, logs missing from the split or the tracker file, failed pairs.
    pub failures: Vec<Message>,
    /// Prompts with no program (their predictions are empty).
    pub without_program: Vec<String>,
    /// The files published (the submission's pickle and table).
    pub outputs: Outputs,
}

impl SplitOutcome {
    /// Pairs that failed.
    pub fn failed_pairs(&self) -> usize {
        self.report
            .pairs
            .iter()
            .filter(|p| matches!(p.status, PairStatus::Failed(_)))
            .count()
    }

    /// Every match of every finished pair, in pair order.
    pub fn matches(&self) -> Vec<&Match> {
        self.report.matches()
    }

    /// Each pair's record as `summary.json` holds it, a failed pair's error rendered with
    /// `names`.
    pub fn pairs_json(&self, names: Names) -> Vec<serde_json::Value> {
        pairs_json(&self.report, &self.scenarios, names)
    }

    /// The line `scenalog mine --log-prompts` prints: logs, pairs listed, written, resumed,
    /// failed, not mined, with matches, prompts without a program.
    pub fn counts_text(&self) -> String {
        let report = &self.report;
        let failed = self.failed_pairs();
        let written = report.pairs.len() - failed;
        format!(
            "{} logs, {} pairs listed: {written} written ({} resumed), {failed} failed, {} not \
             mined (log missing), {} with matches; {} prompts without a program (empty \
             predictions)",
            self.logs,
            self.listed,
            report.resumed(),
            self.listed - report.pairs.len(),
            report.with_matches(),
            self.without_program.len()
        )
    }
}

/// Mines a plan's pairs and publishes the submission; an error means nothing was published (no
/// log to mine, a thread pool, the output folder's lock, a cancelled run).
pub fn run(request: &SplitRequest, plan: SplitPlan) -> Result<SplitOutcome, Error> {
    if plan.logs.is_empty() {
        let causes: Vec<Message> = plan.log_problems.iter().map(Message::text).collect();
        return Err(with_causes("no log to mine", &causes));
    }
    let options = run_options(request, &plan);
    let report = run_mining(&plan.scenarios, &plan.logs, &options)?;
    let mut failures: Vec<Message> = plan.problems.iter().map(Message::text).collect();
    failures.extend(plan.log_problems.iter().map(Message::text));
    failures.extend(report.pairs.iter().filter_map(|p| match &p.status {
        PairStatus::Failed(e) => Some(e.clone()),
        _ => None,
    }));
    let listed = plan.listed_pairs();
    Ok(SplitOutcome {
        outputs: Outputs::of(&plan.out, &options.names, false, None),
        logs: plan.logs.len(),
        listed,
        failures,
        without_program: plan.without_program,
        scenarios: plan.scenarios,
        report,
    })
}

/// Prepares and runs a request ([`prepare`], then [`run`]).
pub fn mine_split(request: &SplitRequest) -> Result<SplitOutcome, Error> {
    run(request, prepare(request)?)
}
