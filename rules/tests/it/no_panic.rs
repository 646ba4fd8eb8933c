//! Properties: parse and check never panic, on arbitrary bytes, on token soup, and on library
//! programs with tokens inserted, deleted or replaced; a checked program exists exactly when there
//! is no error; whatever parses prints to text that parses back to the same text.
//!
//! `long_fuzz` (ignored) runs the same generators for `SCENALOG_FUZZ_SECS` seconds (default 600)
//! and prints how many inputs it tried: `cargo test -p scenalog-rules --release --test it no_panic::
//! -- --ignored --nocapture`.

use std::path::Path;
use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;
use scenalog_rules::lexer::lex;
use scenalog_rules::{check, parse, print_program, CheckOptions};

fn library_sources() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("library");
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .expect("read rules/library")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "dl"))
        .collect();
    paths.sort();
    paths
        .iter()
        .map(|p| std::fs::read_to_string(p).expect("read library program"))
        .collect()
}

/// Token texts seen in the library plus a few hostile ones.
fn token_pool(sources: &[String]) -> Vec<String> {
    let mut pool: Vec<String> = Vec::new();
    for s in sources {
        for t in lex(s).0 {
            let text = s.get(t.span.start..t.span.end).unwrap_or("").to_string();
            if !text.is_empty() && !pool.contains(&text) {
                pool.push(text);
            }
        }
    }
    for extra in [
        "\"",
        "/*",
        "*/",
        "//",
        "%",
        "{",
        "}",
        ":",
        "not",
        "count",
        "min",
        "sum",
        ".decl",
        "-",
        "99999999999999999999",
        "1e999",
        "é",
        "\\",
        "_",
        "referred",
        "related",
        "!",
        "=",
        ":-",
        // Soufflé and Prolog habits (rules/src/habits.rs).
        ";",
        "\\+",
        "'",
        "'BUS'",
        ".output",
        ".input",
        "symbol",
        "number",
        "(",
        ")",
        "\"a\\d\"",
    ] {
        pool.push(extra.to_string());
    }
    pool
}

/// One edit of a program: (operation, token index, pool index).
type Edit = (u8, usize, usize);

/// Applies edits to the token sequence of `src` (0 delete, 1 insert before, 2 replace, 3 duplicate).
fn mutate(src: &str, edits: &[Edit], pool: &[String]) -> String {
    let mut toks: Vec<String> = lex(src)
        .0
        .iter()
        .map(|t| src.get(t.span.start..t.span.end).unwrap_or("").to_string())
        .collect();
    for &(op, i, j) in edits {
        if toks.is_empty() {
            toks.push(pool[j % pool.len()].clone());
            continue;
        }
        let i = i % toks.len();
        let new = pool[j % pool.len()].clone();
        match op % 4 {
            0 => {
                toks.remove(i);
            }
            1 => toks.insert(i, new),
            2 => toks[i] = new,
            _ => {
                let t = toks[i].clone();
                toks.insert(i, t);
            }
        }
    }
    toks.join(" ")
}

/// Everything that must hold for any input.
fn exercise(src: &str) {
    for require_referred in [true, false] {
        let out = check(src, &CheckOptions { require_referred });
        let has_error = out.diagnostics.iter().any(|d| d.is_error());
        assert_eq!(out.program.is_some(), !has_error, "{src:?}");
        for d in &out.diagnostics {
            assert!(
                d.span.start <= d.span.end && d.span.end <= src.len(),
                "{d:?} in {src:?}"
            );
            // A fix always applies to the text it was made for.
            if !d.fix.is_empty() {
                assert!(
                    scenalog_rules::apply_fix(src, d).is_some(),
                    "{d:?} in {src:?}"
                );
            }
        }
        let _ = scenalog_rules::render_human(&out.diagnostics, src, "fuzz.dl", false);
        let _ = scenalog_rules::diagnostics_json(&out.diagnostics, src);
    }
    let (program, _) = parse(src);
    let printed = print_program(&program);
    let (again, diags) = parse(&printed);
    assert!(
        diags.is_empty(),
        "printed form of {src:?} does not parse:\n{printed}\n{diags:#?}"
    );
    assert_eq!(print_program(&again), printed, "{src:?}");
}

const SOUP: &str = "[a-zA-Z_ ()\\{\\}.,:;!<>=+*/%'\"\\\\\\-0-9\n]{0,200}";

fn mutated() -> impl Strategy<Value = String> {
    let sources = library_sources();
    let pool = token_pool(&sources);
    let n = sources.len();
    (
        0..n,
        prop::collection::vec((any::<u8>(), any::<usize>(), any::<usize>()), 1..6),
    )
        .prop_map(move |(k, edits)| mutate(&sources[k], &edits, &pool))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..300)) {
        exercise(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn token_soup_never_panics(src in SOUP) {
        exercise(&src);
    }

    #[test]
    fn mutated_library_programs_never_panic(src in mutated()) {
        exercise(&src);
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    for src in [
        format!(
            "p(X) :- q(X), X < {}1{}.",
            "(".repeat(100_000),
            ")".repeat(100_000)
        ),
        format!("p(X) :- q(X), X < {}1.", "-".repeat(100_000)),
        format!(
            "p(X) :- q(X), N = count : {{ {} }}.",
            "M = count : { ".repeat(50_000)
        ),
    ] {
        let out = check(&src, &CheckOptions::default());
        assert!(out.diagnostics.iter().any(|d| d.code == "E0002"));
    }
}

/// Operator chains are trees as tall as they are long: 100,000 terms of `+`, `*`, mixed, or
/// under signs and calls are a diagnostic, and the clauses after them still parse.
#[test]
fn long_operator_chains_are_an_error_not_a_stack_overflow() {
    let n = 100_000;
    for chain in [
        vec!["T"; n].join(" + "),
        vec!["T"; n].join(" * "),
        vec!["T"; n].join(" - 1 * "),
        format!("-({})", vec!["T"; n].join(" + ")),
        format!("abs({})", vec!["T"; n].join(" / ")),
        format!("{}T", "- ".repeat(n)),
    ] {
        let src = format!(
            "referred(X, T) :- present(X, T), S = {chain}, S > 0.\nreferred(X, T) :- present(X, T), bad(X).\n"
        );
        let out = check(&src, &CheckOptions::default());
        assert!(out.program.is_none());
        assert!(
            out.diagnostics.iter().any(|d| d.code == "E0002"),
            "{:?}",
            out.diagnostics.first()
        );
        // Recovery: the unknown predicate of the next clause is still reported.
        assert!(out.diagnostics.iter().any(|d| d.code == "E0101"));
    }
}

#[test]
#[ignore = "runs for SCENALOG_FUZZ_SECS seconds (default 600)"]
fn long_fuzz() {
    let secs: u64 = std::env::var("SCENALOG_FUZZ_SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
    let deadline = Instant::now() + Duration::from_secs(secs);
    let mut runner = TestRunner::deterministic();
    let bytes = prop::collection::vec(any::<u8>(), 0..400)
        .prop_map(|b| String::from_utf8_lossy(&b).into_owned());
    let soup = proptest::string::string_regex(SOUP).expect("regex");
    let mutated = mutated();
    let mut counts = [0u64; 3];
    while Instant::now() < deadline {
        for _ in 0..100 {
            let b = bytes.new_tree(&mut runner).expect("tree").current();
            exercise(&b);
            let s = soup.new_tree(&mut runner).expect("tree").current();
            exercise(&s);
            let m = mutated.new_tree(&mut runner).expect("tree").current();
            exercise(&m);
            counts.iter_mut().for_each(|c| *c += 1);
        }
    }
    println!(
        "long_fuzz: {} inputs in {secs} s ({} arbitrary bytes, {} token soup, {} mutated library programs)",
        counts.iter().sum::<u64>(),
        counts[0],
        counts[1],
        counts[2]
    );
}
