//! Stratification: dependency graph, components and strata in evaluation order.

use scenalog_rules::strata::{dependency_graph, sccs, EdgeKind};
use scenalog_rules::{check, parse, CheckOptions};

const PROGRAM: &str = "\
referred(V, T) :- chain(V, T), !blocked(V, T), N = count : { slow(W, T) }, N > 0.
chain(V, T) :- ego(E), following(E, V, T).
chain(V, T) :- chain(A, T), following(A, V, T).
blocked(V, T) :- slow(V, T), !stationary(V).
slow(V, T) :- speed(V, T, S), S < 1.0 m/s.
";

#[test]
fn strata_come_in_dependency_order() {
    let out = check(PROGRAM, &CheckOptions::default());
    assert!(out.diagnostics.is_empty(), "{:#?}", out.diagnostics);
    let checked = out.program.expect("checked");
    let order: Vec<Vec<String>> = checked
        .strata
        .iter()
        .map(|s| s.predicates.clone())
        .collect();
    let pos = |p: &str| {
        order
            .iter()
            .position(|s| s.iter().any(|x| x == p))
            .expect(p)
    };
    assert!(pos("slow") < pos("blocked"));
    assert!(pos("blocked") < pos("referred"));
    assert!(pos("chain") < pos("referred"));
    assert_eq!(
        order.len(),
        4,
        "catalog relations get no stratum: {order:?}"
    );
    let chain = &checked.strata[pos("chain")];
    assert!(chain.recursive);
    assert_eq!(chain.clauses, vec![1, 2]);
    assert!(!checked.strata[pos("slow")].recursive);
    assert_eq!(checked.strata[pos("referred")].clauses, vec![0]);
    // Types flow into the predicate table.
    use scenalog_facts::catalog::ColType;
    assert_eq!(
        checked.predicates["chain"].types,
        vec![ColType::Track, ColType::Time]
    );
    assert_eq!(
        checked.predicates["speed"].kind,
        scenalog_rules::PredKind::Catalog
    );
}

#[test]
fn graph_has_positive_negative_and_aggregate_edges() {
    let (program, diags) = parse(PROGRAM);
    assert!(diags.is_empty());
    let g = dependency_graph(&program);
    let edge = |from: &str, to: &str| {
        let (f, t) = (g.index(from).expect(from), g.index(to).expect(to));
        g.edges
            .iter()
            .filter(|e| e.from == f && e.to == t)
            .map(|e| e.kind)
            .collect::<Vec<_>>()
    };
    assert_eq!(edge("referred", "chain"), vec![EdgeKind::Positive]);
    assert_eq!(edge("referred", "blocked"), vec![EdgeKind::Negative]);
    assert_eq!(edge("referred", "slow"), vec![EdgeKind::Aggregate]);
    assert_eq!(edge("chain", "chain"), vec![EdgeKind::Positive]);
    assert!(
        g.index("speed").is_none(),
        "catalog relations are not nodes"
    );
    let comps = sccs(&g);
    assert_eq!(comps.len(), 4);
}

#[test]
fn mutual_recursion_is_one_component() {
    let src = "a(X, T) :- present(X, T).\na(X, T) :- b(X, T).\nb(X, T) :- a(X, T), speed(X, T, _).\nreferred(X, T) :- b(X, T).\n";
    let out = check(src, &CheckOptions::default());
    let checked = out.program.expect("checked");
    let rec: Vec<&scenalog_rules::Stratum> =
        checked.strata.iter().filter(|s| s.recursive).collect();
    assert_eq!(rec.len(), 1);
    assert_eq!(rec[0].predicates, vec!["a".to_string(), "b".to_string()]);
    assert_eq!(rec[0].clauses, vec![0, 1, 2]);
    assert_eq!(
        checked.strata.last().map(|s| s.predicates.clone()),
        Some(vec!["referred".to_string()])
    );
}
