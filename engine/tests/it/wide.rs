//! Programs wider than the engine's common rows (issue 40): rules binding more than
//! `scenalog_engine::value::WIDTH` values and relations with more columns run, with the same
//! answers as narrow programs computing the same thing, up to the checker's limit (E0406 at
//! `WIDEST`).

use scenalog_engine::value::{WIDEST, WIDTH};
use scenalog_engine::{Evaluation, Options};
use scenalog_facts::relation::Value;
use scenalog_rules::{check, CheckOptions};

use crate::features::{ints, run_with};

fn run(src: &str, options: &Options) -> Evaluation {
    match run_with(src, options) {
        Ok(e) => e,
        Err(e) => panic!("evaluation failed: {e}\n{src}"),
    }
}

/// `X1, …, Xn` from `from`.
fn vars(prefix: &str, from: usize, n: usize) -> Vec<String> {
    (from..from + n).map(|i| format!("{prefix}{i}")).collect()
}

#[test]
fn a_fourteen_variable_rule_runs_and_agrees_with_its_narrow_split() {
    // The rule below is wider than the common rows, so it takes the wide path.
    const { assert!(WIDTH < 14) };
    // Two 7-column relations joined on their first column: 13 variables, plus a computed one.
    let mut src = String::new();
    for i in 0..6i64 {
        let a: Vec<String> = (0..7).map(|c| (i * 10 + c).to_string()).collect();
        let b: Vec<String> = (0..7).map(|c| (i * 10 + c + 100).to_string()).collect();
        src += &format!("p({}).\n", a.join(", "));
        src += &format!("q({}, {}).\n", i * 10 + i % 2, b[1..].join(", "));
    }
    let (a, b) = (vars("A", 0, 7), vars("B", 1, 6));
    src += &format!(
        "wide(A0, S) :- p({}), q(A0, {}), S = A6 + B6 + A1 + B1, A3 < B3.\n",
        a.join(", "),
        b.join(", ")
    );
    // The same answer by two narrow rules.
    src += "left(A0, A1, A6) :- p(A0, A1, _, _, _, _, A6).\n";
    src += "right(A0, B1, B6) :- q(A0, B1, _, _, _, _, B6).\n";
    src += "narrow(A0, S) :- left(A0, A1, A6), right(A0, B1, B6), S = A6 + B6 + A1 + B1.\n";
    let e = run(&src, &Options::default());
    let wide = ints(&e, "wide");
    assert_eq!(wide, ints(&e, "narrow"));
    // q's first column is i*10 + i%2: only even i join p's first column i*10.
    let expected: Vec<Vec<i64>> = [0i64, 20, 40]
        .iter()
        .map(|&x| vec![x, (x + 6) + (x + 106) + (x + 1) + (x + 101)])
        .collect();
    assert_eq!(wide, expected);
}

#[test]
fn a_twenty_column_relation_recurses_negates_and_aggregates() {
    let n = 20;
    let cols = vars("C", 0, n);
    let mut src = String::new();
    let start: Vec<String> = (0..n).map(|c| c.to_string()).collect();
    src += &format!("w({}).\n", start.join(", "));
    // Each step adds 1 to the first column and keeps the rest, up to 5.
    src += &format!(
        "w(D, {}) :- w({}), C0 < 5, D = C0 + 1.\n",
        cols[1..].join(", "),
        cols.join(", ")
    );
    src += "odd(1). odd(3). odd(5).\n";
    src += &format!("even(C0) :- w({}), !odd(C0).\n", cols.join(", "));
    src += &format!(
        "total(N, S) :- N = count : {{ w({}) }}, S = sum C0 : {{ w({}) }}.\n",
        cols.join(", "),
        cols.join(", ")
    );
    src += &format!(
        "last(M, L) :- M = max C0 : {{ w({}) }}, w(M, {}), L = C19.\n",
        cols.join(", "),
        cols[1..].join(", ")
    );
    let plain = run(&src, &Options::default());
    let w = ints(&plain, "w");
    assert_eq!(w.len(), 6);
    assert!(w.iter().all(|t| t.len() == n && t[1..] == start_tail(n)));
    assert_eq!(ints(&plain, "even"), vec![vec![0], vec![2], vec![4]]);
    assert_eq!(ints(&plain, "total"), vec![vec![6, 15]]);
    assert_eq!(ints(&plain, "last"), vec![vec![5, 19]]);
    // Proofs through the wide rows: every `w` tuple proved down to the fact.
    let proven = run(
        &src,
        &Options {
            provenance: true,
            ..Options::default()
        },
    );
    assert_eq!(proven, plain);
    for t in proven.tuples("w").unwrap_or_default() {
        let p = proven.prove("w", t).expect("a proof of every w tuple");
        // The fact is a leaf (height 0); each recursive step adds a level.
        assert_eq!(
            p.height(),
            usize::try_from(t_first(t)).unwrap_or(usize::MAX)
        );
    }
}

fn start_tail(n: usize) -> Vec<i64> {
    (1..n as i64).collect()
}

fn t_first(t: &[Value]) -> i64 {
    match t.first() {
        Some(Value::Int(i)) => *i,
        other => panic!("not an int: {other:?}"),
    }
}

#[test]
fn the_widest_rule_runs_and_one_more_is_refused_by_the_checker() {
    let widest = vars("X", 0, WIDEST);
    let values: Vec<String> = (0..WIDEST).map(|c| (c * 3).to_string()).collect();
    let reversed: Vec<String> = widest.iter().rev().cloned().collect();
    let src = format!(
        "r({}).\nrev({}) :- r({}).\n",
        values.join(", "),
        reversed.join(", "),
        widest.join(", ")
    );
    let e = run(&src, &Options::default());
    let expected: Vec<i64> = (0..WIDEST as i64).rev().map(|c| c * 3).collect();
    assert_eq!(ints(&e, "rev"), vec![expected]);
    // One variable more than the widest row: E0406 from the checker, not an engine error.
    let over = vars("X", 0, WIDEST + 1);
    let src = format!(
        "r({}).\ns(X0) :- r({}), r({}, Y).\n",
        values.join(", "),
        over[..WIDEST].join(", "),
        over[1..]
            .join(", ")
            .replacen(&format!(", X{WIDEST}"), "", 1)
    );
    let outcome = check(
        &src,
        &CheckOptions {
            require_referred: false,
        },
    );
    assert!(
        outcome.diagnostics.iter().any(|d| d.code == "E0406"),
        "{:?}",
        outcome.diagnostics
    );
}
