//! Evaluating a program on its own ground facts, with no log (`scenalog run FILE.dl`): the
//! program checked (a `referred` rule not required), refused when it uses catalog relations
//! (those come from a log), evaluated within one pair's [`Limits`] (`mine`'s defaults), and the
//! relations asked for rendered in the program's syntax or as JSON.

use scenalog_engine::{evaluate, Evaluation};
use scenalog_facts::relation::{RelationData, Request, Value};
use scenalog_rules::PredKind;

use crate::api::check::{check, CheckRequest, Checked, ProgramSource};
use crate::api::error::Error;
use crate::api::limits::Limits;

/// A program to evaluate on its own facts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunRequest {
    /// The program.
    pub source: ProgramSource,
    /// How the program is named in messages (its file, `<stdin>`).
    pub display: String,
    /// The relations whose tuples to show (empty: the size of every derived relation).
    pub print: Vec<String>,
    /// The evaluation's limits.
    pub limits: Limits,
}

/// A program checked and, when it checks, evaluated.
pub struct Ran {
    /// The program's text and the checker's diagnostics (shown first, even when it runs).
    pub checked: Checked,
    /// The evaluation, or why there is none: the program does not check (`None`), or it uses
    /// catalog relations, asks to print a relation it lacks or failed to evaluate (`Some(Err)`,
    /// the command's exit 1).
    pub evaluation: Option<Result<Evaluated, Error>>,
}

/// An evaluation and the relations asked for.
pub struct Evaluated {
    evaluation: Evaluation,
    print: Vec<String>,
}

/// Checks and evaluates the request's program. An error only when its file cannot be read (the
/// command's exit 2).
pub fn run(request: &RunRequest) -> Result<Ran, Error> {
    request.limits.check()?;
    let checked = check(&CheckRequest {
        source: request.source.clone(),
        require_referred: false,
    })?;
    let evaluation = checked.outcome.program.as_ref().map(|program| {
        let display = &request.display;
        let catalog: Vec<String> = program
            .predicates
            .values()
            .filter(|p| p.kind == PredKind::Catalog)
            .map(|p| format!("`{}`", p.name))
            .collect();
        if !catalog.is_empty() {
            return Err(Error::plain(format!(
                "{display} uses catalog relation(s) {}, which come from a log; `scenalog run` \
                 evaluates a program on its own facts only (use `scenalog mine` on logs)",
                catalog.join(", ")
            )));
        }
        if let Some(name) = request
            .print
            .iter()
            .find(|n| !program.predicates.contains_key(*n))
        {
            return Err(Error::plain(format!(
                "{display} has no relation `{name}` to print"
            )));
        }
        // Printing some relations reads only those: the others may be inlined or derived only
        // for what those need (the engine's demand), as Soufflé computes for its outputs.
        let options = scenalog_engine::Options {
            reads: (!request.print.is_empty()).then(|| request.print.clone()),
            ..request.limits.engine(1)
        };
        let mut provider = |r: &Request| -> Result<RelationData, String> {
            Err(format!(
                "`{}` comes from a log, and `scenalog run` has none",
                r.name
            ))
        };
        let evaluation = evaluate(program, &mut provider, &options)
            .map_err(|e| Error::plain(format!("{display}: {e}")))?;
        Ok(Evaluated {
            evaluation,
            print: request.print.clone(),
        })
    });
    Ok(Ran {
        checked,
        evaluation,
    })
}

impl Evaluated {
    /// The text `scenalog run` prints: the relations asked for, one ground fact a line in the
    /// program's syntax, sorted; or the size of every derived relation.
    pub fn text(&self) -> String {
        let ev = &self.evaluation;
        let mut out = String::new();
        if self.print.is_empty() {
            for name in &ev.derived {
                out.push_str(&format!("{name}: {}\n", ev.size(name)));
            }
        }
        for name in &self.print {
            for t in ev.tuples(name).unwrap_or_default() {
                out.push_str(&fact_text(name, t));
                out.push('\n');
            }
        }
        out
    }

    /// The JSON `scenalog run --json` prints: relation -> array of tuples, or relation -> size
    /// when nothing was asked for.
    pub fn json(&self) -> serde_json::Value {
        let ev = &self.evaluation;
        let mut obj = serde_json::Map::new();
        if self.print.is_empty() {
            for name in &ev.derived {
                obj.insert(name.clone(), ev.size(name).into());
            }
        }
        for name in &self.print {
            let tuples: Vec<serde_json::Value> = ev
                .tuples(name)
                .unwrap_or_default()
                .iter()
                .map(|t| t.iter().map(value_json).collect())
                .collect();
            obj.insert(name.clone(), tuples.into());
        }
        serde_json::Value::Object(obj)
    }
}

/// A value in the program's syntax: strings quoted, floats with a decimal point.
pub fn value_text(v: &Value) -> String {
    match v {
        Value::Track(t) => t.0.to_string(),
        Value::Time(t) => t.to_string(),
        Value::Lane(l) => l.0.to_string(),
        Value::Str(s) => format!("{:?}", s.as_ref()),
        Value::Float(f) if f.is_finite() && f.fract() == 0.0 => format!("{f:.1}"),
        Value::Float(f) => f.to_string(),
        Value::Int(i) => i.to_string(),
    }
}

fn value_json(v: &Value) -> serde_json::Value {
    match v {
        Value::Track(t) => t.0.into(),
        Value::Time(t) => (*t).into(),
        Value::Lane(l) => l.0.into(),
        Value::Str(s) => s.as_ref().into(),
        Value::Float(f) => (*f).into(),
        Value::Int(i) => (*i).into(),
    }
}

/// One tuple as a ground fact: `rel(a, b).`
pub fn fact_text(relation: &str, tuple: &[Value]) -> String {
    let args: Vec<String> = tuple.iter().map(value_text).collect();
    format!("{relation}({}).", args.join(", "))
}
