//! Times each stage of extraction on a log, one thread:
//! `cargo run --release -p scenalog-extractors --example stages LOG_DIR`.

use std::time::Instant;

use scenalog_extractors::Extractor;
use scenalog_facts::catalog::catalog;
use scenalog_facts::read::load_scene;
use scenalog_facts::relation::Request;

fn main() {
    let Some(dir) = std::env::args().nth(1) else {
        eprintln!("usage: stages LOG_DIR");
        std::process::exit(2);
    };
    let scene = match load_scene(std::path::Path::new(&dir)) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(p) => p,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    pool.install(|| {
        let ex = Extractor::new(&scene);
        let t = Instant::now();
        ex.kinematics();
        println!(
            "kinematics      {:>8.2} ms",
            t.elapsed().as_secs_f64() * 1e3
        );
        let t = Instant::now();
        ex.map_index();
        println!(
            "map index       {:>8.2} ms",
            t.elapsed().as_secs_f64() * 1e3
        );
        let t = Instant::now();
        ex.lanes();
        println!(
            "lanes           {:>8.2} ms",
            t.elapsed().as_secs_f64() * 1e3
        );
        let t = Instant::now();
        ex.turning();
        println!(
            "turning         {:>8.2} ms",
            t.elapsed().as_secs_f64() * 1e3
        );
        let t = Instant::now();
        ex.lane_changes();
        println!(
            "lane changes    {:>8.2} ms",
            t.elapsed().as_secs_f64() * 1e3
        );
        for spec in catalog() {
            let t = Instant::now();
            let n = ex.extract(&Request::all(spec.name)).map_or(0, |r| r.len());
            println!(
                "{:<16}{:>8.2} ms  {n}",
                spec.name,
                t.elapsed().as_secs_f64() * 1e3
            );
        }
    });
}
