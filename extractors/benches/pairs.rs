//! Pair-relation benchmarks on the three real logs in `tests/data/av2/logs/`. Kinematics, map
//! index and lane assignment are computed once beforehand (they belong to the other relations);
//! every iteration starts from a fresh per-frame box index, so R-tree building is included.
//! - `pairs/LOG/REL`: one pair relation, unconstrained, one thread;
//! - `pairs/LOG/all/threads=N`: all nine, on a rayon pool of N threads;
//! - `pairs/LOG/pushdown`: `near(P, B, T, D), D < 5` between pedestrians and vehicles, one thread.

use std::path::PathBuf;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion};
use scenalog_extractors::pairs::{PairContext, PairIndex};
use scenalog_extractors::Extractor;
use scenalog_extractors::{pair_relation, pair_relations};
use scenalog_facts::read::load_scene;
use scenalog_facts::relation::{Constraint, RelationData, Request};
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

/// Answers `req` from a fresh box index; the number of tuples.
fn answer(ex: &Extractor, req: &Request) -> usize {
    let index = PairIndex::new(ex.scene());
    let ctx = PairContext::of(ex, &index);
    one(&ctx, req).len()
}

fn one(ctx: &PairContext, req: &Request) -> RelationData {
    pair_relation(ctx, req).unwrap_or_else(|_| RelationData::empty(&req.name, &[]))
}

fn bench(c: &mut Criterion) {
    let scenes = scenes();
    let mut g = c.benchmark_group("pairs");
    g.sample_size(10);
    g.measurement_time(std::time::Duration::from_secs(3));
    g.warm_up_time(std::time::Duration::from_secs(1));
    let Ok(one_thread) = rayon::ThreadPoolBuilder::new().num_threads(1).build() else {
        return;
    };
    for s in &scenes {
        let ex = Extractor::new(s);
        // The per-scene data the pair relations read, computed once.
        let _ = (ex.kinematics(), ex.map_index(), ex.lanes());
        let log = &s.log_id[..8];
        for name in pair_relations() {
            let req = Request::all(name);
            g.bench_function(format!("{log}/{name}"), |b| {
                b.iter(|| one_thread.install(|| answer(&ex, &req)))
            });
        }
        for threads in [1, 2] {
            let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(threads).build() else {
                continue;
            };
            g.bench_function(format!("{log}/all/threads={threads}"), |b| {
                b.iter(|| {
                    pool.install(|| {
                        let index = PairIndex::new(s);
                        let ctx = PairContext::of(&ex, &index);
                        pair_relations()
                            .into_iter()
                            .map(|n| one(&ctx, &Request::all(n)).len())
                            .sum::<usize>()
                    })
                })
            });
        }
        let vehicle: Arc<str> = Arc::from("VEHICLE");
        let req = Request {
            name: "near".into(),
            constraints: vec![
                (0, Constraint::Category(Arc::from("PEDESTRIAN"))),
                (1, Constraint::Category(vehicle)),
                (3, Constraint::Lt(5.0)),
            ],
        };
        g.bench_function(format!("{log}/pushdown"), |b| {
            b.iter(|| one_thread.install(|| answer(&ex, &req)))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
