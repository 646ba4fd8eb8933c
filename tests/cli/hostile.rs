//! Hostile programs through the built binary, each in a subprocess so that an abort (a stack
//! overflow, an allocation failure) fails the test instead of killing the harness: expressions
//! and nestings far past the limits are diagnostics (E0002) in `check`, `run` and `mine`;
//! programs at the limits run through `mine`'s worker threads; a runaway pair stops at
//! `mine --timeout-ms` and one past the tuple budget (extracted relations included) fails
//! naming the relation, while the other pairs of the run finish. Issue #18, items 1, 3 and 4.

use std::path::{Path, PathBuf};

const LOG: &str = "3b3570b4-7b0b-3268-a571-b0889dbf40b6";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn log_dir() -> PathBuf {
    scenalog_testkit::sample_logs_dir().join(LOG)
}

/// Runs the binary with `args` and `stdin`; the exit code must be a code, not a signal.
fn scenalog(args: &[&str], stdin: &str) -> (i32, String, String) {
    let o = crate::util::with_stdin(args, stdin);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    let Some(code) = o.status.code() else {
        panic!(
            "scenalog {args:?} died of a signal ({:?}); stderr: {}",
            o.status,
            err.chars().take(2000).collect::<String>()
        );
    };
    (code, String::from_utf8_lossy(&o.stdout).into_owned(), err)
}

/// The run's table has a row for `program` and none of its pairs failed.
fn assert_mined(stdout: &str, program: &str) {
    let row = stdout
        .lines()
        .find(|l| l.starts_with(&format!("{program} ")))
        .unwrap_or_default();
    assert!(!row.contains("ERR") && !row.is_empty(), "{stdout}");
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write program");
    p.to_string_lossy().into_owned()
}

/// 100,000-term chains, 100,000 parentheses and 100,000 signs.
fn too_deep() -> Vec<(&'static str, String)> {
    let n = 100_000;
    vec![
        ("plus chain", vec!["T"; n].join(" + ")),
        ("times chain", vec!["T"; n].join(" * ")),
        (
            "parentheses",
            format!("{}T{}", "(".repeat(n), ")".repeat(n)),
        ),
        ("signs", format!("{}T", "- ".repeat(n))),
        ("signed chain", format!("-({})", vec!["T"; n].join(" - "))),
    ]
}

#[test]
fn deep_expressions_are_a_diagnostic_in_check_run_and_mine() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    let out = out.to_string_lossy();
    let log = log_dir();
    let log = log.to_string_lossy();
    for (what, e) in too_deep() {
        let mined = format!("referred(A, T) :- present(A, T), X = {e}, X > 0.\n");
        let file = write(dir.path(), "deep.dl", &mined);
        let (code, stdout, stderr) = scenalog(&["check", "--json", &file], "");
        assert_eq!(code, 1, "{what}: {stderr}");
        assert!(stdout.contains("\"E0002\""), "{what}: {stdout:.300}");

        let own = format!(".decl n(X: int)\nn(1).\nm(X) :- n(T), X = {e}.\n");
        let (code, _, stderr) = scenalog(&["run", "-"], &own);
        assert_ne!(code, 0, "{what}");
        assert!(stderr.contains("E0002"), "{what}: {stderr:.300}");

        let (code, _, stderr) = scenalog(
            &["mine", "--rules", &file, "--logs", &log, "--out", &out],
            "",
        );
        assert_eq!(code, 1, "{what}: {stderr:.300}");
        assert!(stderr.contains("E0002"), "{what}: {stderr:.300}");
    }
}

/// Programs at the limits (128 operators deep, 63 levels of parentheses)
/// check clean and run through `mine`'s worker threads; aggregates nested 60 deep are rejected by
/// the checker (E0406: more variables than the engine holds), not an abort.
#[test]
fn programs_at_the_limits_run_through_mine() {
    let dir = tempfile::tempdir().expect("tempdir");
    // A time plus durations: instants themselves do not add (E0105).
    let chain = format!("T{}", " + 1 s".repeat(128));
    // 126 operators, under a sign (127) and `abs` (128); times cannot be negative, ints can.
    let product = format!("{} * T", vec!["1"; 126].join(" * "));
    let parens = format!("{}T{}", "(".repeat(63), ")".repeat(63));
    let nest = |levels: usize| {
        let mut nested = String::from("present(A, T)");
        for i in 0..levels {
            nested = format!("N{i} = count : {{ {nested} }}");
        }
        nested
    };
    let program = format!(
        "referred(A, T) :- present(A, T), X = {chain}, X > 0, Y = abs(-({product})), Y != X, \
         Z = {parens}, Z = T.\n"
    );
    let file = write(dir.path(), "at_limits.dl", &program);
    let (code, stdout, stderr) = scenalog(&["check", &file], "");
    assert_eq!(code, 0, "{stdout}{stderr}");
    let deep = format!("referred(A, T) :- present(A, T), {}.\n", nest(60));
    let deep = write(dir.path(), "deep_aggregates.dl", &deep);
    // The checker rejects what the engine's tuples cannot hold (E0406), so `check` and `mine`
    // agree: sixty nested aggregates bind more values than the engine's widest rows (64).
    let (code, stdout, stderr) = scenalog(&["check", &deep], "");
    assert_eq!(code, 1, "{stdout}{stderr}");
    assert!(
        stdout.contains("E0406") || stderr.contains("E0406"),
        "{stdout}{stderr}"
    );
    let out = dir.path().join("out");
    let log = log_dir();
    let (code, stdout, stderr) = scenalog(
        &[
            "mine",
            "--rules",
            &file,
            &deep,
            "--logs",
            &log.to_string_lossy(),
            "--out",
            &out.to_string_lossy(),
            "--threads",
            "2",
        ],
        "",
    );
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("deep_aggregates.dl` does not check") && stderr.contains("E0406"),
        "{stderr:.2000}"
    );
    assert!(!stderr.contains("program `at_limits` failed"), "{stderr}");
    // Every track present at a positive time is referred: the table shows them.
    let row = stdout
        .lines()
        .find(|l| l.starts_with("at_limits "))
        .unwrap_or_default()
        .to_string();
    let total: usize = row
        .split_whitespace()
        .last()
        .and_then(|n| n.parse().ok())
        .unwrap_or(0);
    assert!(total > 0, "{stdout}");
}

/// The reproducer: a join of three `present`s that ran past 300 s in `mine`. It was
/// written with `T3 + T < 0`; the engine now reads that as an empty range of `T3` (range
/// narrowing) and answers at once, so the condition is a product, which no range bounds.
#[test]
fn mine_stops_a_runaway_pair_at_its_time_limit_and_finishes_the_others() {
    let dir = tempfile::tempdir().expect("tempdir");
    let slow = write(
        dir.path(),
        "slow.dl",
        "referred(A, T) :- present(A, T), present(B, T), present(C, T3), T3 * T < 0.\n",
    );
    let stopped = root().join("rules/library/stopped_car.dl");
    let out = dir.path().join("out");
    let (code, stdout, stderr) = scenalog(
        &[
            "mine",
            "--rules",
            &slow,
            &stopped.to_string_lossy(),
            "--logs",
            &log_dir().to_string_lossy(),
            "--out",
            &out.to_string_lossy(),
            "--timeout-ms",
            "8000",
        ],
        "",
    );
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("program `slow` failed on log")
            && stderr.contains("longer than 8.0 s while deriving `referred`"),
        "{stderr}"
    );
    assert_mined(&stdout, "stopped_car");
    let matches = std::fs::read_to_string(out.join("matches.json")).expect("matches.json");
    assert!(matches.contains("stopped car"), "{matches:.300}");
}

/// The budget counts extracted relations: an unconstrained `direction` fails while it is
/// extracted; many small derived relations fail together though each is far below the budget.
#[test]
fn mine_fails_a_pair_past_its_tuple_budget_naming_the_relation() {
    let dir = tempfile::tempdir().expect("tempdir");
    let wide = write(
        dir.path(),
        "wide.dl",
        "referred(A, T) :- direction(A, B, T, D, Dist, Lat), Lat >= 0.0.\n",
    );
    let copies: String = (0..40)
        .map(|i| format!("p{i}(A, T) :- present(A, T), T >= {i}.\n"))
        .chain(["referred(A, T) :- p0(A, T), p39(A, T).\n".to_string()])
        .collect();
    let copies = write(dir.path(), "copies.dl", &copies);
    let stopped = root().join("rules/library/stopped_car.dl");
    let out = dir.path().join("out");
    let (code, stdout, stderr) = scenalog(
        &[
            "mine",
            "--rules",
            &wide,
            &copies,
            &stopped.to_string_lossy(),
            "--logs",
            &log_dir().to_string_lossy(),
            "--out",
            &out.to_string_lossy(),
            "--max-tuples",
            "150000",
        ],
        "",
    );
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("relation `direction` would hold more than 150000 tuples"),
        "{stderr}"
    );
    assert!(
        stderr.contains("program `copies` failed")
            && stderr.contains("grew past the budget of 150000 tuples while `p"),
        "{stderr}"
    );
    assert_mined(&stdout, "stopped_car");
}
