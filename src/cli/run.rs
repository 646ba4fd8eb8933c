//! `scenalog run FILE.dl [--print REL]… [--json] [--max-tuples N] [--timeout-ms N]`: evaluate a
//! program on its own ground facts, with no log, within `mine`'s limits by default. Checker diagnostics come first; then each
//! requested relation's tuples, one per line in the program's syntax, sorted (`--json`: one object
//! of relation name -> array of tuples); without `--print`, the size of every derived relation.
//! Exit 0 when it ran, 1 on check or evaluation errors, 2 when the input cannot be read.

use std::io::IsTerminal;
use std::process::ExitCode;

use scenalog_engine::{evaluate, Evaluation, Options};
use scenalog_facts::relation::{RelationData, Request, Value};
use scenalog_rules::{check, diagnostics_json, render_human, CheckOptions, PredKind};

/// Arguments of `scenalog run`.
#[derive(clap::Args)]
pub struct Args {
    /// The rule program; `-` reads it from standard input.
    pub file: String,
    /// Print this relation's tuples (repeatable); default: sizes of all derived relations.
    #[arg(long = "print", value_name = "REL")]
    pub print: Vec<String>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Stop when the program's relations together (its facts and every derived relation) hold
    /// more tuples than this (default: `mine`'s, sized to the machine's memory).
    #[arg(long, value_name = "N")]
    pub max_tuples: Option<u64>,
    /// Stop when evaluation runs longer than this many milliseconds (default: `mine`'s,
    /// 120,000).
    #[arg(long, value_name = "N")]
    pub timeout_ms: Option<u64>,
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

/// The text output: requested relations' tuples as facts, or the sizes of the derived ones.
pub fn render_text(ev: &Evaluation, print: &[String]) -> String {
    let mut out = String::new();
    if print.is_empty() {
        for name in &ev.derived {
            out.push_str(&format!("{name}: {}\n", ev.size(name)));
        }
    }
    for name in print {
        for t in ev.tuples(name).unwrap_or_default() {
            out.push_str(&fact_text(name, t));
            out.push('\n');
        }
    }
    out
}

/// The JSON output: relation -> array of tuples, or relation -> size without `--print`.
pub fn render_json(ev: &Evaluation, print: &[String]) -> serde_json::Value {
    let mut obj = serde_json::Map::new();
    if print.is_empty() {
        for name in &ev.derived {
            obj.insert(name.clone(), ev.size(name).into());
        }
    }
    for name in print {
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

fn read_input(name: &str) -> Result<String, String> {
    crate::input::read_text(std::path::Path::new(name))
}

/// The evaluation's limits: `mine`'s defaults (a tuple budget sized to the machine, a time limit),
/// so a program that derives forever ends with an error naming the limit.
pub fn limits(args: &Args) -> Options {
    crate::pipeline::limits::pair_limits(args.max_tuples, args.timeout_ms, 1)
}

/// Checks and evaluates the program and prints what was asked.
pub fn run(args: Args) -> ExitCode {
    let display = if args.file == "-" {
        "<stdin>"
    } else {
        args.file.as_str()
    };
    let source = match read_input(&args.file) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("scenalog run: {e}");
            return ExitCode::from(2);
        }
    };
    let outcome = check(
        &source,
        &CheckOptions {
            require_referred: false,
        },
    );
    if !outcome.diagnostics.is_empty() {
        if args.json && outcome.program.is_none() {
            outln!(
                "{:#}",
                serde_json::json!({ "diagnostics": diagnostics_json(&outcome.diagnostics, &source) })
            );
        } else {
            let color = std::io::stderr().is_terminal();
            eprint!(
                "{}",
                render_human(&outcome.diagnostics, &source, display, color)
            );
        }
    }
    let Some(program) = outcome.program else {
        return ExitCode::from(1);
    };
    let catalog: Vec<&str> = program
        .predicates
        .values()
        .filter(|p| p.kind == PredKind::Catalog)
        .map(|p| p.name.as_str())
        .collect();
    if !catalog.is_empty() {
        eprintln!(
            "scenalog run: {display} uses catalog relation(s) {}, which come from a log; \
             `scenalog run` evaluates a program on its own facts only (use `scenalog mine` on logs)",
            catalog
                .iter()
                .map(|c| format!("`{c}`"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        return ExitCode::from(1);
    }
    for name in &args.print {
        if !program.predicates.contains_key(name) {
            eprintln!("scenalog run: {display} has no relation `{name}` to print");
            return ExitCode::from(1);
        }
    }
    let options = limits(&args);
    let mut provider = |r: &Request| -> Result<RelationData, String> {
        Err(format!(
            "`{}` comes from a log, and `scenalog run` has none",
            r.name
        ))
    };
    let ev = match evaluate(&program, &mut provider, &options) {
        Ok(ev) => ev,
        Err(e) => {
            eprintln!("scenalog run: {display}: {e}");
            return ExitCode::from(1);
        }
    };
    if args.json {
        outln!("{:#}", render_json(&ev, &args.print));
    } else {
        out!("{}", render_text(&ev, &args.print));
    }
    ExitCode::SUCCESS
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        args: Args,
    }

    /// Without flags, `run` has `mine`'s limits: a program deriving forever stops.
    #[test]
    fn run_has_mines_default_limits() {
        let cli = Cli::parse_from(["run", "p.dl"]);
        let defaults = limits(&cli.args);
        assert_eq!(
            defaults.timeout,
            Some(crate::pipeline::limits::DEFAULT_TIMEOUT)
        );
        assert_eq!(
            defaults.max_tuples,
            crate::pipeline::limits::default_max_tuples(
                crate::pipeline::limits::machine_memory(),
                1
            )
        );
        let cli = Cli::parse_from(["run", "p.dl", "--max-tuples", "7", "--timeout-ms", "9"]);
        let given = limits(&cli.args);
        assert_eq!(given.max_tuples, 7);
        assert_eq!(given.timeout, Some(std::time::Duration::from_millis(9)));
    }
}
