//! The same workloads three ways: the engine from rule text, hand-written datafrog, and Ascent,
//! plus the engine with provenance on. Every variant's tuple counts are asserted equal before
//! anything is timed.
//!
//! After the criterion suite, every variant is timed again in interleaved runs and the ratios
//! are printed;
//! `SCENALOG_BENCH_RATIOS_ONLY=1` skips criterion and prints only those.
//!
//! `SCENALOG_BENCH_PROFILE=NAME[,prov]` runs only the engine on workload `NAME` a few times and
//! exits (for `valgrind --tool=callgrind`); otherwise the criterion suite runs.

use std::collections::HashSet;

use criterion::{BenchmarkGroup, Criterion};
use datafrog::{Iteration, Relation, RelationLeaper, ValueFilter};
use scenalog_engine::{evaluate, Evaluation, Options};
use scenalog_facts::relation::{RelationData, Request};
use scenalog_rules::{check, CheckOptions, CheckedProgram};

/// Chain length for transitive closure.
const CHAIN: u32 = 2000;
/// Random graph: nodes, edges.
const GRAPH: (u32, usize) = (2000, 4000);
/// Random tree for same-generation: nodes.
const TREE: u32 = 2000;
/// Spatio-temporal scene: objects, frames (10 Hz), lanes.
const SCENE: (i32, i32, i32) = (100, 150, 8);

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

/// A random recursive tree as `(child, parent)`: node `i`'s parent is uniform among `0..i`.
fn random_tree(nodes: u32) -> Vec<(u32, u32)> {
    let mut seed = 7;
    (1..nodes).map(|i| (i, lcg(&mut seed) % i)).collect()
}

/// Object positions `(object, frame, x in decimetres, lane)`: each object drives at its own
/// speed on one lane and changes to a neighbouring lane once.
fn scene() -> Vec<(i32, i32, i32, i32)> {
    let (objects, frames, lanes) = SCENE;
    let mut seed = 3;
    let mut out = Vec::new();
    for o in 0..objects {
        let x0 = (lcg(&mut seed) % 3000) as i32;
        let v = 8 + (lcg(&mut seed) % 5) as i32;
        let lane = (lcg(&mut seed) % lanes as u32) as i32;
        let switch = (lcg(&mut seed) % frames as u32) as i32;
        let other = if lane == 0 { 1 } else { lane - 1 };
        for t in 0..frames {
            let l = if t < switch { lane } else { other };
            out.push((o, t, x0 + v * t, l));
        }
    }
    out
}

fn program(src: &str) -> CheckedProgram {
    let out = check(
        src,
        &CheckOptions {
            require_referred: false,
        },
    );
    match out.program {
        Some(p) => p,
        None => panic!("benchmark program does not check: {:?}", out.diagnostics),
    }
}

fn facts(name: &str, edges: &[(u32, u32)]) -> String {
    let mut s = format!(".decl {name}(A: int, B: int)\n");
    for (a, b) in edges {
        s.push_str(&format!("{name}({a}, {b}).\n"));
    }
    s
}

fn engine_run(p: &CheckedProgram, provenance: bool) -> Evaluation {
    let mut provider = |r: &Request| -> Result<RelationData, String> { Err(r.name.clone()) };
    let opts = Options {
        max_tuples: 100_000_000,
        timeout: None,
        provenance,
        ..Options::default()
    };
    match evaluate(p, &mut provider, &opts) {
        Ok(e) => e,
        Err(e) => panic!("benchmark program fails: {e}"),
    }
}

fn engine_counts(p: &CheckedProgram, rels: &[&str], provenance: bool) -> Vec<usize> {
    let e = engine_run(p, provenance);
    rels.iter().map(|r| e.size(r)).collect()
}

/// With provenance, and every counted relation's stamps read (each recursive relation's
/// stamps are put in order on their first read): what provenance costs a caller who proves.
fn engine_stamped(p: &CheckedProgram, rels: &[&str]) -> Vec<usize> {
    let e = engine_run(p, true);
    rels.iter()
        .map(|r| {
            let n = e.size(r);
            assert_eq!(e.stamped(r), n, "{r}: every tuple stamped");
            n
        })
        .collect()
}

fn datafrog_tc(edges: &[(u32, u32)]) -> Relation<(u32, u32)> {
    let mut it = Iteration::new();
    let edge_by_src: Relation<(u32, u32)> = edges.iter().copied().collect();
    let path = it.variable::<(u32, u32)>("path");
    let path_by_dst = it.variable::<(u32, u32)>("path_by_dst");
    path.extend(edges.iter().copied());
    while it.changed() {
        path_by_dst.from_map(&path, |&(x, y)| (y, x));
        path.from_join(&path_by_dst, &edge_by_src, |_, &x, &z| (x, z));
    }
    path.complete()
}

/// `keep(X, Y) :- path(X, Y), !blocked(Y).` over a closure, with our own antijoin by sorted lookup.
fn datafrog_antijoin(edges: &[(u32, u32)], blocked: &[u32]) -> Vec<usize> {
    let path = datafrog_tc(edges);
    let blocked: Relation<u32> = blocked.iter().copied().collect();
    let keep: Relation<(u32, u32)> = path
        .iter()
        .filter(|(_, y)| blocked.elements.binary_search(y).is_err())
        .copied()
        .collect();
    vec![path.len(), keep.len()]
}

/// Same generation: `sg(X, Y) :- parent(X, P), parent(Y, P), X != Y.` and
/// `sg(X, Y) :- parent(X, A), sg(A, B), parent(Y, B).`
fn datafrog_sg(tree: &[(u32, u32)]) -> usize {
    let parent_by_p: Relation<(u32, u32)> = tree.iter().map(|&(c, p)| (p, c)).collect();
    let mut it = Iteration::new();
    let sg = it.variable::<(u32, u32)>("sg");
    let sg_b_x = it.variable::<(u32, u32)>("sg_b_x");
    let base: Relation<(u32, u32)> =
        Relation::from_join(&parent_by_p, &parent_by_p, |_, &x, &y| (x, y));
    sg.extend(base.iter().copied().filter(|(x, y)| x != y));
    while it.changed() {
        // sg(A, B), parent(X, A) -> (B, X)
        sg_b_x.from_join(&sg, &parent_by_p, |_, &b, &x| (b, x));
        // (B, X), parent(Y, B) -> sg(X, Y)
        sg.from_join(&sg_b_x, &parent_by_p, |_, &x, &y| (x, y));
    }
    sg.complete().len()
}

type Pos = (i32, i32, i32, i32);

/// The spatio-temporal workload by hand: counts of near, follow, start, run, sustained, alone.
fn datafrog_st(pos: &[Pos]) -> Vec<usize> {
    datafrog_st_laps(pos, &mut |_| {})
}

/// [`datafrog_st`], calling `lap` with the name of each part as it ends (see [`split`]).
fn datafrog_st_laps(pos: &[Pos], lap: &mut dyn FnMut(&'static str)) -> Vec<usize> {
    let pos: Relation<Pos> = pos.iter().copied().collect();
    let by_t: Relation<(i32, (i32, i32, i32))> =
        Relation::from_map(&pos, |&(o, t, x, l)| (t, (o, x, l)));
    let by_tl: Relation<((i32, i32), (i32, i32))> =
        Relation::from_map(&pos, |&(o, t, x, l)| ((t, l), (o, x)));
    lap("facts");
    let near: Relation<(i32, i32, i32)> = Relation::from_leapjoin(
        &pos,
        (
            by_t.extend_with(|&(_, t, _, _)| t),
            ValueFilter::from(|&(a, _, xa, la): &Pos, &(b, xb, lb): &(i32, i32, i32)| {
                a != b && (xa - xb).abs() < 100 && (la - lb).abs() <= 1
            }),
        ),
        |&(a, t, _, _), &(b, _, _)| (a, b, t),
    );
    lap("close");
    let follow: Relation<(i32, i32, i32)> = Relation::from_leapjoin(
        &pos,
        (
            by_tl.extend_with(|&(_, t, _, l)| (t, l)),
            ValueFilter::from(|&(_, _, xa, _): &Pos, &(_, xb): &(i32, i32)| {
                xb > xa && xb - xa < 300
            }),
        ),
        |&(a, t, _, _), &(b, _)| (a, b, t),
    );
    lap("behind");
    let start: Relation<(i32, i32, i32)> = follow
        .iter()
        .filter(|&&(a, b, t)| follow.elements.binary_search(&(a, b, t - 1)).is_err())
        .copied()
        .collect();
    let follow_keyed: Relation<((i32, i32, i32), ())> = Relation::from_map(&follow, |&k| (k, ()));
    lap("run_start");
    // run(A, B, S, T) kept as ((A, B, T + 1), S): keyed by the frame that extends it.
    let mut it = Iteration::new();
    let run = it.variable::<((i32, i32, i32), i32)>("run");
    run.extend(start.iter().map(|&(a, b, s)| ((a, b, s + 1), s)));
    while it.changed() {
        run.from_join(&run, &follow_keyed, |&(a, b, u), &s, &()| {
            ((a, b, u + 1), s)
        });
    }
    let run = run.complete();
    lap("run");
    let sustained: Relation<(i32, i32, i32)> = run
        .iter()
        .filter(|&&((_, _, next), s)| next - 1 - s >= 20)
        .map(|&((a, b, _), s)| (a, b, s))
        .collect();
    lap("sustained");
    let has_near: Relation<(i32, i32)> = Relation::from_map(&near, |&(a, _, t)| (a, t));
    let alone: Relation<(i32, i32)> = pos
        .iter()
        .map(|&(a, t, _, _)| (a, t))
        .filter(|k| has_near.elements.binary_search(k).is_err())
        .collect();
    lap("has_close + alone");
    vec![
        near.len(),
        follow.len(),
        start.len(),
        run.len(),
        sustained.len(),
        alone.len(),
    ]
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

ascent::ascent! {
    struct AscentSg;
    relation parent(u32, u32);
    relation sg(u32, u32);
    sg(x, y) <-- parent(x, p), parent(y, p), if x != y;
    sg(x, y) <-- parent(x, a), sg(a, b), parent(y, b);
}

ascent::ascent! {
    struct AscentSt;
    relation pos(i32, i32, i32, i32);
    relation near(i32, i32, i32);
    relation follow(i32, i32, i32);
    relation start(i32, i32, i32);
    relation run(i32, i32, i32, i32);
    relation sustained(i32, i32, i32);
    relation has_near(i32, i32);
    relation alone(i32, i32);
    near(a, b, t) <-- pos(a, t, xa, la), pos(b, t, xb, lb),
        if a != b && (xa - xb).abs() < 100 && (la - lb).abs() <= 1;
    follow(a, b, t) <-- pos(a, t, xa, l), pos(b, t, xb, l), if xb > xa && xb - xa < 300;
    start(a, b, t) <-- follow(a, b, t), !follow(a, b, t - 1);
    run(a, b, s, s) <-- start(a, b, s);
    run(a, b, s, u) <-- run(a, b, s, t), let u = t + 1, follow(a, b, u);
    sustained(a, b, s) <-- run(a, b, s, t), if t - s >= 20;
    has_near(a, t) <-- near(a, _, t);
    alone(a, t) <-- pos(a, t, _, _), !has_near(a, t);
}

/// `spatio_temporal` in Ascent by cumulative parts, for [`split`]: what each stratum adds is
/// the difference between two of these (or the full [`AscentSt`]).
mod ascent_parts {
    ascent::ascent! {
        pub struct Facts;
        relation pos(i32, i32, i32, i32);
    }
    ascent::ascent! {
        pub struct Near;
        relation pos(i32, i32, i32, i32);
        relation near(i32, i32, i32);
        near(a, b, t) <-- pos(a, t, xa, la), pos(b, t, xb, lb),
            if a != b && (xa - xb).abs() < 100 && (la - lb).abs() <= 1;
    }
    ascent::ascent! {
        pub struct Follow;
        relation pos(i32, i32, i32, i32);
        relation follow(i32, i32, i32);
        follow(a, b, t) <-- pos(a, t, xa, l), pos(b, t, xb, l), if xb > xa && xb - xa < 300;
    }
    ascent::ascent! {
        pub struct Start;
        relation pos(i32, i32, i32, i32);
        relation follow(i32, i32, i32);
        relation start(i32, i32, i32);
        follow(a, b, t) <-- pos(a, t, xa, l), pos(b, t, xb, l), if xb > xa && xb - xa < 300;
        start(a, b, t) <-- follow(a, b, t), !follow(a, b, t - 1);
    }
    ascent::ascent! {
        pub struct Run;
        relation pos(i32, i32, i32, i32);
        relation follow(i32, i32, i32);
        relation start(i32, i32, i32);
        relation run(i32, i32, i32, i32);
        follow(a, b, t) <-- pos(a, t, xa, l), pos(b, t, xb, l), if xb > xa && xb - xa < 300;
        start(a, b, t) <-- follow(a, b, t), !follow(a, b, t - 1);
        run(a, b, s, s) <-- start(a, b, s);
        run(a, b, s, u) <-- run(a, b, s, t), let u = t + 1, follow(a, b, u);
    }
    ascent::ascent! {
        pub struct Sustained;
        relation pos(i32, i32, i32, i32);
        relation follow(i32, i32, i32);
        relation start(i32, i32, i32);
        relation run(i32, i32, i32, i32);
        relation sustained(i32, i32, i32);
        follow(a, b, t) <-- pos(a, t, xa, l), pos(b, t, xb, l), if xb > xa && xb - xa < 300;
        start(a, b, t) <-- follow(a, b, t), !follow(a, b, t - 1);
        run(a, b, s, s) <-- start(a, b, s);
        run(a, b, s, u) <-- run(a, b, s, t), let u = t + 1, follow(a, b, u);
        sustained(a, b, s) <-- run(a, b, s, t), if t - s >= 20;
    }
    ascent::ascent! {
        pub struct Alone;
        relation pos(i32, i32, i32, i32);
        relation near(i32, i32, i32);
        relation has_near(i32, i32);
        relation alone(i32, i32);
        near(a, b, t) <-- pos(a, t, xa, la), pos(b, t, xb, lb),
            if a != b && (xa - xb).abs() < 100 && (la - lb).abs() <= 1;
        has_near(a, t) <-- near(a, _, t);
        alone(a, t) <-- pos(a, t, _, _), !has_near(a, t);
    }
}

fn ascent_tc(edges: &[(u32, u32)]) -> usize {
    let mut p = AscentTc {
        edge: edges.to_vec(),
        ..Default::default()
    };
    p.run();
    p.path.len()
}

fn ascent_anti(edges: &[(u32, u32)], blocked: &[u32]) -> Vec<usize> {
    let mut p = AscentAnti {
        edge: edges.to_vec(),
        blocked: blocked.iter().map(|&b| (b,)).collect(),
        ..Default::default()
    };
    p.run();
    vec![p.path.len(), p.keep.len()]
}

fn ascent_sg(tree: &[(u32, u32)]) -> usize {
    let mut p = AscentSg {
        parent: tree.to_vec(),
        ..Default::default()
    };
    p.run();
    p.sg.len()
}

fn ascent_st(pos: &[Pos]) -> Vec<usize> {
    let mut p = AscentSt {
        pos: pos.to_vec(),
        ..Default::default()
    };
    p.run();
    vec![
        p.near.len(),
        p.follow.len(),
        p.start.len(),
        p.run.len(),
        p.sustained.len(),
        p.alone.len(),
    ]
}

const TC_RULES: &str = ".decl path(A: int, B: int)\npath(X, Y) :- edge(X, Y).\n\
                        path(X, Z) :- path(X, Y), edge(Y, Z).\n";

const SG_RULES: &str = ".decl sg(A: int, B: int)\n\
                        sg(X, Y) :- parent(X, P), parent(Y, P), X != Y.\n\
                        sg(X, Y) :- parent(X, A), sg(A, B), parent(Y, B).\n";

/// `spatio_temporal`'s rules, one relation each (declaration and clauses), in stratum order.
const ST_PARTS: [(&str, &str); 7] = [
    (
        "close",
        ".decl close(A: int, B: int, T: int)\n\
         close(A, B, T) :- pos(A, T, XA, LA), pos(B, T, XB, LB), A != B, \
         abs(XA - XB) < 100, abs(LA - LB) <= 1.\n",
    ),
    (
        "behind",
        ".decl behind(A: int, B: int, T: int)\n\
         behind(A, B, T) :- pos(A, T, XA, L), pos(B, T, XB, L), XB > XA, XB - XA < 300.\n",
    ),
    (
        "run_start",
        ".decl run_start(A: int, B: int, T: int)\n\
         run_start(A, B, T) :- behind(A, B, T), !behind(A, B, T - 1).\n",
    ),
    (
        "run",
        ".decl run(A: int, B: int, S: int, T: int)\n\
         run(A, B, S, S) :- run_start(A, B, S).\n\
         run(A, B, S, U) :- run(A, B, S, T), U = T + 1, behind(A, B, U).\n",
    ),
    (
        "sustained",
        ".decl sustained(A: int, B: int, S: int)\n\
         sustained(A, B, S) :- run(A, B, S, T), T - S >= 20.\n",
    ),
    (
        "has_close",
        ".decl has_close(A: int, T: int)\nhas_close(A, T) :- close(A, _, T).\n",
    ),
    (
        "alone",
        ".decl alone(A: int, T: int)\nalone(A, T) :- pos(A, T, _, _), !has_close(A, T).\n",
    ),
];

/// The `pos` facts and the rules of `spatio_temporal`'s relations `names` (all with `None`).
fn st_program(pos: &[Pos], names: Option<&[&str]>) -> CheckedProgram {
    let mut src = String::from(".decl pos(O: int, T: int, X: int, L: int)\n");
    for (o, t, x, l) in pos {
        src.push_str(&format!("pos({o}, {t}, {x}, {l}).\n"));
    }
    for (name, rules) in ST_PARTS {
        if names.is_none_or(|n| n.contains(&name)) {
            src.push_str(rules);
        }
    }
    program(&src)
}

const ST_RELS: [&str; 6] = ["close", "behind", "run_start", "run", "sustained", "alone"];

/// One workload: its program, the relations counted, and the two hand-written variants.
struct Workload {
    name: &'static str,
    program: CheckedProgram,
    rels: Vec<&'static str>,
    datafrog: Box<dyn Fn() -> Vec<usize>>,
    ascent: Box<dyn Fn() -> Vec<usize>>,
}

fn workloads() -> Vec<Workload> {
    let mut out = Vec::new();
    for (name, edges) in [
        ("tc_chain", chain(CHAIN)),
        ("tc_random", random_graph(GRAPH.0, GRAPH.1)),
    ] {
        let e1 = edges.clone();
        let e2 = edges.clone();
        out.push(Workload {
            name,
            program: program(&format!("{}{TC_RULES}", facts("edge", &edges))),
            rels: vec!["path"],
            datafrog: Box::new(move || vec![datafrog_tc(&e1).len()]),
            ascent: Box::new(move || vec![ascent_tc(&e2)]),
        });
    }

    let edges = random_graph(GRAPH.0, GRAPH.1);
    let blocked: Vec<u32> = (0..GRAPH.0).filter(|i| i % 3 == 0).collect();
    let mut src = facts("edge", &edges);
    src.push_str(".decl blocked(A: int)\n");
    for b in &blocked {
        src.push_str(&format!("blocked({b}).\n"));
    }
    src.push_str(TC_RULES);
    src.push_str(".decl keep(A: int, B: int)\nkeep(X, Y) :- path(X, Y), !blocked(Y).\n");
    let (e1, b1, e2, b2) = (edges.clone(), blocked.clone(), edges, blocked);
    out.push(Workload {
        name: "antijoin",
        program: program(&src),
        rels: vec!["path", "keep"],
        datafrog: Box::new(move || datafrog_antijoin(&e1, &b1)),
        ascent: Box::new(move || ascent_anti(&e2, &b2)),
    });

    let tree = random_tree(TREE);
    let (t1, t2) = (tree.clone(), tree.clone());
    out.push(Workload {
        name: "same_generation",
        program: program(&format!("{}{SG_RULES}", facts("parent", &tree))),
        rels: vec!["sg"],
        datafrog: Box::new(move || vec![datafrog_sg(&t1)]),
        ascent: Box::new(move || vec![ascent_sg(&t2)]),
    });

    let pos = scene();
    let (p1, p2) = (pos.clone(), pos.clone());
    out.push(Workload {
        name: "spatio_temporal",
        program: st_program(&pos, None),
        rels: ST_RELS.to_vec(),
        datafrog: Box::new(move || datafrog_st(&p1)),
        ascent: Box::new(move || ascent_st(&p2)),
    });
    out
}

fn bench(g: &mut BenchmarkGroup<'_, criterion::measurement::WallTime>, w: &Workload) {
    g.bench_function("engine", |b| {
        b.iter(|| engine_counts(&w.program, &w.rels, false))
    });
    g.bench_function("engine_provenance", |b| {
        b.iter(|| engine_counts(&w.program, &w.rels, true))
    });
    g.bench_function("engine_provenance_stamps_read", |b| {
        b.iter(|| engine_stamped(&w.program, &w.rels))
    });
    g.bench_function("datafrog", |b| b.iter(|| (w.datafrog)()));
    g.bench_function("ascent", |b| b.iter(|| (w.ascent)()));
}

fn main() {
    if std::env::var_os("SCENALOG_BENCH_SPLIT").is_some() {
        split();
        return;
    }
    let all = workloads();
    if let Ok(spec) = std::env::var("SCENALOG_BENCH_PROFILE") {
        let (name, prov) = match spec.split_once(',') {
            Some((n, p)) => (n.to_string(), p == "prov"),
            None => (spec, false),
        };
        let Some(w) = all.iter().find(|w| w.name == name) else {
            panic!("no workload {name}");
        };
        // SCENALOG_BENCH_PROFILE_REPS: how many evaluations (3 unless given), for more samples.
        let reps = std::env::var("SCENALOG_BENCH_PROFILE_REPS")
            .ok()
            .and_then(|r| r.parse().ok())
            .unwrap_or(3);
        for _ in 0..reps {
            eprintln!("{name}: {:?}", engine_counts(&w.program, &w.rels, prov));
        }
        return;
    }
    for w in &all {
        let want = (w.datafrog)();
        assert_eq!(
            engine_counts(&w.program, &w.rels, false),
            want,
            "{}: engine vs datafrog",
            w.name
        );
        assert_eq!(
            engine_counts(&w.program, &w.rels, true),
            want,
            "{}: engine with provenance vs datafrog",
            w.name
        );
        assert_eq!(
            engine_stamped(&w.program, &w.rels),
            want,
            "{}: engine with stamps read vs datafrog",
            w.name
        );
        assert_eq!((w.ascent)(), want, "{}: ascent vs datafrog", w.name);
        eprintln!("{}: {:?} tuples ({:?})", w.name, want, w.rels);
    }
    if std::env::var_os("SCENALOG_BENCH_RATIOS_ONLY").is_some() {
        ratios(&all);
        return;
    }
    let mut c = Criterion::default()
        .warm_up_time(std::time::Duration::from_millis(300))
        .measurement_time(std::time::Duration::from_secs(2))
        .sample_size(10)
        .configure_from_args();
    for w in &all {
        let mut g = c.benchmark_group(w.name);
        bench(&mut g, w);
        g.finish();
    }
    c.final_summary();
    ratios(&all);
}

/// Times every variant of every workload `REPS` times, interleaved (so load on a busy machine
/// falls on all of them alike), and prints the medians and the ratios the README's goals are
/// about: engine / datafrog, engine / Ascent, provenance on / off (the evaluation alone, and
/// with every counted relation's stamps read).
fn ratios(all: &[Workload]) {
    const REPS: usize = 7;
    let time = |f: &dyn Fn()| {
        let t = std::time::Instant::now();
        f();
        t.elapsed().as_secs_f64()
    };
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    eprintln!(
        "\nmedians of {REPS} interleaved runs (s) | engine | +prov | datafrog | ascent \
         | +stamps | engine/datafrog | engine/ascent | prov on/off | stamps on/off"
    );
    for w in all {
        let mut t: [Vec<f64>; 5] = Default::default();
        for _ in 0..REPS {
            t[0].push(time(&|| {
                engine_counts(&w.program, &w.rels, false);
            }));
            t[1].push(time(&|| {
                engine_counts(&w.program, &w.rels, true);
            }));
            t[2].push(time(&|| {
                (w.datafrog)();
            }));
            t[3].push(time(&|| {
                (w.ascent)();
            }));
            t[4].push(time(&|| {
                engine_stamped(&w.program, &w.rels);
            }));
        }
        let [e, p, d, a, s] = t.map(median);
        eprintln!(
            "{:<16} | {e:.4} | {p:.4} | {d:.4} | {a:.4} | {s:.4} | {:.2}x | {:.2}x | {:.2}x | {:.2}x",
            w.name,
            e / d,
            e / a,
            p / e,
            s / e
        );
    }
}

/// `SCENALOG_BENCH_SPLIT=1`: where `spatio_temporal`'s time goes in each system. The engine
/// and Ascent run cumulative parts of the program (the `pos` facts alone; `close`; `behind`;
/// then `run_start`, `run`, `sustained` on it; `close` with `has_close` and `alone`), each
/// part's relation counts asserted equal to the whole program's, and a stratum's time is the
/// difference between the medians of two parts; hand-written datafrog times its own sections.
/// Medians of `REPS` interleaved runs, in milliseconds.
fn split() {
    use ascent_parts as a;
    const REPS: usize = 21;
    let pos = scene();
    let whole = datafrog_st(&pos);
    let subsets: [&[&str]; 7] = [
        &[],
        &["close"],
        &["behind"],
        &["behind", "run_start"],
        &["behind", "run_start", "run"],
        &["behind", "run_start", "run", "sustained"],
        &["close", "has_close", "alone"],
    ];
    let programs: Vec<CheckedProgram> = subsets.iter().map(|n| st_program(&pos, Some(n))).collect();
    for (names, p) in subsets.iter().zip(&programs) {
        let e = engine_run(p, false);
        for (rel, want) in ST_RELS.iter().zip(&whole) {
            if names.contains(rel) {
                assert_eq!(e.size(rel), *want, "{rel} in part {names:?}");
            }
        }
    }
    // One Ascent part from `pos`: the size of its last relation.
    macro_rules! part {
        ($program:ident, $last:ident) => {
            &|| {
                let mut p = a::$program::default();
                p.pos = pos.clone();
                p.run();
                p.$last.len()
            }
        };
    }
    let ascent: [&dyn Fn() -> usize; 7] = [
        part!(Facts, pos),
        part!(Near, near),
        part!(Follow, follow),
        part!(Start, start),
        part!(Run, run),
        part!(Sustained, sustained),
        part!(Alone, alone),
    ];
    // Each Ascent part's last relation has the whole program's count.
    let counts = [
        pos.len(),
        whole[0],
        whole[1],
        whole[2],
        whole[3],
        whole[4],
        whole[5],
    ];
    for (f, want) in ascent.iter().zip(counts) {
        assert_eq!(f(), want, "Ascent part");
    }
    let ms = |t: std::time::Instant| t.elapsed().as_secs_f64() * 1e3;
    let mut engine: Vec<Vec<f64>> = vec![Vec::new(); subsets.len()];
    let mut asc: Vec<Vec<f64>> = vec![Vec::new(); subsets.len()];
    let mut frog: Vec<(&'static str, Vec<f64>)> = Vec::new();
    for _ in 0..REPS {
        for (i, p) in programs.iter().enumerate() {
            let t = std::time::Instant::now();
            engine_run(p, false);
            engine[i].push(ms(t));
            let t = std::time::Instant::now();
            std::hint::black_box(ascent[i]());
            asc[i].push(ms(t));
        }
        let mut k = 0;
        let mut t = std::time::Instant::now();
        datafrog_st_laps(&pos, &mut |name| {
            if frog.len() <= k {
                frog.push((name, Vec::new()));
            }
            frog[k].1.push(ms(t));
            k += 1;
            t = std::time::Instant::now();
        });
    }
    let median = |v: &[f64]| {
        let mut v = v.to_vec();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let e: Vec<f64> = engine.iter().map(|v| median(v)).collect();
    let s: Vec<f64> = asc.iter().map(|v| median(v)).collect();
    let f: Vec<f64> = frog.iter().map(|(_, v)| median(v)).collect();
    // (part, engine, Ascent) from the parts' medians; datafrog's sections in the same order.
    let parts = [
        ("facts", e[0], s[0]),
        ("close", e[1] - e[0], s[1] - s[0]),
        ("behind", e[2] - e[0], s[2] - s[0]),
        ("run_start", e[3] - e[2], s[3] - s[2]),
        ("run", e[4] - e[3], s[4] - s[3]),
        ("sustained", e[5] - e[4], s[5] - s[4]),
        ("has_close + alone", e[6] - e[1], s[6] - s[1]),
    ];
    eprintln!("\nspatio_temporal by part, medians of {REPS} interleaved runs (ms) | engine | datafrog | ascent");
    for ((name, en, asc), (fname, fr)) in parts.iter().zip(frog.iter().map(|(n, _)| n).zip(&f)) {
        assert_eq!(name, fname, "datafrog's sections in the parts' order");
        eprintln!("{name:<18} | {en:.3} | {fr:.3} | {asc:.3}");
    }
    let sum = |v: &[f64]| v.iter().sum::<f64>();
    let (en, asc): (Vec<f64>, Vec<f64>) = parts.iter().map(|&(_, e, s)| (e, s)).unzip();
    eprintln!(
        "{:<18} | {:.3} | {:.3} | {:.3}",
        "sum",
        sum(&en),
        sum(&f),
        sum(&asc)
    );
}
