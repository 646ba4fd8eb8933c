//! Parse + check of a 50-rule program (25 helpers with joins, negation, comparisons and an
//! aggregate, 25 `referred` rules using them), and of generated programs of 10,000 and 100,000
//! rules (a chain of helpers, each its own stratum) to show the checker scales linearly.

use criterion::{criterion_group, criterion_main, Criterion};
use scenalog_rules::{check, parse, CheckOptions};

fn program() -> String {
    let mut src = String::from("// description: benchmark program\n");
    for i in 0..25 {
        src.push_str(&format!(
            "h{i}(V, O, T) :-\n    category(V, \"VEHICLE\"),\n    speed(V, T, S),\n    S > {i}.5,\n    near(V, O, T, D),\n    D < 10.0 + S * 2,\n    direction(V, O, T, \"forward\", _, Lat),\n    abs(Lat) < 3.0,\n    !stationary(O),\n    N = count : {{ following(V, W, T) }},\n    N >= 1.\n"
        ));
    }
    for i in 0..25 {
        src.push_str(&format!(
            "referred(V, T) :- h{i}(V, _, T), !lane_change(V, T, \"left\").\n"
        ));
    }
    src
}

#[path = "../examples/support/chain.rs"]
#[allow(dead_code)]
mod chain;
use chain::chain_program;

fn bench_many(c: &mut Criterion) {
    let mut group = c.benchmark_group("parse+check many rules");
    group.sample_size(10);
    for n in [10_000, 100_000] {
        let src = chain_program(n);
        let out = check(&src, &CheckOptions::default());
        let strata = out.program.as_ref().map_or(0, |p| p.strata.len());
        assert_eq!(strata, n + 2, "{:?}", out.diagnostics.first());
        group.bench_function(format!("{n} rules"), |b| {
            b.iter(|| check(std::hint::black_box(&src), &CheckOptions::default()))
        });
    }
    group.finish();
}

fn bench(c: &mut Criterion) {
    let src = program();
    let out = check(&src, &CheckOptions::default());
    assert!(out.diagnostics.is_empty(), "{:#?}", out.diagnostics);
    assert_eq!(parse(&src).0.clauses.len(), 50);
    c.bench_function("parse+check 50 rules", |b| {
        b.iter(|| check(std::hint::black_box(&src), &CheckOptions::default()))
    });
    c.bench_function("parse 50 rules", |b| {
        b.iter(|| parse(std::hint::black_box(&src)))
    });
}

criterion_group!(benches, bench, bench_many);
criterion_main!(benches);
