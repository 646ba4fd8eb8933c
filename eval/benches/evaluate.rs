//! Evaluating a synthetic submission of 150 logs x 30 prompts built from the real fixture by jittering.

use criterion::{criterion_group, criterion_main, Criterion};
use scenalog_eval::{evaluate, read_pickle, EvalOptions, Submission};
use std::path::PathBuf;

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
            let src = &sources[(l + q) % sources.len()];
            let key = (format!("log-{l:04}"), format!("prompt {q:02}"));
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
    let mut group = c.benchmark_group("evaluate");
    group.sample_size(10);
    group.bench_function("150_logs_x_30_prompts", |b| {
        b.iter(|| evaluate(&p, &g, &EvalOptions::default()).expect("evaluate"))
    });
    group.bench_function("fixture_2_sequences", |b| {
        b.iter(|| evaluate(&pred, &gt, &EvalOptions::default()).expect("evaluate"))
    });
    group.bench_function("read_pickle_predictions", |b| {
        b.iter(|| read_pickle(&data("combined_predictions_dev.pkl")).expect("read"))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
