//! `scenalog run` end to end: tuples as facts, JSON, sizes, limits, catalog use, exit codes.

use std::process::Output;

fn scenalog(args: &[&str], stdin: &str) -> Output {
    crate::util::with_stdin(args, stdin)
}

/// The run ended with exit 0 (else its standard error is shown).
fn assert_ran(out: &Output) {
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

const TC: &str = "edge(1, 2). edge(2, 3). edge(3, 4). label(1, \"a b\"). w(1, 2.5). w(2, 3.0).\n\
path(X, Y) :- edge(X, Y).\n\
path(X, Z) :- path(X, Y), edge(Y, Z).\n\
leaf(X) :- edge(_, X), !edge(X, _).\n";

#[test]
fn prints_requested_relations_as_sorted_facts() {
    let out = scenalog(
        &[
            "run", "-", "--print", "path", "--print", "leaf", "--print", "label", "--print", "w",
        ],
        TC,
    );
    assert_ran(&out);
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "path(1, 2).\npath(1, 3).\npath(1, 4).\npath(2, 3).\npath(2, 4).\npath(3, 4).\n\
         leaf(4).\nlabel(1, \"a b\").\nw(1, 2.5).\nw(2, 3.0).\n"
    );
}

#[test]
fn sizes_without_print_and_json() {
    let out = scenalog(&["run", "-"], TC);
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("path: 6"), "{text}");
    assert!(text.contains("leaf: 1"), "{text}");

    let out = scenalog(
        &["run", "-", "--json", "--print", "leaf", "--print", "label"],
        TC,
    );
    assert_eq!(out.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["leaf"], serde_json::json!([[4]]));
    assert_eq!(v["label"], serde_json::json!([[1, "a b"]]));
}

#[test]
fn limits_stop_with_the_relation_named() {
    let out = scenalog(
        &["run", "-", "--max-tuples", "500"],
        "n(0).\nn(Y) :- n(X), Y = X + 1.\n",
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("`n`"), "{err}");
}

#[test]
fn check_errors_catalog_use_and_unreadable_files() {
    let out = scenalog(&["run", "-"], "p(X) :- q(X.\n");
    assert_eq!(out.status.code(), Some(1));
    assert!(!out.stderr.is_empty());

    let out = scenalog(
        &["run", "-"],
        "referred(V, T) :- category(V, \"BUS\"), present(V, T).\n",
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("`category`") && err.contains("log"), "{err}");

    let out = scenalog(&["run", "/nonexistent/x.dl"], "");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("/nonexistent/x.dl"));

    let out = scenalog(&["run", "-", "--print", "nope"], TC);
    assert_eq!(out.status.code(), Some(1));
}

#[test]
fn warnings_come_first_and_the_program_still_runs() {
    let out = scenalog(
        &["run", "-", "--print", "p"],
        "q(1, 2). q(3, 4).\np(X) :- q(X, Y).\n",
    );
    assert_eq!(out.status.code(), Some(0));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("W0501") && err.contains("`Y`"), "{err}");
    assert_eq!(String::from_utf8_lossy(&out.stdout), "p(1).\np(3).\n");
}

#[test]
fn strings_print_sorted_by_text_not_by_first_appearance() {
    let out = scenalog(
        &["run", "-", "--print", "s"],
        "s(\"zeta\", 1). s(\"alpha\", 2). s(\"mid\", 0).\n",
    );
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "s(\"alpha\", 2).\ns(\"mid\", 0).\ns(\"zeta\", 1).\n"
    );
}

#[test]
fn a_timeout_stops_with_the_relation_named() {
    let out = scenalog(
        &["run", "-", "--timeout-ms", "50"],
        "n(0).\nn(Y) :- n(X), Y = X + 1.\n",
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("`n`") && err.contains("longer than"), "{err}");
}

/// A program that derives forever ends with an error naming the limit and the relation whatever
/// limit stops it: the tuple budget here (the time limit in the test above; without flags both
/// have `mine`'s defaults, `run::limits`).
#[test]
fn a_program_deriving_forever_ends_at_the_tuple_budget() {
    let out = scenalog(
        &["run", "-", "--max-tuples", "5000"],
        "n(0).\nn(Y) :- n(X), Y = X + 1.\n",
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("`n`") && err.contains("5000"), "{err}");
    assert!(
        out.stdout.is_empty(),
        "nothing printed from a failed evaluation"
    );
}

#[test]
fn printing_some_relations_computes_only_what_they_need() {
    // Soufflé's inline_nats: `pair` (nat x nat, 10^8 tuples) is read once on its diagonal.
    let program = "nat(0).\nnat(X + 1) :- X < 10000, nat(X).\npair(X, Y) :- nat(X), nat(Y).\n\
                   query(X) :- pair(X, X), X < 2.\n";
    let out = scenalog(
        &["run", "-", "--print", "query", "--max-tuples", "100000"],
        program,
    );
    assert_ran(&out);
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "query(0).\nquery(1).\n"
    );
    // Printing `pair` too (or every size), it is derived in full: past the budget.
    let out = scenalog(
        &[
            "run",
            "-",
            "--print",
            "query",
            "--print",
            "pair",
            "--max-tuples",
            "100000",
        ],
        program,
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("`pair`"), "{err}");
}
