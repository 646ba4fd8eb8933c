//! `scenalog mine --log-prompts FILE --dataset-dir SPLIT [--tracks TRACKER.pkl] --out DIR`: a
//! split's (log, prompt) pairs, and only those, mined into one submission.
//!
//! The program for a prompt is the `--programs DIR` file whose `// description:` is the prompt,
//! else the library's, else (with `--synthesize`) one the LLM writes; descriptions match after
//! trimming, lower-casing and collapsing spaces, and the submission is keyed by the prompt
//! exactly as the pairs file spells it. A prompt with no program is listed and gets the empty
//! prediction (every object `OTHER_OBJECT` at the output timestamps), so the submission keeps
//! every listed key. A log missing from the tracker file or the split is an error naming it;
//! the other logs are still mined. Each log is read, and its facts extracted, once for all of
//! its prompts. Writes `DIR/submission.pkl` and `DIR/submission.feather` (see
//! [`crate::pipeline::output`]).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::ExitCode;
use std::sync::Arc;

use crate::cli::mine::{
    bundled, default_out, fail, rule_files, synthesize, Format, Options, LIBRARY,
};
use crate::pipeline::output::{OutputNames, SUBMISSION_PICKLE, SUBMISSION_TABLE};
use crate::pipeline::run::{run as run_mining, LogInput, PairStatus, RunOptions, TrackerInput};
use crate::pipeline::scenario::{load_scenario, scenario_from_source, Scenario};

/// The program given to a prompt that has none: it checks, and refers nothing.
const EMPTY_PROGRAM: &str = "referred(X, T) :- category(X, \"ANY\"), present(X, T), T < 0.\n";

/// Reads `{"<log_id>": ["prompt", …]}`.
fn read_pairs(path: &Path) -> Result<BTreeMap<String, Vec<String>>, String> {
    let text = crate::input::read_text(path).map_err(|e| format!("--log-prompts: {e}"))?;
    let pairs: BTreeMap<String, Vec<String>> = serde_json::from_str(&text).map_err(|e| {
        format!(
            "--log-prompts: `{}`: expected a JSON object mapping log ids to lists of prompts: {e}",
            path.display()
        )
    })?;
    for log in pairs.keys() {
        scenalog_input::check_log_id(log)
            .map_err(|e| format!("--log-prompts: `{}`: {e}", path.display()))?;
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
) -> Result<BTreeMap<String, Scenario>, String> {
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
pub struct PairsPlan {
    /// The pairs file: prompts by log id.
    pub pairs: BTreeMap<String, Vec<String>>,
    /// The output directory (created).
    pub out: std::path::PathBuf,
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
}

/// Reads the pairs, the tracker file and the programs of `mine --log-prompts`, and plans the
/// run; an error is the message `scenalog mine` prints before exiting with 2.
pub fn prepare(args: &Options) -> Result<PairsPlan, String> {
    let Some(pairs_path) = &args.log_prompts else {
        return Err("--log-prompts is required here".to_string());
    };
    if !args.rules.is_empty() || !args.logs.is_empty() || args.descriptions.is_some() {
        return Err("--log-prompts takes its programs from --programs and the library, and its logs from --dataset-dir; leave out --rules, --logs and --descriptions".to_string());
    }
    // Flags of the programs-on-logs run that a split's run has no use for: an error, not a flag
    // silently ignored.
    for (set, flag, instead) in [
        (
            args.gt.is_some(),
            "--gt",
            "score the submission afterwards with `scenalog eval OUT/submission.pkl G`",
        ),
        (
            args.eval_timestamps.is_some(),
            "--eval-timestamps",
            "a split's logs are mined at their own timestamps",
        ),
        (
            args.report,
            "--report",
            "picture matches with `scenalog mine --rules … --logs … --report` or `scenalog explain … --picture`",
        ),
        (
            args.format == Format::Json,
            "--format json",
            "OUT/summary.json holds every pair's record",
        ),
    ] {
        if set {
            return Err(format!("{flag} does not go with --log-prompts: {instead}"));
        }
    }
    let Some(split) = &args.dataset_dir else {
        return Err("--log-prompts needs --dataset-dir SPLIT (the AV2 split with each log's ego poses and map)".to_string());
    };
    if !split.is_dir() {
        return Err(format!(
            "--dataset-dir: `{}` is not a directory",
            split.display()
        ));
    }
    let pairs = read_pairs(pairs_path)?;
    let out = args.out.clone().unwrap_or_else(default_out);
    if let Err(e) = std::fs::create_dir_all(&out) {
        return Err(format!(
            "cannot create output directory `{}`: {e}",
            out.display()
        ));
    }
    let tracker = match &args.tracks {
        None => None,
        Some(p) => {
            let bytes = crate::input::read_data(p).map_err(|e| format!("--tracks: {e}"))?;
            let filter = if args.no_confidence_filter {
                scenalog_tracker::Filter::None
            } else {
                scenalog_tracker::Filter::RefAv
            };
            let fingerprint = sha256_hex(&[&bytes, format!("{filter:?}").as_bytes()]);
            match scenalog_tracker::TrackerPickle::from_bytes(&bytes, &p.display().to_string()) {
                Ok(pickle) => Some(Arc::new(TrackerInput {
                    pickle,
                    filter,
                    fingerprint,
                })),
                Err(e) => return Err(format!("--tracks: {e}")),
            }
        }
    };

    // Programs: --programs, then the library, then synthesis.
    let mut problems: Vec<String> = Vec::new();
    let mut sources: Vec<BTreeMap<String, Scenario>> = Vec::new();
    if let Some(dir) = &args.programs {
        match programs_by_description(dir, &mut problems) {
            Ok(m) => sources.push(m),
            Err(e) => return Err(format!("--programs: {e}")),
        }
    }
    if let Some(lib) = bundled(LIBRARY) {
        match programs_by_description(&lib, &mut problems) {
            Ok(m) => sources.push(m),
            Err(e) => return Err(e),
        }
    }
    let prompts: BTreeSet<&String> = pairs.values().flatten().collect();
    let find = |sources: &[BTreeMap<String, Scenario>], p: &str| {
        sources.iter().find_map(|m| m.get(&normal(p)).cloned())
    };
    if args.synthesize {
        let wanted: Vec<&str> = prompts
            .iter()
            .filter(|p| find(&sources, p).is_none())
            .map(|p| p.as_str())
            .collect();
        if !wanted.is_empty() {
            let file = out.join("prompts-to-synthesize.txt");
            let text: String = wanted.iter().map(|p| format!("{p}\n")).collect();
            crate::pipeline::output::write_atomic(&file, text.as_bytes(), false)?;
            match synthesize(&file, &out, args) {
                Ok((programs, failed)) => {
                    problems.extend(failed);
                    let mut m = BTreeMap::new();
                    for (path, source) in programs {
                        match scenario_from_source(&path, source) {
                            Ok(s) => {
                                m.entry(normal(&s.description)).or_insert(s);
                            }
                            Err(e) => problems.push(e),
                        }
                    }
                    sources.push(m);
                }
                Err(e) => return Err(e),
            }
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
                    Err(e) => return Err(format!("internal: the empty program: {e}")),
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
            ..LogInput::new(dir)
        });
    }
    Ok(PairsPlan {
        pairs,
        out,
        scenarios,
        logs,
        problems,
        log_problems,
        without_program,
    })
}

/// The run's options for a plan: its output directory and names, `--threads`, `--resume`, the
/// engine's limits.
pub fn run_options(args: &Options, plan: &PairsPlan, progress: bool) -> RunOptions {
    RunOptions {
        out: plan.out.clone(),
        resume: args.resume,
        timestamps: BTreeMap::new(),
        threads: args.threads.map(|n| n as usize),
        engine: crate::cli::mine::engine_options(args),
        progress,
        names: OutputNames {
            pickle: SUBMISSION_PICKLE,
            table: SUBMISSION_TABLE,
            write_pickle: true,
        },
        keep_submission: false,
        cancel: None,
    }
}

/// Runs `mine --log-prompts`.
pub fn run(args: &Options) -> ExitCode {
    let plan = match prepare(args) {
        Ok(p) => p,
        Err(e) => return fail(e),
    };
    let options = run_options(args, &plan, true);
    let PairsPlan {
        pairs,
        out,
        scenarios,
        logs,
        problems,
        log_problems,
        without_program,
    } = plan;
    for p in problems.iter().chain(&log_problems) {
        eprintln!("scenalog mine: {p}");
    }
    for p in &without_program {
        eprintln!("scenalog mine: no program for the prompt {p:?}: its predictions are empty");
    }
    if logs.is_empty() {
        eprintln!("scenalog mine: no log to mine");
        return ExitCode::from(if log_problems.is_empty() { 2 } else { 1 });
    }
    let report = match run_mining(&scenarios, &logs, &options) {
        Ok(r) => r,
        Err(e) => return fail(e),
    };
    let failed: Vec<&String> = report
        .pairs
        .iter()
        .filter_map(|p| match &p.status {
            PairStatus::Failed(e) => Some(e),
            _ => None,
        })
        .collect();
    let resumed = report.resumed();
    let with_matches = report.with_matches();
    let listed: usize = pairs
        .values()
        .map(|v| v.iter().collect::<BTreeSet<_>>().len())
        .sum();
    let written = report.pairs.len() - failed.len();
    outln!(
        "{} logs, {listed} pairs listed: {written} written ({resumed} resumed), {} failed, {} \
         not mined (log missing), {with_matches} with matches; {} prompts without a program \
         (empty predictions)",
        logs.len(),
        failed.len(),
        listed - report.pairs.len(),
        without_program.len()
    );
    let all: Vec<&String> = problems.iter().chain(&log_problems).chain(failed).collect();
    if !all.is_empty() {
        outln!("\nfailed ({}):", all.len());
        for f in &all {
            outln!("  {}", f.trim_end().replace('\n', "\n    "));
        }
    }
    if !without_program.is_empty() {
        outln!("\nno program ({}):", without_program.len());
        for p in &without_program {
            outln!("  {p}");
        }
    }
    outln!(
        "\nwrote {} (the submission: official pickle, one sequence per written pair) and {} in {}",
        SUBMISSION_PICKLE,
        SUBMISSION_TABLE,
        out.display()
    );
    if all.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
