//! Every single-object relation on small synthetic scenes whose answer is known by construction:
//! at least one positive and one negative case each, plus pushdown and determinism.

use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::Arc;

use scenalog_extractors::{extract, extract_all, relation_json, ExtractError, Extractor};
use scenalog_facts::relation::{Constraint, Request, Value};
use scenalog_facts::{LaneType, Scene};
use scenalog_testkit::{straight, SceneBuilder, Waypoint};
use serde_json::{json, Value as J};

const CAR: [f64; 3] = [4.5, 1.8, 1.5];
const FRAMES: usize = 80;

/// The lane-changing car: lane 2 (y 3.5..7) to lane 1 (y 0..3.5) over frames 20..50 at 10 m/s.
fn changer() -> Vec<Waypoint> {
    (0..FRAMES as u32)
        .map(|f| {
            let x = f as f64;
            let s = ((f as f64 - 20.0) / 30.0).clamp(0.0, 1.0);
            let y = 5.25 - 3.5 * (1.0 - (PI * s).cos()) / 2.0;
            let vy = if (20..=50).contains(&f) {
                -3.5 * PI / 2.0 / 3.0 * (PI * s).sin()
            } else {
                0.0
            };
            (f, x, y, vy.atan2(10.0))
        })
        .collect()
}

/// Drives lane 1 at 10 m/s, brakes at 5 m/s² from frame 30 to stop at x = 90 at frame 50, waits
/// there until frame 70 (a red light), drives on.
fn stopper() -> Vec<Waypoint> {
    let mut w = straight(0, 30, 50.0, 1.75, 0.0, 10.0);
    w.extend((30..50).map(|f| {
        let t = (f - 30) as f64 * 0.1;
        (f, 80.0 + 10.0 * t - 2.5 * t * t, 1.75, 0.0)
    }));
    w.extend((50..70).map(|f| (f, 90.0, 1.75, 0.0)));
    w.extend((70..FRAMES as u32).map(|f| (f, 90.0 + (f - 70) as f64, 1.75, 0.0)));
    w
}

/// A two-lane road along +x (lane 1 right, lane 2 left), an intersection lane 3 after lane 1, a
/// bike lane 4 elsewhere, a crossing at x 60..64, a drivable area, a stop sign at the end of lane 1.
fn road_scene() -> Scene {
    SceneBuilder::new(FRAMES)
        .lane(
            1,
            &[[0.0, 3.5], [100.0, 3.5]],
            &[[0.0, 0.0], [100.0, 0.0]],
            &[3],
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
        .lane(
            3,
            &[[100.0, 3.5], [120.0, 3.5]],
            &[[100.0, 0.0], [120.0, 0.0]],
            &[999],
            None,
            None,
            true,
        )
        .straight_lane(4, 0.0, 50.0, -20.0, -18.0)
        .lane_type(LaneType::Bike)
        .crossing(
            1,
            &[[60.0, -1.0], [60.0, 8.0]],
            &[[64.0, -1.0], [64.0, 8.0]],
        )
        .drivable_area(
            1,
            &[[-5.0, -5.0], [125.0, -5.0], [125.0, 12.0], [-5.0, 12.0]],
        )
        .track("changer", "REGULAR_VEHICLE", CAR, changer())
        .track("stopper", "REGULAR_VEHICLE", CAR, stopper())
        .track(
            "parked",
            "REGULAR_VEHICLE",
            CAR,
            (0..FRAMES as u32).map(|f| (f, 30.0, -3.0, 0.0)).collect(),
        )
        .track(
            "ped",
            "PEDESTRIAN",
            [0.5, 0.5, 1.7],
            (0..FRAMES as u32)
                .map(|f| (f, 62.0, 9.5, -FRAC_PI_2))
                .collect(),
        )
        .track(
            "sign",
            "STOP_SIGN",
            [0.2, 0.8, 2.0],
            (0..FRAMES as u32).map(|f| (f, 98.0, -1.5, PI)).collect(),
        )
        .build()
}

/// A car turning left 90° at 10 m/s on a circle of radius 20 m.
fn turn_scene() -> Scene {
    let (v, r) = (10.0, 20.0);
    let mut way = straight(0, 10, -10.0, 0.0, 0.0, v);
    let w = v / r;
    let n = ((FRAC_PI_2 / w) / 0.1).round() as u32;
    for k in 0..=n {
        let a = (w * 0.1 * k as f64).min(FRAC_PI_2);
        way.push((10 + k, r * a.sin(), r - r * a.cos(), a));
    }
    for k in 1..15 {
        way.push((10 + n + k, r, r + v * 0.1 * k as f64, FRAC_PI_2));
    }
    let frames = way.len();
    SceneBuilder::new(frames)
        .track("turner", "REGULAR_VEHICLE", CAR, way)
        .track(
            "straight",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, frames as u32, 0.0, -50.0, 0.0, 10.0),
        )
        .build()
}

fn rows_with(scene: &Scene, name: &str, constraints: Vec<(usize, Constraint)>) -> Vec<J> {
    let req = Request {
        name: name.into(),
        constraints,
    };
    let data = extract(scene, &req).expect("extract");
    match relation_json(scene, &data) {
        J::Array(v) => v,
        other => panic!("not an array: {other}"),
    }
}

fn rows(scene: &Scene, name: &str) -> Vec<J> {
    rows_with(scene, name, Vec::new())
}

/// Frames at which `track` appears in a (track, time, ...) relation, with the third column.
fn frames_of(rows: &[J], track: &str) -> Vec<(u64, J)> {
    rows.iter()
        .filter(|r| r[0] == track)
        .map(|r| {
            (
                r[1].as_u64().expect("time"),
                r.get(2).cloned().unwrap_or(J::Null),
            )
        })
        .collect()
}

#[test]
fn objects_and_time() {
    let scene = road_scene();
    let cat = rows(&scene, "category");
    assert!(cat.contains(&json!(["changer", "REGULAR_VEHICLE"])));
    assert!(cat.contains(&json!(["changer", "VEHICLE"])));
    assert!(cat.contains(&json!(["ped", "ANY"])));
    assert!(!cat.contains(&json!(["ped", "VEHICLE"])));
    assert!(cat.contains(&json!(["ego", "VEHICLE"])));
    assert_eq!(rows(&scene, "ego"), vec![json!(["ego"])]);
    let present = rows(&scene, "present");
    assert_eq!(present.len(), 6 * FRAMES);
    assert!(present.contains(&json!(["ped", 79])));
    assert!(!present.contains(&json!(["ped", 80])));
    let ns = rows(&scene, "frame_ns");
    assert_eq!(ns.len(), FRAMES);
    assert_eq!(ns[3], json!([3, 300_000_000]));
    let secs = rows(&scene, "seconds");
    assert_eq!(secs[10], json!([10, 1.0]));
}

#[test]
fn kinematics_relations() {
    let scene = road_scene();
    let speed = rows(&scene, "speed");
    let stopper = frames_of(&speed, "stopper");
    assert!((stopper[10].1.as_f64().unwrap() - 10.0).abs() < 1e-6);
    assert!(stopper[60].1.as_f64().unwrap() < 0.5);
    let parked = frames_of(&speed, "parked");
    assert!(parked.iter().all(|(_, v)| v.as_f64().unwrap() == 0.0));
    // The stopper brakes at 5 m/s² over frames 30..50.
    let accel = frames_of(&rows(&scene, "accel"), "stopper");
    assert!(
        (accel[40].1.as_f64().unwrap() + 5.0).abs() < 0.1,
        "{:?}",
        accel[40]
    );
    assert!(accel[10].1.as_f64().unwrap().abs() < 1e-9);
    // The changer moves right: negative lateral acceleration at the start of its move.
    let lat = frames_of(&rows(&scene, "lat_accel"), "changer");
    assert!(lat[22].1.as_f64().unwrap() < -0.1, "{:?}", lat[22]);
    assert!(lat[5].1.as_f64().unwrap().abs() < 1e-9);
    let yaw = frames_of(&rows(&scene, "yaw_rate"), "changer");
    assert!(yaw[25].1.as_f64().unwrap() < 0.0 && yaw[45].1.as_f64().unwrap() > 0.0);
    assert!(yaw[5].1.as_f64().unwrap() == 0.0);
    let st = rows(&scene, "stationary");
    assert!(st.contains(&json!(["parked"])) && st.contains(&json!(["sign"])));
    assert!(!st.contains(&json!(["stopper"])) && !st.contains(&json!(["changer"])));
}

#[test]
fn turning_left_ninety_degrees() {
    let scene = turn_scene();
    let turning = rows(&scene, "turning");
    let t = frames_of(&turning, "turner");
    assert!(!t.is_empty());
    assert!(t.iter().all(|(_, d)| d == "left"));
    // The turn occupies frames 10..=41; the event covers its middle and not the straight parts.
    let frames: Vec<u64> = t.iter().map(|(f, _)| *f).collect();
    assert!(
        frames.contains(&15) && frames.contains(&25) && frames.contains(&38),
        "{frames:?}"
    );
    assert!(!frames.contains(&3) && !frames.contains(&50), "{frames:?}");
    assert!(frames_of(&turning, "straight").is_empty());
    // The lane changer's heading moves 10° each way: no turn.
    assert!(rows(&road_scene(), "turning").is_empty());
}

#[test]
fn lane_change_to_the_right() {
    let scene = road_scene();
    let lc = rows(&scene, "lane_change");
    let c = frames_of(&lc, "changer");
    assert!(c.iter().all(|(_, d)| d == "right"), "{c:?}");
    let frames: Vec<u64> = c.iter().map(|(f, _)| *f).collect();
    // The lateral move runs over frames 20..50 and crosses the boundary at 35.
    assert!(
        frames.contains(&35) && frames.contains(&25) && frames.contains(&45),
        "{frames:?}"
    );
    assert!(frames.iter().all(|&f| (20..=50).contains(&f)), "{frames:?}");
    assert!(frames_of(&lc, "stopper").is_empty());
    let lanes = frames_of(&rows(&scene, "in_lane"), "changer");
    assert_eq!(lanes[10].1, json!(2));
    assert_eq!(lanes[60].1, json!(1));
}

/// Lane 1 (+x) has lane 2 on its left running the other way (AV2 links the lanes either side of
/// a centre line as each other's left neighbour) and lane 3 on its right running the same way.
/// "into_oncoming" drifts from lane 1 into lane 2 (not a lane change); "to_right" changes into
/// lane 3 the same way (a lane change to the right).
#[test]
fn moving_into_an_opposite_direction_neighbour_is_not_a_lane_change() {
    let lateral = |from: f64, to: f64| -> Vec<Waypoint> {
        (0..FRAMES as u32)
            .map(|f| {
                let s = ((f as f64 - 20.0) / 30.0).clamp(0.0, 1.0);
                let y = from + (to - from) * (1.0 - (PI * s).cos()) / 2.0;
                let vy = if (20..=50).contains(&f) {
                    (to - from) * PI / 2.0 / 3.0 * (PI * s).sin()
                } else {
                    0.0
                };
                (f, f as f64, y, vy.atan2(10.0))
            })
            .collect()
    };
    let scene = SceneBuilder::new(FRAMES)
        .lane(
            1,
            &[[0.0, 3.5], [100.0, 3.5]],
            &[[0.0, 0.0], [100.0, 0.0]],
            &[],
            Some(2),
            Some(3),
            false,
        )
        .lane(
            2,
            &[[100.0, 3.5], [0.0, 3.5]],
            &[[100.0, 7.0], [0.0, 7.0]],
            &[],
            Some(1),
            None,
            false,
        )
        .lane(
            3,
            &[[0.0, 0.0], [100.0, 0.0]],
            &[[0.0, -3.5], [100.0, -3.5]],
            &[],
            Some(1),
            None,
            false,
        )
        .track("into_oncoming", "REGULAR_VEHICLE", CAR, lateral(1.75, 5.25))
        .track("to_right", "REGULAR_VEHICLE", CAR, lateral(1.75, -1.75))
        .build();
    let lanes = rows(&scene, "in_lane");
    // both really move between the lanes
    assert_eq!(frames_of(&lanes, "into_oncoming")[10].1, json!(1));
    assert_eq!(frames_of(&lanes, "into_oncoming")[60].1, json!(2));
    assert_eq!(frames_of(&lanes, "to_right")[60].1, json!(3));
    let lc = rows(&scene, "lane_change");
    assert!(frames_of(&lc, "into_oncoming").is_empty(), "{lc:?}");
    let right = frames_of(&lc, "to_right");
    assert!(
        right.iter().any(|(f, d)| *f == 35 && d == "right"),
        "{right:?}"
    );
}

#[test]
fn lanes_and_map_features() {
    let scene = road_scene();
    let lt = rows(&scene, "lane_type");
    assert!(lt.contains(&json!([1, "VEHICLE"])) && lt.contains(&json!([4, "BIKE"])));
    assert!(!lt.contains(&json!([4, "VEHICLE"])));
    assert_eq!(rows(&scene, "intersection_lane"), vec![json!([3])]);
    // Lane 3's successor 999 is dangling: left out.
    assert_eq!(rows(&scene, "lane_successor"), vec![json!([1, 3])]);
    assert_eq!(
        rows(&scene, "lane_neighbor"),
        vec![json!([1, 2, "left"]), json!([2, 1, "right"])]
    );
    let in_lane = rows(&scene, "in_lane");
    assert!(frames_of(&in_lane, "parked").is_empty());
    assert!(frames_of(&in_lane, "stopper")
        .iter()
        .all(|(f, l)| *f >= 60 || l == 1));
    let on_road = rows(&scene, "on_road");
    assert_eq!(frames_of(&on_road, "changer").len(), FRAMES);
    assert!(frames_of(&on_road, "parked").is_empty());
    let da = rows(&scene, "in_drivable_area");
    assert_eq!(frames_of(&da, "parked").len(), FRAMES);
    assert!(frames_of(&da, "ego").is_empty());
    let oi = frames_of(&rows(&scene, "on_intersection"), "stopper");
    let oi: Vec<u64> = oi.iter().map(|(f, _)| *f).collect();
    // x = 90 + (f - 70) > 100 from frame 81: never inside this 80-frame log; at 100 exactly on the
    // boundary at frame 80 (absent). So no frame; the turner scene has no map at all.
    assert!(oi.is_empty(), "{oi:?}");
    let ni = frames_of(&rows(&scene, "near_intersection"), "stopper");
    let at60 = ni.iter().find(|(f, _)| *f == 60).expect("frame 60");
    assert!((at60.1.as_f64().unwrap() - 10.0).abs() < 1e-9, "{at60:?}");
    // The parked car at x = 30 is 70 m from the intersection: beyond the 50 m cap.
    assert!(frames_of(&rows(&scene, "near_intersection"), "parked").is_empty());
}

#[test]
fn on_intersection_positive() {
    let scene = SceneBuilder::new(10)
        .lane(
            3,
            &[[100.0, 3.5], [120.0, 3.5]],
            &[[100.0, 0.0], [120.0, 0.0]],
            &[],
            None,
            None,
            true,
        )
        .track(
            "car",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 10, 105.0, 1.75, 0.0, 1.0),
        )
        .build();
    assert_eq!(frames_of(&rows(&scene, "on_intersection"), "car").len(), 10);
    let ni = frames_of(&rows(&scene, "near_intersection"), "car");
    assert!(ni.iter().all(|(_, d)| d == 0.0));
}

#[test]
fn crosswalk_distance() {
    let scene = road_scene();
    let aw = rows(&scene, "at_crosswalk");
    // Pedestrian box (0.5 m) centred 1.5 m beyond the crossing's edge at y = 8: 1.25 m away.
    let ped = frames_of(&aw, "ped");
    assert_eq!(ped.len(), FRAMES);
    assert!(
        ped.iter()
            .all(|(_, d)| (d.as_f64().unwrap() - 1.25).abs() < 1e-9),
        "{:?}",
        ped[0]
    );
    // The changer's box overlaps the crossing (x 60..64) around frames 58..66: distance 0.
    let ch = frames_of(&aw, "changer");
    let d = |f: u64| {
        ch.iter()
            .find(|(g, _)| *g == f)
            .map(|(_, d)| d.as_f64().unwrap())
    };
    assert_eq!(d(62), Some(0.0));
    assert!(
        (d(50).unwrap() - (60.0 - 52.25)).abs() < 1e-6,
        "{:?}",
        d(50)
    );
    // The parked car at x = 30 is 27.75 m from it; with D < 5 pushed down, it has no tuple.
    let near = rows_with(&scene, "at_crosswalk", vec![(2, Constraint::Lt(5.0))]);
    assert!(frames_of(&near, "parked").is_empty());
    assert!(!frames_of(&near, "ped").is_empty());
}

#[test]
fn stop_sign() {
    let scene = road_scene();
    let ss = rows(&scene, "at_stop_sign");
    let at: Vec<u64> = ss
        .iter()
        .filter(|r| r[0] == "stopper" && r[1] == "sign")
        .map(|r| r[2].as_u64().unwrap())
        .collect();
    // Sign at x = 98: the stopper is 0..10 m before it from x = 88 (frame 48) to x = 98 (frame 78).
    assert!(
        at.contains(&48) && at.contains(&60) && at.contains(&78),
        "{at:?}"
    );
    assert!(!at.contains(&40) && !at.contains(&79), "{at:?}");
    assert!(ss.iter().all(|r| r[0] == "stopper"), "{ss:?}");
    // A car driving the other way past the sign does not face it.
    let wrong_way = SceneBuilder::new(20)
        .lane(
            1,
            &[[0.0, 3.5], [100.0, 3.5]],
            &[[0.0, 0.0], [100.0, 0.0]],
            &[],
            None,
            None,
            false,
        )
        .track(
            "car",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 20, 99.0, 1.75, PI, 0.5),
        )
        .track(
            "sign",
            "STOP_SIGN",
            [0.2, 0.8, 2.0],
            vec![(0, 98.0, -1.5, PI)],
        )
        .build();
    assert!(rows(&wrong_way, "at_stop_sign").is_empty());
}

#[test]
fn pushdown_restricts_and_never_breaks_constraints() {
    let scene = road_scene();
    let ex = Extractor::new(&scene);
    let ped_speed = ex
        .extract(&Request {
            name: "speed".into(),
            constraints: vec![
                (0, Constraint::Category(Arc::from("PEDESTRIAN"))),
                (2, Constraint::Lt(0.5)),
            ],
        })
        .unwrap();
    assert_eq!(ped_speed.len(), FRAMES);
    let vehicles = ex
        .extract(&Request {
            name: "speed".into(),
            constraints: vec![
                (0, Constraint::Category(Arc::from("VEHICLE"))),
                (2, Constraint::Ge(5.0)),
            ],
        })
        .unwrap();
    let j = relation_json(&scene, &vehicles);
    for r in j.as_array().unwrap() {
        assert!(r[0] == "changer" || r[0] == "stopper", "{r}");
        assert!(r[2].as_f64().unwrap() >= 5.0);
    }
    let eq = ex
        .extract(&Request {
            name: "lane_neighbor".into(),
            constraints: vec![(2, Constraint::Eq(Value::Str(Arc::from("left"))))],
        })
        .unwrap();
    assert_eq!(relation_json(&scene, &eq), json!([[1, 2, "left"]]));
    let at_t = ex
        .extract(&Request {
            name: "present".into(),
            constraints: vec![(1, Constraint::Eq(Value::Time(7)))],
        })
        .unwrap();
    assert_eq!(at_t.len(), 6);
    // OneOf (the engine's demand) on tracks and frames: the filtered full relation.
    let full = ex.extract(&Request::all("speed")).unwrap();
    let ids: Vec<Value> = ["changer", "ped"]
        .iter()
        .map(|u| Value::Track(scene.track_by_uuid(u).expect("track").id))
        .collect();
    let frames: Vec<Value> = [0u32, 5, 6, 11].map(Value::Time).to_vec();
    let constraints = vec![
        (0, Constraint::OneOf(ids.clone().into())),
        (1, Constraint::OneOf(frames.clone().into())),
    ];
    let pushed = ex
        .extract(&Request {
            name: "speed".into(),
            constraints,
        })
        .unwrap();
    let want: Vec<Vec<Value>> = (0..full.len())
        .filter_map(|i| full.row(i))
        .filter(|r| ids.contains(&r[0]) && frames.contains(&r[1]))
        .collect();
    let got: Vec<Vec<Value>> = (0..pushed.len()).filter_map(|i| pushed.row(i)).collect();
    assert_eq!(got, want);
    assert_eq!(got.len(), 2 * 4);
    // Errors name what was wrong.
    let bad = ex.extract(&Request::all("no_such"));
    assert!(matches!(bad, Err(ExtractError::UnknownRelation(_))));
    let bad = ex.extract(&Request {
        name: "speed".into(),
        constraints: vec![(2, Constraint::Category(Arc::from("BUS")))],
    });
    assert!(matches!(bad, Err(ExtractError::BadConstraint { .. })));
    let bad = ex.extract(&Request {
        name: "speed".into(),
        constraints: vec![(7, Constraint::Lt(1.0))],
    });
    assert!(matches!(bad, Err(ExtractError::NoSuchColumn { .. })));
}

#[test]
fn extract_all_is_deterministic_across_thread_counts() {
    let scene = road_scene();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| extract_all(&scene));
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
        .install(|| extract_all(&scene));
    assert_eq!(one, two);
    assert!(one.iter().any(|r| r.name == "in_lane" && !r.is_empty()));
}

#[test]
fn logs_in_parallel_match_one_by_one() {
    let scenes = vec![road_scene(), turn_scene()];
    let reqs = vec![
        Request::all("speed"),
        Request::all("turning"),
        Request::all("in_lane"),
    ];
    let together = scenalog_extractors::extract_logs(&scenes, &reqs);
    assert_eq!(together.len(), 2);
    for (scene, answers) in scenes.iter().zip(together) {
        let answers = answers.expect("answers");
        for (req, got) in reqs.iter().zip(answers) {
            assert_eq!(got, extract(scene, req).expect("extract"));
        }
    }
}

#[test]
fn json_uses_uuids_map_ids_frames_and_numbers() {
    let scene = road_scene();
    let ex = Extractor::new(&scene);
    let r = ex
        .extract(&Request {
            name: "in_lane".into(),
            constraints: vec![(1, Constraint::Eq(Value::Time(10)))],
        })
        .unwrap();
    let j = relation_json(&scene, &r);
    assert!(
        j.as_array().unwrap().contains(&json!(["changer", 10, 2])),
        "{j}"
    );
    let r = ex.extract(&Request::all("frame_ns")).unwrap();
    assert_eq!(relation_json(&scene, &r)[1], json!([1, 100_000_000]));
}

#[test]
fn extractor_is_shareable_across_threads() {
    fn assert_sync_send<T: Sync + Send>() {}
    assert_sync_send::<Extractor<'static>>();
    let scene = road_scene();
    let ex = Extractor::new(&scene);
    let (a, b) = rayon::join(
        || ex.extract(&Request::all("lane_change")).map(|r| r.len()),
        || ex.extract(&Request::all("lane_change")).map(|r| r.len()),
    );
    assert_eq!(a, b);
    assert!(a.expect("lane_change") > 0);
}

/// For every relation and a set of constraints on each of its columns, the pushed-down answer is
/// exactly the full relation filtered by those constraints.
#[test]
fn pushdown_equals_filtering_the_full_relation() {
    use scenalog_extractors::query::satisfies;
    use scenalog_facts::catalog::{catalog, ColType};
    let scene = road_scene();
    let ex = Extractor::new(&scene);
    let changer = scene.track_by_uuid["changer"];
    let mut checked = 0;
    for spec in catalog() {
        let full = ex.extract(&Request::all(spec.name)).expect("full");
        for (col, c) in spec.columns.iter().enumerate() {
            let options: Vec<Constraint> = match c.ty {
                ColType::Track => vec![
                    Constraint::Category(Arc::from("VEHICLE")),
                    Constraint::Category(Arc::from("PEDESTRIAN")),
                    Constraint::Eq(Value::Track(changer)),
                ],
                ColType::Time => vec![
                    Constraint::Eq(Value::Time(35)),
                    Constraint::Lt(10.0),
                    Constraint::Ge(70.5),
                ],
                ColType::Float => vec![
                    Constraint::Lt(1.0),
                    Constraint::Ge(2.0),
                    Constraint::Le(0.0),
                ],
                ColType::Str => vec![Constraint::Eq(Value::Str(Arc::from("right")))],
                ColType::Lane | ColType::Int => vec![],
            };
            for c in options {
                let req = Request {
                    name: spec.name.into(),
                    constraints: vec![(col, c.clone())],
                };
                let got = ex.extract(&req).expect("constrained");
                let want: Vec<Vec<Value>> = (0..full.len())
                    .filter_map(|i| full.row(i))
                    .filter(|r| satisfies(&scene, &r[col], &c))
                    .collect();
                let got: Vec<Vec<Value>> = (0..got.len()).filter_map(|i| got.row(i)).collect();
                assert_eq!(got, want, "{} with column {col} {c:?}", spec.name);
                checked += 1;
            }
        }
    }
    assert!(checked > 80, "{checked}");
}

/// A car heading along +y that backs up at 2 m/s, one that drives forwards at 2 m/s, and one whose
/// box faces +y while it moves sideways along +x: `forward_speed` is the velocity on the heading,
/// negative backwards, near 0 sideways, while `speed` is 2 m/s for all three.
#[test]
fn forward_speed_is_signed_along_the_heading() {
    let up = FRAC_PI_2;
    let car = [4.5, 1.8, 1.5];
    let scene = SceneBuilder::new(40)
        .track(
            "backer",
            "REGULAR_VEHICLE",
            car,
            straight(0, 40, 0.0, 0.0, up, -2.0),
        )
        .track(
            "driver",
            "REGULAR_VEHICLE",
            car,
            straight(0, 40, 10.0, 0.0, up, 2.0),
        )
        .track(
            "crab",
            "REGULAR_VEHICLE",
            car,
            (0..40)
                .map(|f| (f, 20.0 + 0.2 * f as f64, 0.0, up))
                .collect(),
        )
        .build();
    let fs = rows(&scene, "forward_speed");
    let speeds = rows(&scene, "speed");
    for (track, want) in [("backer", -2.0), ("driver", 2.0), ("crab", 0.0)] {
        let values: Vec<f64> = frames_of(&fs, track)
            .iter()
            .filter(|(t, _)| (10..30).contains(t))
            .map(|(_, v)| v.as_f64().expect("a number"))
            .collect();
        assert_eq!(values.len(), 20, "{track}");
        assert!(
            values.iter().all(|v| (v - want).abs() < 0.05),
            "{track}: {values:?}"
        );
        let speed: Vec<f64> = frames_of(&speeds, track)
            .iter()
            .filter(|(t, _)| (10..30).contains(t))
            .map(|(_, v)| v.as_f64().expect("a number"))
            .collect();
        assert!(
            speed.iter().all(|v| (v - 2.0).abs() < 0.05),
            "{track}: {speed:?}"
        );
    }
}

/// A car driving one and a half circles counter-clockwise (radius 10 m, 3° a frame, its heading
/// crossing ±180° twice) has turned 540° by the end; one driving them clockwise -540°.
#[test]
fn total_turn_unwraps_the_heading() {
    let circle = |sign: f64| -> Vec<Waypoint> {
        (0..181)
            .map(|f| {
                let a = sign * (3.0 * f as f64).to_radians();
                let (x, y) = (10.0 * a.sin(), sign * 10.0 * (1.0 - a.cos()));
                (f, x, y, a)
            })
            .collect()
    };
    let car = [4.5, 1.8, 1.5];
    let scene = SceneBuilder::new(181)
        .track("left", "REGULAR_VEHICLE", car, circle(1.0))
        .track("right", "REGULAR_VEHICLE", car, circle(-1.0))
        .build();
    let turned = rows(&scene, "total_turn");
    for (track, sign) in [("left", 1.0), ("right", -1.0)] {
        let a = frames_of(&turned, track);
        let at = |t: u64| {
            a.iter()
                .find(|(f, _)| *f == t)
                .and_then(|(_, v)| v.as_f64())
                .unwrap_or(f64::NAN)
        };
        assert!(at(0).abs() < 1e-6, "{track}");
        for (t, want) in [(60, 180.0), (120, 360.0), (180, 540.0)] {
            assert!(
                (at(t) - sign * want).abs() < 1e-6,
                "{track} at {t}: {}",
                at(t)
            );
        }
    }
}
