//! A scenario program read from a file and checked, and its evaluation on one log's scene with
//! the extractors as the engine's provider. Shared by `mine` and `explain`.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use scenalog_engine::{evaluate, EngineError, Evaluation, Options};
use scenalog_extractors::cache::Extractor;
use scenalog_extractors::{Budget, ExtractError};
use scenalog_facts::relation::{RelationData, Request, Value};
use scenalog_facts::scene::{Frame, TrackId};
use scenalog_rules::{check, render_human, CheckOptions, CheckedProgram};

use crate::message::{Field, Message};

/// A checked scenario program and where it came from.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// The file it was read from.
    pub path: PathBuf,
    /// The file's stem (`stopped_car` for `stopped_car.dl`), used in tables.
    pub name: String,
    /// The program's `// description:` comment, or its name with `_` as spaces when it has none:
    /// the prompt its predictions are keyed by.
    pub description: String,
    /// The source text.
    pub source: String,
    /// The checked program.
    pub program: CheckedProgram,
    /// How long checking the program took: part of each of its pairs' time limit (see
    /// [`limits_after_check`]).
    pub check_time: Duration,
    /// The clean candidates of the synthesis search this program was kept from, itself among
    /// them (`synth --candidates K`): a referred box's score is multiplied by the fraction of
    /// them that refer to it too. Empty (every program not from a search): scores as they are.
    pub candidates: Vec<CheckedProgram>,
}

/// Reads and checks a scenario program. The error is printable as is: it names the file and,
/// when the program does not check, carries the rendered diagnostics.
pub fn load_scenario(path: &Path) -> Result<Scenario, String> {
    let source = crate::input::read_text(path)?;
    scenario_from_source(path, source)
}

/// Checks a scenario program given as text (`path` names it in messages and tables).
pub fn scenario_from_source(path: &Path, source: String) -> Result<Scenario, String> {
    let started = Instant::now();
    let outcome = check(&source, &CheckOptions::default());
    let check_time = started.elapsed();
    let display = path.display().to_string();
    let Some(program) = outcome.program else {
        return Err(format!(
            "`{display}` does not check:\n{}",
            render_human(&outcome.diagnostics, &source, &display, false)
        ));
    };
    let name = program_name(path);
    let description = program
        .program
        .description
        .clone()
        .filter(|d| !d.is_empty())
        .unwrap_or_else(|| name.replace('_', " "));
    Ok(Scenario {
        candidates: Vec::new(),
        path: path.to_path_buf(),
        name,
        description,
        source,
        program,
        check_time,
    })
}

/// A program's name: its file's stem, which names its files under `OUT/` (`pairs/<log>/<name>.json`,
/// `programs/<name>.dl`), so never a path: a stem that is empty, `.`/`..`-like or holds a
/// separator or NUL (a path such as `x/..` has no stem) is `program`.
pub fn program_name(path: &Path) -> String {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let plain =
        !stem.is_empty() && !stem.chars().all(|c| c == '.') && !stem.contains(['/', '\\', '\0']);
    if plain {
        stem
    } else {
        "program".to_string()
    }
}

/// The engine's limits for one pair of `scenario` once its check is counted: the pair's time
/// limit less the time the check took, so checking and evaluating a program on a log together
/// stay within the pair's time limit. An error when the check alone took the whole limit.
pub fn limits_after_check(options: &Options, scenario: &Scenario) -> Result<Options, String> {
    let Some(limit) = options.timeout else {
        return Ok(options.clone());
    };
    match limit.checked_sub(scenario.check_time) {
        Some(left) if !left.is_zero() => Ok(Options {
            timeout: Some(left),
            ..options.clone()
        }),
        _ => Err(format!(
            "checking program `{}` took {:.1} s, the whole time limit of a pair ({:.1} s)",
            scenario.name,
            scenario.check_time.as_secs_f64(),
            limit.as_secs_f64()
        )),
    }
}

/// Why a program could not be evaluated on a log: the engine's error, and whether it came from
/// an extracted relation past the tuple budget (the message then says to raise it).
#[derive(Debug, Clone, PartialEq)]
pub struct EvaluationError {
    /// The engine's error.
    pub engine: EngineError,
    /// A relation the extractor computed would have passed the tuple budget.
    pub over_budget: bool,
}

impl EvaluationError {
    /// The error after `context` ("program `p` failed on log L: "): the engine's message, and
    /// for an extraction past the tuple budget, "or raise" and the budget's field.
    pub fn message(&self, context: &str) -> Message {
        let message = Message::text(format!("{context}{}", self.engine));
        if self.over_budget {
            message.then(" or raise ").mention(Field::MaxTuples)
        } else {
            message
        }
    }
}

impl std::fmt::Display for EvaluationError {
    /// The engine's message (without what to raise: see [`EvaluationError::message`]).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.engine)
    }
}

/// Evaluates a checked program on one scene, asking the extractor (and its per-scene cache) for
/// exactly the catalog relations the program uses, with the constraints the program implies.
/// The evaluation's answer is `referred` and `related`: unless `options` name the relations read
/// ([`Options::reads`]) or ask for provenance, the other derived relations hold only what those
/// two need (the engine's demand: `stopped` only for the regular vehicles of `stopped_car`).
pub fn evaluate_on(
    extractor: &Extractor<'_>,
    program: &CheckedProgram,
    options: &Options,
) -> Result<Evaluation, EvaluationError> {
    let options = Options {
        reads: Some(
            options
                .reads
                .clone()
                .unwrap_or_else(|| ANSWER.iter().map(|r| r.to_string()).collect()),
        ),
        ..options.clone()
    };
    evaluate_with(extractor, program, &options, false)
}

/// The relations a scenario's evaluation is read for.
const ANSWER: [&str; 2] = ["referred", "related"];

/// As [`evaluate_on`], but every catalog relation is asked whole, without the constants,
/// categories and bounds the program fixes (so a report can show the values that failed them).
/// Derived relations are the same: the engine filters again.
pub fn evaluate_on_whole(
    extractor: &Extractor<'_>,
    program: &CheckedProgram,
    options: &Options,
) -> Result<Evaluation, EvaluationError> {
    evaluate_with(extractor, program, options, true)
}

/// The extractor computes each relation under the evaluation's budget (its tuple budget and the
/// time left of its timeout), so a dense log fails the pair naming the relation instead of
/// filling memory, and a slow extraction stops at the deadline.
fn evaluate_with(
    extractor: &Extractor<'_>,
    program: &CheckedProgram,
    options: &Options,
    whole: bool,
) -> Result<Evaluation, EvaluationError> {
    let budget = Budget::new(options.max_tuples, Instant::now(), options.timeout);
    let mut over_budget = false;
    let mut provider = |r: &Request| -> Result<RelationData, String> {
        let extracted = if whole {
            extractor.extract_within(&Request::all(&r.name), &budget)
        } else {
            extractor.extract_within(r, &budget)
        };
        extracted.map(|d| (*d).clone()).map_err(|e| {
            over_budget |= matches!(e, ExtractError::TooManyTuples { .. });
            e.to_string()
        })
    };
    evaluate(program, &mut provider, options).map_err(|engine| EvaluationError {
        over_budget: over_budget && matches!(engine, EngineError::Provider { .. }),
        engine,
    })
}

/// The (track, frame) pairs an evaluation derived as `referred`, sorted.
pub fn referred_pairs(ev: &Evaluation) -> Vec<(TrackId, Frame)> {
    let mut all: Vec<(TrackId, Frame)> = ev
        .tuples("referred")
        .unwrap_or_default()
        .iter()
        .filter_map(|t| match t.as_slice() {
            [Value::Track(x), Value::Time(f)] => Some((*x, *f)),
            _ => None,
        })
        .collect();
    all.sort_unstable();
    all
}

/// The (referred track, related track, frame) triples an evaluation derived as `related`,
/// sorted.
pub fn related_triples(ev: &Evaluation) -> Vec<(TrackId, TrackId, Frame)> {
    let mut all: Vec<(TrackId, TrackId, Frame)> = ev
        .tuples("related")
        .unwrap_or_default()
        .iter()
        .filter_map(|t| match t.as_slice() {
            [Value::Track(x), Value::Track(o), Value::Time(f)] => Some((*x, *o, *f)),
            _ => None,
        })
        .collect();
    all.sort_unstable();
    all
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_check_counts_against_the_pairs_time_limit() {
        let mut s = scenario_from_source(
            Path::new("p.dl"),
            "referred(X, T) :- present(X, T).\n".to_string(),
        )
        .expect("checks");
        let limit = Options {
            timeout: Some(Duration::from_secs(10)),
            ..Options::default()
        };
        s.check_time = Duration::from_secs(4);
        let left = limits_after_check(&limit, &s).expect("time left");
        assert_eq!(left.timeout, Some(Duration::from_secs(6)));
        assert_eq!(left.max_tuples, limit.max_tuples);
        s.check_time = Duration::from_secs(10);
        let e = limits_after_check(&limit, &s).expect_err("no time left");
        assert!(e.contains("checking program `p` took 10.0 s"), "{e}");
        let unlimited = Options::default();
        assert_eq!(
            limits_after_check(&unlimited, &s).expect("no limit"),
            unlimited
        );
    }

    /// Demand: `stopped_car` on log 3bffdcff, `referred` read only, inlines the prelude's
    /// `stopped` (used once) and so asks the extractor for the speeds of regular vehicles only,
    /// with the same answer as evaluating every relation.
    #[test]
    fn a_scenario_derives_the_preludes_concepts_only_for_what_it_reads() {
        let log = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(crate::api::inputs::SAMPLE_LOGS)
            .join("3bffdcff-c3a7-38b6-a0f2-64196d130958");
        let scene = scenalog_facts::load_scene(&log).expect("a sample log");
        let extractor = Extractor::new(&scene);
        let source = "referred(V, T) :- category(V, \"REGULAR_VEHICLE\"), stopped(V, T).\n";
        let s =
            scenario_from_source(Path::new("stopped_car.dl"), source.to_string()).expect("checks");
        let demand = evaluate_on(&extractor, &s.program, &Options::default()).expect("runs");
        let every = Options {
            reads: Some(s.program.predicates.keys().cloned().collect()),
            ..Options::default()
        };
        let whole = evaluate_on(&extractor, &s.program, &every).expect("runs");
        assert_eq!(referred_pairs(&demand), referred_pairs(&whole));
        assert!(!referred_pairs(&demand).is_empty());
        // `stopped` is never stored, and every speed asked for is a referred one's.
        assert_eq!(demand.size("stopped"), 0);
        assert!(whole.size("stopped") > 0);
        assert_eq!(demand.size("speed"), demand.size("referred"));
        assert!(whole.size("speed") > demand.size("speed"));
        // As many tuples as the program written inline holds (25,044 -> 14,998 on this log).
        let inline =
            "referred(V, T) :- category(V, \"REGULAR_VEHICLE\"), speed(V, T, S), S < 0.5 m/s.\n";
        let i = scenario_from_source(Path::new("inline.dl"), inline.to_string()).expect("checks");
        let written = evaluate_on(&extractor, &i.program, &every).expect("runs");
        let held = |e: &Evaluation| e.sizes().values().sum::<usize>();
        assert_eq!(held(&demand), held(&written));
        assert!(held(&whole) > held(&demand));
    }
}
