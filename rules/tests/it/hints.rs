//! Hints an LLM (or a person) can act on: every diagnostic here carries a machine-readable fix;
//! the test applies it mechanically and checks the result again, which must check clean.

use scenalog_rules::{apply_fix, check, CheckOptions, Diagnostic};

fn diags(src: &str) -> Vec<Diagnostic> {
    check(src, &CheckOptions::default()).diagnostics
}

/// The only error of `src`: its code, the text under its span, a hint containing `hint`; then
/// its fix applied, which must give `fixed` and check with no error at all.
fn fixes_to(src: &str, code: &str, under: &str, hint: &str, fixed: &str) -> Diagnostic {
    let all = diags(src);
    let errors: Vec<&Diagnostic> = all.iter().filter(|d| d.is_error()).collect();
    assert_eq!(errors.len(), 1, "expected one error in {all:#?}");
    let d = errors[0].clone();
    assert_eq!(d.code, code, "{d:#?}");
    assert_eq!(&src[d.span.start..d.span.end], under, "{d:#?}");
    let h = d.hint.clone().unwrap_or_default();
    assert!(h.contains(hint), "hint {h:?} lacks {hint:?}");
    let Some(out) = apply_fix(src, &d) else {
        panic!("no applicable fix: {d:#?}")
    };
    assert_eq!(out, fixed);
    let after = diags(&out);
    assert!(
        after.iter().all(|d| !d.is_error()),
        "the fixed program still has errors: {after:#?}\n{out}"
    );
    d
}

#[test]
fn a_category_av2_does_not_have_is_an_error_naming_the_closest() {
    let d = fixes_to(
        "referred(X, T) :- category(X, \"EMERGENCY_VEHICLE\"), present(X, T).\n",
        "E0104",
        "\"EMERGENCY_VEHICLE\"",
        "AV2 has no emergency-vehicle class",
        "referred(X, T) :- category(X, \"REGULAR_VEHICLE\"), present(X, T).\n",
    );
    let h = d.hint.unwrap_or_default();
    assert!(
        h.contains("closest: \"REGULAR_VEHICLE\", \"LARGE_VEHICLE\""),
        "{h}"
    );
    fixes_to(
        "referred(X, T) :- category(X, \"CAR\"), present(X, T).\n",
        "E0104",
        "\"CAR\"",
        "REGULAR_VEHICLE",
        "referred(X, T) :- category(X, \"REGULAR_VEHICLE\"), present(X, T).\n",
    );
    fixes_to(
        "referred(X, T) :- category(X, \"EGO\"), present(X, T).\n",
        "E0104",
        "\"EGO\"",
        "EGO_VEHICLE",
        "referred(X, T) :- category(X, \"EGO_VEHICLE\"), present(X, T).\n",
    );
}

#[test]
fn a_category_in_the_wrong_case_or_misspelt_gets_a_did_you_mean() {
    fixes_to(
        "referred(X, T) :- category(X, \"pedestrian\"), present(X, T).\n",
        "E0104",
        "\"pedestrian\"",
        "did you mean \"PEDESTRIAN\"? values are case-sensitive",
        "referred(X, T) :- category(X, \"PEDESTRIAN\"), present(X, T).\n",
    );
    fixes_to(
        "referred(X, T) :- category(X, \"PEDESTRAIN\"), present(X, T).\n",
        "E0104",
        "\"PEDESTRAIN\"",
        "did you mean \"PEDESTRIAN\"?",
        "referred(X, T) :- category(X, \"PEDESTRIAN\"), present(X, T).\n",
    );
}

#[test]
fn a_closed_value_reaching_the_column_through_a_variable_is_checked() {
    fixes_to(
        "referred(X, T) :- C = \"CAR\", category(X, C), present(X, T).\n",
        "E0104",
        "\"CAR\"",
        "REGULAR_VEHICLE",
        "referred(X, T) :- C = \"REGULAR_VEHICLE\", category(X, C), present(X, T).\n",
    );
    // Through a helper's column, its fact written before the join that closes it.
    fixes_to(
        "wanted(\"BUSS\").\nreferred(X, T) :- wanted(C), category(X, C), present(X, T).\n",
        "E0104",
        "\"BUSS\"",
        "did you mean \"BUS\"?",
        "wanted(\"BUS\").\nreferred(X, T) :- wanted(C), category(X, C), present(X, T).\n",
    );
    let d =
        &diags("wanted(\"CAR\").\nreferred(X, T) :- wanted(C), category(X, C), present(X, T).\n")
            [0];
    assert!(
        d.message
            .contains("`wanted`'s column 1, joined with `category`'s column 2"),
        "{}",
        d.message
    );
}

#[test]
fn aliases_of_other_closed_columns_are_fixed_too() {
    fixes_to(
        "referred(X, T) :- direction(X, _, T, \"ahead\", _, _).\n",
        "E0104",
        "\"ahead\"",
        "directions are",
        "referred(X, T) :- direction(X, _, T, \"forward\", _, _).\n",
    );
}

#[test]
fn every_valid_category_checks_clean() {
    for c in scenalog_facts::catalog::CATEGORY_VALUES {
        let src = format!("referred(X, T) :- category(X, \"{c}\"), present(X, T).\n");
        let errors: Vec<Diagnostic> = diags(&src).into_iter().filter(|d| d.is_error()).collect();
        assert!(errors.is_empty(), "{c}: {errors:#?}");
    }
}

#[test]
fn a_disjunction_becomes_one_rule_per_alternative() {
    let d = fixes_to(
        "referred(X, T) :- category(X, \"BUS\"), present(X, T) ; category(X, \"TRUCK\"), present(X, T).\n",
        "E0001",
        ";",
        "referred(X, T) :- category(X, \"BUS\"), present(X, T).\nreferred(X, T) :- category(X, \"TRUCK\"), present(X, T).",
        "referred(X, T) :- category(X, \"BUS\"), present(X, T).\nreferred(X, T) :- category(X, \"TRUCK\"), present(X, T).\n",
    );
    assert!(d.message.contains("no `;`"), "{}", d.message);
    // A parenthesised disjunction among other literals is distributed over them.
    fixes_to(
        "referred(X, T) :- present(X, T), (category(X, \"BUS\") ; category(X, \"TRUCK\")), speed(X, T, S), S > 1.0.\n",
        "E0001",
        ";",
        "one rule per alternative",
        "referred(X, T) :- present(X, T), category(X, \"BUS\"), speed(X, T, S), S > 1.0.\n\
         referred(X, T) :- present(X, T), category(X, \"TRUCK\"), speed(X, T, S), S > 1.0.\n",
    );
}

#[test]
fn prolog_negation_becomes_bang() {
    fixes_to(
        "referred(X, T) :- present(X, T), \\+ ego(X).\n",
        "E0001",
        "\\+",
        "write `referred(X, T) :- present(X, T), !ego(X).`",
        "referred(X, T) :- present(X, T), !ego(X).\n",
    );
}

#[test]
fn aggregate_arguments_in_parentheses_are_removed() {
    fixes_to(
        "referred(X, T) :- present(X, T), N = count(Y) : { near(X, Y, T, _) }, N >= 2.\n",
        "E0001",
        "count(Y)",
        "write `referred(X, T) :- present(X, T), N = count : { near(X, Y, T, _) }, N >= 2.`",
        "referred(X, T) :- present(X, T), N = count : { near(X, Y, T, _) }, N >= 2.\n",
    );
    fixes_to(
        "referred(X, T) :- present(X, T), M = max(D) : { near(X, _, T, D) }, M > 2.0.\n",
        "E0001",
        "max(D)",
        "M = max D : {",
        "referred(X, T) :- present(X, T), M = max D : { near(X, _, T, D) }, M > 2.0.\n",
    );
}

#[test]
fn souffle_directives_are_deleted_and_souffle_types_renamed() {
    fixes_to(
        ".output referred\nreferred(X, T) :- present(X, T).\n",
        "E0001",
        ".output",
        "delete the line `.output referred`",
        "referred(X, T) :- present(X, T).\n",
    );
    fixes_to(
        ".input present\nreferred(X, T) :- present(X, T).\n",
        "E0001",
        ".input",
        "catalog relations come from the logs",
        "referred(X, T) :- present(X, T).\n",
    );
    fixes_to(
        ".decl swift(X: symbol, N: number)\nswift(\"a\", 1).\nreferred(X, T) :- present(X, T), swift(\"a\", N), N > 0.\n",
        "E0001",
        "symbol",
        "drop the line `.decl swift(X: symbol, N: number)`",
        "swift(\"a\", 1).\nreferred(X, T) :- present(X, T), swift(\"a\", N), N > 0.\n",
    );
    fixes_to(
        ".decl swift(X: symbol)\nswift(\"a\").\nreferred(X, T) :- present(X, T), swift(\"a\").\n",
        "E0001",
        "symbol",
        "`.decl swift(X: str)`",
        ".decl swift(X: str)\nswift(\"a\").\nreferred(X, T) :- present(X, T), swift(\"a\").\n",
    );
    fixes_to(
        ".decl referred(X: symbol, T: number)\nreferred(X, T) :- present(X, T).\n",
        "E0001",
        "symbol",
        "`.decl referred(X: track, T: time)`",
        ".decl referred(X: track, T: time)\nreferred(X, T) :- present(X, T).\n",
    );
}

#[test]
fn single_quotes_and_unknown_escapes_are_fixed() {
    fixes_to(
        "referred(X, T) :- category(X, 'BUS'), present(X, T).\n",
        "E0001",
        "'BUS'",
        "double quotes",
        "referred(X, T) :- category(X, \"BUS\"), present(X, T).\n",
    );
    fixes_to(
        "note(\"a\\d\").\nreferred(X, T) :- present(X, T), note(_).\n",
        "E0001",
        "\"a\\d",
        "double it",
        "note(\"a\\\\d\").\nreferred(X, T) :- present(X, T), note(_).\n",
    );
}

#[test]
fn the_rest_of_a_program_with_a_habit_is_still_checked_where_it_is() {
    // The `;` is reported, and the unknown predicate after it too, at its own place.
    let src = ".output referred\nreferred(X, T) :- present(X, T) ; ego(X), present(X, T).\n\
               other(X) :- presnt(X, _).\n";
    let all = diags(src);
    let codes: Vec<(&str, &str)> = all
        .iter()
        .map(|d| (d.code, &src[d.span.start..d.span.end]))
        .collect();
    assert!(codes.contains(&("E0001", ".output")), "{all:#?}");
    assert!(codes.contains(&("E0001", ";")), "{all:#?}");
    assert!(codes.contains(&("E0101", "presnt")), "{all:#?}");
    assert!(!codes.iter().any(|(c, _)| *c == "E0401"), "{all:#?}");
}

#[test]
fn an_unbound_head_time_is_bound_with_the_clauses_object_never_present_t_t() {
    let d = fixes_to(
        "referred(X, T) :- category(X, \"BUS\"), speed(X, T2, S), S > 1.0, T2 > 0.\n",
        "E0201",
        "T",
        "present(X, T)",
        "referred(X, T) :- category(X, \"BUS\"), speed(X, T2, S), S > 1.0, T2 > 0, present(X, T).\n",
    );
    assert!(!d.hint.unwrap_or_default().contains("present(T, T)"));
    fixes_to(
        "referred(X, T) :- on_intersection(Y, T), ego(Y).\n",
        "E0201",
        "X",
        "present(X, T)",
        "referred(X, T) :- on_intersection(Y, T), ego(Y), present(X, T).\n",
    );
}

#[test]
fn an_unbound_related_object_gets_the_helper_that_pairs_the_two() {
    let src = "close_ped(B, P, T) :- category(B, \"BUS\"), near(B, P, T, D), D < 5.0, category(P, \"PEDESTRIAN\").\n\
               referred(B, T) :- close_ped(B, _, T).\n\
               related(B, P, T) :- referred(B, T).\n";
    let fixed = src.replace(
        "related(B, P, T) :- referred(B, T).",
        "related(B, P, T) :- referred(B, T), close_ped(B, P, T).",
    );
    fixes_to(src, "E0201", "P", "close_ped(B, P, T)", &fixed);
    // With no such helper: `near`.
    fixes_to(
        "referred(X, T) :- category(X, \"BUS\"), present(X, T).\nrelated(X, Y, T) :- referred(X, T).\n",
        "E0201",
        "Y",
        "near(X, Y, T, _)",
        "referred(X, T) :- category(X, \"BUS\"), present(X, T).\nrelated(X, Y, T) :- referred(X, T), near(X, Y, T, _).\n",
    );
}

#[test]
fn a_fact_with_variables_becomes_a_rule_over_every_value() {
    fixes_to(
        "slow(X).\nreferred(X, T) :- slow(X), present(X, T).\n",
        "E0201",
        "X",
        "a fact's arguments are constants",
        "slow(X) :- present(X, _).\nreferred(X, T) :- slow(X), present(X, T).\n",
    );
}

#[test]
fn a_wildcard_in_a_head_is_named_after_a_body_variable() {
    fixes_to(
        "big(X, _) :- near(X, Y, T, D), D < 2.0, T > 0.\nreferred(X, T) :- big(X, Y), present(X, T), present(Y, T).\n",
        "E0201",
        "_",
        "`big(X, Y)`",
        "big(X, Y) :- near(X, Y, T, D), D < 2.0, T > 0.\nreferred(X, T) :- big(X, Y), present(X, T), present(Y, T).\n",
    );
}

#[test]
fn warnings_that_change_meaning_are_reported() {
    // A time compared with a float: 2.0 is two tenths of a second, not two seconds.
    let src =
        "referred(X, T2) :- turning(X, T1, \"left\"), turning(X, T2, \"left\"), T2 - T1 >= 2.0.\n";
    let all = diags(src);
    let d = all.iter().find(|d| d.code == "W0504");
    assert!(
        d.is_some_and(
            |d| !d.is_error() && d.hint.as_deref().unwrap_or("").contains("`T2 - T1 >= 2 s`")
        ),
        "{all:#?}"
    );
    assert!(check(src, &CheckOptions::default()).program.is_some());
    assert!(diags(
        "referred(X, T2) :- turning(X, T1, \"left\"), turning(X, T2, \"left\"), T2 - T1 >= 2 s.\n"
    )
    .iter()
    .all(|d| d.code != "W0504"));
    // A time bound from a float: worded as a computation, not a comparison.
    let src = "referred(X, T2) :- turning(X, T, \"left\"), T2 = T + 0.5, present(X, T2).\n";
    let all = diags(src);
    let d = all.iter().find(|d| d.code == "W0504");
    assert!(
        d.is_some_and(|d| d.message.contains("computed with a bare float")
            && !d.message.contains("compared")
            && d.hint.as_deref().unwrap_or("").contains("`T2 = T + 0.5 s`")),
        "{all:#?}"
    );
    // A count whose every variable also occurs outside: always 0 or 1.
    let src = "referred(P, T) :- category(P, \"PEDESTRIAN\"), near(P, Q, T, D), D < 5.0,\n    \
               N = count : { near(P, Q, T, D) }, N >= 3.\n";
    let all = diags(src);
    let d = all.iter().find(|d| d.code == "W0505");
    assert!(
        d.is_some_and(|d| d.hint.as_deref().unwrap_or("").contains("`Q2`")),
        "{all:#?}"
    );
    let ok = "referred(P, T) :- category(P, \"PEDESTRIAN\"), near(P, Q, T, D), D < 5.0,\n    \
              N = count : { near(P, Q2, T, D2), D2 < 5.0 }, N >= 3, Q != P.\n";
    assert!(
        diags(ok).iter().all(|d| d.code != "W0505"),
        "{:#?}",
        diags(ok)
    );
}

#[test]
fn the_concepts_closed_columns_are_checked_and_their_aliases_fixed() {
    // lane_direction's Rel column takes the relative headings: "against" is an alias of
    // "opposite", a typo is an error with a did-you-mean.
    fixes_to(
        "referred(X, T) :- lane_direction(X, T, \"against\").\n",
        "E0104",
        "\"against\"",
        "against traffic is opposite",
        "referred(X, T) :- lane_direction(X, T, \"opposite\").\n",
    );
    let d = diags("referred(X, T) :- lane_direction(X, T, \"oposite\").\n");
    assert!(d.iter().any(|d| d.code == "E0104"), "{d:#?}");
    // The construction super-category is a value; a construction sign is an alias.
    let clean = diags("referred(X, T) :- category(X, \"CONSTRUCTION\"), present(X, T).\n");
    assert!(clean.iter().all(|d| !d.is_error()), "{clean:#?}");
    fixes_to(
        "referred(X, T) :- category(X, \"CONSTRUCTION_SIGN\"), present(X, T).\n",
        "E0104",
        "\"CONSTRUCTION_SIGN\"",
        "no construction-sign class",
        "referred(X, T) :- category(X, \"CONSTRUCTION\"), present(X, T).\n",
    );
}
