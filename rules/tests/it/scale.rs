//! The check grows linearly with the program: doubling a program of each shape the checker once
//! handled in quadratic time (one huge body, bindings written last first, thousands of unknown
//! predicates, calls nested far past the limit, a long chain of rules) about doubles the time of
//! `check`. The ratio is asserted, not the times: a quadratic step makes it about 4, linear
//! about 2, and the bound of 3 leaves room for a busy machine.

use std::time::{Duration, Instant};

use scenalog_rules::{check, CheckOptions};

#[path = "../../examples/support/chain.rs"]
mod chain;
use chain::{
    bindings_program, chain_program, nested_calls_program, unknown_program, wide_body_program,
};

/// Runs of each size; the fastest counts (the least disturbed by other work on the machine).
const REPS: usize = 5;

/// The fastest of `REPS` checks of `src`, and what the check found (so a test can assert that
/// the program was really checked, not refused early).
fn fastest(src: &str) -> (Duration, usize) {
    let mut best = Duration::MAX;
    let mut diags = 0;
    for _ in 0..REPS {
        let t = Instant::now();
        let out = check(src, &CheckOptions::default());
        best = best.min(t.elapsed());
        diags = out.diagnostics.len();
    }
    (best, diags)
}

/// The ratio of the check's time on a program of `2n` items to that on `n`, sizes alternated.
fn doubling_ratio(make: fn(usize) -> String, n: usize) -> (f64, usize, usize) {
    let (small, big) = (make(n), make(2 * n));
    // Warm up allocator and caches on the small one first.
    check(&small, &CheckOptions::default());
    let (t1, d1) = fastest(&small);
    let (t2, d2) = fastest(&big);
    (t2.as_secs_f64() / t1.as_secs_f64().max(1e-9), d1, d2)
}

/// One measurement at a time: the tests of this file would otherwise time each other.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn assert_linear(name: &str, make: fn(usize) -> String, n: usize) -> (usize, usize) {
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    // A linear check doubles (about 2), a quadratic one quadruples (about 4) every time; a
    // measurement disturbed by other work on the machine is taken again, up to three times.
    let (mut ratio, d1, d2) = doubling_ratio(make, n);
    for _ in 0..2 {
        if ratio < 3.0 {
            break;
        }
        ratio = ratio.min(doubling_ratio(make, n).0);
    }
    assert!(
        ratio < 3.0,
        "{name}: checking {} items took {ratio:.2} times as long as {n} (linear: about 2)",
        2 * n
    );
    (d1, d2)
}

#[test]
fn one_body_of_many_atoms_checks_in_linear_time() {
    let (d1, d2) = assert_linear("body", wide_body_program, 10_000);
    // Every atom binds a variable used once: one singleton warning each, all but the head's;
    // and one E0406, since a rule of that many variables is wider than the engine's tuples.
    assert_eq!((d1, d2), (10_000, 20_000));
}

#[test]
fn bindings_written_last_first_check_in_linear_time() {
    let (d1, d2) = assert_linear("bindings", bindings_program, 4_000);
    // The chain of bindings is safe: its one diagnostic is E0406 (more variables than the
    // engine's tuples hold).
    assert_eq!((d1, d2), (1, 1));
    let e0406 = scenalog_rules::check(&bindings_program(4_000), &CheckOptions::default());
    assert!(
        e0406.diagnostics.iter().all(|d| d.code == "E0406"),
        "{:?}",
        e0406.diagnostics
    );
}

#[test]
fn thousands_of_unknown_predicates_check_in_linear_time() {
    let (d1, d2) = assert_linear("unknown", unknown_program, 2_000);
    // One unknown-predicate error a rule, and the unused helpers' warnings.
    assert!(d1 >= 2_000 && d2 >= 4_000, "{d1} {d2}");
}

#[test]
fn calls_nested_past_the_limit_check_in_linear_time() {
    let (d1, d2) = assert_linear("nested", nested_calls_program, 50_000);
    assert!(d1 >= 1 && d2 >= 1, "too deep is an error");
    let out = check(&nested_calls_program(4_000), &CheckOptions::default());
    assert!(out.diagnostics.iter().any(|d| d.code == "E0002"));
}

#[test]
fn a_long_chain_of_rules_checks_in_linear_time() {
    let (d1, d2) = assert_linear("rules", chain_program, 2_000);
    assert_eq!((d1, d2), (0, 0));
}

#[test]
fn hints_quote_a_huge_clause_in_part() {
    // 2,000 unbound head variables in one clause: each hint quotes the clause cut to its ends.
    // Declared track columns, so each hint names the atom that would bind its variable.
    let head: Vec<String> = (0..2_000).map(|i| format!("V{i}")).collect();
    let cols: Vec<String> = head.iter().map(|v| format!("{v}: track")).collect();
    let src = format!(
        ".decl h({})\nh({}) :- present(X, T).\nreferred(X, T) :- present(X, T), h({}).\n",
        cols.join(", "),
        head.join(", "),
        vec!["X"; 2_000].join(", ")
    );
    let out = check(&src, &CheckOptions::default());
    let unsafe_vars: Vec<_> = out
        .diagnostics
        .iter()
        .filter(|d| d.code == "E0201")
        .collect();
    assert_eq!(unsafe_vars.len(), 2_000);
    let longest = out
        .diagnostics
        .iter()
        .filter_map(|d| d.hint.as_ref())
        .map(String::len)
        .max()
        .unwrap_or(0);
    assert!(longest < 1_000, "a hint of {longest} bytes");
    assert!(unsafe_vars.iter().all(|d| d
        .hint
        .as_ref()
        .is_some_and(|h| h.contains("present(") && h.contains(" … "))));
}

#[test]
fn diagnostics_on_one_long_line_render_a_window_each() {
    // 10,000 singleton warnings on one line of about 190 KB: shown whole under each, the text
    // was 1.9 GB (and `scenalog check` took 46 s and 2.8 GB); each now shows a window of it.
    let src = wide_body_program(10_000);
    let outcome = check(&src, &CheckOptions::default());
    let n = outcome.diagnostics.len();
    assert!(n >= 9_999, "{n}");
    let text = scenalog_rules::render_human(&outcome.diagnostics, &src, "wide.dl", false);
    assert!(
        text.len() < 1_000 * n,
        "{} bytes for {n} diagnostics",
        text.len()
    );
    // The real line and column, the span's own text under the caret, `…` where it is cut.
    let last = outcome
        .diagnostics
        .iter()
        .find(|d| d.message.contains("`X9999`"))
        .expect("X9999's warning");
    let (_, column) = scenalog_rules::render::line_column(&src, last.span.start);
    assert!(
        text.contains(&format!("wide.dl:1:{column}")),
        "no 1:{column}"
    );
    assert!(
        text.contains(", present(X9998, T), present(X9999, T).\n"),
        "no window at the end"
    );
    assert!(text.contains("\n1 │ …"), "no cut marked");
}
