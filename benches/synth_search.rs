//! Benchmark of synthesis as a search (`synth --candidates K`), the model's answers excluded:
//! for each of the library's descriptions, K candidates (the library program itself, K times:
//! the cost of running a candidate does not depend on who wrote it) are each run on the three
//! sample logs by the search's matcher (as `mine` evaluates, one extraction a candidate and log)
//! and the medoid is selected. Printed: the median, 90th percentile and maximum time per
//! description for K = 1, 5 and 10, and the time to load the logs once.
//!
//! Run: `cargo bench --bench synth_search` (release build; 2 cores on the reference machine).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use scenalog::api::inputs::rule_files;
use scenalog::api::synth_search::matcher;
use scenalog::api::Limits;
use scenalog_synth::search::select;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn library() -> Vec<String> {
    rule_files(&[root().join("rules/library")])
        .expect("the scenario library")
        .iter()
        .map(|f| std::fs::read_to_string(f).expect("a library program"))
        .collect()
}

fn quantile(sorted: &[Duration], q: f64) -> Duration {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

fn main() {
    let logs = vec![root().join("tests/data/av2/logs")];
    let t0 = Instant::now();
    let m = matcher(&logs, &Limits::default()).expect("the sample logs");
    println!(
        "synth_search: logs loaded once in {:.3} s",
        t0.elapsed().as_secs_f64()
    );
    let programs = library();
    for k in [1usize, 5, 10] {
        let mut times = Vec::with_capacity(programs.len());
        for program in &programs {
            let start = Instant::now();
            let sets: Vec<_> = (0..k).map(|_| (m.0)(program).ok()).collect();
            let chosen = select(&sets, &vec![1; k], &vec![program.len(); k]).chosen;
            times.push(start.elapsed());
            assert!(chosen.is_some() || sets.iter().all(Option::is_none));
        }
        times.sort();
        println!(
            "synth_search: K = {k:2}, {} descriptions: median {:.1} ms, p90 {:.1} ms, max {:.1} ms a description",
            programs.len(),
            quantile(&times, 0.5).as_secs_f64() * 1e3,
            quantile(&times, 0.9).as_secs_f64() * 1e3,
            quantile(&times, 1.0).as_secs_f64() * 1e3,
        );
    }
}
