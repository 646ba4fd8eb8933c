//! Benchmark of `scenalog mine`: the whole scenario library over the three sample logs.
//!
//! - `mine/library_3_logs/threads_1` and `threads_2` (criterion): a whole run as the command does
//!   it (logs and programs in parallel, one extractor per log shared by its programs, every
//!   output written), into a temporary directory.
//! - Per (log, program) medians (printed after criterion's output): each pair alone, with a fresh
//!   extractor (so extraction is counted for every pair), extract + evaluate + tracks, the median
//!   of `SCENALOG_BENCH_REPS` (default 5) repetitions; then the distribution over pairs.
//!
//! Run: `cargo bench --bench mine` (criterion's filter arguments work as usual).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use criterion::Criterion;

// The pipeline is timed directly (below the API, as a run calls it).
use pipeline::run::{run, LogInput, RunOptions};
use pipeline::scenario::{evaluate_on, load_scenario, Scenario};
use scenalog::pipeline;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn library() -> Vec<Scenario> {
    let dir = root().join("rules/library");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("the scenario library")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "dl"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|f| load_scenario(f).expect("library programs check"))
        .collect()
}

fn logs() -> Vec<LogInput> {
    let dir = root().join("tests/data/av2/logs");
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("the sample logs")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    dirs.into_iter()
        .map(|d| LogInput::new(d).expect("a sample log's id"))
        .collect()
}

fn options(out: &Path, threads: usize) -> RunOptions {
    RunOptions {
        out: out.to_path_buf(),
        resume: false,
        timestamps: Default::default(),
        threads: Some(threads),
        engine: scenalog_engine::Options::default(),
        progress: false,
        names: Default::default(),
        keep_submission: false,
        cancel: None,
    }
}

fn whole_runs(c: &mut Criterion, scenarios: &[Scenario], logs: &[LogInput]) {
    let mut g = c.benchmark_group("mine/library_3_logs");
    g.sample_size(10);
    g.warm_up_time(Duration::from_secs(1));
    g.measurement_time(Duration::from_secs(20));
    for threads in [1, 2] {
        let dir = tempfile::tempdir().expect("tempdir");
        // Every pair must succeed, or the figure would time a partial run.
        let report = run(scenarios, logs, &options(dir.path(), threads)).expect("run");
        assert!(!report.any_failed(), "a pair failed");
        g.bench_function(format!("threads_{threads}"), |b| {
            b.iter(|| run(scenarios, logs, &options(dir.path(), threads)).expect("run"))
        });
    }
    g.finish();
}

fn median(v: &mut [Duration]) -> Duration {
    v.sort_unstable();
    v[v.len() / 2]
}

fn per_pair(scenarios: &[Scenario], logs: &[LogInput]) {
    let reps: usize = std::env::var("SCENALOG_BENCH_REPS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(5)
        .max(1);
    let mut rows: Vec<(Duration, String, String)> = Vec::new();
    for log in logs {
        let scene = scenalog_facts::load_scene(&log.dir).expect("log");
        let frames = pipeline::tracks::eval_frames(&scene);
        for s in scenarios {
            let mut times = Vec::with_capacity(reps);
            for _ in 0..reps {
                let t = Instant::now();
                let extractor = scenalog_extractors::cache::Extractor::new(&scene);
                let e = evaluate_on(&extractor, &s.program, &Default::default()).expect("eval");
                let referred: Vec<_> = e
                    .tuples("referred")
                    .unwrap_or_default()
                    .iter()
                    .filter_map(|t| match t.as_slice() {
                        [scenalog_facts::relation::Value::Track(v), scenalog_facts::relation::Value::Time(f)] => {
                            Some((*v, *f))
                        }
                        _ => None,
                    })
                    .collect();
                let labelled = pipeline::tracks::label_frames(&scene, &referred, &[], &frames);
                std::hint::black_box(pipeline::predictions::to_frames(
                    &scene,
                    &s.description,
                    &labelled,
                    None,
                    None,
                ));
                times.push(t.elapsed());
            }
            rows.push((
                median(&mut times),
                pipeline::run::short_id(&log.log_id).to_string(),
                s.name.clone(),
            ));
        }
    }
    let mut all: Vec<Duration> = rows.iter().map(|r| r.0).collect();
    all.sort_unstable();
    let pct = |p: f64| all[((all.len() - 1) as f64 * p).round() as usize];
    let sum: Duration = all.iter().sum();
    println!(
        "\nper (log, program), fresh extractor, median of {reps}: {} pairs, median {:.1} ms, \
         p90 {:.1} ms, max {:.1} ms, sum {:.2} s",
        all.len(),
        pct(0.5).as_secs_f64() * 1e3,
        pct(0.9).as_secs_f64() * 1e3,
        pct(1.0).as_secs_f64() * 1e3,
        sum.as_secs_f64()
    );
    rows.sort_by(|a, b| b.0.cmp(&a.0).then_with(|| a.2.cmp(&b.2)));
    println!("slowest pairs:");
    for (d, log, name) in rows.iter().take(8) {
        println!("  {:>8.1} ms  {log}  {name}", d.as_secs_f64() * 1e3);
    }
}

fn main() {
    let scenarios = library();
    let logs = logs();
    let mut c = Criterion::default().configure_from_args();
    whole_runs(&mut c, &scenarios, &logs);
    c.final_summary();
    per_pair(&scenarios, &logs);
}
