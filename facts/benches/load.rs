//! Loading each real AV2 log in `tests/data/av2/logs/` with `load_scene` (annotations, ego poses
//! and vector map, from disk; the files are in the page cache after the first run).
//!
//! Run: `cargo bench -p scenalog-facts --bench load`.

use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use scenalog_facts::load_scene;

const LOGS: &[&str] = &[
    "3b3570b4-7b0b-3268-a571-b0889dbf40b6",
    "3bffdcff-c3a7-38b6-a0f2-64196d130958",
    "adcf7d18-0510-35b0-a2fa-b4cea13a6d76",
];

fn load(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/av2/logs");
    let mut group = c.benchmark_group("load_scene");
    group.sample_size(50);
    for id in LOGS {
        let dir = root.join(id);
        group.bench_function(&id[..8], |b| {
            b.iter(|| match load_scene(black_box(&dir)) {
                Ok(scene) => scene,
                Err(e) => panic!("{e}"),
            })
        });
    }
    group.finish();
}

criterion_group!(benches, load);
criterion_main!(benches);
