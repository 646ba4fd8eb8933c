//! Every program the checker accepts runs (or stops at a limit: the tuple budget, the timeout,
//! a sum past 64 bits), never refused as a shape the engine cannot evaluate, never a panic: thousands of
//! seeded random programs over Soufflé's shapes the engine once refused or mishandled
//! (expressions in atoms before their variables are bound, aggregates nested, grouped by outer
//! braces, reusing the result's name, with no variable at all, zero-column relations, strings
//! ordered, `mod` and `^`), each evaluated within a small budget, with provenance on for some
//! and every derived tuple proved. A program the checker refuses is skipped; the test asserts
//! that enough of them check for it to mean something (`NO_PANIC_WHY=1` prints why the others
//! were refused, and what stopped at a limit).

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Duration;

use scenalog_engine::{evaluate, EngineError, Options};
use scenalog_facts::relation::{RelationData, Request};
use scenalog_rules::{check, CheckOptions};

use crate::rng::Rng;

const VARS: [&str; 5] = ["A", "B", "C", "D", "E"];

/// An integer argument: a variable, a constant, `_`, or an expression over a variable.
fn int_arg(rng: &mut Rng) -> String {
    let v = *rng.pick(&VARS);
    match rng.below(12) {
        0 => format!("{}", rng.below(4)),
        1 => "_".to_string(),
        2 => format!("{v} + 1"),
        3 => format!("2 * {v}"),
        4 => format!("{v} mod 3"),
        5 => format!("{v} ^ 2"),
        _ => v.to_string(),
    }
}

/// The relations and their arities: inputs `e`, `u`, `z` (no column), then the derived
/// `p0` (no column) to `p3` (three int columns).
const RELATIONS: [(&str, usize); 7] = [
    ("e", 2),
    ("u", 1),
    ("z", 0),
    ("p0", 0),
    ("p1", 1),
    ("p2", 2),
    ("p3", 3),
];

/// An atom over the first `upto` relations, or the string relation `s`.
fn atom(rng: &mut Rng, upto: usize) -> String {
    if rng.below(8) == 0 {
        let x = if rng.below(2) == 0 { "\"b\"" } else { "S" };
        return format!("s({x})");
    }
    let (name, n) = RELATIONS[rng.below(upto)];
    let args: Vec<String> = (0..n).map(|_| int_arg(rng)).collect();
    format!("{name}({})", args.join(", "))
}

/// An aggregate literal over relations below `upto` binding `R` (or a variable named inside),
/// its braces possibly nested, grouped by outer variables or not.
fn aggregate(rng: &mut Rng, upto: usize, depth: usize) -> String {
    let v = *rng.pick(&VARS);
    let func = match rng.below(4) {
        0 => "count".to_string(),
        1 => format!("min {v}"),
        2 => format!("max {v}"),
        _ => format!("sum {v}"),
    };
    let mut inner = vec![atom(rng, upto)];
    if rng.below(2) == 0 {
        inner.push(atom(rng, upto));
    }
    if depth < 2 && rng.below(3) == 0 {
        inner.push(aggregate(rng, upto, depth + 1).replacen("R =", "Q =", 1));
    }
    if rng.below(3) == 0 {
        inner.push(format!("{} < {}", *rng.pick(&VARS), *rng.pick(&VARS)));
    }
    let result = if rng.below(4) == 0 { v } else { "R" };
    format!("{result} = {func} : {{ {} }}", inner.join(", "))
}

/// A body literal of a rule for `RELATIONS[head]`: negations and aggregates read only the
/// relations before it (so the program stratifies), positive atoms any.
fn literal(rng: &mut Rng, head: usize) -> String {
    match rng.below(10) {
        0 => format!("!{}", atom(rng, head)),
        1 => format!(
            "{} {} {}",
            *rng.pick(&VARS),
            *rng.pick(&["<", "<=", "!=", "=", ">="]),
            int_arg(rng)
        ),
        2 => "S < \"c\", s(S)".to_string(),
        3 => aggregate(rng, head, 0),
        _ => atom(rng, RELATIONS.len()),
    }
}

fn rule(rng: &mut Rng) -> String {
    let head = 3 + rng.below(4);
    let n = 1 + rng.below(4);
    let mut body: Vec<String> = (0..n).map(|_| literal(rng, head)).collect();
    // Every variable bound by an input somewhere in the body (in a random place: the engine
    // picks the order), so most programs are safe.
    let at = rng.below(body.len() + 1);
    body.insert(at, "u(A), e(B, C), u(D), e(E, _)".to_string());
    let (name, arity) = RELATIONS[head];
    let pool: Vec<&str> = if body.iter().any(|l| l.starts_with("R =")) {
        vec!["A", "B", "R"]
    } else {
        vec!["A", "B", "C"]
    };
    let args: Vec<String> = (0..arity).map(|_| rng.pick(&pool).to_string()).collect();
    format!("{name}({}) :- {}.\n", args.join(", "), body.join(", "))
}

/// A program of one to four random rules over a few facts.
fn program(rng: &mut Rng) -> String {
    let mut s = String::from(
        ".decl e(x: int, y: int)\n.decl u(x: int)\n.decl z()\n.decl s(x: str)\n\
         .decl p0()\n.decl p1(a: int)\n.decl p2(a: int, b: int)\n.decl p3(a: int, b: int, c: int)\n\
         e(1, 2). e(2, 3). e(3, 1). e(2, 2). u(1). u(2). u(4). z(). s(\"b\"). s(\"a\"). s(\"c\").\n",
    );
    for _ in 0..1 + rng.below(4) {
        s.push_str(&rule(rng));
    }
    s
}

#[test]
fn every_checked_program_runs_or_stops_at_a_limit() {
    let mut rng = Rng(0x0dd_ba11_5eed_0040);
    let (mut checked, mut ran, mut stopped) = (0, 0, 0);
    for case in 0..3000 {
        let text = program(&mut rng);
        let outcome = check(
            &text,
            &CheckOptions {
                require_referred: false,
            },
        );
        let Some(program) = outcome.program else {
            if std::env::var_os("NO_PANIC_WHY").is_some() {
                for d in outcome.diagnostics.iter().filter(|d| d.is_error()) {
                    eprintln!("why {} {}", d.code, d.message);
                }
            }
            continue;
        };
        checked += 1;
        let options = Options {
            max_tuples: 20_000,
            timeout: Some(Duration::from_secs(5)),
            provenance: case % 3 == 0,
            pushdown: true,
            // The widest rows for every fifth program: no panic on that path either.
            wide_rows: case % 5 == 0,
            reads: None,
        };
        let result = catch_unwind(AssertUnwindSafe(|| {
            let mut provider = |r: &Request| -> Result<RelationData, String> {
                Err(format!("no catalog here (asked for {})", r.name))
            };
            let eval = evaluate(&program, &mut provider, &options)?;
            if options.provenance {
                for name in ["p0", "p1", "p2", "p3"] {
                    for t in eval.tuples(name).unwrap_or_default() {
                        assert!(eval.prove(name, t).is_some(), "no proof of {name}{t:?}");
                    }
                }
            }
            Ok::<_, scenalog_engine::EngineError>(())
        }));
        match result {
            Ok(Ok(())) => ran += 1,
            // A budget, a timeout or a shape the engine names: an error, not a crash.
            // A budget, a timeout or a sum past 64 bits: the limits a user sets or meets.
            Ok(Err(
                e @ (EngineError::TooManyTuples { .. }
                | EngineError::Timeout { .. }
                | EngineError::Overflow { .. }),
            )) => {
                if std::env::var_os("NO_PANIC_WHY").is_some() {
                    eprintln!("engine {e}\n{text}");
                }
                stopped += 1
            }
            // The checker accepted it, so the engine must run it.
            Ok(Err(e)) => panic!("case {case}: the engine refused a checked program: {e}\n{text}"),
            Err(_) => panic!("case {case}: the engine panicked on a checked program:\n{text}"),
        }
    }
    eprintln!("{checked} checked programs: {ran} ran, {stopped} stopped at a limit");
    assert!(checked > 500, "only {checked} generated programs check");
    assert!(ran > 400, "only {ran} checked programs ran");
}
