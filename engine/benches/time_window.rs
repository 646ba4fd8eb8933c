//! Time-window joins, `a(V, T1), b(V, T2), T2 > T1, T2 - T1 <= K`: how the engine's time grows
//! with the frames per track. Each of 20 tracks has an `a` and a `b` event at every frame, so the
//! output is about 20 × frames × K tuples: linear in the frames. A plan that joins on `V` and then
//! filters the comparisons looks at frames² pairs per track, and its time quadruples when the
//! frames double.
//!
//! `cargo bench -p scenalog-engine --bench time_window`

use criterion::{BenchmarkId, Criterion};
use scenalog_engine::{evaluate, Options};
use scenalog_facts::relation::{RelationData, Request};
use scenalog_rules::{check, CheckOptions, CheckedProgram};

const TRACKS: u32 = 20;
const K: u32 = 10;

fn program(frames: u32) -> CheckedProgram {
    let mut s = String::from(
        ".decl a(V: int, T: int)\n.decl b(V: int, T: int)\n.decl pair(V: int, T1: int, T2: int)\n",
    );
    s.push_str(&format!(
        "pair(V, T1, T2) :- a(V, T1), b(V, T2), T2 > T1, T2 - T1 <= {K}.\n"
    ));
    for v in 0..TRACKS {
        for t in 0..frames {
            s.push_str(&format!("a({v}, {t}). b({v}, {t}).\n"));
        }
    }
    let out = check(
        &s,
        &CheckOptions {
            require_referred: false,
        },
    );
    match out.program {
        Some(p) => p,
        None => panic!("benchmark program does not check: {:?}", out.diagnostics),
    }
}

fn pairs(p: &CheckedProgram) -> usize {
    let mut provider = |r: &Request| -> Result<RelationData, String> { Err(r.name.clone()) };
    match evaluate(p, &mut provider, &Options::default()) {
        Ok(e) => e.size("pair"),
        Err(e) => panic!("benchmark program fails: {e}"),
    }
}

fn main() {
    let mut c = Criterion::default()
        .warm_up_time(std::time::Duration::from_millis(300))
        .measurement_time(std::time::Duration::from_secs(2))
        .sample_size(10)
        .configure_from_args();
    let mut g = c.benchmark_group("time_window");
    for frames in [250u32, 500, 1000, 2000] {
        let p = program(frames);
        // Per track: for each T1, the T2 in (T1, T1 + K] below `frames`.
        let per_track: u32 = (0..frames).map(|t1| K.min(frames - 1 - t1)).sum();
        let want = (TRACKS * per_track) as usize;
        assert_eq!(pairs(&p), want, "{frames} frames");
        eprintln!("time_window/{frames}: {want} pairs");
        g.bench_with_input(BenchmarkId::from_parameter(frames), &p, |b, p| {
            b.iter(|| pairs(p))
        });
    }
    g.finish();
    c.final_summary();
}
