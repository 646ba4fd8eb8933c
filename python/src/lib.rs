//! `scenalog._native`: the Python extension module behind the `scenalog` package.
//!
//! Owns only the crossing into Python: every function here calls the same library functions
//! as the `scenalog` command (`scenalog::cli::*`, `scenalog::pipeline::*` and the crates they
//! use), hands back JSON text, Arrow IPC bytes or pickle bytes that the Python side
//! (`python/scenalog/`) turns into dicts and `pyarrow` tables, and raises `ScenalogError` with
//! the message the command would print after `scenalog <subcommand>: `. The work runs on its
//! own thread with the GIL released ([`interruptible`]), so other Python threads run meanwhile
//! and Ctrl-C interrupts the call.

mod arrow_out;
mod interrupt;

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use clap::Parser;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use interrupt::{interruptible, interruptible_with};
use scenalog::cli::mine::{pair_failures, plan, run_options, Options};
use scenalog::cli::mine_pairs;
use scenalog::pipeline::report::{write_run_report, REPORT_DIR};
use scenalog::pipeline::run::{
    pairs_json, run as run_mining, run_unpublished, PairStatus, RunOptions,
};

pyo3::create_exception!(
    scenalog,
    ScenalogError,
    PyException,
    "An error of Scenalog, with the message the command prints."
);

/// An error message as a `ScenalogError`.
fn err(message: impl std::fmt::Display) -> PyErr {
    ScenalogError::new_err(message.to_string())
}

/// Checks a program given as text (`path` None) or read from `path`; the diagnostics as the
/// JSON array `scenalog check --json` prints for one file.
#[pyfunction]
#[pyo3(signature = (text, path=None, require_referred=true))]
fn check(
    py: Python<'_>,
    text: String,
    path: Option<String>,
    require_referred: bool,
) -> PyResult<String> {
    let work = move || -> Result<String, String> {
        let source = match &path {
            Some(p) => scenalog::input::read_text(std::path::Path::new(p))?,
            None => text,
        };
        let options = scenalog_rules::CheckOptions { require_referred };
        let outcome = scenalog_rules::check(&source, &options);
        Ok(scenalog_rules::diagnostics_json(&outcome.diagnostics, &source).to_string())
    };
    interruptible(py, work)?.map_err(err)
}

/// A log's summary as `scenalog facts LOG --json` prints it (with `load_ms`).
#[pyfunction]
fn facts_summary(py: Python<'_>, log_dir: PathBuf) -> PyResult<String> {
    let work = move || -> Result<String, String> {
        let start = std::time::Instant::now();
        let scene = scenalog_facts::load_scene(&log_dir).map_err(|e| e.to_string())?;
        let mut json = scenalog_facts::SceneSummary::of(&scene).to_json();
        json["load_ms"] = serde_json::json!(start.elapsed().as_secs_f64() * 1e3);
        Ok(json.to_string())
    };
    interruptible(py, work)?.map_err(err)
}

/// One catalog relation extracted from a log, as Arrow IPC stream bytes (see [`arrow_out`]).
#[pyfunction]
fn facts_relation<'py>(
    py: Python<'py>,
    log_dir: PathBuf,
    relation: String,
) -> PyResult<Bound<'py, PyBytes>> {
    let work = move || -> Result<Vec<u8>, String> {
        let Some(spec) = scenalog_facts::catalog::relation(&relation) else {
            return Err(format!(
                "`{relation}` is not a relation of the catalog (see `scenalog catalog`)"
            ));
        };
        let scene = scenalog_facts::load_scene(&log_dir).map_err(|e| e.to_string())?;
        let request = scenalog_facts::relation::Request::all(&relation);
        let data = scenalog_extractors::extract(&scene, &request)
            .map_err(|e| format!("extracting {relation}: {e}"))?;
        arrow_out::relation_ipc(&scene, spec, &data)
    };
    let bytes = interruptible(py, work)?.map_err(err)?;
    Ok(PyBytes::new(py, &bytes))
}

/// `scenalog mine`'s options, parsed from an argument list as the command parses them.
#[derive(Parser)]
#[command(name = "scenalog mine", no_binary_name = true)]
struct MineArgv {
    #[command(flatten)]
    options: Options,
}

/// Runs `scenalog mine` with these arguments (`--rules … --logs … --out …`, or the split's
/// `--log-prompts … --dataset-dir … --out …`), without progress bars or printing; returns
/// JSON: `out`, `pickle` and `table` (the file names written in `out`), `matches`, `pairs`,
/// `failures` and `score` (as `scenalog mine --format json`, plus `pairs`).
#[pyfunction]
fn mine(py: Python<'_>, argv: Vec<String>) -> PyResult<String> {
    let parsed =
        MineArgv::try_parse_from(&argv).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let args = parsed.options;
    if args.descriptions.is_some() || args.synthesize {
        return Err(PyValueError::new_err(
            "synthesis (--descriptions, --synthesize) is the command's: run `scenalog mine` for it, or `scenalog synth --descriptions` and mine its programs",
        ));
    }
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let work = move || -> Result<String, String> {
        if args.log_prompts.is_some() {
            mine_split(&args, flag)
        } else {
            mine_programs(&args, flag)
        }
    };
    interruptible_with(py, Some(cancel), work)?.map_err(err)
}

/// `scenalog mine --rules … --logs …` as [`mine`] reports it.
fn mine_programs(args: &Options, cancel: Arc<AtomicBool>) -> Result<String, String> {
    let plan = plan(args)?;
    if plan.scenarios.is_empty() {
        return Err(with_causes("no program to mine", &plan.failures));
    }
    if plan.logs.is_empty() {
        return Err(with_causes("no log to mine", &plan.log_problems));
    }
    let options = RunOptions {
        cancel: Some(cancel),
        ..run_options(args, &plan, false)
    };
    // As the command: the outputs, the scored pickle and the report are one generation.
    let (report, generation) = run_unpublished(&plan.scenarios, &plan.logs, &options)?;
    let mut failures = plan.failures.clone();
    failures.extend(plan.log_problems.iter().cloned());
    failures.extend(report.log_failures.iter().map(|(_, e)| e.clone()));
    failures.extend(pair_failures(&report));
    let score = match &plan.gt {
        Some((_, g)) => match scenalog::pipeline::summary::score(&report.submission, g)? {
            Some(s) => {
                let path = generation.path(scenalog::pipeline::output::SCORED_PICKLE);
                scenalog_eval::write_pickle(&s.predictions, &path).map_err(|e| e.to_string())?;
                s.report.to_json()
            }
            None => serde_json::Value::Null,
        },
        None => serde_json::Value::Null,
    };
    let page = if args.report {
        write_run_report(
            generation.dir(),
            &plan.out,
            &report,
            &plan.scenarios,
            &plan.logs,
            args.report_max_pictures,
            &scenalog::pipeline::report::scored_prompts(plan.gt.as_ref().map(|(_, g)| g)),
        )
        .map_err(|e| format!("the report: {e}"))?;
        let page = plan.out.join(REPORT_DIR).join("index.html");
        serde_json::Value::String(page.display().to_string())
    } else {
        serde_json::Value::Null
    };
    generation.publish()?;
    Ok(serde_json::json!({
        "report": page,
        "out": plan.out.display().to_string(),
        "pickle": scenalog::pipeline::output::PREDICTIONS_PICKLE,
        "table": scenalog::pipeline::output::PREDICTIONS_TABLE,
        "matches": report.matches(),
        "pairs": pairs_json(&report, &plan.scenarios),
        "failures": failures,
        "score": score,
        "without_program": [],
    })
    .to_string())
}

/// `scenalog mine --log-prompts …` as [`mine`] reports it.
fn mine_split(args: &Options, cancel: Arc<AtomicBool>) -> Result<String, String> {
    let plan = mine_pairs::prepare(args)?;
    if plan.logs.is_empty() {
        return Err(with_causes("no log to mine", &plan.log_problems));
    }
    let options = RunOptions {
        cancel: Some(cancel),
        ..mine_pairs::run_options(args, &plan, false)
    };
    let report = run_mining(&plan.scenarios, &plan.logs, &options)?;
    let mut failures = plan.problems.clone();
    failures.extend(plan.log_problems.iter().cloned());
    failures.extend(report.pairs.iter().filter_map(|p| match &p.status {
        PairStatus::Failed(e) => Some(e.clone()),
        _ => None,
    }));
    Ok(serde_json::json!({
        "out": plan.out.display().to_string(),
        "pickle": scenalog::pipeline::output::SUBMISSION_PICKLE,
        "table": scenalog::pipeline::output::SUBMISSION_TABLE,
        "matches": report.matches(),
        "pairs": pairs_json(&report, &plan.scenarios),
        "failures": failures,
        "score": serde_json::Value::Null,
        "report": serde_json::Value::Null,
        "without_program": plan.without_program,
    })
    .to_string())
}

/// `message`, followed by the problems that caused it, one a line.
fn with_causes(message: &str, causes: &[String]) -> String {
    let mut out = message.to_string();
    for c in causes {
        out.push_str("\n  ");
        out.push_str(c);
    }
    out
}

/// Why `track` is (or is not) referred by the program `rules` on `log` at `at` seconds: the
/// JSON `scenalog explain --json` prints.
#[pyfunction]
#[pyo3(signature = (rules, log, track, at=None, why_not=false))]
fn explain(
    py: Python<'_>,
    rules: PathBuf,
    log: PathBuf,
    track: String,
    at: Option<f64>,
    why_not: bool,
) -> PyResult<String> {
    if let Some(a) = at {
        if !a.is_finite() || a < 0.0 {
            return Err(PyValueError::new_err(format!(
                "at: expected a finite number of seconds >= 0, got {a}"
            )));
        }
    }
    let work = move || -> Result<String, String> {
        let x = scenalog::cli::explain::explain_track(
            &rules,
            &log,
            &track,
            at,
            why_not,
            &scenalog::pipeline::budget::pair_limits(None, None, 1),
        )
        .map_err(|(_, e)| e)?;
        let renderer = scenalog::pipeline::explain::Renderer {
            scene: &x.scene,
            scenario: &x.scenario,
        };
        Ok(scenalog::pipeline::explain::explanation_json(&renderer, &x.explanation).to_string())
    };
    interruptible(py, work)?.map_err(err)
}

/// One side of an evaluation: a file (official pickle or Arrow table), or pickle or Arrow IPC
/// file bytes made by the Python side.
enum Source {
    Path(PathBuf),
    Pickle(Vec<u8>),
    Arrow(Vec<u8>),
}

impl Source {
    fn from_py(kind: &str, value: &Bound<'_, PyAny>) -> PyResult<Source> {
        Ok(match kind {
            "path" => Source::Path(value.extract()?),
            "pickle" => Source::Pickle(value.extract()?),
            "arrow" => Source::Arrow(value.extract()?),
            other => {
                return Err(PyValueError::new_err(format!(
                    "unknown source kind `{other}`"
                )))
            }
        })
    }

    fn read(&self, what: &str) -> Result<scenalog_eval::Submission, String> {
        match self {
            Source::Path(p) => scenalog_eval::read_any(p),
            Source::Pickle(b) => scenalog_eval::read_pickle_bytes(b, what),
            Source::Arrow(b) => scenalog_eval::table_from_bytes(b, what),
        }
        .map_err(|e| e.to_string())
    }
}

/// The official metrics of `pred` against `gt` (each a kind — "path", "pickle", "arrow" — and
/// its value): the JSON `scenalog eval --json` prints. `rate` and `timestamps` (JSON text of
/// `{log_id: [timestamp_ns, ...]}`) are `eval --rate` and `eval --timestamps`.
#[pyfunction]
#[pyo3(signature = (pred_kind, pred, gt_kind, gt, max_range_m=50.0, dataset_dir=None, rate=None, timestamps=None))]
#[allow(clippy::too_many_arguments)]
fn evaluate(
    py: Python<'_>,
    pred_kind: &str,
    pred: &Bound<'_, PyAny>,
    gt_kind: &str,
    gt: &Bound<'_, PyAny>,
    max_range_m: f64,
    dataset_dir: Option<PathBuf>,
    rate: Option<u32>,
    timestamps: Option<String>,
) -> PyResult<String> {
    let sampling = match (rate, timestamps) {
        (Some(_), Some(_)) => {
            return Err(PyValueError::new_err(
                "rate and timestamps: give one or the other",
            ))
        }
        (Some(0), None) => return Err(PyValueError::new_err("rate: expected at least 1 (Hz)")),
        (Some(hz), None) => Some(scenalog_eval::Sampling::Rate(hz)),
        (None, Some(text)) => Some(scenalog_eval::Sampling::Timestamps(
            scenalog_eval::parse_timestamps(&text, "timestamps").map_err(|e| err(e.to_string()))?,
        )),
        (None, None) => None,
    };
    if !(max_range_m.is_finite() && max_range_m > 0.0) {
        return Err(PyValueError::new_err(format!(
            "max_range_m: expected a finite number greater than 0, got {max_range_m}"
        )));
    }
    let pred = Source::from_py(pred_kind, pred)?;
    let gt = Source::from_py(gt_kind, gt)?;
    let work = move || -> Result<String, String> {
        let mut pred = pred.read("predictions")?;
        let mut gt = gt.read("ground truth")?;
        if let Some(s) = &sampling {
            scenalog_eval::resample(&mut pred, &mut gt, s).map_err(|e| e.to_string())?;
        }
        let roi = match &dataset_dir {
            None => None,
            Some(dir) => {
                let ids = gt.sequences.keys().chain(pred.sequences.keys());
                let maps = scenalog_eval::RoiMaps::load(dir, ids.map(|k| k.0.as_str()))
                    .map_err(|e| format!("dataset_dir: {e}"))?;
                Some(std::sync::Arc::new(maps))
            }
        };
        let opts = scenalog_eval::EvalOptions { max_range_m, roi };
        let report = scenalog_eval::evaluate(&pred, &gt, &opts).map_err(|e| e.to_string())?;
        Ok(report.to_json().to_string())
    };
    interruptible(py, work)?.map_err(err)
}

/// One submission pickle from the pickles of disjoint runs (e.g. one a log): byte for byte
/// the pickle a single run over all of them writes. A (log, prompt) key in two parts is an
/// error naming it.
#[pyfunction]
fn join_pickles<'py>(py: Python<'py>, parts: Vec<Vec<u8>>) -> PyResult<Bound<'py, PyBytes>> {
    let work = move || -> Result<Vec<u8>, String> {
        let mut all = scenalog_eval::Submission::default();
        for (i, part) in parts.iter().enumerate() {
            let sub = scenalog_eval::read_pickle_bytes(part, &format!("part {i}"))
                .map_err(|e| e.to_string())?;
            for (key, frames) in sub.sequences {
                if all.sequences.contains_key(&key) {
                    return Err(format!(
                        "the sequence ({}, {:?}) is in two parts",
                        key.0, key.1
                    ));
                }
                all.sequences.insert(key, frames);
            }
        }
        Ok(scenalog_eval::pickle_bytes(&all))
    };
    let bytes = interruptible(py, work)?.map_err(err)?;
    Ok(PyBytes::new(py, &bytes))
}

/// Logs found: `(directory, log id)` pairs, and the duplicates left out.
type FoundLogs = (Vec<(String, String)>, Vec<String>);

/// The `.dl` files `rules` names, as `scenalog mine --rules` finds them (files as given,
/// directories' `.dl` files sorted by name).
#[pyfunction]
fn rule_files(rules: Vec<PathBuf>) -> PyResult<Vec<String>> {
    scenalog::cli::mine::rule_files(&rules)
        .map(|v| v.iter().map(|p| p.display().to_string()).collect())
        .map_err(err)
}

/// The logs `logs` names, as `scenalog mine --logs` finds them (a log directory, or a directory
/// of logs): `(directory, log id)` pairs, and the duplicates left out.
#[pyfunction]
fn log_dirs(logs: Vec<PathBuf>) -> PyResult<FoundLogs> {
    let (found, problems) = scenalog::cli::mine::log_dirs(&logs).map_err(err)?;
    Ok((
        found
            .into_iter()
            .map(|l| (l.dir.display().to_string(), l.log_id))
            .collect(),
        problems,
    ))
}

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ScenalogError", m.py().get_type::<ScenalogError>())?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(facts_summary, m)?)?;
    m.add_function(wrap_pyfunction!(facts_relation, m)?)?;
    m.add_function(wrap_pyfunction!(mine, m)?)?;
    m.add_function(wrap_pyfunction!(explain, m)?)?;
    m.add_function(wrap_pyfunction!(evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(join_pickles, m)?)?;
    m.add_function(wrap_pyfunction!(rule_files, m)?)?;
    m.add_function(wrap_pyfunction!(log_dirs, m)?)?;
    Ok(())
}
