//! The scenario library (`rules/library/*.dl`) tested scenario by scenario.
//!
//! On the three real logs, each program of a family is compared with the same question answered
//! directly from whole extracted relations in Rust (an oracle that shares no code with the
//! engine's planning); on synthetic scenes built in code, programs that find nothing on the sample
//! logs are shown to find exactly what was staged, and nothing in a near-miss variant.

use std::collections::{BTreeMap, BTreeSet};
use std::f64::consts::{FRAC_PI_2, PI};

use scenalog_engine::{evaluate, Evaluation, Options};
use scenalog_extractors::cache::Extractor;
use scenalog_facts::relation::{RelationData, Request, Value};
use scenalog_facts::{Frame, Scene, TrackId};
use scenalog_rules::{check, CheckOptions, CheckedProgram};
use scenalog_testkit::{repo_root as root, sample_scenes as scenes};
use scenalog_testkit::{straight, SceneBuilder, Waypoint};

fn program(name: &str) -> CheckedProgram {
    let path = root().join("rules/library").join(format!("{name}.dl"));
    let src = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    match check(&src, &CheckOptions::default()).program {
        Some(p) => p,
        None => panic!("{name}.dl does not check"),
    }
}

fn evaluate_on(ex: &Extractor<'_>, p: &CheckedProgram) -> Evaluation {
    let mut provider = |r: &Request| -> Result<RelationData, String> {
        ex.extract(r)
            .map(|d| (*d).clone())
            .map_err(|e| e.to_string())
    };
    evaluate(p, &mut provider, &Options::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// `referred` as (track, frame) pairs.
fn referred(ev: &Evaluation) -> BTreeSet<(TrackId, Frame)> {
    ev.tuples("referred")
        .unwrap_or_default()
        .iter()
        .map(|t| match (&t[0], &t[1]) {
            (Value::Track(x), Value::Time(f)) => (*x, *f),
            other => panic!("referred tuple of the wrong shape: {other:?}"),
        })
        .collect()
}

/// A whole catalog relation's rows.
fn rows(ex: &Extractor<'_>, name: &str) -> Vec<Vec<Value>> {
    let d = ex
        .extract(&Request::all(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    scenalog_testkit::rows(&d)
}

fn track(v: &Value) -> TrackId {
    match v {
        Value::Track(t) => *t,
        other => panic!("not a track: {other:?}"),
    }
}

fn time(v: &Value) -> Frame {
    match v {
        Value::Time(t) => *t,
        other => panic!("not a time: {other:?}"),
    }
}

fn float(v: &Value) -> f64 {
    match v {
        Value::Float(x) => *x,
        other => panic!("not a float: {other:?}"),
    }
}

fn text(v: &Value) -> &str {
    match v {
        Value::Str(s) => s,
        other => panic!("not a string: {other:?}"),
    }
}

/// Tracks of a (super-)category, as `category` answers it.
fn of_category(ex: &Extractor<'_>, c: &str) -> BTreeSet<TrackId> {
    rows(ex, "category")
        .iter()
        .filter(|r| text(&r[1]) == c)
        .map(|r| track(&r[0]))
        .collect()
}

/// Runs a library program on every real log and compares it with an oracle computed from the
/// extractor's whole relations; returns the total number of matches (must be > 0 for the
/// comparison to mean anything).
fn compare_on_real_logs(
    name: &str,
    oracle: impl Fn(&Extractor<'_>) -> BTreeSet<(TrackId, Frame)>,
) -> usize {
    let p = program(name);
    let mut total = 0;
    for scene in scenes() {
        let ex = Extractor::new(scene);
        let got = referred(&evaluate_on(&ex, &p));
        let want = oracle(&ex);
        assert_eq!(got, want, "{name} on {}", scene.log_id);
        total += got.len();
    }
    assert!(total > 0, "{name} matched nothing: the comparison is empty");
    total
}

#[test]
fn parked_vehicle_is_every_frame_of_a_stationary_non_ego_vehicle() {
    compare_on_real_logs("parked_vehicle", |ex| {
        let vehicles = of_category(ex, "VEHICLE");
        let still: BTreeSet<TrackId> = rows(ex, "stationary")
            .iter()
            .map(|r| track(&r[0]))
            .collect();
        let ego = ex.scene().ego;
        rows(ex, "present")
            .iter()
            .map(|r| (track(&r[0]), time(&r[1])))
            .filter(|(v, _)| vehicles.contains(v) && still.contains(v) && *v != ego)
            .collect()
    });
}

#[test]
fn car_turning_right_is_a_regular_vehicle_in_a_right_turn() {
    compare_on_real_logs("car_turning_right", |ex| {
        let cars = of_category(ex, "REGULAR_VEHICLE");
        rows(ex, "turning")
            .iter()
            .filter(|r| text(&r[2]) == "right" && cars.contains(&track(&r[0])))
            .map(|r| (track(&r[0]), time(&r[1])))
            .collect()
    });
}

#[test]
fn vehicles_changing_lanes_is_any_lane_change_of_a_non_ego_vehicle() {
    compare_on_real_logs("vehicles_changing_lanes", |ex| {
        let vehicles = of_category(ex, "VEHICLE");
        let ego = ex.scene().ego;
        rows(ex, "lane_change")
            .iter()
            .map(|r| (track(&r[0]), time(&r[1])))
            .filter(|(v, _)| vehicles.contains(v) && *v != ego)
            .collect()
    });
}

#[test]
fn following_too_closely_is_a_gap_under_one_second_at_speed() {
    compare_on_real_logs("vehicle_following_too_closely", |ex| {
        let vehicles = of_category(ex, "VEHICLE");
        let speed: BTreeMap<(TrackId, Frame), f64> = rows(ex, "speed")
            .iter()
            .map(|r| ((track(&r[0]), time(&r[1])), float(&r[2])))
            .collect();
        let gap: BTreeMap<(TrackId, TrackId, Frame), f64> = rows(ex, "near")
            .iter()
            .map(|r| ((track(&r[0]), track(&r[1]), time(&r[2])), float(&r[3])))
            .collect();
        rows(ex, "following")
            .iter()
            .map(|r| (track(&r[0]), track(&r[1]), time(&r[2])))
            .filter(|(v, l, _)| vehicles.contains(v) && vehicles.contains(l))
            .filter(|&(v, l, t)| {
                let s = speed.get(&(v, t)).copied().unwrap_or(0.0);
                s > 5.0 && gap.get(&(v, l, t)).is_some_and(|&g| g < s)
            })
            .map(|(v, _, t)| (v, t))
            .collect()
    });
}

#[test]
fn two_cars_ahead_of_ego_is_two_hops_of_direct_leads() {
    compare_on_real_logs("vehicle_two_cars_ahead_of_ego", |ex| {
        let vehicles = of_category(ex, "VEHICLE");
        let ego = ex.scene().ego;
        let follow: Vec<(TrackId, TrackId, Frame)> = rows(ex, "following")
            .iter()
            .map(|r| (track(&r[0]), track(&r[1]), time(&r[2])))
            .collect();
        // Direct leads only: X follows Y with no Z such that X follows Z and Z follows Y.
        let pairs: BTreeSet<(TrackId, TrackId, Frame)> = follow.iter().copied().collect();
        let direct = |x: TrackId, t: Frame| -> Vec<TrackId> {
            let leads: Vec<TrackId> = follow
                .iter()
                .filter(|&&(a, _, f)| a == x && f == t)
                .map(|&(_, y, _)| y)
                .collect();
            leads
                .iter()
                .copied()
                .filter(|&y| !leads.iter().any(|&z| pairs.contains(&(z, y, t))))
                .collect()
        };
        let frames: BTreeSet<Frame> = follow.iter().map(|&(_, _, t)| t).collect();
        let mut out = BTreeSet::new();
        for t in frames {
            for first in direct(ego, t) {
                for second in direct(first, t) {
                    if vehicles.contains(&second) {
                        out.insert((second, t));
                    }
                }
            }
        }
        out
    });
}

#[test]
fn a_group_of_people_is_a_connected_cluster_of_three_or_more_pedestrians() {
    compare_on_real_logs("a_group_of_people", |ex| {
        let peds = of_category(ex, "PEDESTRIAN");
        // Per frame, each pedestrian's links: the other pedestrians within 2 m of its box.
        let mut links: BTreeMap<Frame, BTreeMap<TrackId, Vec<TrackId>>> = BTreeMap::new();
        for r in rows(ex, "near") {
            let (p, q, t, d) = (track(&r[0]), track(&r[1]), time(&r[2]), float(&r[3]));
            if p != q && peds.contains(&p) && peds.contains(&q) && d <= 2.0 {
                let frame = links.entry(t).or_default();
                frame.entry(p).or_default().push(q);
                frame.entry(q).or_default().push(p);
            }
        }
        // A group is a connected cluster of links, found by flooding from each pedestrian not
        // yet placed (a chain counts, not only a pedestrian's own neighbours).
        let mut out = BTreeSet::new();
        for (t, adj) in links {
            let mut placed = BTreeSet::new();
            for &start in adj.keys() {
                if !placed.insert(start) {
                    continue;
                }
                let mut cluster = vec![start];
                let mut i = 0;
                while let Some(&p) = cluster.get(i) {
                    for &q in &adj[&p] {
                        if placed.insert(q) {
                            cluster.push(q);
                        }
                    }
                    i += 1;
                }
                if cluster.len() >= 3 {
                    out.extend(cluster.into_iter().map(|p| (p, t)));
                }
            }
        }
        out
    });
}

#[test]
fn vehicle_with_bicycle_to_its_right_uses_the_right_region_within_three_metres() {
    compare_on_real_logs("vehicle_with_bicycle_to_its_right", |ex| {
        let vehicles = of_category(ex, "VEHICLE");
        let bikes = of_category(ex, "BICYCLE");
        rows(ex, "direction")
            .iter()
            .filter(|r| text(&r[3]) == "right" && float(&r[4]) <= 3.0 && float(&r[5]) <= 5.0)
            .filter(|r| vehicles.contains(&track(&r[0])) && bikes.contains(&track(&r[1])))
            .map(|r| (track(&r[0]), time(&r[2])))
            .collect()
    });
}

#[test]
fn moving_vehicles_not_on_road_are_outside_the_drivable_area_and_moving() {
    let read = |path: &str| {
        std::fs::read_to_string(root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
    };
    // The oracle below is written for this exact program and the prelude's `moving` (0.5 m/s
    // or more) and `on_sidewalk` (present outside the drivable area); fail loudly if they
    // change.
    let src = read("rules/library/moving_vehicles_not_on_road.dl");
    assert!(
        src.contains("moving(V, T)") && src.contains("on_sidewalk(V, T)"),
        "{src}"
    );
    let prelude = read("rules/prelude.dl");
    for clause in [
        "moving(X, T) :- speed(X, T, V), V >= 0.5 m/s.",
        "on_sidewalk(X, T) :- present(X, T), !in_drivable_area(X, T).",
    ] {
        assert!(
            prelude.contains(clause),
            "the prelude no longer has `{clause}`"
        );
    }
    compare_on_real_logs("moving_vehicles_not_on_road", |ex| {
        let vehicles = of_category(ex, "VEHICLE");
        let drivable: BTreeSet<(TrackId, Frame)> = rows(ex, "in_drivable_area")
            .iter()
            .map(|r| (track(&r[0]), time(&r[1])))
            .collect();
        let present: BTreeSet<(TrackId, Frame)> = rows(ex, "present")
            .iter()
            .map(|r| (track(&r[0]), time(&r[1])))
            .collect();
        rows(ex, "speed")
            .iter()
            .filter(|r| float(&r[2]) >= 0.5)
            .map(|r| (track(&r[0]), time(&r[1])))
            .filter(|k| vehicles.contains(&k.0) && present.contains(k) && !drivable.contains(k))
            .collect()
    });
}

// ---- synthetic scenes -------------------------------------------------------------------------

const CAR: [f64; 3] = [4.5, 1.8, 1.5];
const BUS: [f64; 3] = [12.0, 2.5, 3.0];
const PED: [f64; 3] = [0.5, 0.5, 1.7];
const EGO: [f64; 3] = [4.877, 2.0, 1.473];

fn still(n: u32, x: f64, y: f64, yaw: f64) -> Vec<Waypoint> {
    (0..n).map(|f| (f, x, y, yaw)).collect()
}

/// The uuids a program refers to on a synthetic scene, with the frames of each.
fn referred_uuids(scene: &Scene, name: &str) -> BTreeMap<String, BTreeSet<Frame>> {
    let ex = Extractor::new(scene);
    let mut out: BTreeMap<String, BTreeSet<Frame>> = BTreeMap::new();
    for (t, f) in referred(&evaluate_on(&ex, &program(name))) {
        out.entry(scene.track(t).uuid.clone())
            .or_default()
            .insert(f);
    }
    out
}

fn uuids(m: &BTreeMap<String, BTreeSet<Frame>>) -> Vec<&str> {
    m.keys().map(|k| k.as_str()).collect()
}

#[test]
fn vehicle_over_twenty_metres_per_second_finds_the_fast_car_only() {
    let scene = SceneBuilder::new(40)
        .track(
            "fast",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 40, 0.0, 0.0, 0.0, 25.0),
        )
        .track(
            "slow",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 40, 0.0, 10.0, 0.0, 15.0),
        )
        .track(
            "runner",
            "PEDESTRIAN",
            PED,
            straight(0, 40, 0.0, 20.0, 0.0, 21.0),
        )
        .build();
    let got = referred_uuids(&scene, "vehicle_traveling_over_20_meters_per_second");
    assert_eq!(uuids(&got), ["fast"]);
    assert_eq!(got["fast"].len(), 40, "every frame: {:?}", got["fast"]);
}

#[test]
fn bus_with_three_pedestrians_needs_three() {
    let n = 20;
    let with = |peds: usize| {
        let mut b = SceneBuilder::new(n as usize).track("bus", "BUS", BUS, still(n, 0.0, 0.0, 0.0));
        for i in 0..peds {
            // Beside the bus's right side, 2 m out, spaced along it.
            b = b.track(
                &format!("p{i}"),
                "PEDESTRIAN",
                PED,
                still(n, -4.0 + 4.0 * i as f64, -3.25, 0.0),
            );
        }
        b.track("far", "PEDESTRIAN", PED, still(n, 0.0, -20.0, 0.0))
            .build()
    };
    let name = "bus_with_at_least_3_pedestrians_within_5_meters";
    let got = referred_uuids(&with(3), name);
    assert_eq!(uuids(&got), ["bus"]);
    assert_eq!(got["bus"].len(), n as usize);
    assert!(referred_uuids(&with(2), name).is_empty());
}

#[test]
fn multiple_buses_ahead_needs_two_buses_in_front_of_the_ego() {
    let n = 20;
    let scene = |second_ahead: bool| {
        let x2 = if second_ahead { 35.0 } else { -35.0 };
        SceneBuilder::new(n as usize)
            .track(
                "ego",
                "EGO_VEHICLE",
                EGO,
                straight(0, n, 0.0, 0.0, 0.0, 5.0),
            )
            .track("bus1", "BUS", BUS, straight(0, n, 18.0, 0.0, 0.0, 5.0))
            .track("bus2", "BUS", BUS, straight(0, n, x2, 0.5, 0.0, 5.0))
            .build()
    };
    let got = referred_uuids(&scene(true), "multiple_buses_ahead");
    assert_eq!(uuids(&got), ["bus1", "bus2"]);
    assert!(referred_uuids(&scene(false), "multiple_buses_ahead").is_empty());
}

#[test]
fn motorcyclist_braking_hard_needs_minus_three_metres_per_second_squared() {
    let n = 60u32;
    // From 15 m/s, decelerating at `a` m/s² from frame 20 until stopped.
    let braking = |y: f64, a: f64| -> Vec<Waypoint> {
        let mut x = 0.0;
        let mut v: f64 = 15.0;
        (0..n)
            .map(|f| {
                let w = (f, x, y, 0.0);
                if f >= 20 {
                    v = (v - a * 0.1).max(0.0);
                }
                x += v * 0.1;
                w
            })
            .collect()
    };
    // The motorcyclist is the rider's box; the motorcycle under it is a separate MOTORCYCLE
    // box, which braking as hard is not a motorcyclist braking.
    let rider = [2.0, 0.8, 1.7];
    let scene = SceneBuilder::new(n as usize)
        .track("hard", "MOTORCYCLIST", rider, braking(0.0, 4.0))
        .track("gentle", "MOTORCYCLIST", rider, braking(5.0, 2.2))
        .track(
            "motorcycle",
            "MOTORCYCLE",
            [2.0, 0.8, 1.4],
            braking(15.0, 4.0),
        )
        .track("car", "REGULAR_VEHICLE", CAR, braking(10.0, 4.0))
        .build();
    let got = referred_uuids(&scene, "motorcyclist_braking_hard");
    assert_eq!(uuids(&got), ["hard"]);
    let frames = &got["hard"];
    assert!(
        frames.contains(&30),
        "mid-braking frame missing: {frames:?}"
    );
    assert!(!frames.contains(&5), "cruising frame found: {frames:?}");
}

/// A stopped vehicle at the origin heading +x and a walker crossing 3 m ahead of its front.
fn crossing_scene(vehicle_category: &str, walker_category: &str, walker_x: f64) -> Scene {
    let n = 120u32;
    let walk: Vec<Waypoint> = (0..n)
        .map(|f| (f, walker_x, -8.0 + 0.14 * f as f64, FRAC_PI_2))
        .collect();
    let size = if vehicle_category == "EGO_VEHICLE" {
        EGO
    } else {
        CAR
    };
    let mut b = SceneBuilder::new(n as usize)
        .track("vehicle", vehicle_category, size, still(n, 0.0, 0.0, 0.0))
        .track("walker", walker_category, [0.8, 0.4, 0.6], walk);
    if vehicle_category != "EGO_VEHICLE" {
        b = b.track("ego", "EGO_VEHICLE", EGO, still(n, -40.0, 20.0, 0.0));
    }
    b.build()
}

#[test]
fn dog_crossing_in_front_of_vehicle_finds_the_dog_during_the_crossing() {
    let got = referred_uuids(
        &crossing_scene("REGULAR_VEHICLE", "DOG", 5.25),
        "dog_crossing_in_front_of_vehicle",
    );
    assert_eq!(uuids(&got), ["walker"]);
    let f = &got["walker"];
    // y = -8 + 0.14 f is within 5 m of the midplane for f in 22..=92.
    assert!(
        f.contains(&57) && !f.contains(&5) && !f.contains(&110),
        "{f:?}"
    );
    // Behind the vehicle: not in front of it.
    assert!(referred_uuids(
        &crossing_scene("REGULAR_VEHICLE", "DOG", -5.25),
        "dog_crossing_in_front_of_vehicle"
    )
    .is_empty());
    // A pedestrian is not a dog.
    assert!(referred_uuids(
        &crossing_scene("REGULAR_VEHICLE", "PEDESTRIAN", 5.25),
        "dog_crossing_in_front_of_vehicle"
    )
    .is_empty());
}

#[test]
fn pedestrian_crossing_ahead_of_ego_needs_the_ego() {
    let name = "pedestrian_crossing_ahead_of_ego_vehicle";
    let got = referred_uuids(&crossing_scene("EGO_VEHICLE", "PEDESTRIAN", 5.5), name);
    assert_eq!(uuids(&got), ["walker"]);
    assert!(got["walker"].contains(&57));
    // The same crossing in front of another car is not ahead of the ego.
    assert!(
        referred_uuids(&crossing_scene("REGULAR_VEHICLE", "PEDESTRIAN", 5.25), name).is_empty()
    );
}

/// A two-lane road along +x: lane 1 (y 0..3.5, right) and lane 2 (y 3.5..7, left), neighbours.
/// The ego drives lane 1 at 10 m/s and moves into lane 2 over frames 20..50 when `changes`.
fn two_lane_road(changes: bool) -> Scene {
    let n = 80u32;
    let way: Vec<Waypoint> = (0..n)
        .map(|f| {
            let x = f as f64;
            let s = if changes {
                ((f as f64 - 20.0) / 30.0).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let y = 1.75 + 3.5 * (1.0 - (PI * s).cos()) / 2.0;
            let vy = if changes && (20..=50).contains(&f) {
                3.5 * PI / 2.0 / 3.0 * (PI * s).sin()
            } else {
                0.0
            };
            (f, x, y, vy.atan2(10.0))
        })
        .collect();
    SceneBuilder::new(n as usize)
        .lane(
            1,
            &[[0.0, 3.5], [100.0, 3.5]],
            &[[0.0, 0.0], [100.0, 0.0]],
            &[],
            Some(2),
            None,
            false,
        )
        .lane(
            2,
            &[[0.0, 7.0], [100.0, 7.0]],
            &[[0.0, 3.5], [100.0, 3.5]],
            &[],
            None,
            Some(1),
            false,
        )
        .track("ego", "EGO_VEHICLE", EGO, way)
        .build()
}

#[test]
fn ego_changing_lanes_to_the_left_finds_the_manoeuvre() {
    let name = "ego_vehicle_changing_lanes_to_the_left";
    let got = referred_uuids(&two_lane_road(true), name);
    assert_eq!(uuids(&got), ["ego"]);
    let f = &got["ego"];
    assert!(
        f.contains(&35) && !f.contains(&5) && !f.contains(&70),
        "{f:?}"
    );
    assert!(referred_uuids(&two_lane_road(false), name).is_empty());
}
