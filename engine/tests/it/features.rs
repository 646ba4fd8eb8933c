//! Hand-written cases for each feature of the engine, and regression tests for the two datafrog
//! 2.0.1 defects the engine avoids.

use scenalog_engine::{evaluate, EngineError, Evaluation, Options};
use scenalog_facts::relation::{RelationData, Request, Value};
use scenalog_rules::{check, CheckOptions};

/// Checks `src` (no `referred` needed) and evaluates it with no catalog.
pub(crate) fn run_with(src: &str, options: &Options) -> Result<Evaluation, EngineError> {
    let outcome = check(
        src,
        &CheckOptions {
            require_referred: false,
        },
    );
    let Some(program) = outcome.program else {
        panic!("program does not check: {:?}", outcome.diagnostics);
    };
    let mut provider = |r: &Request| -> Result<RelationData, String> {
        Err(format!("no catalog here (asked for {})", r.name))
    };
    evaluate(&program, &mut provider, options)
}

fn run(src: &str) -> Evaluation {
    match run_with(src, &Options::default()) {
        Ok(e) => e,
        Err(e) => panic!("evaluation failed: {e}"),
    }
}

/// The tuples of `rel`, every value an integer (or time).
pub(crate) fn ints(e: &Evaluation, rel: &str) -> Vec<Vec<i64>> {
    e.tuples(rel)
        .unwrap_or_default()
        .iter()
        .map(|t| {
            t.iter()
                .map(|v| match v {
                    Value::Int(i) => *i,
                    Value::Time(t) => i64::from(*t),
                    other => panic!("not an int: {other:?}"),
                })
                .collect()
        })
        .collect()
}

#[test]
fn transitive_closure_of_a_chain() {
    let mut src = String::from(
        ".decl edge(X: int, Y: int)\n.decl path(X: int, Y: int)\n\
         path(X, Y) :- edge(X, Y).\npath(X, Z) :- path(X, Y), edge(Y, Z).\n",
    );
    for i in 0..30 {
        src.push_str(&format!("edge({i}, {}).\n", i + 1));
    }
    let e = run(&src);
    // 31 nodes in a chain: 31 * 30 / 2 pairs.
    assert_eq!(e.size("path"), 465);
    assert_eq!(e.size("edge"), 30);
    let p = ints(&e, "path");
    assert_eq!(p[0], vec![0, 1]);
    assert_eq!(p[p.len() - 1], vec![29, 30]);
    assert!(e.derived.contains(&"path".to_string()));
}

#[test]
fn negation_against_a_lower_stratum() {
    let src = ".decl node(X: int)\n.decl edge(X: int, Y: int)\n.decl reach(X: int)\n.decl unreached(X: int)\n\
        node(1). node(2). node(3). node(4).\nedge(1, 2). edge(2, 3).\n\
        reach(1).\nreach(Y) :- reach(X), edge(X, Y).\n\
        unreached(X) :- node(X), !reach(X).\n";
    let e = run(src);
    assert_eq!(ints(&e, "reach"), vec![vec![1], vec![2], vec![3]]);
    assert_eq!(ints(&e, "unreached"), vec![vec![4]]);
}

#[test]
fn negation_with_wildcards_and_constants() {
    let src = ".decl p(X: int, Y: int)\n.decl q(X: int)\n.decl r(X: int)\n.decl s(X: int)\n\
        p(1, 10). p(2, 20). q(1). q(2). q(3).\n\
        r(X) :- q(X), !p(X, _).\n\
        s(X) :- q(X), !p(X, 20).\n";
    let e = run(src);
    assert_eq!(ints(&e, "r"), vec![vec![3]]);
    assert_eq!(ints(&e, "s"), vec![vec![1], vec![3]]);
}

#[test]
fn comparisons_arithmetic_and_bindings() {
    let src = ".decl v(X: int, Y: float)\n.decl big(X: int)\n.decl twice(X: int, Z: int)\n.decl neg(X: float)\n\
        v(1, -2.5). v(2, 0.5). v(3, 4.0).\n\
        big(X) :- v(X, Y), Y > 0.0, X != 3.\n\
        twice(X, Z) :- v(X, _), Z = X * 2 + 1.\n\
        neg(Y) :- v(_, Y), Y < 0.0.\n";
    let e = run(src);
    assert_eq!(ints(&e, "big"), vec![vec![2]]);
    assert_eq!(ints(&e, "twice"), vec![vec![1, 3], vec![2, 5], vec![3, 7]]);
    assert_eq!(e.tuples("neg"), Some(&[vec![Value::Float(-2.5)]][..]));
}

#[test]
fn sustained_runs_by_t_plus_one_recursion() {
    // run(X, S, T): X is fast at every frame from S to T.
    let src = ".decl fast(X: int, T: int)\n.decl run(X: int, S: int, T: int)\n\
        fast(1, 0). fast(1, 1). fast(1, 2). fast(1, 5). fast(2, 3).\n\
        run(X, T, T) :- fast(X, T).\n\
        run(X, S, U) :- run(X, S, T), U = T + 1, fast(X, U).\n";
    let e = run(src);
    assert_eq!(
        ints(&e, "run"),
        vec![
            vec![1, 0, 0],
            vec![1, 0, 1],
            vec![1, 0, 2],
            vec![1, 1, 1],
            vec![1, 1, 2],
            vec![1, 2, 2],
            vec![1, 5, 5],
            vec![2, 3, 3]
        ]
    );
}

#[test]
fn strings_sort_by_text_and_repeated_variables_select() {
    let src = ".decl n(X: str, Y: str)\n.decl same(X: str)\n\
        n(\"b\", \"b\"). n(\"a\", \"c\"). n(\"c\", \"c\").\n\
        same(X) :- n(X, X).\n";
    let e = run(src);
    let s: Vec<String> = e
        .tuples("same")
        .unwrap_or_default()
        .iter()
        .map(|t| format!("{:?}", t[0]))
        .collect();
    assert_eq!(s, vec!["Str(\"b\")", "Str(\"c\")"]);
}

/// The string tuples of `rel`, each as its texts.
fn strs(e: &Evaluation, rel: &str) -> Vec<Vec<String>> {
    e.tuples(rel)
        .unwrap_or_default()
        .iter()
        .map(|t| {
            t.iter()
                .map(|v| match v {
                    Value::Str(s) => s.to_string(),
                    other => panic!("not a string: {other:?}"),
                })
                .collect()
        })
        .collect()
}

#[test]
fn strings_are_ordered_by_text_in_comparisons_min_and_max() {
    // Met in the order b, a, c: an order by first meeting would give lt("b", "a") (Soufflé's
    // answer is lt("a", "b"), lt("a", "c"), lt("b", "c")).
    let src = "s(\"b\"). s(\"a\"). s(\"c\").\n\
        lt(X, Y) :- s(X), s(Y), X < Y.\n\
        le(X) :- s(X), X <= \"b\".\n\
        gt(X) :- s(X), \"a\" < X.\n\
        lo(M) :- M = min X : { s(X) }.\n\
        hi(M) :- M = max X : { s(X) }.\n\
        lo2(M) :- s(Y), M = min X : { s(X), X > Y }.\n";
    let e = run(src);
    let v = |x: &[&str]| x.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    assert_eq!(
        strs(&e, "lt"),
        vec![v(&["a", "b"]), v(&["a", "c"]), v(&["b", "c"])]
    );
    assert_eq!(strs(&e, "le"), vec![v(&["a"]), v(&["b"])]);
    assert_eq!(strs(&e, "gt"), vec![v(&["b"]), v(&["c"])]);
    assert_eq!(strs(&e, "lo"), vec![v(&["a"])]);
    assert_eq!(strs(&e, "hi"), vec![v(&["c"])]);
    assert_eq!(strs(&e, "lo2"), vec![v(&["b"]), v(&["c"])]);
    // A string first met after the comparison was planned (a later clause of the same
    // recursive stratum), and met after "p" though its text sorts before: still by text.
    let late = "s(\"b\").\n\
        u(Y) :- v(Y), Y < \"p\".\n\
        v(\"aa\") :- s(\"b\").\n\
        v(Y) :- u(Y).\n";
    assert_eq!(strs(&run(late), "u"), vec![v(&["aa"])]);
}

#[test]
fn expression_arguments_are_joined_before_or_after_what_binds_them() {
    // Soufflé's answers: g = {1, 2, 3} (with the fact 4), c = {2, 3}.
    let e = run("g(4). v(1). v(2). v(3).\ng(X) :- g(X + 1), v(X).\n");
    assert_eq!(ints(&e, "g"), vec![vec![1], vec![2], vec![3], vec![4]]);
    let e = run("p(4, 2). p(6, 3). p(5, 1).\nc(N) :- p(2 * N, N).\n");
    assert_eq!(ints(&e, "c"), vec![vec![2], vec![3]]);
    // Written the other way round, the same answer.
    let e = run("g(4). v(1). v(2). v(3).\ng(X) :- v(X), g(X + 1).\n");
    assert_eq!(ints(&e, "g"), vec![vec![1], vec![2], vec![3], vec![4]]);
    // An expression of a variable the same atom binds earlier is compared after the lookup,
    // not computed before it (that read an unbound slot and found nothing: Soufflé's `tak`).
    let src = "t(0, 0, 1, 7). t(1, 0, 2, 8). t(1, 0, 3, 9). t(2, 1, 4, 4).\n\
               q(N, Q) :- t(N, 0, N + 1, Q).\n\
               r(N, Q) :- t(N, Z, N + Z + 1, Q).\n";
    let e = run(src);
    assert_eq!(ints(&e, "q"), vec![vec![0, 7], vec![1, 8]]);
    assert_eq!(ints(&e, "r"), vec![vec![0, 7], vec![1, 8], vec![2, 4]]);
}

#[test]
fn aggregates_are_scoped_as_souffle_scopes_them() {
    // The result's name reused inside the braces names a variable local to them: r(2).
    let e = run("a(1). a(2).\nr(Y) :- Y = min Z + Y : { a(Z), a(Y) }.\n");
    assert_eq!(ints(&e, "r"), vec![vec![2]]);
    // A nested aggregate grouped by the variables of the braces around it: 0 + 1 + 2.
    let e = run("p(1). p(2). p(3).\nd(S) :- S = sum Y : { p(N), Y = count : { p(Z), Z < N } }.\n");
    assert_eq!(ints(&e, "d"), vec![vec![3]]);
    // Braces with no variable: the count of matching tuples (one or none).
    let e = run("a(1).\nc(N) :- N = count : { a(1) }.\nd(N) :- N = count : { a(2) }.\n");
    assert_eq!(ints(&e, "c"), vec![vec![1]]);
    assert_eq!(ints(&e, "d"), vec![vec![0]]);
    let e = run("a().\nc(N) :- N = count : { a() }.\n");
    assert_eq!(ints(&e, "c"), vec![vec![1]]);
}

#[test]
fn min_and_max_witnesses_are_the_tuples_that_reach_them() {
    // Soufflé's aggregate_witnesses, with its answers.
    let src = "student(\"Anna\", 170). student(\"Rachel\", 177). student(\"Quarantina\", 180).\n\
               tallest(S, N) :- N = max H : { student(S, H) }.\n\
               a(1, 2). a(5, 6). a(-50, 3). a(54, 5).\n\
               min_sum(X, Y, S) :- S = min W : { a(X, Y), W = X + Y }.\n\
               min_sum_not_reduced(X, Y, S) :- S = min X + Y : { a(X, Y) }.\n\
               d(1, 1). d(1, 2). d(1, 3). d(1, 4).\n\
               h(1, 2, 3). h(24, 5, 6). h(7, 8, 9). h(10, 11, 12).\n\
               two(X, Y) :- _ = min X + Y : { d(X, Y) }.\n\
               one(R, W) :- R = min 2 * W : { d(W, _) }.\n\
               sides(R, W1, W2) :- R = max X : { h(X, W1, W2) }.\n\
               tie(W) :- _ = max Y : { d(Y, W) }.\n\
               per(X, W) :- d(X, _), _ = max Z : { d(X, Z), W = Z * 10 }.\n";
    let e = run(src);
    assert_eq!(
        e.tuples("tallest").unwrap_or_default(),
        &[vec![Value::Str("Quarantina".into()), Value::Int(180)]]
    );
    assert_eq!(ints(&e, "min_sum"), vec![vec![-50, 3, -47]]);
    assert_eq!(ints(&e, "min_sum_not_reduced"), vec![vec![-50, 3, -47]]);
    assert_eq!(ints(&e, "two"), vec![vec![1, 1]]);
    assert_eq!(ints(&e, "one"), vec![vec![2, 1]]);
    assert_eq!(ints(&e, "sides"), vec![vec![24, 5, 6]]);
    // On a tie every witness is an answer; a group variable bound outside keeps grouping.
    assert_eq!(ints(&e, "tie"), vec![vec![1], vec![2], vec![3], vec![4]]);
    assert_eq!(ints(&e, "per"), vec![vec![1, 40]]);
    // `count` and `sum` have no witnesses: a head variable bound only in their braces is unsafe.
    let outcome = check(
        "d(1, 1).\nc(W, N) :- N = count : { d(W, _) }.\n",
        &CheckOptions {
            require_referred: false,
        },
    );
    assert!(outcome.diagnostics.iter().any(|d| d.code == "E0201"));
}

#[test]
fn a_relation_no_one_reads_is_derived_only_where_its_uses_bind_it() {
    // `slow` over 1,000 objects, read only for the 10 buses: with demand, `slow` holds those.
    let mut src = String::new();
    for i in 0..1000 {
        let kind = if i % 100 == 0 { "BUS" } else { "CAR" };
        src.push_str(&format!(
            "v_kind({i}, \"{kind}\"). v_speed({i}, {}).\n",
            i % 7
        ));
    }
    src.push_str("slow(X, S) :- v_speed(X, S), S < 3.\n");
    src.push_str("r(X, S) :- v_kind(X, \"BUS\"), slow(X, S).\n");
    // A second use (a relation used once is inlined instead: see the next tests).
    src.push_str("r2(X) :- v_kind(X, \"BUS\"), slow(X, 1).\n");
    // A negated use keeps a relation whole; so does a use inside an aggregate's braces.
    src.push_str("fast(X) :- v_speed(X, S), S >= 5.\n");
    src.push_str("q(X) :- v_kind(X, \"BUS\"), !fast(X).\n");
    src.push_str("n(C) :- C = count : { fast(_) }.\n");
    let whole = run(&src);
    let demand = Options {
        reads: Some(vec!["r".into(), "r2".into(), "q".into(), "n".into()]),
        ..Options::default()
    };
    let e = run_with(&src, &demand).expect("evaluates");
    for rel in ["r", "r2", "q", "n"] {
        assert_eq!(ints_of(&e, rel), ints_of(&whole, rel), "{rel}");
    }
    assert_eq!(whole.size("slow"), 429);
    assert_eq!(e.size("slow"), 5, "only the buses' slow tuples");
    assert_eq!(e.size("fast"), whole.size("fast"));
    // With provenance (explanations read every relation), nothing is restricted.
    let proven = run_with(
        &src,
        &Options {
            provenance: true,
            ..demand
        },
    )
    .expect("evaluates");
    assert_eq!(proven.size("slow"), 429);
}

#[test]
fn columns_bound_by_unrelated_atoms_are_not_paired_by_demand() {
    // `p` is bound in X by 100 `a` facts and in Y by 100 `b` facts: one magic relation over both
    // columns would hold their 10,000 pairs, past the budget of 5,000; one per column holds 100
    // values each, and `p` (200 tuples) only those of the 20 with both ends demanded.
    let mut src = String::new();
    for i in 0..100 {
        src.push_str(&format!("a({i}, \"k\"). b({}, \"k\").\n", i + 1000));
    }
    for i in 0..200 {
        src.push_str(&format!("q({}, {}).\n", i * 5, 1000 + i));
    }
    src.push_str("p(X, Y) :- q(X, Y).\n");
    src.push_str("r(X, Y) :- a(X, \"k\"), b(Y, \"k\"), p(X, Y).\n");
    src.push_str("r2(Y, X) :- b(Y, \"k\"), a(X, \"k\"), p(X, Y).\n");
    let whole = run(&src);
    let options = Options {
        max_tuples: 5000,
        reads: Some(vec!["r".into(), "r2".into()]),
        ..Options::default()
    };
    let e = run_with(&src, &options).expect("evaluates within the budget");
    assert_eq!(ints_of(&e, "r"), ints_of(&whole, "r"));
    assert_eq!(ints_of(&e, "r2"), ints_of(&whole, "r2"));
    assert_eq!(e.size("r"), 20);
    assert_eq!(whole.size("p"), 200);
    assert_eq!(e.size("p"), 20, "only the pairs with both ends demanded");
}

#[test]
fn a_relation_used_once_and_not_read_is_inlined_not_stored() {
    // Soufflé's example/inline_nats: `pair` is nat x nat (10^8 tuples), read once on its
    // diagonal below 2; inlined, the rule joins `nat` with itself on X and keeps two tuples.
    let mut src = String::from("nat(0).\nnat(X + 1) :- X < 10000, nat(X).\n");
    src.push_str("pair(X, Y) :- nat(X), nat(Y).\n");
    src.push_str("query(X) :- pair(X, X), X < 2.\n");
    // Inlined into a use with `_`, a relation of two rules, one of them negating.
    src.push_str("k(1, 7). k(2, 8). k(3, 9). bad(8).\n");
    src.push_str("good(X, Z) :- k(X, Z), !bad(Z).\ngood(X, Z) :- nat(X), X > 9998, Z = X * 2.\n");
    src.push_str("g(X) :- good(X, _), X != 1.\n");
    let options = Options {
        max_tuples: 50_000,
        reads: Some(vec!["query".into(), "g".into()]),
        ..Options::default()
    };
    let e = run_with(&src, &options).expect("evaluates within the budget");
    assert_eq!(ints(&e, "query"), vec![vec![0], vec![1]]);
    assert_eq!(ints(&e, "g"), vec![vec![3], vec![9999], vec![10000]]);
    assert_eq!(e.size("pair"), 0, "never stored");
    // Read, `pair` is derived in full, past the budget.
    let read = Options {
        reads: Some(vec!["query".into(), "pair".into()]),
        ..options
    };
    assert!(run_with(&src, &read).is_err());
}

/// The tuples of `rel` with every value printed (ints and strings alike).
fn ints_of(e: &Evaluation, rel: &str) -> Vec<String> {
    e.tuples(rel)
        .unwrap_or_default()
        .iter()
        .map(|t| format!("{t:?}"))
        .collect()
}

#[test]
fn atoms_that_only_test_existence_are_not_enumerated() {
    // 1,001 facts: the product of three `e(_)` is 10^9 bindings, all the same; the budget of
    // 5,000 tuples would stop an evaluation that enumerated them.
    let mut src: String = (0..1001).map(|i| format!("e({i}).\n")).collect();
    src.push_str("n(1). n(2). n(3).\nk(2, 7). k(2, 8). k(3, 9).\n");
    src.push_str("q(1) :- e(_), e(_), e(_).\n");
    // Existence tests between, before and after atoms that bind, with a filter after them.
    src.push_str("r(X) :- n(X), e(_), k(X, _), e(Y), X < 3.\n");
    src.push_str("s(X, Z) :- e(_), n(X), k(X, Z), e(W), W > 999.\n");
    let options = Options {
        max_tuples: 5000,
        timeout: None,
        provenance: false,
        pushdown: true,
        wide_rows: false,
        reads: None,
    };
    let e = run_with(&src, &options).expect("evaluates within the budget");
    assert_eq!(ints(&e, "q"), vec![vec![1]]);
    assert_eq!(ints(&e, "r"), vec![vec![2]]);
    assert_eq!(ints(&e, "s"), vec![vec![2, 7], vec![2, 8], vec![3, 9]]);
}

#[test]
fn a_run_of_atoms_nothing_later_reads_is_joined_until_it_matches() {
    // Soufflé's independent_body: `c(Y), d(Y)` shares no variable with the rest of the body,
    // so one matching pair stands for all 1,000; enumerating them would push 100 x 1,000 head
    // tuples, past the budget of 5,000.
    let mut src: String = (0..100).map(|i| format!("b({i}).\n")).collect();
    src.extend((0..1000).map(|i| format!("c({i}). d({i}).\n")));
    src.push_str("a(X) :- b(X), c(Y), d(Y).\n");
    // A run in the middle, with a filter inside it, then an atom that binds again.
    src.push_str("m(X, Z) :- b(X), c(Y), d(W), W = Y + 999, b(Z), Z = X + 1.\n");
    // Not a run: the head reads Y, so every pair counts (two of them pass the filter).
    src.push_str("h(X, Y) :- b(X), X < 2, c(Y), d(Y), Y > 997.\n");
    let options = Options {
        max_tuples: 5000,
        ..Options::default()
    };
    let e = run_with(&src, &options).expect("evaluates within the budget");
    assert_eq!(ints(&e, "a").len(), 100);
    assert_eq!(ints(&e, "m").len(), 99);
    assert_eq!(
        ints(&e, "h"),
        vec![vec![0, 998], vec![0, 999], vec![1, 998], vec![1, 999]]
    );
}

#[test]
fn modulo_and_power_as_souffle_computes_them() {
    // Soufflé's `%` (written `mod`) keeps the dividend's sign; `^` of integers is an integer,
    // a negative exponent truncated toward zero; by zero, or past 64 bits, no tuple.
    let src = "n(7). n(-7). n(2). n(0).\n\
        r(X, Y, Z) :- n(X), n(Y), Z = X mod Y.\n\
        p(X, Z) :- n(X), Z = X ^ 2 - 2 ^ -1 + 1 ^ 99999999999.\n\
        big(Z) :- n(X), X > 0, Z = X ^ 40.\n\
        s(A, B, C) :- A = -2 ^ 2, B = 2 ^ 3 ^ 2, C = 7 mod 2 * 3.\n";
    let e = run(src);
    assert_eq!(
        ints(&e, "r"),
        vec![
            vec![-7, -7, 0],
            vec![-7, 2, -1],
            vec![-7, 7, 0],
            vec![0, -7, 0],
            vec![0, 2, 0],
            vec![0, 7, 0],
            vec![2, -7, 2],
            vec![2, 2, 0],
            vec![2, 7, 2],
            vec![7, -7, 0],
            vec![7, 2, 1],
            vec![7, 7, 0],
        ]
    );
    assert_eq!(
        ints(&e, "p"),
        vec![vec![-7, 50], vec![0, 1], vec![2, 5], vec![7, 50]]
    );
    // 2^40 fits; 7^40 does not.
    assert_eq!(ints(&e, "big"), vec![vec![1 << 40]]);
    assert_eq!(ints(&e, "s"), vec![vec![-4, 512, 3]]);
}

#[test]
fn a_relation_that_grows_past_the_limit_is_named() {
    let src = ".decl n(X: int)\nn(0).\nn(Y) :- n(X), Y = X + 1.\n";
    let options = Options {
        max_tuples: 1000,
        timeout: None,
        provenance: false,
        pushdown: true,
        wide_rows: false,
        reads: None,
    };
    match run_with(src, &options) {
        Err(EngineError::TooManyTuples { relation, limit }) => {
            assert_eq!(relation, "n");
            assert_eq!(limit, 1000);
        }
        other => panic!("expected a limit error, got {other:?}"),
    }
}

#[test]
fn a_timeout_is_reported_with_the_relation() {
    let src = ".decl n(X: int)\nn(0).\nn(Y) :- n(X), Y = X + 1.\n";
    let options = Options {
        max_tuples: usize::MAX,
        timeout: Some(std::time::Duration::from_millis(50)),
        provenance: false,
        pushdown: true,
        wide_rows: false,
        reads: None,
    };
    match run_with(src, &options) {
        Err(EngineError::Timeout { relation, .. }) => assert_eq!(relation, "n"),
        other => panic!("expected a timeout, got {other:?}"),
    }
}

/// datafrog 2.0.1: `Relation::from_antijoin` yields nothing even when tuples have no match.
#[test]
fn datafrog_from_antijoin_returns_nothing_but_the_engine_negates() {
    let input = datafrog::Relation::from_vec(vec![(1u32, 10u32), (2, 20), (3, 30)]);
    let remove = datafrog::Relation::from_vec(vec![2u32]);
    let out = datafrog::Relation::from_antijoin(&input, &remove, |&k, &v| (k, v));
    // The correct answer would be [(1, 10), (3, 30)].
    assert_eq!(out.elements.len(), 0, "datafrog's antijoin was fixed");
    let src = ".decl p(X: int, Y: int)\n.decl rm(X: int)\n.decl out(X: int, Y: int)\n\
        p(1, 10). p(2, 20). p(3, 30). rm(2).\nout(X, Y) :- p(X, Y), !rm(X).\n";
    assert_eq!(ints(&run(src), "out"), vec![vec![1, 10], vec![3, 30]]);
}

/// datafrog 2.0.1: a leapjoin made only of filters (no proposing leaper) panics.
#[test]
fn datafrog_all_filter_leapjoin_panics_but_the_engine_filters() {
    let result = std::panic::catch_unwind(|| {
        let mut iteration = datafrog::Iteration::new();
        let source = iteration.variable::<(u32, u32)>("source");
        source.extend(vec![(1u32, 1u32), (2, 3)]);
        let out = iteration.variable::<(u32, u32)>("out");
        let banned = datafrog::Relation::from_vec(vec![(2u32, 3u32)]);
        let allowed = datafrog::Relation::from_vec(vec![(1u32, 1u32), (2, 3)]);
        while iteration.changed() {
            let not_banned = datafrog::FilterAnti::from(&banned, |&(k, v): &(u32, u32)| (k, v));
            let known = datafrog::FilterWith::from(&allowed, |&(k, v): &(u32, u32)| (k, v));
            out.from_leapjoin(&source, (not_banned, known), |&(k, v), _: &()| (k, v));
        }
    });
    assert!(
        result.is_err(),
        "datafrog's all-filter leapjoin no longer panics"
    );
    let src = ".decl s(X: int, Y: int)\n.decl banned(X: int)\n.decl out(X: int, Y: int)\n\
        s(1, 1). s(2, 3). banned(2).\nout(X, Y) :- s(X, Y), !banned(X).\n";
    assert_eq!(ints(&run(src), "out"), vec![vec![1, 1]]);
}

#[test]
fn count_groups_by_outer_variables_and_counts_empty_groups_as_zero() {
    let src = ".decl node(X: int)\n.decl edge(X: int, Y: int)\n.decl degree(X: int, N: int)\n.decl total(N: int)\n\
        node(1). node(2). node(3).\nedge(1, 2). edge(1, 3). edge(2, 3). edge(2, 3).\n\
        degree(X, N) :- node(X), N = count : { edge(X, Y) }.\n\
        total(N) :- N = count : { edge(_, Y) }.\n";
    let e = run(src);
    assert_eq!(ints(&e, "degree"), vec![vec![1, 2], vec![2, 1], vec![3, 0]]);
    // The matching tuples of the body (the `_` is a fresh variable, as in Soufflé): the three
    // distinct edges, not the two distinct values of Y.
    assert_eq!(ints(&e, "total"), vec![vec![3]]);
}

#[test]
fn aggregates_fold_over_matching_tuples_so_wildcards_and_brace_local_variables_count() {
    // Node 1 has four out-edges; `count : { edge(X, _) }` is 4, not 1 (issue 14).
    let src = ".decl node(X: int)
.decl edge(X: int, Y: int)
.decl w(X: int, Y: int, V: int)
        .decl out_deg(X: int, N: int)
.decl local_deg(X: int, N: int)
.decl s(X: int, N: int)
        .decl lo(X: int, N: int)
.decl hi(X: int, N: int)
.decl pairs(X: int, N: int)
        .decl around(X: int, N: int)
        node(1). node(2). node(3).
        edge(1, 2). edge(1, 3). edge(1, 4). edge(1, 5). edge(2, 3).
        w(1, 2, 7). w(1, 3, 7). w(1, 4, 1). w(2, 3, 5).
        out_deg(X, N) :- node(X), N = count : { edge(X, _) }.
        local_deg(X, N) :- node(X), N = count : { edge(X, Y) }.
        s(X, N) :- node(X), N = sum V : { w(X, _, V) }.
        lo(X, N) :- node(X), N = min V : { w(X, _, V) }.
        hi(X, N) :- node(X), N = max V : { w(X, _, V) }.
        pairs(X, N) :- node(X), N = count : { edge(X, Y), edge(Y, _) }.
        around(X, N) :- node(X), N = count : { edge(_, Z), Z > X }.
";
    let e = run(src);
    assert_eq!(
        ints(&e, "out_deg"),
        vec![vec![1, 4], vec![2, 1], vec![3, 0]]
    );
    assert_eq!(ints(&e, "out_deg"), ints(&e, "local_deg"));
    // 7 + 7 + 1: the two weights of 7 sit on different tuples and both count.
    assert_eq!(ints(&e, "s"), vec![vec![1, 15], vec![2, 5], vec![3, 0]]);
    assert_eq!(ints(&e, "lo"), vec![vec![1, 1], vec![2, 5]]);
    assert_eq!(ints(&e, "hi"), vec![vec![1, 7], vec![2, 5]]);
    // Combinations: (1,2)+(2,3) only; node 2's (2,3) has no out-edge of 3.
    assert_eq!(ints(&e, "pairs"), vec![vec![1, 1], vec![2, 0], vec![3, 0]]);
    // Correlated (X only in a comparison): edges whose target is above X, each edge once.
    assert_eq!(ints(&e, "around"), vec![vec![1, 5], vec![2, 4], vec![3, 2]]);
}

#[test]
fn min_max_and_sum_per_group() {
    let src = ".decl d(X: int, V: int)\n.decl k(X: int)\n.decl lo(X: int, M: int)\n.decl hi(X: int, M: int)\n.decl s(X: int, M: int)\n\
        k(1). k(2). k(3).\nd(1, 5). d(1, -2). d(1, 9). d(2, 4).\n\
        lo(X, M) :- k(X), M = min V : { d(X, V) }.\n\
        hi(X, M) :- k(X), M = max V : { d(X, V) }.\n\
        s(X, M) :- k(X), M = sum V : { d(X, V) }.\n";
    let e = run(src);
    assert_eq!(ints(&e, "lo"), vec![vec![1, -2], vec![2, 4]]);
    assert_eq!(ints(&e, "hi"), vec![vec![1, 9], vec![2, 4]]);
    assert_eq!(ints(&e, "s"), vec![vec![1, 12], vec![2, 4], vec![3, 0]]);
}

#[test]
fn provider_is_asked_only_for_used_relations_with_the_constraints_the_program_fixes() {
    use scenalog_facts::relation::{Column, Constraint};
    use scenalog_facts::scene::TrackId;
    let src = "fast_bus(X, T) :- category(X, \"BUS\"), speed(X, T, S), S > 10.0.\n\
        referred(X, T) :- fast_bus(X, T).\n";
    let outcome = check(src, &CheckOptions::default());
    let Some(program) = outcome.program else {
        panic!("{:?}", outcome.diagnostics);
    };
    let mut asked: Vec<Request> = Vec::new();
    let mut provider = |r: &Request| -> Result<RelationData, String> {
        asked.push(r.clone());
        // A superset of what is needed: the engine must still filter.
        match r.name.as_str() {
            "category" => Ok(RelationData {
                name: r.name.clone(),
                columns: vec![
                    Column::Track(vec![TrackId(1), TrackId(2)]),
                    Column::Str(vec!["BUS".into(), "PEDESTRIAN".into()]),
                ],
            }),
            "speed" => Ok(RelationData {
                name: r.name.clone(),
                columns: vec![
                    Column::Track(vec![TrackId(1), TrackId(1), TrackId(2)]),
                    Column::Time(vec![0, 1, 0]),
                    Column::Float(vec![12.0, 3.0, 20.0]),
                ],
            }),
            other => Err(format!("unexpected request for {other}")),
        }
    };
    let e = match evaluate(&program, &mut provider, &Options::default()) {
        Ok(e) => e,
        Err(e) => panic!("{e}"),
    };
    assert_eq!(
        e.tuples("fast_bus"),
        Some(&[vec![Value::Track(TrackId(1)), Value::Time(0)]][..])
    );
    let names: Vec<&str> = asked.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(names, vec!["category", "speed"]);
    assert_eq!(
        asked[0].constraints,
        vec![(1, Constraint::Eq(Value::Str("BUS".into())))]
    );
    assert_eq!(
        asked[1].constraints,
        vec![
            (0, Constraint::Category("BUS".into())),
            (2, Constraint::Gt(10.0)),
            // Pushdown: the buses `category` answered (track 2 is a pedestrian there).
            (0, Constraint::OneOf(vec![Value::Track(TrackId(1))].into())),
        ]
    );
}

#[test]
fn malformed_provided_relations_are_named() {
    use scenalog_facts::relation::Column;
    let src = "s(X, T) :- speed(X, T, _).\nreferred(X, T) :- s(X, T).\n";
    let outcome = check(src, &CheckOptions::default());
    let Some(program) = outcome.program else {
        panic!("{:?}", outcome.diagnostics);
    };
    let mut provider = |r: &Request| -> Result<RelationData, String> {
        Ok(RelationData {
            name: r.name.clone(),
            columns: vec![Column::Int(vec![1])],
        })
    };
    match evaluate(&program, &mut provider, &Options::default()) {
        Err(EngineError::BadInput { relation, .. }) => assert_eq!(relation, "speed"),
        other => panic!("expected a bad-input error, got {other:?}"),
    }
    let mut failing =
        |_: &Request| -> Result<RelationData, String> { Err("log missing".to_string()) };
    match evaluate(&program, &mut failing, &Options::default()) {
        Err(EngineError::Provider { relation, message }) => {
            assert_eq!(relation, "speed");
            assert_eq!(message, "log missing");
        }
        other => panic!("expected a provider error, got {other:?}"),
    }
}

fn proved(src: &str) -> Evaluation {
    let options = Options {
        provenance: true,
        ..Options::default()
    };
    match run_with(src, &options) {
        Ok(e) => e,
        Err(e) => panic!("evaluation failed: {e}"),
    }
}

fn show(p: &scenalog_engine::Proof, depth: usize, out: &mut String) {
    let args: Vec<String> = p.tuple.iter().map(|v| format!("{v:?}")).collect();
    out.push_str(&format!(
        "{}{}({}) by {:?}\n",
        "  ".repeat(depth),
        p.relation,
        args.join(", "),
        p.clause
    ));
    for c in &p.children {
        show(c, depth + 1, out);
    }
}

#[test]
fn proofs_of_recursive_tuples_bottom_out_in_ground_facts() {
    let src = ".decl edge(X: int, Y: int)\n.decl path(X: int, Y: int)\n\
        edge(1, 2). edge(2, 3). edge(3, 4). edge(1, 4).\n\
        path(X, Y) :- edge(X, Y).\npath(X, Z) :- path(X, Y), edge(Y, Z).\n";
    let e = proved(src);
    let p = match e.prove("path", &[Value::Int(1), Value::Int(3)]) {
        Some(p) => p,
        None => panic!("no proof"),
    };
    let mut text = String::new();
    show(&p, 0, &mut text);
    // Clauses 0-3 are the edge facts, 4 and 5 the rules.
    // path(1,3) <- path(1,2) <- edge(1,2) (fact, clause 0); edge(2,3) (fact, clause 1).
    assert_eq!(
        text,
        "path(Int(1), Int(3)) by Some(5)\n  path(Int(1), Int(2)) by Some(4)\n    \
         edge(Int(1), Int(2)) by Some(0)\n  edge(Int(2), Int(3)) by Some(1)\n"
    );
    assert_eq!(p.height(), 2);
    // path(1, 4) holds directly from edge(1, 4): round 0, height 1.
    let direct = e.prove("path", &[Value::Int(1), Value::Int(4)]);
    assert_eq!(direct.map(|p| p.height()), Some(1));
    let stamp = e.stamp("path", &[Value::Int(1), Value::Int(4)]);
    assert_eq!(stamp.map(|s| (s.round, s.clause)), Some((0, 4)));
    assert!(e.prove("path", &[Value::Int(4), Value::Int(1)]).is_none());
    // Without provenance there are no proofs.
    assert!(run(src)
        .prove("path", &[Value::Int(1), Value::Int(3)])
        .is_none());
}

/// A proof as deep as a 20,000-edge chain is built, measured and dropped without recursion
/// per level (the test thread's stack is 2 MiB; one frame per level would overflow it).
#[test]
fn a_proof_twenty_thousand_rounds_deep_does_not_overflow_the_stack() {
    const N: i64 = 20_000;
    let mut src = String::from(".decl edge(X: int, Y: int)\n.decl reach(X: int)\nreach(0).\n");
    for i in 0..N {
        src.push_str(&format!("edge({i}, {}).\n", i + 1));
    }
    src.push_str("reach(Y) :- reach(X), edge(X, Y).\n");
    let e = proved(&src);
    assert_eq!(e.size("reach"), N as usize + 1);
    let p = match e.prove("reach", &[Value::Int(N)]) {
        Some(p) => p,
        None => panic!("no proof"),
    };
    assert_eq!(p.height(), N as usize);
    // Down the left spine: reach(N - 1), reach(N - 2), ... reach(0), each with its edge.
    let mut node = &p;
    let mut depth = 0;
    while let [first, edge] = node.children.as_slice() {
        assert_eq!(edge.relation, "edge");
        assert_eq!(
            edge.tuple,
            vec![Value::Int(N - 1 - depth), Value::Int(N - depth)]
        );
        node = first;
        depth += 1;
    }
    assert_eq!(depth, N);
    assert_eq!(node.tuple, vec![Value::Int(0)]);
}

#[test]
fn proofs_through_negation_bindings_and_t_plus_one() {
    let src =
        ".decl fast(X: int, T: int)\n.decl stopped(X: int)\n.decl run(X: int, S: int, T: int)\n\
        .decl moving_run(X: int, S: int, T: int)\n\
        fast(1, 0). fast(1, 1). fast(1, 2). stopped(2). fast(2, 0).\n\
        run(X, T, T) :- fast(X, T).\n\
        run(X, S, U) :- run(X, S, T), U = T + 1, fast(X, U).\n\
        moving_run(X, S, T) :- run(X, S, T), !stopped(X).\n";
    let e = proved(src);
    let p = match e.prove("moving_run", &[Value::Int(1), Value::Int(0), Value::Int(2)]) {
        Some(p) => p,
        None => panic!("no proof"),
    };
    // moving_run <- run(1,0,2) <- run(1,0,1) <- run(1,0,0) <- fast(1,0).
    assert_eq!(p.height(), 4);
    assert_eq!(p.children.len(), 1);
    assert!(e
        .prove("moving_run", &[Value::Int(2), Value::Int(0), Value::Int(0)])
        .is_none());
}

#[test]
fn correlated_aggregates_use_outer_variables_in_comparisons() {
    // The fastest speed within one frame either side of each frame.
    let src = ".decl sp(X: int, T: int, S: float)\n.decl at(X: int, T: int)\n.decl fastest(X: int, T: int, M: float)\n\
        .decl around(X: int, T: int, N: int)\n\
        sp(1, 0, 1.0). sp(1, 1, 5.0). sp(1, 2, 2.0). sp(1, 3, 0.5). at(1, 0). at(1, 3). at(1, 9).\n\
        fastest(X, T, M) :- at(X, T), M = max S : { sp(X, T2, S), T2 >= T - 1, T2 <= T + 1 }.\n\
        around(X, T, N) :- at(X, T), N = count : { sp(X, T2, _), T2 >= T - 1, T2 <= T + 1 }.\n";
    let e = run(src);
    assert_eq!(
        e.tuples("fastest"),
        Some(
            &[
                vec![Value::Int(1), Value::Int(0), Value::Float(5.0)],
                vec![Value::Int(1), Value::Int(3), Value::Float(2.0)]
            ][..]
        )
    );
    assert_eq!(
        ints(&e, "around"),
        vec![vec![1, 0, 2], vec![1, 3, 2], vec![1, 9, 0]]
    );
}

/// Inputs and derived relations share one budget: two relations of 600 tuples each pass a
/// per-relation limit of 1,000 but not a budget of 1,000 for the whole evaluation.
#[test]
fn the_tuple_budget_counts_every_relation_together() {
    let src = ".decl a(X: int)\n.decl b(X: int)\na(0).\na(Y) :- a(X), Y = X + 1, Y < 600.\nb(Y) :- a(X), Y = X + 1000.\n";
    let options = Options {
        max_tuples: 1000,
        timeout: None,
        provenance: false,
        pushdown: true,
        wide_rows: false,
        reads: None,
    };
    match run_with(src, &options) {
        Err(EngineError::TooManyTuples { relation, limit }) => {
            assert_eq!(relation, "b");
            assert_eq!(limit, 1000);
        }
        other => panic!("expected the budget to run out in `b`, got {other:?}"),
    }
    let roomy = Options {
        max_tuples: 1200,
        ..options
    };
    let e = run_with(src, &roomy).expect("fits in 1,200");
    assert_eq!((e.size("a"), e.size("b")), (600, 600));
}

/// A `sum` past the 64-bit range is an error naming the rule's relation, never a saturated
/// number: both for an aggregate over completed relations and for one run per binding.
#[test]
fn an_integer_sum_that_overflows_is_an_error_naming_the_rule() {
    let plain = ".decl v(X: int)\nv(9223372036854775807).\nv(1).\ns(N) :- N = sum X : { v(X) }.\n";
    let correlated = ".decl v(X: int)\n.decl k(X: int)\nv(9223372036854775807).\nv(1).\nk(0).\ng(K, N) :- k(K), N = sum X : { v(X), X > K }.\n";
    for (src, rel) in [(plain, "s"), (correlated, "g")] {
        match run_with(src, &Options::default()) {
            Err(e @ EngineError::Overflow { .. }) => {
                assert_eq!(
                    e,
                    EngineError::Overflow {
                        relation: rel.into()
                    }
                );
                assert!(e.to_string().contains(&format!("`{rel}`")), "{e}");
            }
            other => panic!("expected an overflow in `{rel}`, got {other:?}"),
        }
    }
    // Just inside the range still sums exactly.
    let fits = ".decl v(X: int)\nv(9223372036854775806).\nv(1).\ns(N) :- N = sum X : { v(X) }.\n";
    let e = run_with(fits, &Options::default()).expect("fits");
    assert_eq!(
        e.tuples("s").map(|t| t.to_vec()),
        Some(vec![vec![Value::Int(i64::MAX)]])
    );
}

/// Comparisons that bound a column by values bound before its atom (`T2 > T1, T2 - T1 <= K`,
/// `abs(X - Y) < d`, `Y + c >= X`, float and mixed int/float bounds, times near 0, integers
/// near the 64-bit limits) narrow the join to a range of the sorted copy: the results must be
/// those of the same comparisons filtering every pair of a product made first, and of a
/// brute-force count.
#[test]
fn window_comparisons_narrow_the_join_without_changing_results() {
    let mut src = String::from(
        ".decl a(V: int, T: time)\n.decl b(V: int, T: time)\n.decl p(V: int, X: int)\n\
         .decl q(V: int, X: float)\n\
         .decl w1(V: int, T1: time, T2: time)\n.decl w2(V: int, T1: time, T2: time)\n\
         .decl w3(V: int, X: int, Y: int)\n.decl w4(V: int, X: int, Y: int)\n\
         .decl w5(V: int, X: float, Y: float)\n.decl w6(V: int, X: float, Y: float)\n\
         .decl w7(V: int, X: float, I: int)\n.decl w8(V: int, T1: time, T2: time)\n\
         .decl w9(V: int, X: int, Y: int)\n\
         w1(V, T1, T2) :- a(V, T1), b(V, T2), T2 > T1, T2 - T1 <= 3.\n\
         w2(V, T1, T2) :- a(V, T1), b(V, T2), T1 - T2 < 2, T2 <= T1.\n\
         w3(V, X, Y) :- p(V, X), p(V, Y), abs(X - Y) < 5, X != Y.\n\
         w4(V, X, Y) :- p(V, X), p(V, Y), Y + 3 >= X, Y < X + 7.\n\
         w5(V, X, Y) :- q(V, X), q(V, Y), abs(Y - X) <= 1.5.\n\
         w6(V, X, Y) :- q(V, X), q(V, Y), Y - X < 0.3, Y > X.\n\
         w7(V, X, I) :- q(V, X), p(V, I), X >= I, X < I + 2.\n\
         w8(V, T1, T2) :- a(V, T1), b(V, T2), T2 >= T1 - 5, T2 <= T1 - 2.\n\
         w9(V, X, Y) :- p(V, X), p(V, Y), Y - X >= 9223372036854775800.\n\
         .decl ab(V: int, T1: time, T2: time)\n.decl pp(V: int, X: int, Y: int)\n\
         .decl qq(V: int, X: float, Y: float)\n.decl qp(V: int, X: float, I: int)\n\
         ab(V, T1, T2) :- a(V, T1), b(V, T2).\npp(V, X, Y) :- p(V, X), p(V, Y).\n\
         qq(V, X, Y) :- q(V, X), q(V, Y).\nqp(V, X, I) :- q(V, X), p(V, I).\n\
         .decl u1(V: int, T1: time, T2: time)\nu1(V, T1, T2) :- ab(V, T1, T2), T2 > T1, T2 - T1 <= 3.\n\
         .decl u2(V: int, T1: time, T2: time)\nu2(V, T1, T2) :- ab(V, T1, T2), T1 - T2 < 2, T2 <= T1.\n\
         .decl u3(V: int, X: int, Y: int)\nu3(V, X, Y) :- pp(V, X, Y), abs(X - Y) < 5, X != Y.\n\
         .decl u4(V: int, X: int, Y: int)\nu4(V, X, Y) :- pp(V, X, Y), Y + 3 >= X, Y < X + 7.\n\
         .decl u5(V: int, X: float, Y: float)\nu5(V, X, Y) :- qq(V, X, Y), abs(Y - X) <= 1.5.\n\
         .decl u6(V: int, X: float, Y: float)\nu6(V, X, Y) :- qq(V, X, Y), Y - X < 0.3, Y > X.\n\
         .decl u7(V: int, X: float, I: int)\nu7(V, X, I) :- qp(V, X, I), X >= I, X < I + 2.\n\
         .decl u8(V: int, T1: time, T2: time)\nu8(V, T1, T2) :- ab(V, T1, T2), T2 >= T1 - 5, T2 <= T1 - 2.\n\
         .decl u9(V: int, X: int, Y: int)\nu9(V, X, Y) :- pp(V, X, Y), Y - X >= 9223372036854775800.\n",
    );
    let mut seed = 11u64;
    let mut next = |m: u64| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 33) % m
    };
    let mut a = Vec::new();
    let mut b = Vec::new();
    let mut ps = vec![std::collections::BTreeSet::new(); 3];
    for (v, seen) in ps.iter_mut().enumerate() {
        for t in 0..60u64 {
            if next(3) > 0 {
                a.push((v, t));
                src.push_str(&format!("a({v}, {t}).\n"));
            }
            if next(3) > 0 {
                b.push((v, t));
                src.push_str(&format!("b({v}, {t}).\n"));
            }
        }
        for _ in 0..30 {
            let x = next(60) as i64 - 30;
            seen.insert(x);
            src.push_str(&format!("p({v}, {x}).\n"));
            let f = (next(400) as f64 - 200.0) / 40.0;
            src.push_str(&format!("q({v}, {f:?}).\n"));
        }
        src.push_str(&format!(
            "p({v}, 9223372036854775807).\np({v}, -9223372036854775807).\nq({v}, 1e300).\n\
             q({v}, -1e300).\nq({v}, 0.0).\nq({v}, 1.5).\nq({v}, -1.5).\n"
        ));
    }
    let outcome = check(
        &src,
        &CheckOptions {
            require_referred: false,
        },
    );
    let Some(program) = outcome.program else {
        panic!("program does not check: {:?}", outcome.diagnostics);
    };
    let mut provider =
        |r: &Request| -> Result<RelationData, String> { Err(format!("no catalog ({})", r.name)) };
    let new = match evaluate(&program, &mut provider, &Options::default()) {
        Ok(e) => e,
        Err(e) => panic!("evaluation failed: {e}"),
    };
    // Each window rule against the same comparisons filtering a product made first (`uN`
    // over `ab`, `pp`, `qq`, `qp`), where no column is bounded by an earlier atom, so every
    // pair is filtered and nothing is narrowed.
    for n in 1..=9 {
        let (w, u) = (format!("w{n}"), format!("u{n}"));
        assert_eq!(new.tuples(&w), new.tuples(&u), "{w}");
        assert!(new.size(&w) > 0, "{w} matches something");
    }
    let brute = |lo: i64, hi: i64| {
        a.iter()
            .map(|&(v, t1)| {
                b.iter()
                    .filter(|&&(w, t2)| w == v && (lo..=hi).contains(&(t2 as i64 - t1 as i64)))
                    .count()
            })
            .sum::<usize>()
    };
    assert_eq!(new.size("w1"), brute(1, 3));
    assert_eq!(new.size("w2"), brute(-1, 0));
    assert_eq!(new.size("w8"), brute(-5, -2));
    // `Y - X` that large without overflowing: `MAX - X` for X in 0..=7, `Y + MAX` for Y in
    // -7..=0 (the pair (-MAX, MAX) overflows, so it fails in both evaluations).
    let w9: usize = ps
        .iter()
        .map(|s| s.range(0..=7).count() + s.range(-7..=0).count())
        .sum();
    assert_eq!(new.size("w9"), w9);
}

/// Negation searched in the sorted negated relation (no wildcard): keys copied from slots,
/// keys computed (`B - 1`), a key the column cannot store (time -1: in no tuple, so the
/// negation holds, even where the relation has a tuple at the top of the encoding), and a
/// wildcard (a projected set) giving the same answers as written out by hand.
#[test]
fn negation_by_search_in_the_sorted_relation() {
    let e = run(
        ".decl p(A: int, B: int)\n.decl q(A: int, B: int)\n.decl x(A: int)\n\
         .decl slots(A: int, B: int)\n.decl shifted(A: int, B: int)\n\
         .decl r(A: int, T: time)\n.decl tq(A: int, T: time)\n.decl early(A: int, T: time)\n\
         .decl wild(A: int, B: int)\n\
         p(1, 1). p(1, 2). p(2, 5). p(9223372036854775807, 9223372036854775807).\n\
         q(1, 1). q(2, 4). q(9223372036854775807, 9223372036854775807).\n\
         x(1). x(2). x(9223372036854775807).\n\
         slots(A, B) :- p(A, B), !q(A, B).\n\
         shifted(A, B) :- p(A, B), !q(A, B - 1).\n\
         r(1, 0). r(1, 3). r(2, 0). tq(1, 2). tq(9223372036854775807, 4294967295).\n\
         early(A, T) :- r(A, T), !tq(A, T - 1).\n\
         wild(A, B) :- p(A, B), !q(_, B).\n",
    );
    let m = i64::MAX;
    assert_eq!(ints(&e, "slots"), vec![vec![1, 2], vec![2, 5]]);
    // q(1, 0), q(1, 1), q(2, 4) and q(MAX, MAX - 1): only (1, 2) and (2, 5) have theirs.
    assert_eq!(ints(&e, "shifted"), vec![vec![1, 1], vec![m, m]]);
    // T - 1 is -1 at time 0 (no time can be): held; tq(1, 2) removes r(1, 3).
    assert_eq!(ints(&e, "early"), vec![vec![1, 0], vec![2, 0]]);
    // B in q's second column: 1, 4, MAX.
    assert_eq!(ints(&e, "wild"), vec![vec![1, 2], vec![2, 5]]);
}

/// A program's ground facts count against the budget as they are loaded (they are evaluated in
/// one pass, not joined): 30 facts pass a budget of 30 and fail one of 29, naming the relation.
#[test]
fn ground_facts_count_against_the_budget() {
    let mut src = String::from(".decl f(X: int, Y: int)\n");
    for i in 0..30 {
        src.push_str(&format!("f({i}, {}).\n", i * 2));
    }
    let tight = Options {
        max_tuples: 29,
        ..Options::default()
    };
    match run_with(&src, &tight) {
        Err(EngineError::TooManyTuples { relation, limit }) => {
            assert_eq!((relation.as_str(), limit), ("f", 29));
        }
        other => panic!("expected the budget to run out in `f`, got {other:?}"),
    }
    let fits = Options {
        max_tuples: 30,
        ..Options::default()
    };
    let e = run_with(&src, &fits).expect("30 facts fit in 30");
    assert_eq!(e.size("f"), 30);
    assert_eq!(ints(&e, "f")[29], vec![29, 58]);
}

/// A stratum of facts alone is evaluated without planning each fact; the tuples and stamps
/// must be what planning them gives. The same heads behind a body that always holds
/// (`:- 1 < 2.`) go through the planner: expressions, negative numbers, an int in a float
/// column, strings, a time that cannot be stored (-1) and a repeated fact must all agree.
#[test]
fn facts_alone_give_what_planned_facts_give() {
    let decls = ".decl f(A: int, B: float, C: str, T: time)\n.decl g(A: int)\n";
    let heads = [
        "f(1 + 2, 2.5, \"bus\", 7)",
        "f(-4, 3, \"car\", 0)",
        "f(9223372036854775807, -0.0, \"\", 2)",
        "f(5, 1.0 / 4.0, \"bus\", -1)",
        "f(1 + 2, 2.5, \"bus\", 7)",
        "g(abs(-7))",
        "g(7)",
    ];
    let facts: String = heads.iter().map(|h| format!("{h}.\n")).collect();
    let planned: String = heads.iter().map(|h| format!("{h} :- 1 < 2.\n")).collect();
    let a = proved(&format!("{decls}{facts}"));
    let b = proved(&format!("{decls}{planned}"));
    for rel in ["f", "g"] {
        let (ta, tb) = (a.tuples(rel), b.tuples(rel));
        assert_eq!(ta, tb, "{rel}: facts alone vs planned");
        let tuples = ta.unwrap_or_default();
        assert_eq!(a.stamped(rel), tuples.len(), "{rel}: every fact stamped");
        for t in tuples {
            let (sa, sb) = (a.stamp(rel, t), b.stamp(rel, t));
            assert_eq!(sa, sb, "{rel}{t:?}: stamps");
            let p = a.prove(rel, t).expect("a fact proves");
            assert_eq!((p.clause, p.children.len()), (sa.map(|s| s.clause), 0));
        }
    }
    // The repeated fact is stamped by its first clause; the time -1 derived nothing.
    assert_eq!(a.size("f"), 3);
    assert_eq!(a.size("g"), 1);
    let first = a.tuples("f").unwrap_or_default();
    let three = first.iter().find(|t| t[0] == Value::Int(3));
    assert_eq!(
        three
            .and_then(|t| a.stamp("f", t))
            .map(|s| (s.round, s.clause)),
        Some((0, 0))
    );
    assert_eq!(a.stamp("g", &[Value::Int(7)]).map(|s| s.clause), Some(5));
    // Without provenance nothing is stamped.
    assert_eq!(run(&format!("{decls}{facts}")).stamped("f"), 0);
}

/// A recursive relation's stamps are put in its tuples' order on their first read: every
/// tuple of a closure then carries the round it first appeared in (on a chain, round k holds
/// the paths of k + 1 edges) and the clause that derived it.
#[test]
fn recursive_stamps_aligned_on_first_read_give_each_tuples_round() {
    let mut src = String::from(".decl edge(X: int, Y: int)\n.decl path(X: int, Y: int)\n");
    for i in 0..40 {
        src.push_str(&format!("edge({i}, {}).\n", i + 1));
    }
    src.push_str("path(X, Y) :- edge(X, Y).\npath(X, Z) :- path(X, Y), edge(Y, Z).\n");
    let e = proved(&src);
    let n = e.size("path");
    assert_eq!(n, 40 * 41 / 2);
    assert_eq!(e.stamped("path"), n);
    for t in e.tuples("path").unwrap_or_default() {
        let (Value::Int(x), Value::Int(y)) = (&t[0], &t[1]) else {
            panic!("not ints: {t:?}");
        };
        let s = e.stamp("path", t).expect("stamped");
        let len = usize::try_from(y - x).expect("forward");
        assert_eq!(
            (s.round, s.clause),
            (len - 1, if len == 1 { 40 } else { 41 })
        );
    }
}

/// A `count` whose braces hold no variable counts constant tuples (Soufflé's answers): 1 when
/// the fact is there, 0 when not, and `{ b() }` for a fact of no columns. It panicked (an index
/// past the empty head) before; no warning names a variable it does not have.
#[test]
fn a_count_over_braces_without_variables_counts_constant_tuples() {
    let src = "a(1). b().\n\
               c(N) :- N = count : { a(1) }.\n\
               d(N) :- N = count : { a(2) }.\n\
               e(N) :- N = count : { b() }.\n\
               f(N) :- N = count : { a(_) }.\n";
    let warned = check(
        src,
        &CheckOptions {
            require_referred: false,
        },
    );
    assert!(
        warned.diagnostics.iter().all(|d| d.code != "W0505"),
        "{:#?}",
        warned.diagnostics
    );
    let e = run(src);
    assert_eq!(ints(&e, "c"), vec![vec![1]]);
    assert_eq!(ints(&e, "d"), vec![vec![0]]);
    assert_eq!(ints(&e, "e"), vec![vec![1]]);
    assert_eq!(ints(&e, "f"), vec![vec![1]]);
}
