//! The same workloads three ways: the engine from rule text, hand-written datafrog, and Ascent.
//! Every variant's tuple count is asserted equal before anything is timed.

use std::collections::HashSet;

use criterion::{criterion_group, criterion_main, Criterion};
use datafrog::{Iteration, Relation};
use scenalog_engine::{evaluate, Options};
use scenalog_facts::relation::{RelationData, Request};
use scenalog_rules::{check, CheckOptions, CheckedProgram};

/// Chain length for transitive closure (the 2,000 gives ~2M tuples; see README).
const CHAIN: u32 = 500;
/// Random graph: nodes, edges.
const GRAPH: (u32, usize) = (2000, 4000);

fn lcg(seed: &mut u64) -> u32 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 33) as u32
}

fn chain(n: u32) -> Vec<(u32, u32)> {
    (0..n - 1).map(|i| (i, i + 1)).collect()
}

/// A sparse random graph: mostly forward edges so the closure stays bounded (a DAG-like graph).
fn random_graph(nodes: u32, edges: usize) -> Vec<(u32, u32)> {
    let mut seed = 42;
    let mut set = HashSet::new();
    while set.len() < edges {
        let a = lcg(&mut seed) % nodes;
        let b = lcg(&mut seed) % nodes;
        if a < b && b - a < 40 {
            set.insert((a, b));
        }
    }
    let mut v: Vec<_> = set.into_iter().collect();
    v.sort_unstable();
    v
}

fn program(facts: &str, rules: &str) -> CheckedProgram {
    let src = format!("{facts}{rules}");
    let out = check(
        &src,
        &CheckOptions {
            require_referred: false,
        },
    );
    out.program.expect("benchmark program checks")
}

fn facts(name: &str, edges: &[(u32, u32)]) -> String {
    let mut s = format!(".decl {name}(A: int, B: int)\n");
    for (a, b) in edges {
        s.push_str(&format!("{name}({a}, {b}).\n"));
    }
    s
}

fn engine_count(p: &CheckedProgram, rel: &str) -> usize {
    let mut provider = |r: &Request| -> Result<RelationData, String> { Err(r.name.clone()) };
    let opts = Options {
        max_tuples: 100_000_000,
        timeout: None,
        ..Options::default()
    };
    evaluate(p, &mut provider, &opts)
        .expect("evaluates")
        .size(rel)
}

fn datafrog_tc(edges: &[(u32, u32)]) -> usize {
    let mut it = Iteration::new();
    let edge_by_src: Relation<(u32, u32)> = edges.iter().copied().collect();
    let path = it.variable::<(u32, u32)>("path");
    let path_by_dst = it.variable::<(u32, u32)>("path_by_dst");
    path.extend(edges.iter().copied());
    while it.changed() {
        path_by_dst.from_map(&path, |&(x, y)| (y, x));
        path.from_join(&path_by_dst, &edge_by_src, |_, &x, &z| (x, z));
    }
    path.complete().len()
}

/// `keep(X, Y) :- path(X, Y), !blocked(Y).` over a closure, with our own antijoin by sorted lookup.
fn datafrog_antijoin(edges: &[(u32, u32)], blocked: &[u32]) -> usize {
    let mut it = Iteration::new();
    let edge_by_src: Relation<(u32, u32)> = edges.iter().copied().collect();
    let path = it.variable::<(u32, u32)>("path");
    let path_by_dst = it.variable::<(u32, u32)>("path_by_dst");
    path.extend(edges.iter().copied());
    while it.changed() {
        path_by_dst.from_map(&path, |&(x, y)| (y, x));
        path.from_join(&path_by_dst, &edge_by_src, |_, &x, &z| (x, z));
    }
    let path = path.complete();
    let blocked: Relation<u32> = blocked.iter().copied().collect();
    path.iter()
        .filter(|(_, y)| blocked.elements.binary_search(y).is_err())
        .count()
}

ascent::ascent! {
    struct AscentTc;
    relation edge(u32, u32);
    relation path(u32, u32);
    path(x, y) <-- edge(x, y);
    path(x, z) <-- path(x, y), edge(y, z);
}

ascent::ascent! {
    struct AscentAnti;
    relation edge(u32, u32);
    relation blocked(u32);
    relation path(u32, u32);
    relation keep(u32, u32);
    path(x, y) <-- edge(x, y);
    path(x, z) <-- path(x, y), edge(y, z);
    keep(x, y) <-- path(x, y), !blocked(y);
}

fn ascent_tc(edges: &[(u32, u32)]) -> usize {
    let mut p = AscentTc {
        edge: edges.to_vec(),
        ..Default::default()
    };
    p.run();
    p.path.len()
}

fn ascent_anti(edges: &[(u32, u32)], blocked: &[u32]) -> usize {
    let mut p = AscentAnti {
        edge: edges.to_vec(),
        blocked: blocked.iter().map(|&b| (b,)).collect(),
        ..Default::default()
    };
    p.run();
    p.keep.len()
}

const TC_RULES: &str = ".decl path(A: int, B: int)\npath(X, Y) :- edge(X, Y).\npath(X, Z) :- path(X, Y), edge(Y, Z).\n";

fn bench_tc(c: &mut Criterion, name: &str, edges: &[(u32, u32)]) {
    let p = program(&facts("edge", edges), TC_RULES);
    let n = datafrog_tc(edges);
    assert_eq!(engine_count(&p, "path"), n, "{name}: engine vs datafrog");
    assert_eq!(ascent_tc(edges), n, "{name}: ascent vs datafrog");
    eprintln!("{name}: {n} tuples");
    let mut g = c.benchmark_group(name);
    g.sample_size(10);
    g.bench_function("engine", |b| b.iter(|| engine_count(&p, "path")));
    g.bench_function("datafrog", |b| b.iter(|| datafrog_tc(edges)));
    g.bench_function("ascent", |b| b.iter(|| ascent_tc(edges)));
    g.finish();
}

fn workloads(c: &mut Criterion) {
    bench_tc(c, "tc_chain", &chain(CHAIN));
    bench_tc(c, "tc_random", &random_graph(GRAPH.0, GRAPH.1));

    let edges = random_graph(GRAPH.0, GRAPH.1);
    let blocked: Vec<u32> = (0..GRAPH.0).filter(|i| i % 3 == 0).collect();
    let mut f = facts("edge", &edges);
    f.push_str(".decl blocked(A: int)\n");
    for b in &blocked {
        f.push_str(&format!("blocked({b}).\n"));
    }
    let p = program(
        &f,
        &format!("{TC_RULES}.decl keep(A: int, B: int)\nkeep(X, Y) :- path(X, Y), !blocked(Y).\n"),
    );
    let n = datafrog_antijoin(&edges, &blocked);
    assert_eq!(engine_count(&p, "keep"), n, "antijoin: engine vs datafrog");
    assert_eq!(
        ascent_anti(&edges, &blocked),
        n,
        "antijoin: ascent vs datafrog"
    );
    eprintln!("antijoin: {n} tuples");
    let mut g = c.benchmark_group("antijoin");
    g.sample_size(10);
    g.bench_function("engine", |b| b.iter(|| engine_count(&p, "keep")));
    g.bench_function("datafrog", |b| {
        b.iter(|| datafrog_antijoin(&edges, &blocked))
    });
    g.bench_function("ascent", |b| b.iter(|| ascent_anti(&edges, &blocked)));
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(3));
    targets = workloads
}
criterion_main!(benches);
