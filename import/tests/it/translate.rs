//! The translation of each RefAV construct. Meaning is tested on the real sample log 3b3570b4:
//! RefAV's algebra must hold on what the imported programs find (a `scenario_not` and its
//! positive part split the input, `reverse_relationship` of `get_objects_in_relative_direction`
//! is `has_objects_in_relative_direction`, `max_number` caps the related objects, …), and errors
//! must name the line and the construct.

use std::collections::BTreeSet;
use std::sync::OnceLock;

use scenalog_engine::{evaluate, Options};
use scenalog_extractors::cache::Extractor;
use scenalog_facts::read::load_scene;
use scenalog_facts::relation::{RelationData, Request, Value};
use scenalog_facts::Scene;
use scenalog_import::{
    import_checked, import_checked_with, Defect, Defects, ImportError, Semantics,
};
use scenalog_rules::{check, CheckOptions};

fn scene() -> &'static Scene {
    static SCENE: OnceLock<Scene> = OnceLock::new();
    SCENE.get_or_init(|| sample_log("3b3570b4-7b0b-3268-a571-b0889dbf40b6"))
}

/// One of the bundled sample logs.
fn sample_log(id: &str) -> Scene {
    let log = scenalog_testkit::sample_log(id);
    load_scene(&log).unwrap_or_else(|e| panic!("{}: {e}", log.display()))
}

const HEAD: &str = "vehicles = get_objects_of_category(log_dir, category='VEHICLE')\n\
                    peds = get_objects_of_category(log_dir, category='PEDESTRIAN')\n\
                    objects = get_objects_of_category(log_dir, category='ANY')\n";

fn imported(body: &str) -> String {
    let src = format!("{HEAD}{body}\noutput_scenario(result, description, log_dir, output_dir)\n");
    match import_checked(&src, "test program.txt") {
        Ok(p) => p.program,
        Err(e) => panic!("does not import: {e:?}\n{src}"),
    }
}

fn errors(src: &str) -> Vec<ImportError> {
    match import_checked(src, "test program.txt") {
        Ok(p) => panic!("imported, expected an error:\n{}", p.program),
        Err(e) => e,
    }
}

type Pairs = BTreeSet<(u32, u32)>;
type Triples = BTreeSet<(u32, u32, u32)>;

/// Referred (track, frame) and related (track, other, frame) of `result` on the sample log.
fn run(body: &str) -> (Pairs, Triples) {
    run_program(&imported(body))
}

/// [`run`] with the program imported in `semantics`.
fn run_in(semantics: Semantics, body: &str) -> (Pairs, Triples) {
    let src = format!("{HEAD}{body}\noutput_scenario(result, description, log_dir, output_dir)\n");
    match import_checked_with(&src, "test program.txt", semantics) {
        Ok(p) => run_program(&p.program),
        Err(e) => panic!("does not import: {e:?}\n{src}"),
    }
}

/// RefAV's definitions with only `defect` reproduced, and with none.
fn with_and_without(defect: Defect) -> [Semantics; 2] {
    [
        Semantics::Refav(Defects::NONE.with(defect)),
        Semantics::Refav(Defects::NONE),
    ]
}

fn run_program(program: &str) -> (Pairs, Triples) {
    run_program_on(scene(), program)
}

/// The sample log adcf7d18, whose pedestrians walk on and off its 11 crosswalks (3b3570b4 has
/// none at a crosswalk).
fn crosswalk_scene() -> &'static Scene {
    static SCENE: OnceLock<Scene> = OnceLock::new();
    SCENE.get_or_init(|| sample_log("adcf7d18-0510-35b0-a2fa-b4cea13a6d76"))
}

fn run_program_on(scene: &Scene, program: &str) -> (Pairs, Triples) {
    let program = program.to_string();
    let Some(checked) = check(&program, &CheckOptions::default()).program else {
        panic!("does not check:\n{program}")
    };
    let ex = Extractor::new(scene);
    let mut provider = |r: &Request| -> Result<RelationData, String> {
        ex.extract(r)
            .map(|d| (*d).clone())
            .map_err(|e| e.to_string())
    };
    let e = evaluate(&checked, &mut provider, &Options::default())
        .unwrap_or_else(|e| panic!("{e}\n{program}"));
    let id = |v: &Value| match v {
        Value::Track(t) => t.0,
        Value::Time(f) => *f,
        other => panic!("{other:?}"),
    };
    let referred = e
        .tuples("referred")
        .unwrap_or(&[])
        .iter()
        .map(|t| (id(&t[0]), id(&t[1])))
        .collect();
    let related = e
        .tuples("related")
        .unwrap_or(&[])
        .iter()
        .map(|t| (id(&t[0]), id(&t[1]), id(&t[2])))
        .collect();
    (referred, related)
}

#[test]
fn scenario_not_and_its_positive_part_split_the_input() {
    let (all, _) = run("result = vehicles");
    let (moving, _) = run("result = scenario_not(stationary)(vehicles, log_dir)");
    let (parked, _) = run("result = stationary(vehicles, log_dir)");
    assert!(!moving.is_empty() && !parked.is_empty());
    assert!(moving.is_disjoint(&parked));
    assert_eq!(moving.union(&parked).copied().collect::<Pairs>(), all);
    // has_velocity returns nothing for stationary objects, so its negation keeps them all
    let (not_fast, _) =
        run("result = scenario_not(has_velocity)(vehicles, log_dir, min_velocity=3)");
    assert!(parked.is_subset(&not_fast));
    let (fast, _) = run("result = has_velocity(vehicles, log_dir, 3)"); // positional min_velocity
    assert!(fast.is_disjoint(&not_fast));
    assert_eq!(fast.union(&not_fast).copied().collect::<Pairs>(), all);
}

#[test]
fn and_or_of_filters() {
    let (a, _) = run("result = has_velocity(vehicles, log_dir, min_velocity=2)");
    let (b, _) = run("result = on_intersection(vehicles, log_dir)");
    let (and, _) = run(
        "a = has_velocity(vehicles, log_dir, min_velocity=2)\nb = on_intersection(vehicles, log_dir)\nresult = scenario_and([a, b])",
    );
    let (or, _) = run(
        "result = scenario_or([has_velocity(vehicles, log_dir, min_velocity=2), on_intersection(vehicles, log_dir)])",
    );
    assert!(!and.is_empty());
    assert_eq!(and, a.intersection(&b).copied().collect());
    assert_eq!(or, a.union(&b).copied().collect());
}

#[test]
fn relative_direction_min_max_number_and_reverse() {
    let call = |extra: &str| {
        format!("result = has_objects_in_relative_direction(vehicles, vehicles, log_dir, direction='forward', within_distance=30{extra})")
    };
    let (one, rel_one) = run(&call(""));
    let (two, _) = run(&call(", min_number=2"));
    let (capped, rel_capped) = run(&call(", max_number=1"));
    assert!(
        !two.is_empty() && two.len() < one.len(),
        "{} vs {}",
        two.len(),
        one.len()
    );
    assert!(two.is_subset(&one));
    assert_eq!(
        capped, one,
        "max_number caps the related objects, not the referred"
    );
    // at most one related object per (track, frame) with max_number=1, and fewer in all
    let mut seen = BTreeSet::new();
    for (x, _, t) in &rel_capped {
        assert!(seen.insert((*x, *t)), "two related for {x} at {t}");
    }
    assert!(rel_capped.len() < rel_one.len());
    // get_objects_in_relative_direction is the reverse: the related objects become the referred
    let (got, got_rel) = run(
        "result = get_objects_in_relative_direction(vehicles, vehicles, log_dir, direction='forward', within_distance=30)",
    );
    let expect: Pairs = rel_one.iter().map(|(_, y, t)| (*y, *t)).collect();
    assert_eq!(got, expect);
    assert!(got_rel
        .iter()
        .all(|(y, x, t)| rel_one.contains(&(*x, *y, *t))));
    // and reversing that again gives has_objects_in_relative_direction (RefAV special-cases it)
    let (back, _) = run(
        "result = reverse_relationship(get_objects_in_relative_direction)(vehicles, vehicles, log_dir, direction='forward', within_distance=30, min_number=1)",
    );
    assert_eq!(back, one);
    // a nested call as an argument
    let (nested, _) = run(
        "result = has_objects_in_relative_direction(scenario_not(stationary)(vehicles, log_dir), vehicles, log_dir, 'forward', 1, np.inf, 30)",
    );
    let (moving, _) = run("result = scenario_not(stationary)(vehicles, log_dir)");
    assert_eq!(nested, one.intersection(&moving).copied().collect());
}

#[test]
fn reverse_relationship_of_near_objects() {
    let (near, rel) = run("result = near_objects(vehicles, peds, log_dir, distance_thresh=5)");
    let (rev, rev_rel) = run(
        "result = reverse_relationship(near_objects)(vehicles, peds, log_dir, distance_thresh=5)",
    );
    assert!(!near.is_empty());
    assert_eq!(rev, rel.iter().map(|(_, p, t)| (*p, *t)).collect::<Pairs>());
    assert_eq!(
        rev_rel,
        rel.iter()
            .map(|(v, p, t)| (*p, *v, *t))
            .collect::<Triples>()
    );
    let (three, _) =
        run("result = near_objects(vehicles, peds, log_dir, distance_thresh=5, min_objects=3)");
    assert!(three.is_subset(&near) && three.len() < near.len());
}

#[test]
fn crossing_extents_and_sense() {
    let (default, _) = run("result = being_crossed_by(vehicles, objects, log_dir)");
    let (wide, _) = run(
        "result = being_crossed_by(vehicles, objects, log_dir, forward_thresh=20, lateral_thresh=10)",
    );
    let (cw, _) = run("result = being_crossed_by(vehicles, objects, log_dir, forward_thresh=20, lateral_thresh=10, in_direction='clockwise')");
    let (ccw, _) = run("result = being_crossed_by(vehicles, objects, log_dir, forward_thresh=20, lateral_thresh=10, in_direction='counterclockwise')");
    assert!(!default.is_empty());
    assert!(
        default.is_subset(&wide),
        "larger extents find at least as much"
    );
    assert!(wide.len() > default.len());
    assert_eq!(cw.union(&ccw).copied().collect::<Pairs>(), wide);
    assert!(!cw.is_empty() && !ccw.is_empty());
}

#[test]
fn the_emitted_program_names_its_description_and_lines() {
    let p = imported("result = changing_lanes(vehicles, log_dir, direction='left')");
    assert!(p.starts_with("// description: test program\n"), "{p}");
    assert!(
        p.contains("// line 4: result = changing_lanes(vehicles, log_dir, direction='left')"),
        "{p}"
    );
    assert!(p.contains("lane_change(X, T, \"left\")"), "{p}");
    let p = imported("description = 'my words'\nresult = turning(vehicles, log_dir)");
    assert!(p.starts_with("// description: my words\n"), "{p}");
}

#[test]
fn errors_name_the_line_and_the_construct() {
    let e = errors(&format!("{HEAD}for v in vehicles:\n    pass\noutput_scenario(vehicles, description, log_dir, output_dir)\n"));
    assert_eq!(
        (e[0].line, e[0].construct.as_str(), e[0].refav_broken),
        (4, "for loop", false)
    );
    let e = errors(&format!("{HEAD}x = accelerating(vehicles, log_dir, speed=1.0)\noutput_scenario(x, description, log_dir, output_dir)\n"));
    assert_eq!(
        (e[0].line, e[0].construct.as_str(), e[0].refav_broken),
        (4, "accelerating", true)
    );
    assert!(
        e[0].message.contains("unexpected keyword argument 'speed'"),
        "{}",
        e[0].message
    );
    let e = errors(&format!("{HEAD}x = on_road_lane(vehicles, log_dir)\noutput_scenario(x, description, log_dir, output_dir)\n"));
    assert!(e[0].refav_broken && e[0].message.contains("no function named 'on_road_lane'"));
    let e = errors(&format!("{HEAD}x = near_objects(vehicles, peds, log_dir, distance_thresh=2 * 5)\noutput_scenario(x, description, log_dir, output_dir)\n"));
    assert_eq!(
        (e[0].line, e[0].construct.as_str()),
        (4, "arithmetic expression")
    );
    let e = errors(&format!("{HEAD}x = get_objects_in_relative_direction(vehicles, peds, log_dir, direction='above')\noutput_scenario(x, description, log_dir, output_dir)\n"));
    assert!(e[0].message.contains("'above'"), "{}", e[0].message);
    // a category AV2 does not have is an error (RefAV silently finds nothing)
    let e = errors("cars = get_objects_of_category(log_dir, category='CAR')\noutput_scenario(cars, description, log_dir, output_dir)\n");
    assert_eq!((e[0].line, e[0].refav_broken), (1, false), "{e:?}");
    assert!(e[0].message.contains("'CAR'"), "{e:?}");
    // no output_scenario
    let e = errors(HEAD);
    assert_eq!(e[0].construct, "output_scenario");
    // a syntax error
    let e = errors("x = (\n");
    assert!(e[0].refav_broken && e[0].construct == "Python syntax");
    // an undefined name stops the program, as Python does
    let e = errors("x = is_category(cars, log_dir, category='BUS')\ny = is_category(x, log_dir, category='BUS')\noutput_scenario(y, description, log_dir, output_dir)\n");
    assert_eq!(e.len(), 1);
    assert!(e[0].message.contains("name 'cars' is not defined"));
}

mod fuzz {
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// No input makes the importer panic, and what it accepts checks.
        #[test]
        fn never_panics(src in "[a-z_=()\\[\\]',. 0-9\\n]{0,120}") {
            if let Ok(p) = scenalog_import::import_checked(&src, "fuzz.py") {
                let ok = scenalog_rules::check(&p.program, &scenalog_rules::CheckOptions::default()).program.is_some();
                prop_assert!(ok);
            }
        }

        /// Mutations of a real program (a character deleted or replaced) never panic.
        #[test]
        fn mutated_real_program_never_panics(at in 0usize..400, c in proptest::char::any()) {
            let src = include_str!("../data/refav_programs/vehicle with a bicycle to its right.txt");
            let mut chars: Vec<char> = src.chars().collect();
            if !chars.is_empty() {
                let i = at % chars.len();
                chars[i] = c;
            }
            let mutated: String = chars.into_iter().collect();
            let _ = scenalog_import::import_checked(&mutated, "mutated.txt");
        }
    }
}

/// `at_pedestrian_crossing` at RefAV's default distance is the prelude's `at_a_crosswalk`
/// (`rules/prelude.dl`), written with it; another distance keeps the catalog relation. Both
/// find the same pairs as the catalog relation written out.
#[test]
fn at_pedestrian_crossing_at_the_default_distance_is_the_prelude_concept() {
    let prelude = scenalog_rules::prelude::relation("at_a_crosswalk").expect("prelude relation");
    assert_eq!(
        prelude.definition,
        ["at_a_crosswalk(X, T) :- at_crosswalk(X, T, D), D <= 1.0 m."]
    );
    let default = imported("result = at_pedestrian_crossing(peds, log_dir)");
    assert!(default.contains("at_a_crosswalk(X, T)"), "{default}");
    let wider = imported("result = at_pedestrian_crossing(peds, log_dir, within_distance=2)");
    assert!(wider.contains("at_crosswalk(X, T, D), D <= 2"), "{wider}");
    let (by_prelude, _) = run("result = at_pedestrian_crossing(objects, log_dir)");
    let (by_catalog, _) =
        run("result = at_pedestrian_crossing(objects, log_dir, within_distance=1.0000001)");
    assert!(!by_prelude.is_empty());
    assert!(by_prelude.is_subset(&by_catalog));
}

/// `get_objects_in_relative_direction(..., min_number=N)` keeps only the frames where the track
/// has at least N candidates in the direction: its referred objects are the related objects of
/// `has_objects_in_relative_direction` with the same count.
#[test]
fn get_objects_in_relative_direction_keeps_min_number() {
    let args = "vehicles, vehicles, log_dir, direction='forward', within_distance=30";
    let (_, rel_one) = run(&format!(
        "result = has_objects_in_relative_direction({args})"
    ));
    let (_, rel_two) = run(&format!(
        "result = has_objects_in_relative_direction({args}, min_number=2)"
    ));
    let (got_any, _) = run(&format!(
        "result = get_objects_in_relative_direction({args})"
    ));
    let (got_two, _) = run(&format!(
        "result = get_objects_in_relative_direction({args}, min_number=2)"
    ));
    let expect: Pairs = rel_two.iter().map(|(_, y, t)| (*y, *t)).collect();
    assert_eq!(got_two, expect);
    assert_eq!(
        got_any,
        rel_one.iter().map(|(_, y, t)| (*y, *t)).collect::<Pairs>()
    );
    assert!(!got_two.is_empty() && got_two.len() < got_any.len());
}

/// A reversed relation carries the original tracks' related objects along, as RefAV nests them
/// under the reversed relation: the vehicle behind a vehicle with a pedestrian on its right is
/// related to both.
#[test]
fn reversal_carries_the_tracks_related_objects() {
    let with_ped = "a = has_objects_in_relative_direction(vehicles, peds, log_dir, direction='right', within_distance=5, lateral_thresh=2)\n";
    let (_, a_rel) = run(&format!("{with_ped}result = a"));
    let (behind, behind_rel) = run(&format!(
        "{with_ped}result = get_objects_in_relative_direction(a, vehicles, log_dir, direction='backward', max_number=1, within_distance=25)"
    ));
    assert!(!behind.is_empty());
    // (behind, front, T) pairs; each also relates the front vehicle's pedestrians at T
    let fronts: Triples = behind_rel
        .iter()
        .filter(|(_, x, t)| a_rel.iter().any(|(f, _, ft)| f == x && ft == t))
        .copied()
        .collect();
    let mut expect = fronts.clone();
    for (y, x, t) in &fronts {
        for (f, p, ft) in &a_rel {
            if f == x && ft == t {
                expect.insert((*y, *p, *t));
            }
        }
    }
    assert_eq!(behind_rel, expect);
    assert!(behind_rel.len() > fronts.len());
}

/// `scenario_not(reverse_relationship(f))(a, b, log_dir)`: RefAV's `scenario_not` takes the
/// tracks of `a` and removes the frames where a track is a top-level object of the reversed
/// relation, whose top level is `b`'s crossers.
#[test]
fn scenario_not_of_a_reversed_relation() {
    let (all, _) = run("result = vehicles");
    // the reversal's top level is pedestrians, so no vehicle is removed (RefAV's own outcome)
    let (kept, _) = run(
        "result = scenario_not(reverse_relationship(being_crossed_by))(vehicles, peds, log_dir)",
    );
    assert_eq!(kept, all);
    // among vehicles, those crossing another vehicle at a frame are removed at that frame
    let (crossers, _) =
        run("result = reverse_relationship(being_crossed_by)(vehicles, vehicles, log_dir)");
    let (rest, _) = run(
        "result = scenario_not(reverse_relationship(being_crossed_by))(vehicles, vehicles, log_dir)",
    );
    assert!(!crossers.is_empty());
    assert_eq!(rest, all.difference(&crossers).copied().collect::<Pairs>());
    // log_dir by keyword: RefAV's wrapper reads it from the third positional argument
    let e = errors(&format!("{HEAD}x = scenario_not(reverse_relationship(being_crossed_by))(vehicles, peds, log_dir=log_dir)\noutput_scenario(x, description, log_dir, output_dir)\n"));
    assert!(e[0].refav_broken, "{e:?}");
}

/// `accelerating(..., thresh=X)` is RefAV's first API: forward acceleration >= X without an
/// upper bound, and (as then) stationary objects not excluded; the program says which API.
#[test]
fn first_api_accelerating_thresh() {
    let first = imported("result = accelerating(vehicles, log_dir, thresh=1.0)");
    assert!(first.contains("// RefAV API: first"), "{first}");
    assert!(first.contains("accel(X, T, V), V >= 1.0 m/s2."), "{first}");
    let current = imported("result = accelerating(vehicles, log_dir, min_accel=1.0)");
    assert!(current.contains("// RefAV API: current"), "{current}");
    let (old, _) = run("result = accelerating(objects, log_dir, thresh=-1.0)");
    let (new, _) = run("result = accelerating(objects, log_dir, min_accel=-1.0)");
    let (parked, _) = run("result = stationary(objects, log_dir)");
    assert!(new.is_subset(&old) && new.len() < old.len());
    let extra: Pairs = old.difference(&new).copied().collect();
    assert!(
        extra.is_subset(&parked),
        "only stationary objects are added"
    );
    match import_checked(
        &format!("{HEAD}x = accelerating(vehicles, log_dir, thresh=2)\noutput_scenario(x, description, log_dir, output_dir)\n"),
        "t.txt",
    ) {
        Ok(p) => assert!(p.first_api && p.notes.iter().any(|n| n.contains("first API"))),
        Err(e) => panic!("{e:?}"),
    }
}

/// `--defects ego-back-edge`: RefAV's back edge of the ego 1.02 m ahead of the rear axle widens
/// "behind the ego" and shortens its sides; without it the box runs back to 1.02 m behind.
#[test]
fn the_ego_back_edge_defect_widens_behind_and_shortens_the_sides() {
    let [slip, meant] = with_and_without(Defect::EgoBackEdge);
    let ego = "ego = get_objects_of_category(log_dir, category='EGO_VEHICLE')\n";
    for (dir, wider) in [("backward", true), ("right", false), ("left", false)] {
        let body = format!(
            "{ego}result = has_objects_in_relative_direction(ego, vehicles, log_dir, direction='{dir}', within_distance=20, lateral_thresh=3)"
        );
        let (_, with) = run_in(slip, &body);
        let (_, without) = run_in(meant, &body);
        let (big, small) = if wider {
            (&with, &without)
        } else {
            (&without, &with)
        };
        assert!(small.is_subset(big), "{dir}");
        assert!(
            big.len() > small.len(),
            "{dir}: {} vs {}",
            big.len(),
            small.len()
        );
    }
}

/// `--defects reverse-carry-over`: a reversal makes the tracks' earlier related objects that are
/// among its candidates referred objects, at the frames of the earlier relation where the
/// function relates the track to something; without it only the function's own pairs reverse.
/// "The ego two cars ahead of another vehicle": the first reversal relates the vehicle behind
/// the ego to the ego, a VEHICLE candidate of the second, so RefAV makes the ego referred.
#[test]
fn the_reverse_carry_over_defect_makes_earlier_related_candidates_referred() {
    let [carry, meant] = with_and_without(Defect::ReverseCarryOver);
    let first = "ego = get_objects_of_category(log_dir, category='EGO_VEHICLE')\n\
                 behind = get_objects_in_relative_direction(ego, vehicles, log_dir, direction='backward', max_number=1, within_distance=25)\n";
    let body = format!("{first}result = get_objects_in_relative_direction(behind, vehicles, log_dir, direction='backward', max_number=1, within_distance=25)");
    let (with, with_rel) = run_in(carry, &body);
    let (without, without_rel) = run_in(meant, &body);
    let (_, behind_rel) = run_in(meant, &format!("{first}result = behind"));
    assert!(without.is_subset(&with));
    let extra: Pairs = with.difference(&without).copied().collect();
    assert!(!extra.is_empty());
    let ego = scene().ego.0;
    for &(z, t) in &extra {
        assert_eq!(z, ego, "only the ego is carried here");
        // the ego is related at t to a vehicle v behind it, and v has a vehicle behind it at t
        let carriers: Vec<u32> = behind_rel
            .iter()
            .filter(|&&(v, e, ft)| {
                e == z && ft == t && without_rel.iter().any(|&(_, w, wt)| w == v && wt == t)
            })
            .map(|&(v, _, _)| v)
            .collect();
        assert!(!carriers.is_empty(), "({z}, {t})");
        // and in the result the ego is related to that vehicle at t
        assert!(
            carriers.iter().any(|v| with_rel.contains(&(z, *v, t))),
            "({z}, {t})"
        );
    }
}

/// `--defects crossing-direction`: after the first candidate found crossing a track, RefAV
/// tests the later ones against the forward plane; for a forward crossing nothing changes.
#[test]
fn the_crossing_direction_defect_changes_only_sideways_crossings() {
    let [overwrite, meant] = with_and_without(Defect::CrossingDirection);
    let moving = "moving = scenario_not(stationary)(vehicles, log_dir)\n";
    let body = |dir: &str| {
        format!("{moving}result = being_crossed_by(moving, moving, log_dir, direction='{dir}', forward_thresh=5, lateral_thresh=10)")
    };
    assert_eq!(
        run_in(overwrite, &body("forward")),
        run_in(meant, &body("forward"))
    );
    let (with, _) = run_in(overwrite, &body("right"));
    let (without, _) = run_in(meant, &body("right"));
    assert_ne!(with, without);
    // Every track keeps at least the frames of its first crosser's crossings, so no track that
    // is crossed on the right loses every frame.
    let tracks = |p: &Pairs| p.iter().map(|x| x.0).collect::<BTreeSet<u32>>();
    assert!(tracks(&without).is_subset(&tracks(&with)));
}

/// `--defects crosswalk-loop`: RefAV's `at_pedestrian_crossing` tests, after a track's first
/// frame, only the crossings its box overlapped at the frame before, and none once it overlapped
/// none. On adcf7d18: a pedestrian off every crossing at its first frame is at one at most at
/// that frame, and at a later frame only at a crossing it stood on the frame before.
#[test]
fn the_crosswalk_loop_defect_loses_pedestrians_that_step_onto_a_crosswalk() {
    let [looped, meant] = with_and_without(Defect::CrosswalkLoop);
    let src = |semantics| {
        let text = "peds = get_objects_of_category(log_dir, category='PEDESTRIAN')\n\
                    result = at_pedestrian_crossing(peds, log_dir, within_distance=1)\n\
                    output_scenario(result, description, log_dir, output_dir)\n";
        match import_checked_with(text, "peds at crosswalk.txt", semantics) {
            Ok(p) => p.program,
            Err(e) => panic!("{e:?}"),
        }
    };
    let scene = crosswalk_scene();
    let (with, _) = run_program_on(scene, &src(looped));
    let (without, _) = run_program_on(scene, &src(meant));
    assert!(with.is_subset(&without));
    assert!(
        with.len() < without.len(),
        "{} vs {}",
        with.len(),
        without.len()
    );
    // RefAV's own rule, from the crossings each box overlaps (D = 0) and is within 1 m of.
    let ex = Extractor::new(scene);
    let data = ex
        .extract(&Request::all("refav_crosswalk"))
        .unwrap_or_else(|e| panic!("{e}"));
    let mut near: BTreeSet<(u32, u32, i64)> = BTreeSet::new();
    let mut on: BTreeSet<(u32, u32, i64)> = BTreeSet::new();
    for i in 0..data.len() {
        let row = data.row(i).unwrap_or_else(|| panic!("row {i}"));
        let (Value::Track(x), Value::Time(t), Value::Int(c), Value::Float(d)) =
            (&row[0], &row[1], &row[2], &row[3])
        else {
            panic!("{row:?}")
        };
        if *d <= 1.0 {
            near.insert((x.0, *t, *c));
        }
        if *d <= 0.0 {
            on.insert((x.0, *t, *c));
        }
    }
    let mut expect = Pairs::new();
    for t in scene.tracks.iter().filter(|t| t.category == "PEDESTRIAN") {
        let x = t.id.0;
        let frames: Vec<u32> = t.boxes.iter().map(|b| b.frame).collect();
        let Some(&first) = frames.first() else {
            continue;
        };
        if near.iter().any(|&(y, f, _)| y == x && f == first) {
            expect.insert((x, first));
        }
        for w in frames.windows(2) {
            let (p, f) = (w[0], w[1]);
            let was_on: Vec<i64> = on
                .iter()
                .filter(|&&(y, g, _)| y == x && g == p)
                .map(|r| r.2)
                .collect();
            if was_on.is_empty() {
                break; // RefAV's list is empty from here on
            }
            if was_on.iter().any(|&c| near.contains(&(x, f, c))) {
                expect.insert((x, f));
            }
        }
    }
    assert_eq!(with, expect);
}

/// `--defects turning-spikes`: RefAV's `turning` sums runs of the raw yaw rate, so a one-frame
/// heading spike splits a turn into runs too short to count; without it (the rate's 3-sample
/// median) the split turns are found whole. On the sample log "vehicle turning right" finds
/// RefAV's 258 (track, frame) pairs with the defect and more without it, the same ones and
/// the frames of the turns the spikes split.
#[test]
fn the_turning_spikes_defect_splits_turns() {
    let [spikes, meant] = with_and_without(Defect::TurningSpikes);
    let body = "result = turning(vehicles, log_dir, direction='right')";
    let (with, _) = run_in(spikes, body);
    let (without, _) = run_in(meant, body);
    assert_eq!(with.len(), 258);
    assert!(
        with.is_subset(&without),
        "{:?}",
        with.difference(&without).collect::<Vec<_>>()
    );
    assert!(without.len() > with.len());
    // every vehicle RefAV's rule finds turning right is found without the defect too
    let tracks = |p: &Pairs| p.iter().map(|x| x.0).collect::<BTreeSet<u32>>();
    assert!(tracks(&with).is_subset(&tracks(&without)));
}

/// The tracks of a (track, frame) set.
fn tracks_of(p: &Pairs) -> BTreeSet<u32> {
    p.iter().map(|&(t, _)| t).collect()
}

/// A copy of the sample log 3b3570b4 in a temporary folder with `cache` as its
/// `cache/color_cache.json`.
fn log_with_color_cache(cache: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    let tmp = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let to = scenalog_testkit::copy_sample_log(scenalog_testkit::SAMPLE_LOGS[0], tmp.path());
    std::fs::create_dir_all(to.join("cache")).unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(to.join("cache/color_cache.json"), cache).unwrap_or_else(|e| panic!("{e}"));
    (tmp, to)
}

#[test]
fn is_color_reads_refavs_colour_cache_and_without_one_keeps_every_object() {
    let base = scene();
    let vehicles: Vec<&scenalog_facts::Track> = base
        .tracks
        .iter()
        .filter(|t| t.id != base.ego && scenalog_facts::scene::is_vehicle_category(&t.category))
        .collect();
    let [red, blue, unknown, ..] = vehicles[..] else {
        panic!("fewer than 3 vehicles")
    };
    // As RefAV's construct_caches writes it: json.dump of uuid -> colour word, or null where
    // no crop was found; a uuid of another log's track is ignored.
    let cache = format!(
        "{{\"{}\": \"red\", \"{}\": \"blue\", \"{}\": null, \"not-in-this-log\": \"red\"}}",
        red.uuid, blue.uuid, unknown.uuid
    );
    let (_tmp, dir) = log_with_color_cache(&cache);
    let cached = load_scene(&dir).unwrap_or_else(|e| panic!("{e}"));
    let program = imported("result = is_color(vehicles, log_dir, color='red')");
    assert!(
        program.contains("refav_color(X, C), C != \"red\""),
        "{program}"
    );
    assert!(
        program.contains("// note: is_color reads RefAV's colour cache"),
        "{program}"
    );
    let all = tracks_of(&run("result = vehicles").0);
    // RefAV keeps the red one and every vehicle the cache does not hold; the blue one and the
    // one without a colour go.
    let want: BTreeSet<u32> = all
        .iter()
        .copied()
        .filter(|&t| t != blue.id.0 && t != unknown.id.0)
        .collect();
    let (with_cache, _) = run_program_on(&cached, &program);
    assert_eq!(tracks_of(&with_cache), want);
    assert!(tracks_of(&with_cache).contains(&red.id.0));
    // Without a cache (the bundled log has none) RefAV's is_color keeps every object.
    assert_eq!(tracks_of(&run_program(&program).0), all);
    // A colour RefAV does not know: every cached object goes, as its code (not its docstring)
    // has it.
    let green = imported("result = is_color(vehicles, log_dir, color='green')");
    let kept = tracks_of(&run_program_on(&cached, &green).0);
    assert!(kept
        .iter()
        .all(|t| ![red.id.0, blue.id.0, unknown.id.0].contains(t)));
    assert_eq!(kept.len(), all.len() - 3);
    // A cache RefAV does not write is an error naming the file, not a quiet answer.
    let (_tmp2, bad) = log_with_color_cache(&format!("{{\"{}\": 3}}", red.uuid));
    let bad = load_scene(&bad).unwrap_or_else(|e| panic!("{e}"));
    let Some(checked) = check(&program, &CheckOptions::default()).program else {
        panic!("does not check")
    };
    let ex = Extractor::new(&bad);
    let mut provider = |r: &Request| -> Result<RelationData, String> {
        ex.extract(r)
            .map(|d| (*d).clone())
            .map_err(|e| e.to_string())
    };
    let err = match evaluate(&checked, &mut provider, &Options::default()) {
        Ok(_) => panic!("an unreadable colour cache gave an answer"),
        Err(e) => e.to_string(),
    };
    assert!(err.contains("color_cache.json"), "{err}");
}
