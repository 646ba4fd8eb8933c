//! Benchmark of synthesis as a search (`synth --candidates K`), the model's answers excluded:
//! for each of the library's descriptions, K candidates (the library program itself, K times:
//! the cost of running a candidate does not depend on who wrote it) are each run on the three
//! sample logs by the search's matcher (as `mine` evaluates, one extraction a candidate and log)
//! and the medoid is selected. Printed: the median, 90th percentile and maximum time per
//! description for K = 1, 5 and 10, the time to load the logs once, the time of one evidence
//! round's evidence (what the kept program matches, in words: counts, the longest match's proof
//! or the nearest misses), and K = 10 with one evidence round, per description.
//!
//! Run: `cargo bench --bench synth_search` (release build; 2 cores on the reference machine).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use scenalog::api::inputs::rule_files;
use scenalog::api::synth_search::search_logs;
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
    let (m, evidence) = search_logs(&logs, &Limits::default()).expect("the sample logs");
    println!(
        "synth_search: logs loaded once in {:.3} s",
        t0.elapsed().as_secs_f64()
    );
    let programs = library();
    let mut evidence_times = Vec::with_capacity(programs.len());
    for program in &programs {
        let start = Instant::now();
        let text = (evidence.0)(program);
        evidence_times.push(start.elapsed());
        if start.elapsed().as_secs_f64() > 1.0 {
            // The programs that match nothing pay for the why-not reports of their misses.
            println!(
                "synth_search: evidence took {:.1} s for {}",
                start.elapsed().as_secs_f64(),
                program.lines().next().unwrap_or_default()
            );
        }
        assert!(text.is_ok_and(|t| t.starts_with("On the 3 logs")));
    }
    let mut by_program = evidence_times.clone();
    by_program.sort();
    print_line("evidence round", programs.len(), &by_program);
    for k in [1usize, 5, 10] {
        let mut times = Vec::with_capacity(programs.len());
        for program in &programs {
            let start = Instant::now();
            let sets: Vec<_> = (0..k).map(|_| (m.0)(program).ok()).collect();
            let chosen = select(&sets, &vec![1; k], &vec![program.len(); k]).chosen;
            times.push(start.elapsed());
            assert!(chosen.is_some() || sets.iter().all(Option::is_none));
        }
        let mut with_evidence: Vec<Duration> = times
            .iter()
            .zip(&evidence_times)
            .map(|(a, b)| *a + *b)
            .collect();
        times.sort();
        print_line(&format!("K = {k:2}"), programs.len(), &times);
        if k == 10 {
            with_evidence.sort();
            print_line(
                "K = 10 and one evidence round",
                programs.len(),
                &with_evidence,
            );
        }
    }
}

fn print_line(what: &str, n: usize, sorted: &[Duration]) {
    println!(
        "synth_search: {what}, {n} descriptions: median {:.1} ms, p90 {:.1} ms, max {:.1} ms a description",
        quantile(sorted, 0.5).as_secs_f64() * 1e3,
        quantile(sorted, 0.9).as_secs_f64() * 1e3,
        quantile(sorted, 1.0).as_secs_f64() * 1e3,
    );
}
