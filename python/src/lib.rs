//! `scenalog._native`: the Python extension module behind the `scenalog` package.
//!
//! Owns only the crossing into Python: every function here builds a request of the library API
//! (`scenalog::api`, which the `scenalog` command calls too, and nothing else of the workspace:
//! `tests/tidy.rs` reads this file) from its keyword arguments, with no argument parsing, and
//! hands back JSON text, Arrow IPC bytes or pickle bytes that the Python side
//! (`python/scenalog/`) turns into dicts and `pyarrow` tables. Errors are the API's messages
//! rendered with keyword arguments where the command names its flags (`max_tuples`, not
//! `--max-tuples`, [`Names::Keywords`]): `ValueError` for a value out of range,
//! `ScenalogFileNotFoundError` for a missing file, `ScenalogError` otherwise. The work runs on
//! its own thread with the GIL released ([`interruptible`]), so other Python threads run
//! meanwhile and Ctrl-C interrupts the call.

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
use scenalog::api::facts::{Facts, FactsRequest};
use scenalog::api::mine::MineRequest;
use scenalog::api::split::SplitRequest;
use scenalog::api::synth::{OneRequest, SynthSettings};
use scenalog::api::{Error, ErrorKind, Limits, Message, Names};

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

/// Messages with their fields named as keyword arguments.
fn keywords(messages: &[Message]) -> Vec<String> {
    messages.iter().map(Message::keywords).collect()
}

/// The limits `max_tuples` and `timeout_ms` give (each refused, naming it, when negative).
fn limits(max_tuples: Option<i64>, timeout_ms: Option<i64>) -> PyResult<Limits> {
    Ok(Limits {
        max_tuples: count("max_tuples", max_tuples)?,
        timeout_ms: count("timeout_ms", timeout_ms)?,
    })
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
    let request = FactsRequest {
        log: log_dir,
        ..FactsRequest::default()
    };
    let work = move || match scenalog::api::facts::facts(&request)? {
        Facts::Summary(summary) => Ok(summary.json().to_string()),
        Facts::Relation(_) => Err(Error::plain("internal: a relation for a summary")),
    };
    interruptible(py, work)?.map_err(|e| api_err(e, None))
}

/// One catalog relation extracted from a log within `max_tuples` and `timeout_ms` (one pair's
/// limits of `mine` by default), as Arrow IPC stream bytes (the catalog's columns).
#[pyfunction]
#[pyo3(signature = (log_dir, relation, max_tuples=None, timeout_ms=None))]
fn facts_relation<'py>(
    py: Python<'py>,
    log_dir: PathBuf,
    relation: String,
    max_tuples: Option<i64>,
    timeout_ms: Option<i64>,
) -> PyResult<Bound<'py, PyBytes>> {
    let request = FactsRequest {
        log: log_dir,
        relation: Some(relation),
        limits: limits(max_tuples, timeout_ms)?,
    };
    let work = move || match scenalog::api::facts::facts(&request)? {
        Facts::Relation(relation) => relation.arrow_ipc(),
        Facts::Summary(_) => Err(Error::plain("internal: a summary for a relation")),
    };
    let bytes = interruptible(py, work)?.map_err(|e| api_err(e, None))?;
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
        limits: limits(max_tuples, timeout_ms)?,
        report: count("report_max_pictures", report)?.map(|n| n as usize),
        cancel: Some(cancel.clone()),
        ..MineRequest::default()
    };
    let work = move || mine_programs(&request);
    interruptible_with(py, Some(cancel), work)?.map_err(|e| api_err(e, None))
}

/// A run of programs on logs as [`mine`] reports it.
fn mine_programs(request: &MineRequest) -> Result<String, Error> {
    // As the command: the outputs, the scored pickle and the report are one generation.
    let outcome = scenalog::api::mine::mine(request)?;
    if let Some(e) = outcome.score_errors.first() {
        return Err(Error::plain(e));
    }
    if let Some(Err(e)) = &outcome.report_page {
        return Err(Error::plain(format!("the report: {e}")));
    }
    outcome.published.clone()?;
    let outputs = &outcome.outputs;
    let pickle = outputs.pickle.as_ref().map(|p| p.name);
    Ok(serde_json::json!({
        "report": outputs.report.as_ref().map(|p| p.display().to_string()),
        "out": outputs.dir.display().to_string(),
        "pickle": pickle,
        "table": outputs.table.name,
        "matches": outcome.matches(),
        "pairs": outcome.pairs_json(Names::Keywords),
        "failures": keywords(&outcome.failures),
        "score": outcome.scored.as_ref().map(|s| s.report.to_json()),
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
        limits: limits(max_tuples, timeout_ms)?,
        cancel: Some(cancel.clone()),
        ..SplitRequest::new(log_prompts, dataset_dir)
    };
    let work = move || split_pairs(&request);
    interruptible_with(py, Some(cancel), work)?.map_err(|e| api_err(e, None))
}

/// A split's run as [`mine_split`] reports it.
fn split_pairs(request: &SplitRequest) -> Result<String, Error> {
    let outcome = scenalog::api::split::mine_split(request)?;
    let outputs = &outcome.outputs;
    Ok(serde_json::json!({
        "out": outputs.dir.display().to_string(),
        "pickle": outputs.pickle.as_ref().map(|p| p.name),
        "table": outputs.table.name,
        "matches": outcome.matches(),
        "pairs": outcome.pairs_json(Names::Keywords),
        "failures": keywords(&outcome.failures),
        "score": serde_json::Value::Null,
        "report": serde_json::Value::Null,
        "without_program": outcome.without_program,
    })
    .to_string())
}

/// Why `track` is (or is not) referred by the program `rules` on `log` at `at` seconds, the
/// program evaluated within `max_tuples` and `timeout_ms` (one pair's limits of `mine` by
/// default): the JSON `scenalog explain --json` prints.
#[pyfunction]
#[pyo3(signature = (rules, log, track, at=None, why_not=false, max_tuples=None, timeout_ms=None))]
#[allow(clippy::too_many_arguments)]
fn explain(
    py: Python<'_>,
    rules: PathBuf,
    log: PathBuf,
    track: String,
    at: Option<f64>,
    why_not: bool,
    max_tuples: Option<i64>,
    timeout_ms: Option<i64>,
) -> PyResult<String> {
    let request = ExplainRequest {
        rules,
        log,
        track,
        at,
        why_not,
        limits: limits(max_tuples, timeout_ms)?,
    };
    let work = move || -> Result<String, Error> {
        let explained = scenalog::api::explain::explain(&request).map_err(|e| e.error)?;
        Ok(explained.json().to_string())
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
        (None, Some(text)) => Frames::Timestamps(
            scenalog::api::eval::timestamps_from_json(&text).map_err(|e| api_err(e, None))?,
        ),
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
/// the pickle a single run over all of them writes (the `eval` crate's joiner, which `mine`'s
/// runs use too). A (log, prompt) key in two parts is an error naming it.
#[pyfunction]
fn join_pickles<'py>(py: Python<'py>, parts: Vec<Vec<u8>>) -> PyResult<Bound<'py, PyBytes>> {
    let work = move || {
        let parts: Vec<&[u8]> = parts.iter().map(Vec::as_slice).collect();
        scenalog::api::join_pickles(&parts).map_err(Error::plain)
    };
    let bytes = interruptible(py, work)?.map_err(|e| api_err(e, None))?;
    Ok(PyBytes::new(py, &bytes))
}

/// Logs found: `(directory, log id)` pairs, and the duplicates left out.
type FoundLogs = (Vec<(String, String)>, Vec<String>);

/// The `.dl` files `rules` names, as `scenalog mine --rules` finds them (files as given,
/// directories' `.dl` files sorted by name).
#[pyfunction]
fn rule_files(rules: Vec<PathBuf>) -> PyResult<Vec<String>> {
    scenalog::api::inputs::rule_files(&rules)
        .map(|v| v.iter().map(|p| p.display().to_string()).collect())
        .map_err(|e| api_err(e, None))
}

/// The logs `logs` names, as `scenalog mine --logs` finds them (a log directory, or a directory
/// of logs): `(directory, log id)` pairs, and the duplicates left out.
#[pyfunction]
fn log_dirs(logs: Vec<PathBuf>) -> PyResult<FoundLogs> {
    let (found, problems) = scenalog::api::inputs::log_dirs(&logs).map_err(|e| api_err(e, None))?;
    Ok((
        found
            .into_iter()
            .map(|l| (l.dir.display().to_string(), l.log_id))
            .collect(),
        problems,
    ))
}

/// Synthesizes a program for `description` with the LLM server (as `scenalog synth`), with
/// `candidates` candidates run on `logs` (none: the sample logs) and `evidence_rounds`; returns
/// the transcript as JSON (`rounds`, `outcome`, and with candidates `search` and `evidence`)
/// with the kept `program` and whether it is `clean`. An unreachable server, or a budget spent
/// before any answer, is a `ScenalogError`.
#[pyfunction]
#[pyo3(signature = (description, candidates=1, logs=Vec::new(), evidence_rounds=None, grammar=None, rounds=3, base_url=None, model=None, api_key=None, temperature=Some(0.0), timeout_s=300, retries=4, examples=Some(8), held_out=false, max_tokens=None, cache_dir=None))]
#[allow(clippy::too_many_arguments)]
fn synthesize(
    py: Python<'_>,
    description: String,
    candidates: i64,
    logs: Vec<PathBuf>,
    evidence_rounds: Option<i64>,
    grammar: Option<String>,
    rounds: i64,
    base_url: Option<String>,
    model: Option<String>,
    api_key: Option<String>,
    temperature: Option<f64>,
    timeout_s: i64,
    retries: i64,
    examples: Option<i64>,
    held_out: bool,
    max_tokens: Option<i64>,
    cache_dir: Option<PathBuf>,
) -> PyResult<String> {
    let whole = |name: &str, v: i64| -> PyResult<usize> {
        usize::try_from(v)
            .map_err(|_| PyValueError::new_err(format!("{name}: expected 0 or more, got {v}")))
    };
    let grammar = grammar
        .map(|g| scenalog::api::synth::grammar_field(&g))
        .transpose()
        .map_err(|e| api_err(e, None))?;
    let settings = SynthSettings {
        cache_dir,
        rounds: whole("rounds", rounds)?.max(1),
        base_url,
        model,
        api_key,
        temperature,
        timeout: std::time::Duration::from_secs(whole("timeout_s", timeout_s)? as u64),
        retries: whole("retries", retries)? as u32,
        examples: examples.map(|e| whole("examples", e)).transpose()?,
        library: None,
        held_out,
        candidates: whole("candidates", candidates)?,
        match_logs: logs,
        match_limits: Limits::default(),
        max_tokens: count("max_tokens", max_tokens)?,
        evidence_rounds: evidence_rounds
            .map(|n| whole("evidence_rounds", n))
            .transpose()?,
        grammar,
    };
    let work = move || -> Result<String, Error> {
        let configured = scenalog::api::synth::config(&settings, None)?;
        let synth = scenalog::api::synth::synthesizer(configured.config)?;
        let done = scenalog::api::synth::synthesize_one(
            &synth,
            &OneRequest {
                description,
                output: None,
                transcript: None,
            },
        )?;
        let t = &done.transcript;
        if let scenalog::api::synth::Outcome::Unreachable { error }
        | scenalog::api::synth::Outcome::OverBudget { error } = &t.outcome
        {
            return Err(Error::plain(error.clone()));
        }
        let mut json: serde_json::Value = serde_json::from_str(&t.to_json()).unwrap_or_default();
        json["program"] = serde_json::json!(t.program());
        json["clean"] = serde_json::json!(t.is_clean());
        json["usage"] = serde_json::json!(t.usage());
        Ok(json.to_string())
    };
    interruptible(py, work)?.map_err(|e| api_err(e, None))
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
    m.add_function(wrap_pyfunction!(synthesize, m)?)?;
    Ok(())
}
