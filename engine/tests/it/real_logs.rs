//! The engine on the three real Argoverse 2 logs in `tests/data/av2/logs/`, with the extractors
//! as the provider (as the mining pipeline calls it): every program of the rules library
//! evaluates, and one is checked against the same query computed directly from the extracted
//! relations.

use std::collections::{BTreeSet, HashSet};

use scenalog_engine::{evaluate, Options};
use scenalog_extractors::cache::Extractor;
use scenalog_facts::read::load_scene;
use scenalog_facts::relation::{RelationData, Request, Value};
use scenalog_rules::{check, CheckOptions, CheckedProgram};

use scenalog_testkit::{library_files, repo_root as root, sample_log_dirs as logs};

fn library() -> Vec<(String, CheckedProgram)> {
    library_files()
        .into_iter()
        .map(|f| {
            let src = std::fs::read_to_string(&f).unwrap_or_else(|e| panic!("{e}"));
            let outcome = check(&src, &CheckOptions::default());
            let name = f.display().to_string();
            match outcome.program {
                Some(p) => (name, p),
                None => panic!("{name} does not check: {:?}", outcome.diagnostics),
            }
        })
        .collect()
}

#[test]
fn every_library_program_evaluates_on_every_real_log() {
    let programs = library();
    assert!(programs.len() > 50, "only {} programs", programs.len());
    let mut nonempty = 0;
    for log in logs() {
        let scene = load_scene(&log).unwrap_or_else(|e| panic!("{}: {e}", log.display()));
        let ex = Extractor::new(&scene);
        for (name, program) in &programs {
            let mut provider = |r: &Request| -> Result<RelationData, String> {
                ex.extract(r)
                    .map(|d| (*d).clone())
                    .map_err(|e| e.to_string())
            };
            match evaluate(program, &mut provider, &Options::default()) {
                Ok(e) => nonempty += usize::from(e.size("referred") > 0),
                Err(e) => panic!("{name} on {}: {e}", log.display()),
            }
        }
    }
    assert!(
        nonempty > 20,
        "only {nonempty} (program, log) pairs found anything"
    );
}

/// With provenance on, every library program on every real log gives the same relations as
/// with it off, every derived tuple has a stamp, and the first tuples of each derived relation
/// prove: a derivation tree whose root is the tuple and whose nodes each name their clause.
#[test]
fn every_library_program_proves_its_derived_tuples_on_the_real_logs() {
    let programs = library();
    let options = Options {
        provenance: true,
        ..Options::default()
    };
    let (mut stamped, mut proved) = (0, 0);
    for log in logs() {
        let scene = load_scene(&log).unwrap_or_else(|e| panic!("{}: {e}", log.display()));
        let ex = Extractor::new(&scene);
        let mut provider = |r: &Request| -> Result<RelationData, String> {
            ex.extract(r)
                .map(|d| (*d).clone())
                .map_err(|e| e.to_string())
        };
        for (name, program) in &programs {
            let on = evaluate(program, &mut provider, &options)
                .unwrap_or_else(|e| panic!("{name} on {}: {e}", log.display()));
            let off = evaluate(program, &mut provider, &Options::default())
                .unwrap_or_else(|e| panic!("{name} on {}: {e}", log.display()));
            assert!(on == off, "{name} on {}", log.display());
            for rel in &on.derived {
                let tuples = on.tuples(rel).unwrap_or_default();
                for t in tuples {
                    assert!(
                        on.stamp(rel, t).is_some(),
                        "{name}: no stamp for {rel}{t:?}"
                    );
                    stamped += 1;
                }
                for t in tuples.iter().take(3) {
                    let proof = on.prove(rel, t).unwrap_or_else(|| {
                        panic!("{name} on {}: {rel}{t:?} does not prove", log.display())
                    });
                    assert_eq!((&proof.relation, &proof.tuple), (rel, t));
                    assert!(
                        proof.clause.is_some(),
                        "{name}: {rel}{t:?} proved by no clause"
                    );
                    proved += 1;
                }
            }
        }
    }
    assert!(stamped > 1000, "only {stamped} derived tuples stamped");
    assert!(proved > 200, "only {proved} derived tuples proved");
}

#[test]
fn stopped_car_matches_the_query_computed_by_hand() {
    let src = std::fs::read_to_string(root().join("rules/library/stopped_car.dl"))
        .unwrap_or_else(|e| panic!("{e}"));
    let Some(program) = check(&src, &CheckOptions::default()).program else {
        panic!("stopped_car.dl does not check");
    };
    let mut total = 0;
    for log in logs() {
        let scene = load_scene(&log).unwrap_or_else(|e| panic!("{}: {e}", log.display()));
        let ex = Extractor::new(&scene);
        let mut asked = Vec::new();
        let mut provider = |r: &Request| -> Result<RelationData, String> {
            asked.push(r.name.clone());
            ex.extract(r)
                .map(|d| (*d).clone())
                .map_err(|e| e.to_string())
        };
        let e = evaluate(&program, &mut provider, &Options::default())
            .unwrap_or_else(|e| panic!("{e}"));
        asked.sort();
        assert_eq!(asked, vec!["category", "speed"]);
        // By hand, from whole relations: cars (REGULAR_VEHICLE), speed < 0.5, parked or not.
        let whole = |n: &str| {
            ex.extract(&Request::all(n))
                .unwrap_or_else(|e| panic!("{e}"))
        };
        let category = whole("category");
        let cars: HashSet<String> = (0..category.len())
            .filter_map(|i| category.row(i))
            .filter(|r| r[1] == Value::Str("REGULAR_VEHICLE".into()))
            .map(|r| format!("{:?}", r[0]))
            .collect();
        let speed = whole("speed");
        let expected: BTreeSet<String> = (0..speed.len())
            .filter_map(|i| speed.row(i))
            .filter(|r| matches!(r[2], Value::Float(s) if s < 0.5))
            .filter(|r| cars.contains(&format!("{:?}", r[0])))
            .map(|r| format!("{:?} {:?}", r[0], r[1]))
            .collect();
        let got: BTreeSet<String> = e
            .tuples("referred")
            .unwrap_or_default()
            .iter()
            .map(|t| format!("{:?} {:?}", t[0], t[1]))
            .collect();
        assert_eq!(got, expected, "{}", log.display());
        total += got.len();
    }
    assert!(
        total > 0,
        "no stopped car in any log: the check compared nothing"
    );
}
