//! Demand pushdown (`Options::pushdown`): every program of the rules library evaluated on the
//! three real AV2 logs with pushdown on and off gives the same derived relations, and pushdown
//! does cut what the extractors are asked for; plus hand-written cases of the request flow
//! (one request per distinct use, bindings through a lower stratum and through `ego`).

use std::collections::BTreeMap;

use scenalog_engine::value::cmp_value;
use scenalog_engine::{evaluate, EngineError, Evaluation, Options};
use scenalog_extractors::cache::Extractor;
use scenalog_extractors::query::satisfies;
use scenalog_facts::read::load_scene;
use scenalog_facts::relation::{Column, Constraint, RelationData, Request, Value};
use scenalog_facts::TrackId;
use scenalog_rules::{check, CheckOptions, CheckedProgram};
use scenalog_testkit::SceneBuilder;

use scenalog_testkit::{library_files, sample_log_dirs as logs};

fn library() -> Vec<(String, CheckedProgram)> {
    library_files()
        .into_iter()
        .map(|f| {
            let src = std::fs::read_to_string(&f).unwrap_or_else(|e| panic!("{e}"));
            let name = f
                .file_name()
                .map_or(String::new(), |n| n.to_string_lossy().into());
            match check(&src, &CheckOptions::default()).program {
                Some(p) => (name, p),
                None => panic!("{name} does not check"),
            }
        })
        .collect()
}

fn checked(src: &str) -> CheckedProgram {
    let outcome = check(
        src,
        &CheckOptions {
            require_referred: false,
        },
    );
    match outcome.program {
        Some(p) => p,
        None => panic!("program does not check: {:?}", outcome.diagnostics),
    }
}

/// The derived relations of an evaluation.
fn derived(e: &Evaluation) -> BTreeMap<String, Vec<Vec<Value>>> {
    e.derived
        .iter()
        .map(|n| (n.clone(), e.tuples(n).unwrap_or_default().to_vec()))
        .collect()
}

/// Evaluates with the extractor as provider; returns the evaluation, the requests sent and the
/// catalog tuples received.
fn run(
    ex: &Extractor<'_>,
    p: &CheckedProgram,
    pushdown: bool,
) -> Result<(Evaluation, Vec<Request>, usize), EngineError> {
    let mut asked = Vec::new();
    let mut received = 0;
    let mut provider = |r: &Request| -> Result<RelationData, String> {
        asked.push(r.clone());
        let d = ex.extract(r).map_err(|e| e.to_string())?;
        received += d.len();
        Ok((*d).clone())
    };
    let options = Options {
        pushdown,
        ..Options::default()
    };
    let e = evaluate(p, &mut provider, &options)?;
    Ok((e, asked, received))
}

#[test]
fn every_library_program_derives_the_same_with_pushdown_on_and_off() {
    let programs = library();
    assert!(programs.len() > 50, "only {} programs", programs.len());
    let (mut bound, mut fewer, mut compared, mut nonempty) = (0, 0, 0, 0);
    let mut tuple_level: BTreeMap<String, usize> = BTreeMap::new();
    let (mut received_on, mut received_off) = (0usize, 0usize);
    for log in logs() {
        let scene = load_scene(&log).unwrap_or_else(|e| panic!("{}: {e}", log.display()));
        let ex = Extractor::new(&scene);
        for (name, p) in &programs {
            let (on, asked, got_on) =
                run(&ex, p, true).unwrap_or_else(|e| panic!("{name}, pushdown on: {e}"));
            let (off, _, got_off) =
                run(&ex, p, false).unwrap_or_else(|e| panic!("{name}, pushdown off: {e}"));
            assert_eq!(
                derived(&on),
                derived(&off),
                "{name} on {}: pushdown changed a derived relation",
                log.display()
            );
            // Every catalog tuple pushdown loaded is one the full evaluation loaded too.
            for rel in on.names() {
                if on.derived.iter().any(|d| d == rel) {
                    continue;
                }
                let tuples = on.tuples(rel).unwrap_or_default();
                let all = off.tuples(rel).unwrap_or_default();
                let within = tuples.iter().all(|t| {
                    all.binary_search_by(|a| {
                        a.iter()
                            .zip(t)
                            .map(|(x, y)| cmp_value(x, y))
                            .find(|o| o.is_ne())
                            .unwrap_or(std::cmp::Ordering::Equal)
                    })
                    .is_ok()
                });
                assert!(
                    within,
                    "{name}: {rel} holds tuples the unpushed evaluation lacks"
                );
            }
            compared += 1;
            nonempty += usize::from(on.size("referred") > 0);
            bound += usize::from(asked.iter().any(|r| {
                r.constraints
                    .iter()
                    .any(|(_, c)| matches!(c, Constraint::OneOf(_)))
            }));
            if asked.iter().any(|r| {
                r.constraints
                    .iter()
                    .any(|(_, c)| matches!(c, Constraint::Triples(_)))
            }) {
                *tuple_level.entry(name.clone()).or_default() += 1;
            }
            fewer += usize::from(got_on < got_off);
            received_on += got_on;
            received_off += got_off;
        }
    }
    assert_eq!(compared, programs.len() * 3);
    // The comparison is not vacuous: many programs find something, many requests are bound,
    // and pushdown asks the extractors for fewer tuples overall.
    assert!(
        nonempty > 40,
        "only {nonempty} (program, log) pairs found anything"
    );
    assert!(
        bound > 60,
        "only {bound} evaluations sent a OneOf constraint"
    );
    // Tuple-level demand (`Triples`) is exercised: the pair relations bound through an earlier
    // pair relation of the same body (`near` after `following`, `heading_relative` after
    // `crossing` or `facing`) on every log.
    for program in [
        "vehicle_following_too_closely.dl",
        "vehicle_being_overtaken_on_the_left.dl",
        "vehicle_facing_the_ego_vehicle.dl",
    ] {
        assert!(
            tuple_level.get(program).is_some_and(|&n| n >= 2),
            "{program}: {tuple_level:?}"
        );
    }
    assert!(
        tuple_level.len() >= 5,
        "only {} programs sent a Triples constraint",
        tuple_level.len()
    );
    assert!(
        fewer > 40,
        "pushdown received fewer tuples in only {fewer} evaluations"
    );
    assert!(
        received_on * 2 < received_off,
        "pushdown received {received_on} catalog tuples, without {received_off}"
    );
}

/// A provider over fixed relations that honours every constraint exactly (as the extractors
/// must), recording the requests.
fn fixed_provider<'a>(
    tables: &'a BTreeMap<&'static str, RelationData>,
    asked: &'a mut Vec<Request>,
) -> impl FnMut(&Request) -> Result<RelationData, String> + 'a {
    let scene = SceneBuilder::new(8).build();
    move |r: &Request| {
        asked.push(r.clone());
        let d = tables
            .get(r.name.as_str())
            .ok_or_else(|| format!("no table {}", r.name))?;
        let keep: Vec<usize> = (0..d.len())
            .filter(|&i| {
                r.constraints.iter().all(|(c, k)| {
                    d.columns[*c]
                        .get(i)
                        .is_some_and(|v| satisfies(&scene, &v, k))
                })
            })
            .collect();
        Ok(RelationData {
            name: d.name.clone(),
            columns: d
                .columns
                .iter()
                .map(|c| match c {
                    Column::Track(v) => Column::Track(keep.iter().map(|&i| v[i]).collect()),
                    Column::Time(v) => Column::Time(keep.iter().map(|&i| v[i]).collect()),
                    Column::Str(v) => Column::Str(keep.iter().map(|&i| v[i].clone()).collect()),
                    Column::Float(v) => Column::Float(keep.iter().map(|&i| v[i]).collect()),
                    other => other.clone(),
                })
                .collect(),
        })
    }
}

/// Evaluates `p` over `tables` with pushdown on or off; returns the evaluation and the requests.
fn run_fixed(
    tables: &BTreeMap<&'static str, RelationData>,
    p: &CheckedProgram,
    pushdown: bool,
) -> (Evaluation, Vec<Request>) {
    let mut asked = Vec::new();
    let e = {
        let mut provider = fixed_provider(tables, &mut asked);
        let options = Options {
            pushdown,
            ..Options::default()
        };
        evaluate(p, &mut provider, &options).unwrap_or_else(|e| panic!("{e}"))
    };
    (e, asked)
}

fn tables() -> BTreeMap<&'static str, RelationData> {
    let t = |i: u32| TrackId(i);
    let s = |x: &str| -> std::sync::Arc<str> { x.into() };
    let mut m = BTreeMap::new();
    m.insert(
        "ego",
        RelationData {
            name: "ego".into(),
            columns: vec![Column::Track(vec![t(0)])],
        },
    );
    // direction(X, Y, T, Dir, Dist, Lat): 0 sees 1 on the right at 0..2; 1 sees 2 backward at 1;
    // 3 sees 4 on the right at 0; 4 sees 5 backward at 0; 2 sees 1 forward at 1.
    let rows: Vec<(u32, u32, u32, &str)> = vec![
        (0, 1, 0, "right"),
        (0, 1, 1, "right"),
        (1, 2, 1, "backward"),
        (3, 4, 0, "right"),
        (4, 5, 0, "backward"),
        (2, 1, 1, "forward"),
    ];
    m.insert(
        "direction",
        RelationData {
            name: "direction".into(),
            columns: vec![
                Column::Track(rows.iter().map(|r| t(r.0)).collect()),
                Column::Track(rows.iter().map(|r| t(r.1)).collect()),
                Column::Time(rows.iter().map(|r| r.2).collect()),
                Column::Str(rows.iter().map(|r| s(r.3)).collect()),
                Column::Float(rows.iter().map(|_| 1.0).collect()),
                Column::Float(rows.iter().map(|_| 0.0).collect()),
            ],
        },
    );
    m
}

#[test]
fn uses_are_asked_for_separately_and_bound_through_a_lower_stratum() {
    // `right_of_ego` is complete before `referred`'s stratum, so the second use of `direction`
    // is bound to its tracks (1) and frames (0, 1); each use keeps its own constant.
    let src = "right_of_ego(Y, T) :- ego(E), direction(E, Y, T, \"right\", _, _).\n\
               referred(Z, T) :- right_of_ego(Y, T), direction(Y, Z, T, \"backward\", _, _).\n";
    let p = checked(src);
    let tables = tables();
    let (on, asked_on) = run_fixed(&tables, &p, true);
    let (off, asked_off) = run_fixed(&tables, &p, false);
    let want = [vec![Value::Track(TrackId(2)), Value::Time(1)]];
    assert_eq!(on.tuples("referred"), Some(&want[..]));
    assert_eq!(off.tuples("referred"), Some(&want[..]));
    // Off: one request for `direction` whose two uses share no constant.
    let off_dir: Vec<&Request> = asked_off.iter().filter(|r| r.name == "direction").collect();
    assert_eq!(off_dir.len(), 1);
    assert!(off_dir[0].constraints.is_empty());
    // On: one request per use, each with its constant and its bound subjects.
    let on_dir: Vec<&Request> = asked_on.iter().filter(|r| r.name == "direction").collect();
    assert_eq!(on_dir.len(), 2, "{on_dir:?}");
    let ego_one = Constraint::OneOf(vec![Value::Track(TrackId(0))].into());
    assert!(on_dir[0].constraints.contains(&(0, ego_one)));
    assert!(on_dir[0]
        .constraints
        .contains(&(3, Constraint::Eq(Value::Str("right".into())))));
    let helper_tracks = Constraint::OneOf(vec![Value::Track(TrackId(1))].into());
    let helper_frames = Constraint::OneOf(vec![Value::Time(0), Value::Time(1)].into());
    assert!(on_dir[1].constraints.contains(&(0, helper_tracks)));
    assert!(on_dir[1].constraints.contains(&(2, helper_frames)));
    assert!(on_dir[1]
        .constraints
        .contains(&(3, Constraint::Eq(Value::Str("backward".into())))));
    // The catalog relation holds only the demanded tuples: 2 + 1 instead of all 6.
    assert_eq!(on.size("direction"), 3);
    assert_eq!(off.size("direction"), 6);
}

#[test]
fn an_empty_binding_asks_for_nothing_and_the_budget_counts_every_answer() {
    let src = "far(Y, T) :- ego(E), direction(E, Y, T, \"forward\", _, _).\n\
               referred(Z, T) :- far(Y, T), direction(Y, Z, T, _, _, _).\n";
    let p = checked(src);
    let tables = tables();
    let mut asked = Vec::new();
    let e = {
        let mut provider = fixed_provider(&tables, &mut asked);
        evaluate(&p, &mut provider, &Options::default()).unwrap_or_else(|e| panic!("{e}"))
    };
    assert_eq!(e.size("referred"), 0);
    // `far` is empty, so the second use needs no tuple and is not asked for.
    assert_eq!(asked.iter().filter(|r| r.name == "direction").count(), 1);
    // Budget: ego (1) + direction (6 with pushdown off) = 7 tuples; a budget of 6 fails on the
    // catalog input with pushdown off, and holds with it on (1 + 0 loaded).
    let src = "referred(Y, T) :- ego(E), direction(E, Y, T, _, _, _).\n";
    let p = checked(src);
    for (pushdown, ok) in [(false, false), (true, true)] {
        let mut asked = Vec::new();
        let mut provider = fixed_provider(&tables, &mut asked);
        let options = Options {
            max_tuples: 6,
            pushdown,
            ..Options::default()
        };
        match evaluate(&p, &mut provider, &options) {
            Ok(e) => {
                assert!(ok, "pushdown {pushdown}: expected the budget to be passed");
                assert_eq!(e.size("referred"), 2);
            }
            Err(EngineError::TooManyTuples { relation, .. }) => {
                assert!(!ok, "pushdown {pushdown}: {relation} passed the budget");
                assert!(relation == "direction" || relation == "ego", "{relation}");
            }
            Err(e) => panic!("{e}"),
        }
    }
}

#[test]
fn a_pair_relation_bound_by_a_relation_of_all_its_pair_columns_gets_their_triples() {
    // `pair` (complete before `referred`'s stratum) binds X, Y and T of the second `direction`
    // use together: the request carries exactly `pair`'s (X, Y, T) triples, and the result is
    // the one without pushdown.
    let src = "pair(X, Y, T) :- direction(X, Y, T, \"right\", _, _).\n\
               referred(Y, T) :- pair(X, Y, T), direction(X, Y, T, D, _, _), D != \"forward\".\n";
    let p = checked(src);
    let tables = tables();
    let (on, asked_on) = run_fixed(&tables, &p, true);
    let (off, _) = run_fixed(&tables, &p, false);
    let want: Vec<Vec<Value>> = vec![
        vec![Value::Track(TrackId(1)), Value::Time(0)],
        vec![Value::Track(TrackId(1)), Value::Time(1)],
        vec![Value::Track(TrackId(4)), Value::Time(0)],
    ];
    assert_eq!(on.tuples("referred"), Some(&want[..]));
    assert_eq!(off.tuples("referred"), Some(&want[..]));
    let t = TrackId;
    let triples =
        Constraint::Triples(vec![(t(0), t(1), 0), (t(0), t(1), 1), (t(3), t(4), 0)].into());
    let second: Vec<&Request> = asked_on
        .iter()
        .filter(|r| r.name == "direction" && r.constraints.iter().all(|(c, _)| *c != 3))
        .collect();
    assert_eq!(second.len(), 1, "{asked_on:?}");
    assert!(
        second[0].constraints.contains(&(0, triples)),
        "{:?}",
        second[0]
    );
    // A binding that leaves one of X, Y, T free sends no triples.
    let src = "pair(X, T) :- direction(X, _, T, \"right\", _, _).\n\
               referred(Y, T) :- pair(X, T), direction(X, Y, T, _, _, _).\n";
    let p = checked(src);
    let mut asked = Vec::new();
    {
        let mut provider = fixed_provider(&tables, &mut asked);
        evaluate(&p, &mut provider, &Options::default()).unwrap_or_else(|e| panic!("{e}"));
    }
    assert!(asked
        .iter()
        .flat_map(|r| &r.constraints)
        .all(|(_, c)| !matches!(c, Constraint::Triples(_))));
}

/// Rules that differ only in a bound on one relation, in one stratum or in many (issue #42):
/// the relation is loaded a few times, not once per rule, and the answer is the one pushdown
/// off gives. Before, 2,000 such rules on one log took 28 s (a load, sort and merge each).
#[test]
fn rules_differing_only_in_bounds_share_one_load_of_the_relation() {
    let log = &logs()[0];
    let scene = load_scene(log).unwrap_or_else(|e| panic!("{}: {e}", log.display()));
    let ex = Extractor::new(&scene);
    // Bounds descending (no earlier request subsumes a later one), and both sides.
    let n = 300;
    let mut src = String::new();
    for i in 0..n {
        src.push_str(&format!(
            "p{i}(V, T) :- present(V, T), T > {}, T <= {}.\n",
            (n - i) % 97,
            150 - i % 50
        ));
        src.push_str(&format!("q(V, T) :- p{i}(V, T).\n"));
    }
    // One stratum, several bounds: one request with the loosest bounds.
    src.push_str("r(V, T) :- present(V, T), T > 40.\nr(V, T) :- present(V, T), T >= 10, T < 20.\n");
    let p = checked(&src);
    let (on, asked, _) = run(&ex, &p, true).expect("pushdown on");
    let (off, _, _) = run(&ex, &p, false).expect("pushdown off");
    assert_eq!(derived(&on), derived(&off));
    let present = asked.iter().filter(|r| r.name == "present").count();
    assert!(present <= 3, "present asked {present} times: {asked:#?}");
    assert!(!on.tuples("q").unwrap_or_default().is_empty());
}
