//! Evaluating a synthetic submission of 150 logs x 30 prompts built from the real fixture by jittering.

use criterion::{criterion_group, criterion_main, Criterion};
use scenalog_eval::{evaluate, read_pickle, EvalOptions, RoiMaps, RoiRaster, Submission};
use std::path::PathBuf;
use std::sync::Arc;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/av2/eval")
        .join(name)
}

/// A deterministic jitter in [-0.5, 0.5) m.
fn jitter(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
}

/// `logs` x `prompts` sequences, each a jittered copy of a fixture sequence; all sequences of a log come
/// from one real log, whose index ends the log id (so the ROI benchmark can give it that log's raster).
fn synthetic(
    pred: &Submission,
    gt: &Submission,
    logs: usize,
    prompts: usize,
) -> (Submission, Submission) {
    let mut p = Submission::default();
    let mut g = Submission::default();
    let sources: Vec<_> = gt.sequences.keys().cloned().collect();
    let mut state = 7u64;
    for l in 0..logs {
        for q in 0..prompts {
            let s = l % sources.len();
            let src = &sources[s];
            let key = (format!("log-{l:04}-{s}"), format!("prompt {q:02}"));
            g.sequences.insert(key.clone(), gt.sequences[src].clone());
            let mut frames = pred.sequences[src].clone();
            for f in &mut frames {
                for t in &mut f.translation_m {
                    t[0] += jitter(&mut state);
                    t[1] += jitter(&mut state);
                }
            }
            p.sequences.insert(key, frames);
        }
    }
    (p, g)
}

fn bench(c: &mut Criterion) {
    let pred = read_pickle(&data("combined_predictions_dev.pkl")).expect("predictions");
    let gt = read_pickle(&data("combined_gt_dev.pkl")).expect("ground truth");
    let (p, g) = synthetic(&pred, &gt, 150, 30);
    let logs_dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/data/av2/logs");
    let sources: Vec<String> = gt.sequences.keys().map(|k| k.0.clone()).collect();
    let real = RoiMaps::load(&logs_dir, sources.iter().map(|s| s.as_str())).expect("maps");
    let fixture_roi = EvalOptions {
        roi: Some(Arc::new(real.clone())),
        ..EvalOptions::default()
    };
    // the synthetic logs share the rasters of the real logs they were copied from
    let mut maps = RoiMaps::default();
    for (log, _) in g.sequences.keys() {
        let s: usize = log
            .rsplit('-')
            .next()
            .and_then(|s| s.parse().ok())
            .expect("tag");
        maps.insert(log.clone(), real.shared(&sources[s]).expect("raster"));
    }
    let synthetic_roi = EvalOptions {
        roi: Some(Arc::new(maps)),
        ..EvalOptions::default()
    };
    let mut group = c.benchmark_group("evaluate");
    group.sample_size(10);
    group.bench_function("150_logs_x_30_prompts", |b| {
        b.iter(|| evaluate(&p, &g, &EvalOptions::default()).expect("evaluate"))
    });
    group.bench_function("fixture_2_sequences", |b| {
        b.iter(|| evaluate(&pred, &gt, &EvalOptions::default()).expect("evaluate"))
    });
    group.bench_function("150_logs_x_30_prompts_roi", |b| {
        b.iter(|| evaluate(&p, &g, &synthetic_roi).expect("evaluate"))
    });
    group.bench_function("fixture_2_sequences_roi", |b| {
        b.iter(|| evaluate(&pred, &gt, &fixture_roi).expect("evaluate"))
    });
    let map_b = logs_dir.join(&sources[1]).join("map");
    group.bench_function("roi_raster_from_map_3bffdcff", |b| {
        b.iter(|| RoiRaster::from_map_dir(&map_b).expect("raster"))
    });
    group.bench_function("read_pickle_predictions", |b| {
        b.iter(|| read_pickle(&data("combined_predictions_dev.pkl")).expect("read"))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
