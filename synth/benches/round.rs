//! The work a repair round does besides waiting for the model: building the prompt, hashing it
//! for the cache, and turning an answer into checked feedback.

use criterion::{criterion_group, criterion_main, Criterion};
use scenalog_synth::extract::{extract, with_description, Extracted};
use scenalog_synth::{library, prompt, repair, Cache};
use std::hint::black_box;

const ANSWER: &str = "Here is the program:\n\n```scenalog\nreferred(V, T) :- category(V, \"VEHICLE\"), turning_left(V, T), speed(V, T, S), S > \"fast\".\n```\n";

fn bench(c: &mut Criterion) {
    let mut lib = library::embedded();
    library::retain_clean(&mut lib);
    let description = "vehicle making a left turn";
    c.bench_function("prompt (8 most similar examples)", |b| {
        b.iter(|| prompt::messages(black_box(description), &lib, Some(8)))
    });
    let messages = prompt::messages(description, &lib, Some(8));
    c.bench_function("cache key of a prompt", |b| {
        b.iter(|| Cache::key("model", black_box(&messages)))
    });
    c.bench_function("extract, check and feedback of a wrong answer", |b| {
        b.iter(|| {
            let Extracted::Program(code) = extract(black_box(ANSWER)) else {
                return String::new();
            };
            let program = with_description(&code, description);
            let outcome = scenalog_rules::check(&program, &scenalog_rules::CheckOptions::default());
            repair::error_feedback(&program, &outcome.diagnostics)
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
