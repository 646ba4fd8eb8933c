//! Extraction benchmarks on the three real logs in `tests/data/av2/logs/`:
//! - `all/LOG/threads=N`: every relation of the catalog from a fresh [`Extractor`] (kinematics,
//!   map index, lane assignment and all), on a rayon pool of N threads;
//! - `demand/LOG`: the demand-driven path of a typical two-relation program,
//!   `category(X, "VEHICLE"), speed(X, T, V), V < 0.5`, from a fresh context on one thread;
//! - `demand_pairs/LOG`: `category(P, "PEDESTRIAN"), category(B, "BUS"), near(P, B, T, D), D < 5`
//!   (the pushdown keeps car-to-car pairs out), fresh context, one thread.

use std::path::PathBuf;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion};
use scenalog_extractors::{extract_all_with, Extractor};
use scenalog_facts::read::load_scene;
use scenalog_facts::relation::{Constraint, Request, Value};
use scenalog_facts::Scene;

const LOGS: [&str; 3] = [
    "3b3570b4-7b0b-3268-a571-b0889dbf40b6",
    "3bffdcff-c3a7-38b6-a0f2-64196d130958",
    "adcf7d18-0510-35b0-a2fa-b4cea13a6d76",
];

fn scenes() -> Vec<Scene> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/data/av2/logs");
    LOGS.iter()
        .filter_map(|id| match load_scene(&root.join(id)) {
            Ok(s) => Some(s),
            Err(e) => {
                eprintln!("skipping {id}: {e}");
                None
            }
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let scenes = scenes();
    let mut g = c.benchmark_group("all");
    g.sample_size(20);
    for threads in [1, 2] {
        let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(threads).build() else {
            continue;
        };
        for s in &scenes {
            g.bench_function(format!("{}/threads={threads}", &s.log_id[..8]), |b| {
                b.iter(|| pool.install(|| extract_all_with(&Extractor::new(s)).len()))
            });
        }
    }
    g.finish();

    let vehicle = Arc::<str>::from("VEHICLE");
    let category = Request {
        name: "category".into(),
        constraints: vec![(1, Constraint::Eq(Value::Str(vehicle.clone())))],
    };
    let speed = Request {
        name: "speed".into(),
        constraints: vec![(0, Constraint::Category(vehicle)), (2, Constraint::Lt(0.5))],
    };
    let mut g = c.benchmark_group("demand");
    g.sample_size(30);
    let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(1).build() else {
        return;
    };
    for s in &scenes {
        g.bench_function(&s.log_id[..8], |b| {
            b.iter(|| {
                pool.install(|| {
                    let ex = Extractor::new(s);
                    let a = ex.extract(&category).map_or(0, |r| r.len());
                    let b = ex.extract(&speed).map_or(0, |r| r.len());
                    a + b
                })
            })
        });
    }
    g.finish();

    let cat = |c: &str| Request {
        name: "category".into(),
        constraints: vec![(1, Constraint::Eq(Value::Str(Arc::from(c))))],
    };
    let near = Request {
        name: "near".into(),
        constraints: vec![
            (0, Constraint::Category(Arc::from("PEDESTRIAN"))),
            (1, Constraint::Category(Arc::from("BUS"))),
            (3, Constraint::Lt(5.0)),
        ],
    };
    let mut g = c.benchmark_group("demand_pairs");
    g.sample_size(30);
    for s in &scenes {
        g.bench_function(&s.log_id[..8], |b| {
            b.iter(|| {
                pool.install(|| {
                    let ex = Extractor::new(s);
                    [cat("PEDESTRIAN"), cat("BUS"), near.clone()]
                        .iter()
                        .map(|r| ex.extract(r).map_or(0, |d| d.len()))
                        .sum::<usize>()
                })
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
