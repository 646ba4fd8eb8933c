//! `scenalog._native`: the Python extension module behind the `scenalog` package.
//!
//! Owns only the crossing into Python: every function here builds a request of the library API
//! (`scenalog::api`, which the `scenalog` command calls too) from its keyword arguments, with
//! no argument parsing, and hands back JSON text, Arrow IPC bytes or pickle bytes that the
//! Python side (`python/scenalog/`) turns into dicts and `pyarrow` tables. Errors are the
//! command's messages with keyword arguments named instead of flags (`max_tuples`, not
//! `--max-tuples`): `ValueError` for a value out of range, `ScenalogFileNotFoundError` for a
//! missing file, `ScenalogError` otherwise. The work runs on its own thread with the GIL
//! released ([`interruptible`]), so other Python threads run meanwhile and Ctrl-C interrupts
//! the call.

mod arrow_out;
mod interrupt;

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::GILOnceCell;
use pyo3::types::{PyBytes, PyType};

use interrupt::{interruptible, interruptible_with};
use scenalog::api::check::{CheckRequest, ProgramSource};
use scenalog::api::eval::{EvalRequest, Frames, SubmissionSource};
use scenalog::api::explain::ExplainRequest;
use scenalog::api::mine::{Limits, MineRequest};
use scenalog::api::split::SplitRequest;
use scenalog::api::{Error, ErrorKind, Names};
use scenalog::pipeline::report::REPORT_DIR;
use scenalog::pipeline::run::{pairs_json, PairStatus, RunReport};
use scenalog::pipeline::scenario::Scenario;

pyo3::create_exception!(
    scenalog,
    ScenalogError,
    PyException,
    "An error of Scenalog, with the message the command prints (naming keyword arguments)."
);

/// The package's `ScenalogFileNotFoundError` (a `ScenalogError` and a `FileNotFoundError`),
/// defined in Python and registered here by `scenalog/__init__.py`.
static NOT_FOUND: GILOnceCell<Py<PyType>> = GILOnceCell::new();

/// Registers the class raised for a file that does not exist.
#[pyfunction]
fn _register_not_found(py: Python<'_>, cls: Bound<'_, PyType>) -> PyResult<()> {
    let _ = NOT_FOUND.set(py, cls.unbind());
    Ok(())
}

/// `ENOENT`, "no such file or directory" (2 on every platform Python runs on).
const ENOENT: i32 = 2;

/// An error message as a `ScenalogError`, flags named as keyword arguments.
fn err(message: impl std::fmt::Display) -> PyErr {
    ScenalogError::new_err(Names::Keywords.reword(&message.to_string()))
}

/// An API error as Python's: `ValueError` for a value out of range, the registered
/// `ScenalogFileNotFoundError` (its `filename` set when given) for a missing file,
/// `ScenalogError` otherwise; the message names keyword arguments.
fn api_err(e: Error, filename: Option<&str>) -> PyErr {
    let message = e.keywords();
    match e.kind {
        ErrorKind::Invalid => PyValueError::new_err(message),
        ErrorKind::NotFound => Python::with_gil(|py| {
            let Some(cls) = NOT_FOUND.get(py) else {
                return ScenalogError::new_err(message);
            };
            // OSError's (errno, strerror, filename) form sets `errno` and `filename`.
            let made = match filename {
                Some(f) => cls.bind(py).call1((ENOENT, message.clone(), f)),
                None => cls.bind(py).call1((message.clone(),)),
            };
            match made {
                Ok(instance) => PyErr::from_value(instance),
                Err(e) => e,
            }
        }),
        ErrorKind::Failed => ScenalogError::new_err(message),
    }
}

/// A count a keyword argument gives, refused (naming it) when negative.
fn count(keyword: &str, value: Option<i64>) -> PyResult<Option<u64>> {
    match value {
        Some(v) if v < 0 => Err(PyValueError::new_err(format!(
            "{keyword}: expected a number of at least 0, got {v}"
        ))),
        Some(v) => Ok(Some(v as u64)),
        None => Ok(None),
    }
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
    let filename = path.clone();
    let source = match path {
        Some(p) => ProgramSource::File(PathBuf::from(p)),
        None => ProgramSource::Text(text),
    };
    let request = CheckRequest {
        source,
        require_referred,
    };
    let work =
        move || scenalog::api::check::check(&request).map(|c| c.diagnostics_json().to_string());
    interruptible(py, work)?.map_err(|e| api_err(e, filename.as_deref()))
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

/// Mines `rules` (files or directories of `.dl` files) on `logs` (log directories or
/// directories of logs) into `out`, as `scenalog mine --rules … --logs … --out …`, without
/// progress bars or printing; `report` is the most matches the report pictures (no report
/// when None). Returns JSON: `out`, `pickle` and `table` (the file names written in `out`),
/// `matches`, `pairs`, `failures`, `score`, `report` and `without_program`.
#[pyfunction]
#[pyo3(signature = (rules, logs, out, threads=None, resume=false, gt=None, eval_timestamps=None, max_tuples=None, timeout_ms=None, report=None))]
#[allow(clippy::too_many_arguments)]
fn mine(
    py: Python<'_>,
    rules: Vec<PathBuf>,
    logs: Vec<PathBuf>,
    out: PathBuf,
    threads: Option<i64>,
    resume: bool,
    gt: Option<PathBuf>,
    eval_timestamps: Option<PathBuf>,
    max_tuples: Option<i64>,
    timeout_ms: Option<i64>,
    report: Option<i64>,
) -> PyResult<String> {
    let cancel = Arc::new(AtomicBool::new(false));
    let request = MineRequest {
        rules,
        logs,
        out: Some(out),
        threads: count("threads", threads)?.map(|n| n as usize),
        resume,
        // The official pickle too: MineResult.submission holds its bytes.
        pickle: true,
        gt,
        eval_timestamps,
        limits: Limits {
            max_tuples: count("max_tuples", max_tuples)?,
            timeout_ms: count("timeout_ms", timeout_ms)?,
        },
        report: count("report_max_pictures", report)?.map(|n| n as usize),
        cancel: Some(cancel.clone()),
        ..MineRequest::default()
    };
    let work = move || mine_programs(&request);
    interruptible_with(py, Some(cancel), work)?.map_err(|e| api_err(e, None))
}

/// A run of programs on logs as [`mine`] reports it.
fn mine_programs(request: &MineRequest) -> Result<String, Error> {
    let plan = scenalog::api::mine::plan(request)?;
    if plan.scenarios.is_empty() {
        return Err(with_causes("no program to mine", &plan.failures));
    }
    if plan.logs.is_empty() {
        return Err(with_causes("no log to mine", &plan.log_problems));
    }
    // As the command: the outputs, the scored pickle and the report are one generation.
    let outcome = scenalog::api::mine::run(request, &plan)?;
    if let Some(e) = outcome.score_errors.first() {
        return Err(Error::plain(e));
    }
    let page = match &outcome.report_page {
        Some(Ok(_)) => {
            let page = plan.out.join(REPORT_DIR).join("index.html");
            serde_json::Value::String(page.display().to_string())
        }
        Some(Err(e)) => return Err(Error::plain(format!("the report: {e}"))),
        None => serde_json::Value::Null,
    };
    outcome.published.clone()?;
    let report = &outcome.report;
    let mut failures = plan.failures.clone();
    failures.extend(plan.log_problems.iter().cloned());
    failures.extend(report.log_failures.iter().map(|(_, e)| e.clone()));
    failures.extend(outcome.pair_failures.iter().cloned());
    let score = match &outcome.scored {
        Some(s) => s.report.to_json(),
        None => serde_json::Value::Null,
    };
    Ok(serde_json::json!({
        "report": page,
        "out": plan.out.display().to_string(),
        "pickle": scenalog::pipeline::output::PREDICTIONS_PICKLE,
        "table": scenalog::pipeline::output::PREDICTIONS_TABLE,
        "matches": report.matches(),
        "pairs": pairs(report, &plan.scenarios),
        "failures": reworded(&failures),
        "score": score,
        "without_program": [],
    })
    .to_string())
}

/// Mines a split's pairs (`log_prompts`, a JSON file `{log_id: [prompt, …]}`) of the logs in
/// `dataset_dir` into `out`, as `scenalog mine --log-prompts …`; returns [`mine`]'s JSON.
#[pyfunction]
#[pyo3(signature = (log_prompts, dataset_dir, out, tracks=None, programs=None, confidence_filter=true, threads=None, resume=false, max_tuples=None, timeout_ms=None))]
#[allow(clippy::too_many_arguments)]
fn mine_split(
    py: Python<'_>,
    log_prompts: PathBuf,
    dataset_dir: PathBuf,
    out: PathBuf,
    tracks: Option<PathBuf>,
    programs: Option<PathBuf>,
    confidence_filter: bool,
    threads: Option<i64>,
    resume: bool,
    max_tuples: Option<i64>,
    timeout_ms: Option<i64>,
) -> PyResult<String> {
    let cancel = Arc::new(AtomicBool::new(false));
    let request = SplitRequest {
        out: Some(out),
        tracks,
        programs,
        confidence_filter,
        threads: count("threads", threads)?.map(|n| n as usize),
        resume,
        limits: Limits {
            max_tuples: count("max_tuples", max_tuples)?,
            timeout_ms: count("timeout_ms", timeout_ms)?,
        },
        cancel: Some(cancel.clone()),
        ..SplitRequest::new(log_prompts, dataset_dir)
    };
    let work = move || split_pairs(&request);
    interruptible_with(py, Some(cancel), work)?.map_err(|e| api_err(e, None))
}

/// A split's run as [`mine_split`] reports it.
fn split_pairs(request: &SplitRequest) -> Result<String, Error> {
    let plan = scenalog::api::split::prepare(request)?;
    if plan.logs.is_empty() {
        return Err(with_causes("no log to mine", &plan.log_problems));
    }
    let report = scenalog::api::split::run(request, &plan)?;
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
        "pairs": pairs(&report, &plan.scenarios),
        "failures": reworded(&failures),
        "score": serde_json::Value::Null,
        "report": serde_json::Value::Null,
        "without_program": plan.without_program,
    })
    .to_string())
}

/// Each pair's record as `summary.json` holds it, a failed pair's error naming keyword
/// arguments.
fn pairs(report: &RunReport, scenarios: &[Scenario]) -> Vec<serde_json::Value> {
    let mut pairs = pairs_json(report, scenarios);
    for p in &mut pairs {
        if let Some(error) = p.get_mut("error") {
            if let Some(text) = error.as_str() {
                *error = serde_json::Value::String(Names::Keywords.reword(text));
            }
        }
    }
    pairs
}

/// Messages from below the API with their flags named as keyword arguments.
fn reworded(messages: &[String]) -> Vec<String> {
    messages.iter().map(|m| Names::Keywords.reword(m)).collect()
}

/// `message`, followed by the problems that caused it, one a line.
fn with_causes(message: &str, causes: &[String]) -> Error {
    let mut out = message.to_string();
    for c in causes {
        out.push_str("\n  ");
        out.push_str(c);
    }
    Error::plain(out)
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
    let request = ExplainRequest {
        rules,
        log,
        track,
        at,
        why_not,
        limits: Limits::default(),
    };
    let work = move || -> Result<String, Error> {
        let x = scenalog::api::explain::explain_request(&request).map_err(|e| e.error)?;
        let renderer = scenalog::pipeline::explain::Renderer {
            scene: &x.scene,
            scenario: &x.scenario,
        };
        Ok(scenalog::pipeline::explain::explanation_json(&renderer, &x.explanation).to_string())
    };
    interruptible(py, work)?.map_err(|e| api_err(e, None))
}

/// One side of an evaluation from its kind ("path", "pickle", "arrow") and value.
fn submission_source(kind: &str, value: &Bound<'_, PyAny>) -> PyResult<SubmissionSource> {
    Ok(match kind {
        "path" => SubmissionSource::File(value.extract()?),
        "pickle" => SubmissionSource::Pickle(value.extract()?),
        "arrow" => SubmissionSource::Arrow(value.extract()?),
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown source kind `{other}`"
            )))
        }
    })
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
    let frames = match (rate, timestamps) {
        (Some(_), Some(_)) => {
            return Err(PyValueError::new_err(
                "rate and timestamps: give one or the other",
            ))
        }
        (Some(hz), None) => Frames::Rate(hz),
        (None, Some(text)) => {
            Frames::Timestamps(scenalog_eval::parse_timestamps(&text, "timestamps").map_err(err)?)
        }
        (None, None) => Frames::All,
    };
    let request = EvalRequest {
        max_range_m,
        dataset_dir,
        frames,
        ..EvalRequest::new(
            submission_source(pred_kind, pred)?,
            submission_source(gt_kind, gt)?,
        )
    };
    let work = move || scenalog::api::eval::evaluate(&request).map(|r| r.to_json().to_string());
    interruptible(py, work)?.map_err(|e| api_err(e, None))
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
    scenalog::api::mine::rule_files(&rules)
        .map(|v| v.iter().map(|p| p.display().to_string()).collect())
        .map_err(|e| api_err(e, None))
}

/// The logs `logs` names, as `scenalog mine --logs` finds them (a log directory, or a directory
/// of logs): `(directory, log id)` pairs, and the duplicates left out.
#[pyfunction]
fn log_dirs(logs: Vec<PathBuf>) -> PyResult<FoundLogs> {
    let (found, problems) = scenalog::api::mine::log_dirs(&logs).map_err(|e| api_err(e, None))?;
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
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(_register_not_found, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(facts_summary, m)?)?;
    m.add_function(wrap_pyfunction!(facts_relation, m)?)?;
    m.add_function(wrap_pyfunction!(mine, m)?)?;
    m.add_function(wrap_pyfunction!(mine_split, m)?)?;
    m.add_function(wrap_pyfunction!(explain, m)?)?;
    m.add_function(wrap_pyfunction!(evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(join_pickles, m)?)?;
    m.add_function(wrap_pyfunction!(rule_files, m)?)?;
    m.add_function(wrap_pyfunction!(log_dirs, m)?)?;
    Ok(())
}
