//! One small program per diagnostic code: the code, the exact text under the span, and the hint.
//! Each diagnostic's whole rendering (message, caret, related spans, hint) is a snapshot in
//! `snapshots/<test>.txt`: a wording change is one `UPDATE_EXPECT=1 cargo test -p scenalog-rules
//! --test it codes::` and a review of the diff.

use std::cell::Cell;

use expect_test::expect_file;
use scenalog_rules::ast::{Expr, ExprKind, Literal, Number};
use scenalog_rules::{check, render_human, CheckOptions, Diagnostic, Severity};

fn diags(src: &str) -> Vec<Diagnostic> {
    check(src, &CheckOptions::default()).diagnostics
}

/// The only diagnostic with `code`; asserts the text under its span and that its hint contains `hint`.
fn expect(src: &str, code: &str, under: &str, hint: &str) -> Diagnostic {
    let all = diags(src);
    let found: Vec<&Diagnostic> = all.iter().filter(|d| d.code == code).collect();
    assert_eq!(found.len(), 1, "expected one {code} in {all:#?}");
    let d = found[0].clone();
    assert_eq!(&src[d.span.start..d.span.end], under, "{d:#?}");
    let h = d.hint.clone().unwrap_or_default();
    assert!(h.contains(hint), "hint {h:?} lacks {hint:?}");
    let expected_severity = if code.starts_with('W') {
        Severity::Warning
    } else {
        Severity::Error
    };
    assert_eq!(d.severity, expected_severity);
    snapshot(&render_human(
        std::slice::from_ref(&d),
        src,
        "test.dl",
        false,
    ));
    d
}

thread_local! {
    /// Snapshots taken so far by the running test (each test runs on a thread of its own).
    static TAKEN: Cell<usize> = const { Cell::new(0) };
}

/// `text` against the running test's next snapshot file, `snapshots/<test>[-<n>].txt`.
fn snapshot(text: &str) {
    let thread = std::thread::current();
    let test = thread
        .name()
        .and_then(|n| n.rsplit("::").next())
        .unwrap_or("unnamed");
    let n = TAKEN.with(|t| {
        let n = t.get();
        t.set(n + 1);
        n
    });
    let file = match n {
        0 => format!("snapshots/{test}.txt"),
        n => format!("snapshots/{test}-{n}.txt"),
    };
    expect_file![file].assert_eq(text);
}

#[test]
fn e0001_syntax_error_says_what_was_expected_and_found() {
    let src = "referred(X, T) :- present(X, T) present(X, T).\n";
    let d = expect(src, "E0001", "present", "separated by `,`");
    assert!(d.message.contains("expected `,` or `.`"), "{}", d.message);
    assert!(
        d.message.contains("found identifier `present`"),
        "{}",
        d.message
    );
}

#[test]
fn e0001_lowercase_variable_hints_capital_or_quotes() {
    let src = "referred(x, T) :- present(X, T).\n";
    let d = expect(src, "E0001", "x", "write `X`");
    assert!(d.message.contains("expected a term"), "{}", d.message);
}

#[test]
fn e0001_recovery_reports_several_syntax_errors() {
    let src = "a(X) :- present(X, ).\nreferred(X, T) :- present(X, T).\nb(X) :- present(X T).\nc(X :- x.\n";
    let all = diags(src);
    let syntax: Vec<&str> = all
        .iter()
        .filter(|d| d.code == "E0001")
        .map(|d| &src[d.span.start..d.span.end])
        .collect();
    assert_eq!(syntax, vec![")", "T", ":-"], "{all:#?}");
    // Broken clauses' heads are not also reported as unknown predicates.
    assert!(all.iter().all(|d| d.code != "E0101"), "{all:#?}");
}

#[test]
fn e0001_unterminated_string_and_bad_character() {
    let src = "referred(X, T) :- category(X, \"CAR), present(X, T).\nb(X) :- present(X, T) # 1.\n";
    let all = diags(src);
    let msgs: Vec<&str> = all
        .iter()
        .filter(|d| d.code == "E0001")
        .map(|d| d.message.as_str())
        .collect();
    assert_eq!(msgs.len(), 2, "{all:#?}");
    assert!(msgs[0].contains("unterminated string"));
    assert!(msgs[1].contains("unexpected character '#'"));
}

#[test]
fn e0002_long_operator_chain_is_too_deep() {
    // 128 operators fit, the 129th does not; the span covers the chain up to it.
    let fits = format!(
        "referred(X, T) :- speed(X, T, V), S = V{}, S > 0.\n",
        " + V".repeat(128)
    );
    assert!(check(&fits, &CheckOptions::default()).program.is_some());
    let src = format!(
        "referred(X, T) :- speed(X, T, V), S = V{}, S > 0.\n",
        " + V".repeat(129)
    );
    let under = format!("V{}", " + V".repeat(129));
    let d = expect(&src, "E0002", &under, "intermediate bindings");
    assert!(d.message.contains("128 operators"), "{}", d.message);
}

#[test]
fn e0003_a_program_past_4_mib_is_refused_before_parsing() {
    let rule = "referred(X, T) :- present(X, T), T > 0.\n";
    let fits = rule.repeat(scenalog_rules::MAX_PROGRAM_BYTES / rule.len());
    assert!(check(&fits, &CheckOptions::default()).program.is_some());
    let src = rule.repeat(scenalog_rules::MAX_PROGRAM_BYTES / rule.len() + 1);
    let all = diags(&src);
    assert_eq!(all.len(), 1, "{all:#?}");
    assert_eq!(all[0].code, "E0003");
    assert!(
        all[0].message.contains(&src.len().to_string()),
        "{}",
        all[0].message
    );
    assert!(all[0].hint.as_deref().unwrap_or_default().contains("split"));
}

#[test]
fn e0002_deep_parentheses_are_too_deep() {
    let src = format!(
        "referred(X, T) :- present(X, T), T > {}1{}.\n",
        "(".repeat(70),
        ")".repeat(70)
    );
    let d = expect(&src, "E0002", "(", "helper rules");
    assert!(d.message.contains("64 levels"), "{}", d.message);
}

#[test]
fn e0101_unknown_predicate_suggests_catalog_and_program_names() {
    let src = "stopped_car(X, T) :- speed(X, T, S), S < 0.5 m/s.\nreferred(X, T) :- stoped_car(X, T), nearr(X, _, T, _).\n";
    let all = diags(src);
    let unknown: Vec<&Diagnostic> = all.iter().filter(|d| d.code == "E0101").collect();
    assert_eq!(unknown.len(), 2, "{all:#?}");
    assert_eq!(
        &src[unknown[0].span.start..unknown[0].span.end],
        "stoped_car"
    );
    assert!(unknown[0]
        .hint
        .as_deref()
        .unwrap_or("")
        .contains("`stopped_car` (defined in this program)"));
    assert_eq!(&src[unknown[1].span.start..unknown[1].span.end], "nearr");
    assert!(unknown[1]
        .hint
        .as_deref()
        .unwrap_or("")
        .contains("near(X: track, Y: track, T: time, D: float<m>)"));
}

#[test]
fn e0102_wrong_arity_shows_signature() {
    let src = "referred(X, T) :- near(X, Y, T), category(Y, \"BUS\").\n";
    let d = expect(
        src,
        "E0102",
        "near(X, Y, T)",
        "near(X: track, Y: track, T: time, D: float<m>)",
    );
    assert!(d.message.contains("takes 4 arguments, found 3"));
}

#[test]
fn e0102_helper_arity_points_at_its_definition() {
    let src = "slow(X, T) :- speed(X, T, S), S < 1.0 m/s.\nreferred(X, T) :- slow(X, T, 3).\n";
    let d = expect(src, "E0102", "slow(X, T, 3)", "with 2 arguments");
    assert_eq!(d.related.len(), 1);
    assert_eq!(&src[d.related[0].0.start..d.related[0].0.end], "slow(X, T)");
}

#[test]
fn e0103_type_mismatch_time_where_track_goes() {
    let src = "referred(X, T) :- present(X, T), near(T, X, T, _).\n";
    let d = expect(
        src,
        "E0103",
        "T",
        "near(X: track, Y: track, T: time, D: float<m>)",
    );
    assert!(
        d.message
            .contains("argument 1 of `near` is a track, but `T` is a time"),
        "{}",
        d.message
    );
    assert_eq!(
        d.related.len(),
        1,
        "the related span says where T became a time"
    );
}

#[test]
fn e0103_string_where_number_goes() {
    let src = "referred(X, T) :- speed(X, T, \"fast\").\n";
    let d = expect(
        src,
        "E0103",
        "\"fast\"",
        "speed(X: track, T: time, V: float<m/s>)",
    );
    assert!(d.message.contains("found the string"));
}

#[test]
fn e0103_inferred_helper_types_by_unification() {
    // `lane_of`'s second column is a lane (from in_lane); using it as a track is a mismatch.
    let src = "lane_of(X, L, T) :- in_lane(X, T, L).\nreferred(X, T) :- lane_of(X, Y, T), category(Y, \"BUS\").\n";
    let d = expect(src, "E0103", "Y", "signature is category");
    assert!(
        d.message.contains("is a track, but `Y` is a lane"),
        "{}",
        d.message
    );
}

#[test]
fn e0103_decl_wins_over_uses() {
    let src = ".decl fast(X: track, T: time, V: int)\nfast(X, T, V) :- speed(X, T, V), V > 10.0 m/s.\nreferred(X, T) :- fast(X, T, _).\n";
    let d = expect(src, "E0103", "V", "");
    assert!(
        d.message
            .contains("argument 3 of `fast` is an int, but `V` is a float"),
        "{}",
        d.message
    );
}

#[test]
fn e0103_comparison_of_track_with_number() {
    let src = "referred(X, T) :- present(X, T), X > 3.\n";
    let d = expect(src, "E0103", "X > 3", "both sides of a comparison");
    assert!(
        d.message.contains("cannot compare a track with a number"),
        "{}",
        d.message
    );
}

#[test]
fn e0104_string_outside_closed_values() {
    let src = "referred(X, T) :- turning(X, T, \"lef\").\n";
    let d = expect(src, "E0104", "\"lef\"", "did you mean \"left\"?");
    assert!(d
        .hint
        .as_deref()
        .unwrap_or("")
        .contains("\"left\", \"right\""));
    let src = "referred(X, T) :- direction(X, _, T, D, _, _), D = \"forwards\".\n";
    expect(
        src,
        "E0104",
        "\"forwards\"",
        "\"forward\", \"backward\", \"left\", \"right\"",
    );
}

#[test]
fn e0201_unsafe_head_variable() {
    let src = "referred(X, T) :- present(Y, T), category(Y, \"BUS\").\n";
    let d = expect(src, "E0201", "X", "present(X, T)");
    assert!(d.message.contains("in the head"));
}

#[test]
fn e0201_unsafe_in_negation_comparison_and_aggregate() {
    let src = "referred(X, T) :- present(X, T), !near(X, Y, T, _).\n";
    expect(src, "E0201", "Y", "write `_` if any value will do");
    let src = "referred(X, T) :- present(X, T), S > 3.0 m/s.\n";
    expect(src, "E0201", "S", "bind `S`");
    let src = "referred(X, T) :- present(X, T), M = max S : { speed(X, T, V) }, M > 1.0.\n";
    expect(src, "E0201", "S", "bind `S`");
}

#[test]
fn e0201_binding_and_aggregate_result_are_safe() {
    let src =
        "referred(X, T) :- speed(X, T0, _), T = T0 + 1, N = count : { near(X, Y, T, _) }, N > 2.\n";
    let all = diags(src);
    assert!(all.iter().all(|d| d.code != "E0201"), "{all:#?}");
}

#[test]
fn e0301_negation_through_recursion_names_the_cycle() {
    let src =
        "a(X, T) :- present(X, T), !b(X, T).\nb(X, T) :- a(X, T).\nreferred(X, T) :- a(X, T).\n";
    let d = expect(src, "E0301", "!b(X, T)", "negation of itself");
    assert!(
        d.message.contains("`a` uses `!b`, `b` uses `a`"),
        "{}",
        d.message
    );
    let related: Vec<&str> = d
        .related
        .iter()
        .map(|(s, _)| &src[s.start..s.end])
        .collect();
    assert_eq!(
        related,
        vec!["a(X, T) :- present(X, T), !b(X, T).", "b(X, T) :- a(X, T)."]
    );
}

#[test]
fn e0302_aggregation_through_recursion() {
    let src = "c(X, T, N) :- present(X, T), N = count : { c(Y, T, _), near(X, Y, T, _) }.\nreferred(X, T) :- c(X, T, N), N > 1.\n";
    let d = expect(src, "E0302", "c(Y, T, _)", "aggregate over");
    assert!(
        d.message.contains("aggregation through recursion"),
        "{}",
        d.message
    );
    assert_eq!(d.related.len(), 1);
}

#[test]
fn e0401_no_referred_unless_not_required() {
    let src = "slow(X, T) :- speed(X, T, S), S < 1.0 m/s.\n";
    expect(src, "E0401", "slow(X, T)", "referred(X, T) :-");
    let out = check(
        src,
        &CheckOptions {
            require_referred: false,
        },
    );
    assert!(out.program.is_some(), "{:#?}", out.diagnostics);
}

#[test]
fn e0402_referred_and_related_shape() {
    let src = "referred(X) :- present(X, _).\n";
    expect(
        src,
        "E0402",
        "referred(X)",
        "referred(Track: track, T: time)",
    );
    let src =
        "referred(X, T) :- present(X, T).\nrelated(X, L, T) :- referred(X, T), in_lane(X, T, L).\n";
    let d = expect(
        src,
        "E0402",
        "L",
        "related(Track: track, Other: track, T: time)",
    );
    assert!(
        d.message.contains("is a track, but `L` is a lane"),
        "{}",
        d.message
    );
}

#[test]
fn e0403_catalog_relation_in_a_head() {
    let src =
        "near(X, Y, T, 0.0) :- present(X, T), present(Y, T).\nreferred(X, T) :- present(X, T).\n";
    expect(
        src,
        "E0403",
        "near",
        "near(X: track, Y: track, T: time, D: float<m>)",
    );
}

#[test]
fn e0404_declared_twice() {
    let src = ".decl p(X: track)\n.decl p(X: track)\np(X) :- ego(X).\nreferred(X, T) :- p(X), present(X, T).\n";
    let d = expect(src, "E0404", "p", "one `.decl`");
    assert_eq!(
        Some(d.span.start),
        src.rfind(".decl p").map(|i| i + 6),
        "the second declaration"
    );
    assert_eq!(d.related.len(), 1);
}

#[test]
fn w0501_variable_used_once() {
    let src = "referred(X, T) :- present(X, T), speed(X, T, Speed).\n";
    let d = expect(src, "W0501", "Speed", "write `_`");
    let out = check(src, &CheckOptions::default());
    assert!(out.program.is_some(), "warnings do not stop the program");
    assert_eq!(out.program.map(|p| p.warnings), Some(vec![d]));
}

#[test]
fn w0502_declared_but_never_defined() {
    let src = ".decl p(X: track)\nreferred(X, T) :- present(X, T), !p(X).\n";
    expect(src, "W0502", "p", "add a rule");
}

#[test]
fn w0503_helper_never_used() {
    let src = "slow(X, T) :- speed(X, T, S), S < 1.0 m/s.\nreferred(X, T) :- present(X, T).\n";
    expect(src, "W0503", "slow", "use `slow`");
}

#[test]
fn several_errors_at_once_in_source_order() {
    let src = "referred(X, T) :- nearr(X, T).\nrelated(X, Y, T) :- referred(X, T), near(X, Y, T).\nfoo(X) :- ego(X), speed(X, T, \"a\").\n";
    let all = diags(src);
    let codes: Vec<&str> = all.iter().map(|d| d.code).collect();
    assert!(codes.starts_with(&["E0101", "E0102"]), "{codes:?}");
    assert!(codes.contains(&"E0103"), "{codes:?}");
    let starts: Vec<usize> = all.iter().map(|d| d.span.start).collect();
    let mut sorted = starts.clone();
    sorted.sort();
    assert_eq!(starts, sorted);
}

#[test]
fn every_code_is_documented() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/DIAGNOSTICS.md"))
        .expect("DIAGNOSTICS.md");
    for (code, _, _) in scenalog_rules::diagnostics::CODES {
        assert!(
            doc.contains(&format!("## {code}")),
            "{code} is not documented"
        );
    }
}

#[test]
fn e0405_a_helper_named_like_what_a_used_prelude_relation_needs() {
    let src = "stopped(X, T) :- speed(X, T, V), V < 2.0 m/s.\nreferred(X, T) :- waiting(X, T).\n";
    let d = expect(src, "E0405", "stopped", "another name");
    assert!(d.message.contains("`waiting`"), "{}", d.message);
    // Its own variant of a concept it uses directly is allowed, with W0509 saying so.
    let own = "stopped(X, T) :- speed(X, T, V), V < 2.0 m/s.\nreferred(X, T) :- stopped(X, T).\n";
    let codes: Vec<&str> = diags(own).iter().map(|d| d.code).collect();
    assert_eq!(codes, vec!["W0509"], "{:#?}", diags(own));
}

#[test]
fn w0509_a_prelude_concept_redefined_is_said_with_the_prelude_s_definition() {
    // Parked cars are stopped in the prelude; this local `stopped` leaves them out in silence.
    let src = "stopped(X, T) :- speed(X, T, V), V < 0.5 m/s, !stationary(X).\n\
               referred(V, T) :- category(V, \"REGULAR_VEHICLE\"), stopped(V, T).\n";
    let d = expect(src, "W0509", "stopped", "delete these clauses");
    assert!(
        d.message
            .contains("rules/prelude.dl:15: `stopped(X, T) :- speed(X, T, V), V < 0.5 m/s.`"),
        "{}",
        d.message
    );
    // A variant under its own name is no warning.
    let variant = src.replace("stopped(", "stopped_active(");
    assert!(diags(&variant).is_empty(), "{:#?}", diags(&variant));
    // Declared and defined: one warning, at the declaration.
    let declared = format!(".decl stopped(X: track, T: time)\n{src}");
    let w: Vec<Diagnostic> = diags(&declared)
        .into_iter()
        .filter(|d| d.code == "W0509")
        .collect();
    assert_eq!(w.len(), 1, "{w:#?}");
    assert_eq!(&declared[w[0].span.start..w[0].span.end], "stopped");
    assert!(w[0].span.start < 20);
}

#[test]
fn e0407_a_prelude_concept_redefined_with_another_arity() {
    let src = "nearby(A, B) :- category(A, \"BUS\"), category(B, \"PEDESTRIAN\").\n\
               referred(V, T) :- nearby(V, _), present(V, T).\n";
    let d = expect(src, "E0407", "nearby", "my_nearby");
    assert!(d.message.contains("3 columns"), "{}", d.message);
    assert!(d.message.contains("of 2"), "{}", d.message);
}

#[test]
fn e0406_a_rule_wider_than_the_engine_holds() {
    // `wide(n)`: a rule joining n presences, 2n variables; the engine's widest row holds 64.
    let wide = |n: usize| {
        let head: Vec<String> = (0..n).map(|i| format!("A{i}")).collect();
        let body: Vec<String> = (0..n).map(|i| format!("present(A{i}, T{i})")).collect();
        format!(
            "p({}) :- {}.\nreferred(A0, T) :- p({}), present(A0, T).\n",
            head.join(", "),
            body.join(", "),
            head.join(", ")
        )
    };
    let over = wide(33);
    let d = expect(
        &over,
        "E0406",
        &over[..over.find(" :-").unwrap_or(0)],
        "helper rule",
    );
    assert!(d.message.contains("binds 66 values"), "{}", d.message);
    // Sixty-four is the engine's widest row: that rule checks (and runs: engine/tests/it/wide.rs).
    assert!(
        diags(&wide(32)).iter().all(|x| x.code != "E0406"),
        "{:#?}",
        diags(&wide(32))
    );
    // Each `_` inside braces, computed atom argument and aggregate takes a value of the row too.
    let braces: Vec<String> = (0..31).map(|i| format!("present(A{i}, _)")).collect();
    let counted = format!(
        "referred(A0, T) :- present(A0, T), N = count : {{ {} }}, N > 1.\n",
        braces.join(", ")
    );
    assert!(
        diags(&counted).iter().any(|x| x.code == "E0406"),
        "31 variables, 31 `_` and one aggregate, with N and T: 65"
    );
}

#[test]
fn w0506_to_w0508_programs_that_check_but_mean_something_else() {
    let d = expect(
        "referred(V, T) :- category(V, \"BUS\"), present(V, T), N = count : { near(V, _, T, D), category(_, \"PEDESTRIAN\"), D < 10.0 }, N >= 3.\n",
        "W0506",
        "category(_, \"PEDESTRIAN\")",
        "name the column in both atoms (`Y1`)",
    );
    assert_eq!(d.fix.len(), 2);
    expect(
        "referred(X, T) :- present(X, T), stopped(_, T).\n",
        "W0506",
        "stopped(_, T)",
        "joins nothing",
    );
    expect(
        "p(V, P, T) :- near(V, P, T, D), D < 10.0 m.\nreferred(V, T) :- present(V, T), N = count : { p(V, _, _) }, N >= 3.\n",
        "W0507",
        "_",
        "write `T` here",
    );
    expect(
        "referred(P, T) :- near(P, B, T, D), D < 2.0 m, category(B, \"BUS\").\nrelated(P, B, T) :- near(P, B, T, D), D < 10.0 m, category(B, \"BUS\").\n",
        "W0508",
        "related(P, B, T)",
        "add `referred(P, T)`",
    );
    // The referred object written second: the hint swaps the columns, and the fixed program
    // checks clean (adding `referred(B, T)` instead would empty `related`).
    let swapped = "referred(P, T) :- near(P, B, T, D), D < 2.0 m, category(P, \"PEDESTRIAN\"), category(B, \"BUS\").\nrelated(B, P, T) :- referred(P, T), near(P, B, T, D), D < 5.0 m, category(B, \"BUS\").\n";
    let d = expect(swapped, "W0508", "related(B, P, T)", "`related(P, B, T)`");
    assert!(d.message.contains("columns swapped"), "{}", d.message);
    let fixed = scenalog_rules::apply_fix(swapped, &d).expect("a fix");
    assert!(
        fixed.contains("related(P, B, T) :- referred(P, T)"),
        "{fixed}"
    );
    assert!(diags(&fixed).is_empty(), "{fixed}: {:#?}", diags(&fixed));
    // Tied to referred by the same helper, or by `referred` itself: no warning.
    for clean in [
        "h(P, B, T) :- near(P, B, T, D), D < 2.0 m.\nreferred(P, T) :- h(P, _, T).\nrelated(P, B, T) :- h(P, B, T).\n",
        "referred(P, T) :- near(P, B, T, D), D < 2.0 m, category(B, \"BUS\").\nrelated(P, B, T) :- referred(P, T), near(P, B, T, D), D < 10.0 m.\n",
    ] {
        assert!(diags(clean).is_empty(), "{clean}: {:#?}", diags(clean));
    }
}

/// The nesting limit is what the documentation says: 64 levels of parentheses, signs, calls or
/// aggregates parse, 65 are E0002 ("more than 64"), whichever construct nests.
#[test]
fn e0002_nesting_limit_is_64_levels_for_every_construct() {
    let parens = |k: usize| {
        format!(
            "referred(X, T) :- present(X, T), T > {}1{}.\n",
            "(".repeat(k),
            ")".repeat(k)
        )
    };
    let signs = |k: usize| {
        format!(
            "referred(X, T) :- present(X, T), S = {}T, S > 0.\n",
            "- ".repeat(k)
        )
    };
    let calls = |k: usize| {
        format!(
            "referred(X, T) :- present(X, T), S = {}T{}, S > 0.\n",
            "abs(".repeat(k),
            ")".repeat(k)
        )
    };
    let aggregates = |k: usize| {
        let mut body = "present(Y, T)".to_string();
        for i in 0..k {
            body = format!("N{i} = count : {{ {body} }}");
        }
        format!("referred(X, T) :- present(X, T), {body}.\n")
    };
    let makers: [(&str, &dyn Fn(usize) -> String); 4] = [
        ("parentheses", &parens),
        ("signs", &signs),
        ("calls", &calls),
        ("aggregates", &aggregates),
    ];
    for (what, make) in makers {
        let too_deep = |k: usize| {
            check(&make(k), &CheckOptions::default())
                .diagnostics
                .iter()
                .any(|d| d.code == "E0002")
        };
        assert!(!too_deep(64), "{what}: 64 levels must parse");
        assert!(too_deep(65), "{what}: 65 levels must be E0002");
    }
}

#[test]
fn w0510_an_aggregate_tied_to_nothing_folds_over_the_whole_log() {
    let src = "referred(V, T) :- category(V, \"BUS\"), present(V, T), N = count : { category(P, \"PEDESTRIAN\") }, N >= 3.\n";
    let d = expect(
        src,
        "W0510",
        "N = count : { category(P, \"PEDESTRIAN\") }",
        "`present(P, T)`",
    );
    assert!(
        d.message.contains("the same for every V, T"),
        "{}",
        d.message
    );
    // Either tie the hint names checks without it.
    for tied in [
        src.replace("\"PEDESTRIAN\") }", "\"PEDESTRIAN\"), present(P, T) }"),
        src.replace(
            "\"PEDESTRIAN\") }",
            "\"PEDESTRIAN\"), near(V, P, T, D), D < 10.0 }",
        ),
    ] {
        assert!(
            diags(&tied).iter().all(|x| x.code != "W0510"),
            "{tied}: {:#?}",
            diags(&tied)
        );
    }
    // A general Datalog program may count everything on purpose.
    let run = "total(N) :- N = count : { e(_, _) }.\nper(X, N) :- e(X, _), N = count : { e(_, _) }.\ne(1, 2).\n";
    let general = check(
        run,
        &CheckOptions {
            require_referred: false,
        },
    );
    assert!(
        general.diagnostics.iter().all(|x| x.code != "W0510"),
        "{:#?}",
        general.diagnostics
    );
}

/// Every quantity of a checked program with the number the checker read it as.
fn readings(src: &str) -> Vec<(String, Number)> {
    let checked = check(src, &CheckOptions::default())
        .program
        .unwrap_or_else(|| panic!("{src}: {:#?}", diags(src)));
    let mut out = Vec::new();
    fn walk(e: &Expr, out: &mut Vec<(String, Number)>) {
        match &e.kind {
            ExprKind::Quantity(q) => {
                let n = q.read_as.expect("the checker reads every quantity");
                out.push((format!("{} {}", q.value, q.unit), n));
            }
            ExprKind::Neg(x) => walk(x, out),
            ExprKind::Binary(_, a, b) => {
                walk(a, out);
                walk(b, out);
            }
            ExprKind::Call(_, args) => args.iter().for_each(|a| walk(a, out)),
            _ => {}
        }
    }
    fn lits(body: &[Literal], out: &mut Vec<(String, Number)>) {
        for l in body {
            match l {
                Literal::Pos(a) | Literal::Neg(a, _) => a.args.iter().for_each(|e| walk(e, out)),
                Literal::Cmp(c) => {
                    walk(&c.lhs, out);
                    walk(&c.rhs, out);
                }
                Literal::Agg(g) => lits(&g.body, out),
            }
        }
    }
    let own = src.len();
    for c in checked
        .program
        .clauses
        .iter()
        .filter(|c| c.span.start < own)
    {
        lits(&c.body, &mut out);
    }
    out
}

#[test]
fn e0105_w0511_numbers_are_read_in_the_unit_of_their_place() {
    // "Faster than 50 km/h" written bare is read as 50 m/s (180 km/h): a warning whose fix
    // writes that reading's unit, so no km/h threshold checks clean.
    let bare = "referred(V, T) :- category(V, \"VEHICLE\"), speed(V, T, S), S > 50.0.\n";
    let d = expect(
        bare,
        "W0511",
        "50.0",
        "`50 m/s` (this reading) or `50 km/h`",
    );
    assert!(
        d.message.contains("read as 50 m/s = 180 km/h"),
        "{}",
        d.message
    );
    let fixed = scenalog_rules::apply_fix(bare, &d).expect("a fix");
    assert!(fixed.contains("S > 50.0 m/s."), "{fixed}");
    assert!(diags(&fixed).is_empty(), "{:#?}", diags(&fixed));
    // With its unit it is converted at check time.
    let kmh = bare.replace("50.0", "50 km/h");
    let r = readings(&kmh);
    assert_eq!(r.len(), 1);
    assert!(
        matches!(r[0].1, Number::Float(v) if (v - 50.0 / 3.6).abs() < 1e-9),
        "{r:?}"
    );
    // A yaw rate in rad/s on a deg/s column.
    let yaw = "referred(V, T) :- yaw_rate(V, T, W), W > 0.3.\n";
    let d = expect(yaw, "W0511", "0.3", "`0.3 rad/s`");
    assert!(
        d.message.contains("0.3 deg/s = 0.005 rad/s"),
        "{}",
        d.message
    );
    let r = readings(&yaw.replace("0.3", "0.3 rad/s"));
    assert!(
        matches!(r[0].1, Number::Float(v) if (v - 17.188733853924695).abs() < 1e-9),
        "{r:?}"
    );
    // 0 and counts need no unit.
    for clean in [
        "referred(V, T) :- speed(V, T, S), S > 0.0.\n",
        "referred(V, T) :- present(V, T), N = count : { near(V, P, T, D), D < 5 m }, N >= 3.\n",
        "referred(V, T) :- present(V, T), T >= 0.\n",
    ] {
        assert!(diags(clean).is_empty(), "{clean}: {:#?}", diags(clean));
    }
    // Units that cannot meet.
    let d = expect(
        "referred(V, T) :- speed(V, T, S), near(V, Y, T, D), D < S.\n",
        "E0105",
        "D < S",
        "measure the same thing",
    );
    assert!(
        d.message.contains("a distance (m) with a speed (m/s)"),
        "{}",
        d.message
    );
    expect(
        "referred(V, T) :- speed(V, T, S), S > 3 s.\n",
        "E0105",
        "S > 3 s",
        "same thing",
    );
    expect(
        "referred(V, T) :- present(V, T), present(V, T2), X = T + T2, X > 0.\n",
        "E0105",
        "T + T2",
        "same thing",
    );
    // A helper's column carries the unit its rule put there.
    expect(
        "fast(V, T, S) :- speed(V, T, S).\nreferred(V, T) :- fast(V, T, S), S > 2 m.\n",
        "E0105",
        "S > 2 m",
        "same thing",
    );
    // Arithmetic keeps units: a speed times a time is a distance.
    let headway = "referred(V, T) :- speed(V, T, S), near(V, Y, T, Gap), category(Y, \"BUS\"), Gap < S * 1.0.\n";
    let d = expect(headway, "W0511", "1.0", "`1 s`");
    let fixed = scenalog_rules::apply_fix(headway, &d).expect("a fix");
    assert!(diags(&fixed).is_empty(), "{fixed}: {:#?}", diags(&fixed));
}

#[test]
fn e0106_time_is_a_moment_and_durations_carry_seconds() {
    // `T + 1` is a tenth of a second: an error whose fix writes that reading in seconds.
    let next = "referred(V, T) :- stopped(V, T), T2 = T + 1, stopped(V, T2).\n";
    let d = expect(next, "E0106", "1", "`T + 1 s`");
    assert!(
        d.message.contains("read as 1 frame of 0.1 s = 0.1 s"),
        "{}",
        d.message
    );
    let fixed = scenalog_rules::apply_fix(next, &d).expect("a fix");
    assert!(fixed.contains("T2 = T + 0.1 s,"), "{fixed}");
    assert_eq!(
        readings(&fixed),
        vec![("0.1 s".to_string(), Number::Int(1))]
    );
    // A duration compared with a bare number: read as frames, fixed in seconds.
    let within = "referred(V, T2) :- stopped(V, T1), moving(V, T2), T2 > T1, T2 - T1 <= 30.\n";
    let d = expect(within, "W0511", "30", "`3 s`");
    let fixed = scenalog_rules::apply_fix(within, &d).expect("a fix");
    assert!(fixed.contains("T2 - T1 <= 3 s."), "{fixed}");
    assert_eq!(readings(&fixed), vec![("3 s".to_string(), Number::Int(30))]);
    // Seconds and milliseconds become frames where a time is; elsewhere seconds.
    let r = readings("referred(V, T) :- present(V, T), T0 = T - 500 ms, present(V, T0).\n");
    assert_eq!(r, vec![("500 ms".to_string(), Number::Int(5))]);
    let r = readings("referred(V, T) :- seconds(T, S), S >= 2 min, present(V, T).\n");
    assert_eq!(r, vec![("2 min".to_string(), Number::Float(120.0))]);
}

#[test]
fn w0512_a_duration_measured_by_counting_samples() {
    let src = "referred(X, T) :- stopped(X, T), T0 = T - 3 s, N = count : { stopped(X, U), U >= T0, U <= T }, N >= 31.\n";
    let d = expect(src, "W0512", "N >= 31", "M = count : { present(X, W)");
    assert!(
        d.message.contains("3 s at 10 Hz and 15 s at 2 Hz"),
        "{}",
        d.message
    );
    // The idiom of the hint, and counting objects, are not counting samples.
    for clean in [
        "referred(X, T) :- stopped(X, T), T0 = T - 3 s, stopped(X, T0), N = count : { stopped(X, U), U >= T0, U <= T }, M = count : { present(X, W), W >= T0, W <= T }, N = M.\n",
        "referred(X, T) :- category(X, \"BUS\"), present(X, T), N = count : { near(X, P, T, D), D < 5 m, category(P, \"PEDESTRIAN\") }, N >= 3.\n",
    ] {
        assert!(diags(clean).is_empty(), "{clean}: {:#?}", diags(clean));
    }
}

#[test]
fn a_declared_column_carries_its_unit_as_the_catalog_prints_it() {
    // A signature copied from `scenalog catalog` is a declaration: `float<m/s>`.
    let src = ".decl quick(V: track, T: time, S: float<m/s>)\nquick(V, T, S) :- speed(V, T, S).\n\
               referred(V, T) :- quick(V, T, S), S > 50 km/h.\n";
    let r = readings(src);
    assert!(
        matches!(r[..], [(_, Number::Float(v))] if (v - 50.0 / 3.6).abs() < 1e-9),
        "{r:?}"
    );
    let printed = scenalog_rules::print_program(&scenalog_rules::parse(src).0);
    assert!(
        printed.contains(".decl quick(V: track, T: time, S: float<m/s>)"),
        "{printed}"
    );
    expect(
        &src.replace("50 km/h", "2 m"),
        "E0105",
        "S > 2 m",
        "same thing",
    );
    // A column holds base units: km/h there would rescale nothing, so it is refused.
    let d = expect(
        &src.replace("float<m/s>", "float<km/h>"),
        "E0001",
        "<km/h>",
        "`S > 50 km/h`",
    );
    assert!(d.message.contains("base unit"), "{}", d.message);
}

#[test]
fn e0201_a_head_variable_bound_only_in_a_count_has_no_witness() {
    // `min`/`max` witnesses are the tuples that reach them; `count` and `sum` have none.
    let src = "referred(P, T) :- ego(E), present(E, T), N = count : { near(E, P, T, _) }, N > 2.\n";
    let d = expect(src, "E0201", "P", "no witness");
    assert!(d.hint.unwrap_or_default().contains("`count`"));
    let ok = "referred(P, T) :- ego(E), D = min X : { near(E, P, T, X) }, D < 10 m.\n";
    assert!(diags(ok).iter().all(|d| !d.is_error()), "{:#?}", diags(ok));
}

#[test]
fn w0515_a_min_witness_is_said_to_be_one() {
    // P and T are bound only in the braces: the pedestrian nearest over the whole log, not the
    // nearest at each moment; a program that meant the latter hears it.
    let src = "referred(P, T) :- ego(E), D = min X : { near(E, P, T, X) }, D < 10 m.\n";
    let d = expect(
        src,
        "W0515",
        "D = min X : { near(E, P, T, X) }",
        "outside the braces",
    );
    assert!(d.message.contains("`P`, `T`"), "{}", d.message);
    // Bound outside, they group it: no witness, no warning.
    let grouped =
        "referred(P, T) :- ego(E), present(P, T), D = min X : { near(E, P, T, X) }, D < 10 m.\n";
    assert!(
        diags(grouped).iter().all(|x| x.code != "W0515"),
        "{:#?}",
        diags(grouped)
    );
}

#[test]
fn w0514_percent_after_an_operand_starts_a_comment() {
    // `T % 2 = 0, T > 0.` would be the remainder in Soufflé; here the rest of the line is a
    // comment, so the clause runs on into the next one and the parser stops there.
    let src = "referred(V, T) :- present(V, T), T % 2 = 0,\n    T > 0.\n";
    let all = diags(src);
    let w: Vec<_> = all.iter().filter(|d| d.code == "W0514").collect();
    assert_eq!(w.len(), 1, "{all:#?}");
    assert_eq!(&src[w[0].span.start..w[0].span.end], "%");
    let fixed = scenalog_rules::apply_fix(src, w[0]).unwrap_or_default();
    assert!(fixed.contains("T mod 2 = 0"), "{fixed}");
    // Glued to its operands, the fix adds the spaces `mod` needs.
    let glued = "referred(V, T) :- present(V, T), T%2 = 0.\n";
    let d = expect(glued, "W0514", "%", "mod");
    let fixed = scenalog_rules::apply_fix(glued, &d).unwrap_or_default();
    assert!(fixed.contains("T mod 2 = 0"), "{fixed}");
    assert!(diags(&fixed).is_empty(), "{fixed}: {:#?}", diags(&fixed));
    // Comments after code are comments.
    for src in [
        "referred(V, T) :- present(V, T). % every track, every frame\n",
        "referred(V, T) :- near(V, P, T, D), D < 5 m, % metres\n    P != V.\n",
        "referred(V, T) :- present(V, T) % 2 tracks at most\n    .\n",
    ] {
        let all = diags(src);
        assert!(all.iter().all(|d| d.code != "W0514"), "{src}{all:#?}");
    }
}

#[test]
fn w0513_a_lower_bound_on_a_distance_past_its_range_writes_the_negation() {
    let src =
        "referred(P, T) :- ego(E), category(P, \"PEDESTRIAN\"), near(E, P, T, D), D > 30 m.\n";
    let d = expect(src, "W0513", "D > 30 m", "not within 30 m");
    let Some(out) = scenalog_rules::apply_fix(src, &d) else {
        panic!("no fix: {d:#?}")
    };
    assert!(diags(&out).is_empty(), "{out}\n{:#?}", diags(&out));
    assert!(out.contains("!near_within_30_m(E, P, T)"), "{out}");
    // Written the other way round, and with `>=`: the same warning, the bound kept exact.
    let src = "referred(P, T) :- ego(E), category(P, \"PEDESTRIAN\"), at_crosswalk(P, T, D), 20.0 <= D.\n";
    let d = expect(src, "W0513", "20.0 <= D", "not within 20.0");
    let out = scenalog_rules::apply_fix(src, &d).unwrap_or_default();
    assert!(out.contains("D < 20.0"), "{out}");
}

#[test]
fn w0513_an_upper_bound_past_the_range_removes_nothing() {
    let src =
        "referred(P, T) :- ego(E), category(P, \"PEDESTRIAN\"), near(E, P, T, D), D < 80 m.\n";
    let d = expect(src, "W0513", "D < 80 m", "within 50 m");
    assert!(d.fix.is_empty());
}

#[test]
fn w0513_bounds_inside_the_range_and_unbounded_distances_are_fine() {
    for src in [
        "referred(P, T) :- ego(E), category(P, \"PEDESTRIAN\"), near(E, P, T, D), D > 10 m, D < 30 m.\n",
        "referred(P, T) :- ego(E), category(P, \"PEDESTRIAN\"), near(E, P, T, D), D < 30 m.\n",
        "referred(P, T) :- ego(E), category(P, \"PEDESTRIAN\"), near(E, P, T, _).\n",
    ] {
        let all = diags(src);
        assert!(all.iter().all(|d| d.code != "W0513"), "{src}{all:#?}");
    }
    // Where the distance is used again, the fix would change what the rule says: the hint only.
    let src = "close(P, T, D) :- ego(E), near(E, P, T, D), D > 30 m.\nreferred(P, T) :- category(P, \"PEDESTRIAN\"), close(P, T, _).\n";
    let d = expect(src, "W0513", "D > 30 m", "not within 30 m");
    assert!(d.fix.is_empty());
}

#[test]
fn strings_may_be_ordered_and_min_max_taken_of_them() {
    // The engine orders strings by text (E0107, which refused this, is retired).
    for fine in [
        "s(\"b\"). s(\"a\").\nlt(X, Y) :- s(X), s(Y), X < Y.\nreferred(X, T) :- present(X, T).\n",
        "referred(X, T) :- turning(X, T, D), D >= \"left\".\n",
        "s(\"b\").\nm(M) :- M = min X : { s(X) }.\nreferred(X, T) :- present(X, T), m(_).\n",
    ] {
        let d = diags(fine);
        assert!(!d.iter().any(|d| d.is_error()), "{fine}{d:#?}");
    }
    // `min` of tracks is not an order the language gives.
    let d =
        diags("m(M) :- M = max X : { present(X, _) }.\nreferred(X, T) :- present(X, T), m(X).\n");
    assert!(
        d.iter()
            .any(|d| d.code == "E0104" || d.message.contains("numbers or strings")),
        "{d:#?}"
    );
}

#[test]
fn e0408_a_declaration_naming_two_columns_alike() {
    let src = ".decl pair(a: track, a: track)\npair(X, Y) :- near(X, Y, _, _).\nreferred(X, T) :- present(X, T), pair(X, _).\n";
    let d = expect(
        src,
        "E0408",
        ".decl pair(a: track, a: track)",
        "its own name",
    );
    assert!(d.message.contains("`a`"), "{}", d.message);
    let fine = ".decl pair(a: track, b: track)\npair(X, Y) :- near(X, Y, _, _).\nreferred(X, T) :- present(X, T), pair(X, _).\n";
    assert!(diags(fine).iter().all(|d| d.code != "E0408"));
}
