//! Demand pushdown on the real sample logs: helper- and ego-bound joins, their parts alone, with
//! `Options::pushdown` on and off.
//!
//! Each sample is one evaluation with the extractors as provider, from a fresh [`Extractor`]
//! whose shared per-scene data (kinematics, map index, lanes, the per-frame box index) is
//! prepared before the clock starts, as in a mining run where many programs share it: what is
//! timed is extraction of the requested relations plus evaluation. Medians of `SAMPLES` runs;
//! derived relations are asserted equal with pushdown on and off before anything is timed.
//!
//! `cargo bench -p scenalog-engine --bench demand` (optionally a log directory as argument;
//! default: the three logs in `tests/data/av2/logs`).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use scenalog_engine::{evaluate, Evaluation, Options};
use scenalog_extractors::cache::Extractor;
use scenalog_extractors::pairs::pair_index;
use scenalog_facts::read::load_scene;
use scenalog_facts::relation::{RelationData, Request};
use scenalog_facts::Scene;
use scenalog_rules::{check, CheckOptions, CheckedProgram};

const SAMPLES: usize = 7;

const VEHICLES: &str = "vehicles(X, T) :- category(X, \"VEHICLE\"), present(X, T).\n";
const PEDS: &str = "peds(X, T) :- category(X, \"PEDESTRIAN\"), present(X, T).\n";
const EGO: &str = "ego_2(X, T) :- category(X, \"EGO_VEHICLE\"), present(X, T).\n";

/// `scenalog import refav` of "vehicle behind another vehicle that has a pedestrian on its
/// right side" (comments dropped), and its two parts as programs of their own.
fn ped_right_programs() -> [(&'static str, String); 3] {
    let right = "right_cand(X, Y, T, D) :- vehicles(X, T), peds(Y, T), X != Y, \
                 direction(X, Y, T, \"right\", D, Lat), D <= 5.0, Lat < 2.0.\n\
                 with_ped_right(X, T) :- right_cand(X, _, T, _).\n";
    let behind = |subjects: &str| {
        format!(
            "behind_cand(X, Y, T, D) :- {subjects}(X, T), vehicles(Y, T), X != Y, \
             direction(X, Y, T, \"backward\", D, Lat), D <= 25.0.\n\
             behind_pairs(X, Y, T) :- behind_cand(X, Y, T, D), \
             R = count : {{ behind_cand(X, Y2, T, D2), D2 < D }}, R < 1.\n\
             referred(Y, T) :- behind_pairs(_, Y, T).\n\
             related(Y, X, T) :- behind_pairs(X, Y, T).\n"
        )
    };
    [
        (
            "ped-right then behind (whole)",
            format!("{VEHICLES}{PEDS}{right}{}", behind("with_ped_right")),
        ),
        (
            "part 1: vehicles with a pedestrian on the right",
            format!("{VEHICLES}{PEDS}{right}referred(X, T) :- with_ped_right(X, T).\n"),
        ),
        (
            "part 2: the vehicle behind any vehicle",
            format!("{VEHICLES}{}", behind("vehicles")),
        ),
    ]
}

/// `scenalog import refav` of "vehicle to the back right of the ego vehicle" (two ego-bound
/// `direction` uses, "right" then "backward"), and its first part alone.
fn ego_programs() -> [(&'static str, String); 2] {
    let right = "right_cand(X, Y, T, D) :- ego_2(X, T), vehicles(Y, T), X != Y, \
                 direction(X, Y, T, \"right\", D, Lat), D <= 20.0, Lat < 5.0.\n\
                 back_right(Y, T) :- right_cand(_, Y, T, _).\n";
    let back = "back_cand(X, Y, T, D) :- ego_2(X, T), back_right(Y, T), X != Y, \
                direction(X, Y, T, \"backward\", D, Lat), D <= 20.0, Lat < 5.0.\n\
                referred(Y, T) :- back_cand(_, Y, T, _).\n";
    [
        (
            "ego: back right of the ego (whole)",
            format!("{EGO}{VEHICLES}{right}{back}"),
        ),
        (
            "ego part 1: right of the ego",
            format!("{EGO}{VEHICLES}{right}referred(Y, T) :- back_right(Y, T).\n"),
        ),
    ]
}

fn checked(src: &str) -> CheckedProgram {
    let outcome = check(src, &CheckOptions::default());
    match outcome.program {
        Some(p) => p,
        None => panic!("does not check: {:?}\n{src}", outcome.diagnostics),
    }
}

/// One evaluation from a fresh extractor whose shared data is prepared untimed; returns the
/// evaluation, the time of extraction + evaluation and the catalog tuples received.
fn once(scene: &Scene, p: &CheckedProgram, pushdown: bool) -> (Evaluation, Duration, usize) {
    let ex = Extractor::new(scene);
    ex.prepare();
    pair_index(&ex);
    let mut received = 0;
    let mut provider = |r: &Request| -> Result<RelationData, String> {
        let d = ex.extract(r).map_err(|e| e.to_string())?;
        received += d.len();
        Ok((*d).clone())
    };
    let options = Options {
        pushdown,
        ..Options::default()
    };
    let start = Instant::now();
    let e = evaluate(p, &mut provider, &options).unwrap_or_else(|e| panic!("{e}"));
    (e, start.elapsed(), received)
}

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn ms(d: Duration) -> String {
    format!("{:.1} ms", d.as_secs_f64() * 1e3)
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let arg = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    let logs: Vec<PathBuf> = match arg {
        Some(dir) => vec![PathBuf::from(dir)],
        None => {
            let dir = root.join("tests/data/av2/logs");
            let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
                .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_dir())
                .collect();
            v.sort();
            v
        }
    };
    let programs: Vec<(&str, CheckedProgram)> = ped_right_programs()
        .into_iter()
        .chain(ego_programs())
        .map(|(n, s)| (n, checked(&s)))
        .collect();
    println!("| log | program | referred | catalog tuples on / off | pushdown on | pushdown off | off / on |");
    println!("|---|---|---:|---:|---:|---:|---:|");
    for log in &logs {
        let scene = load_scene(log).unwrap_or_else(|e| panic!("{}: {e}", log.display()));
        let short: String = log.file_name().map_or(String::new(), |n| {
            n.to_string_lossy().chars().take(8).collect()
        });
        for (name, p) in &programs {
            let (on, _, got_on) = once(&scene, p, true);
            let (off, _, got_off) = once(&scene, p, false);
            for d in &on.derived {
                assert_eq!(on.tuples(d), off.tuples(d), "{name}: {d} differs");
            }
            let mut t_on = Vec::new();
            let mut t_off = Vec::new();
            for _ in 0..SAMPLES {
                t_on.push(once(&scene, p, true).1);
                t_off.push(once(&scene, p, false).1);
            }
            let (m_on, m_off) = (median(t_on), median(t_off));
            println!(
                "| {short} | {name} | {} | {got_on} / {got_off} | {} | {} | {:.1}x |",
                on.size("referred"),
                ms(m_on),
                ms(m_off),
                m_off.as_secs_f64() / m_on.as_secs_f64()
            );
        }
    }
}
