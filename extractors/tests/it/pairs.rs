//! Pair relations on small synthetic scenes whose answer is known by construction: at least one
//! positive and one negative case per relation, plus pushdown.

use std::f64::consts::{FRAC_PI_2, PI};

use scenalog_extractors::pairs::{self, PairContext};
use scenalog_extractors::{pair_relation, pair_relations, Extractor};
use scenalog_facts::relation::{Constraint, RelationData, Request, Value};
use scenalog_facts::{Frame, Scene};
use scenalog_testkit::{straight, SceneBuilder, Waypoint};

const CAR: [f64; 3] = [4.5, 1.8, 1.5];
const PED: [f64; 3] = [0.6, 0.6, 1.7];

/// One row: X's uuid, Y's uuid, T, the remaining values.
type Row = (String, String, Frame, Vec<Value>);

fn request(name: &str, constraints: Vec<(usize, Constraint)>) -> Request {
    Request {
        name: name.into(),
        constraints,
    }
}

/// Answers `req` on `scene` through the pairs API and returns the rows with uuids.
fn run(scene: &Scene, req: &Request) -> Vec<Row> {
    let ex = Extractor::new(scene);
    let index = pairs::pair_index(&ex);
    let ctx = PairContext::of(&ex, &index);
    let data = pair_relation(&ctx, req).unwrap_or_else(|e| panic!("{e}"));
    to_rows(scene, &data)
}

fn to_rows(scene: &Scene, data: &RelationData) -> Vec<Row> {
    (0..data.len())
        .map(|i| {
            let row = data.row(i).expect("row in range");
            let (Value::Track(x), Value::Track(y), Value::Time(t)) = (&row[0], &row[1], &row[2])
            else {
                panic!("pair rows start with X, Y, T: {row:?}")
            };
            (
                scene.track(*x).uuid.clone(),
                scene.track(*y).uuid.clone(),
                *t,
                row[3..].to_vec(),
            )
        })
        .collect()
}

fn all(scene: &Scene, name: &str) -> Vec<Row> {
    run(scene, &request(name, Vec::new()))
}

/// Rows of pair (x, y).
fn of<'a>(rows: &'a [Row], x: &str, y: &str) -> Vec<&'a Row> {
    rows.iter().filter(|r| r.0 == x && r.1 == y).collect()
}

/// Frames at which pair (x, y) holds (with any values).
fn frames(rows: &[Row], x: &str, y: &str) -> Vec<Frame> {
    let mut f: Vec<Frame> = of(rows, x, y).iter().map(|r| r.2).collect();
    f.dedup();
    f
}

fn float(v: &Value) -> f64 {
    match v {
        Value::Float(x) => *x,
        other => panic!("expected a float, got {other:?}"),
    }
}

fn string(v: &Value) -> &str {
    match v {
        Value::Str(s) => s,
        other => panic!("expected a string, got {other:?}"),
    }
}

fn still(frames: u32, x: f64, y: f64, yaw: f64) -> Vec<Waypoint> {
    (0..frames).map(|f| (f, x, y, yaw)).collect()
}

/// A parked car `x` at the origin with heading `yaw`, and objects placed in its own frame
/// (forward, left) with the same heading.
fn direction_scene(yaw: f64) -> Scene {
    let (s, c) = yaw.sin_cos();
    let at = |fwd: f64, left: f64| (fwd * c - left * s, fwd * s + left * c);
    let mut b = SceneBuilder::new(10).track("x", "REGULAR_VEHICLE", CAR, still(10, 0.0, 0.0, yaw));
    for (name, cat, fwd, left) in [
        ("front", "REGULAR_VEHICLE", 10.0, 0.0),
        ("back", "REGULAR_VEHICLE", -10.0, 0.0),
        ("left", "REGULAR_VEHICLE", 0.0, 6.0),
        ("right", "REGULAR_VEHICLE", 0.0, -6.0),
        ("corner", "REGULAR_VEHICLE", 10.0, 6.0),
        ("ahead", "PEDESTRIAN", 20.0, 5.0),
        ("overlap", "REGULAR_VEHICLE", 1.0, 0.5),
        ("far", "REGULAR_VEHICLE", 80.0, 0.0),
    ] {
        let cat_size = if cat == "PEDESTRIAN" { PED } else { CAR };
        let (px, py) = at(fwd, left);
        b = b.track(name, cat, cat_size, still(10, px, py, yaw));
    }
    b.build()
}

#[test]
fn near_is_the_rectangle_distance_within_fifty_metres() {
    for yaw in [0.0, 1.0, FRAC_PI_2, -2.5] {
        let scene = direction_scene(yaw);
        let rows = all(&scene, "near");
        let d = |y: &str| {
            let r = of(&rows, "x", y);
            assert_eq!(r.len(), 10, "near(x, {y}) at every frame, yaw {yaw}");
            float(&r[0].3[0])
        };
        // Boxes 4.5 x 1.8, same heading: gaps along the axis.
        assert!((d("front") - 5.5).abs() < 1e-4, "{}", d("front"));
        assert!((d("back") - 5.5).abs() < 1e-4);
        assert!((d("left") - 4.2).abs() < 1e-4);
        assert!((d("corner") - (5.5f64).hypot(4.2)).abs() < 1e-4);
        assert_eq!(d("overlap"), 0.0);
        assert!(of(&rows, "x", "far").is_empty(), "80 m away: no pair");
        // Symmetric, same distance.
        for r in &rows {
            assert!(
                rows.iter()
                    .any(|s| s.0 == r.1 && s.1 == r.0 && s.2 == r.2 && s.3 == r.3),
                "{r:?} has no mirror"
            );
            assert_ne!(r.0, r.1);
        }
    }
}

#[test]
fn direction_regions_in_the_objects_own_frame() {
    for yaw in [0.0, 1.0, FRAC_PI_2, -2.5] {
        let scene = direction_scene(yaw);
        let rows = all(&scene, "direction");
        let dirs = |y: &str| {
            let mut d: Vec<(String, f64, f64)> = of(&rows, "x", y)
                .iter()
                .filter(|r| r.2 == 0)
                .map(|r| (string(&r.3[0]).to_string(), float(&r.3[1]), float(&r.3[2])))
                .collect();
            d.sort_by(|a, b| a.0.cmp(&b.0));
            d
        };
        let one = |y: &str, dir: &str, lat: f64| {
            let d = dirs(y);
            assert_eq!(d.len(), 1, "{y} at yaw {yaw}: {d:?}");
            assert_eq!(d[0].0, dir, "{y} at yaw {yaw}");
            assert!((d[0].2 - lat).abs() < 1e-9, "{y}: lat {}", d[0].2);
        };
        one("front", "forward", 0.0);
        one("back", "backward", 0.0);
        one("left", "left", 0.0);
        one("right", "right", 0.0);
        // Ahead and to the left: both, each with its lateral offset.
        let c = dirs("corner");
        assert_eq!(
            c.iter().map(|d| d.0.as_str()).collect::<Vec<_>>(),
            ["forward", "left"]
        );
        assert!((c[0].2 - (6.0 - 0.9)).abs() < 1e-9);
        assert!((c[1].2 - (10.0 - 2.25)).abs() < 1e-9);
        assert!(
            (c[0].1 - (5.5f64).hypot(4.2)).abs() < 1e-4,
            "Dist is near's D"
        );
        // The centre inside X's box: no direction.
        assert!(dirs("overlap").is_empty());
        assert!(dirs("far").is_empty());
        // Seen from the front car, x is behind.
        let back: Vec<_> = of(&rows, "front", "x")
            .iter()
            .map(|r| string(&r.3[0]).to_string())
            .collect();
        assert!(back.iter().all(|d| d == "backward") && !back.is_empty());
    }
}

#[test]
fn facing_within_22_5_degrees_of_the_forward_axis() {
    let scene = direction_scene(1.0);
    let rows = all(&scene, "facing");
    assert_eq!(frames(&rows, "x", "front").len(), 10);
    // atan2(5, 20) = 14°.
    assert_eq!(frames(&rows, "x", "ahead").len(), 10);
    // atan2(6, 10) = 31°, and sideways or behind: not facing.
    for y in ["corner", "left", "right", "back", "far"] {
        assert!(frames(&rows, "x", y).is_empty(), "{y}");
    }
    // The front car faces away from x.
    assert!(frames(&rows, "front", "x").is_empty());
    assert_eq!(frames(&rows, "back", "x").len(), 10);
}

#[test]
fn pushdown_equals_the_filtered_relation() {
    let scene = direction_scene(0.3);
    let id = |u: &str| scene.track_by_uuid(u).expect("track").id;
    let cases: Vec<Request> = vec![
        request("near", vec![(3, Constraint::Lt(5.0))]),
        request(
            "near",
            vec![(3, Constraint::Le(5.5)), (3, Constraint::Gt(0.0))],
        ),
        request("near", vec![(1, Constraint::Category("PEDESTRIAN".into()))]),
        request("near", vec![(0, Constraint::Category("VEHICLE".into()))]),
        request("near", vec![(1, Constraint::Eq(Value::Track(id("front"))))]),
        request("near", vec![(2, Constraint::Eq(Value::Time(3)))]),
        request(
            "near",
            vec![(2, Constraint::Ge(2.5)), (2, Constraint::Lt(6.0))],
        ),
        request(
            "direction",
            vec![(3, Constraint::Eq(Value::Str("left".into())))],
        ),
        request(
            "direction",
            vec![(4, Constraint::Lt(5.0)), (5, Constraint::Le(0.0))],
        ),
        request("facing", vec![(0, Constraint::Eq(Value::Track(id("x"))))]),
    ];
    let mut nonempty = 0;
    for req in cases {
        let pushed = run(&scene, &req);
        let full = all(&scene, &req.name);
        // The full relation through our API, filtered by the constraints with the crate's own
        // `satisfies`, must equal the pushed-down answer.
        let filtered: Vec<Row> = full
            .into_iter()
            .filter(|r| {
                let vals: Vec<Value> = [
                    Value::Track(id(&r.0)),
                    Value::Track(id(&r.1)),
                    Value::Time(r.2),
                ]
                .into_iter()
                .chain(r.3.iter().cloned())
                .collect();
                req.constraints
                    .iter()
                    .all(|(c, k)| scenalog_extractors::query::satisfies(&scene, &vals[*c], k))
            })
            .collect();
        assert_eq!(pushed, filtered, "{req:?}");
        nonempty += usize::from(!pushed.is_empty());
    }
    assert_eq!(nonempty, 10, "every case selects something");
    let lt5 = run(&scene, &request("near", vec![(3, Constraint::Lt(5.0))]));
    let ys: std::collections::BTreeSet<&str> = of_x(&lt5, "x");
    assert_eq!(ys, ["left", "overlap", "right"].into_iter().collect());
}

fn of_x<'a>(rows: &'a [Row], x: &str) -> std::collections::BTreeSet<&'a str> {
    rows.iter()
        .filter(|r| r.0 == x)
        .map(|r| r.1.as_str())
        .collect()
}

#[test]
fn bad_requests_are_errors() {
    let scene = direction_scene(0.0);
    let ex = Extractor::new(&scene);
    let index = pairs::pair_index(&ex);
    let ctx = PairContext::of(&ex, &index);
    // A relation that is not a pair relation, or not a relation at all.
    assert!(pair_relation(&ctx, &request("speed", Vec::new())).is_err());
    assert!(pair_relation(&ctx, &request("nearby", Vec::new())).is_err());
    assert!(pair_relation(&ctx, &request("near", vec![(7, Constraint::Lt(1.0))])).is_err());
    assert!(pair_relation(
        &ctx,
        &request("near", vec![(3, Constraint::Category("BUS".into()))])
    )
    .is_err());
    // A NaN bound selects nothing, without panicking.
    let nan = pair_relation(&ctx, &request("near", vec![(3, Constraint::Lt(f64::NAN))]));
    assert_eq!(nan.map(|d| d.len()).ok(), Some(0));
}

/// A stopped bus (12 m long) at the origin heading +x; pedestrians walking across at 1.4 m/s:
/// "ped" 9 m ahead of the bus centre (3 m ahead of its front) from y = -8 to +8 (crossing y = 0
/// at frame ~57); "ped2" the other way later; "behind" 9 m behind; "far" 25 m ahead (beyond the
/// 10 m half-midplane); "along" walking past the bus's left side.
fn crossing_scene() -> Scene {
    let n = 120u32;
    let walk = |x: f64, y0: f64, vy: f64| -> Vec<Waypoint> {
        (0..n)
            .map(|f| {
                (
                    f,
                    x,
                    y0 + vy * 0.1 * f as f64,
                    if vy > 0.0 { FRAC_PI_2 } else { -FRAC_PI_2 },
                )
            })
            .collect()
    };
    SceneBuilder::new(n as usize)
        .track("bus", "BUS", [12.0, 2.5, 3.0], still(n, 0.0, 0.0, 0.0))
        .track("ped", "PEDESTRIAN", PED, walk(9.0, -8.0, 1.4))
        .track("ped2", "PEDESTRIAN", PED, walk(12.0, 14.0, -1.4))
        .track("behind", "PEDESTRIAN", PED, walk(-9.0, -8.0, 1.4))
        .track("far", "PEDESTRIAN", PED, walk(25.0, -8.0, 1.4))
        .track(
            "along",
            "PEDESTRIAN",
            PED,
            (0..n)
                .map(|f| (f, -20.0 + 0.3 * f as f64, 3.0, 0.0))
                .collect(),
        )
        .build()
}

#[test]
fn pedestrian_crossing_in_front_of_a_stopped_bus() {
    let scene = crossing_scene();
    let rows = all(&scene, "crossing");
    let dir_frames = |y: &str, dir: &str| -> Vec<Frame> {
        of(&rows, "bus", y)
            .iter()
            .filter(|r| string(&r.3[0]) == dir)
            .map(|r| r.2)
            .collect()
    };
    let f = dir_frames("ped", "forward");
    // y = -8 + 0.14 f: |y| <= 5 for f in 22..=92 (y(21) = -5.06, y(93) = 5.02).
    assert_eq!(f.first(), Some(&22), "{f:?}");
    assert_eq!(f.last(), Some(&92), "{f:?}");
    assert_eq!(f.len(), 71, "one contiguous span: {f:?}");
    // The second pedestrian is found too (every candidate is evaluated), the other way round.
    let f2 = dir_frames("ped2", "forward");
    assert!(f2.contains(&100) && !f2.contains(&50), "{f2:?}");
    // Behind the bus: backward, not forward.
    assert!(dir_frames("behind", "forward").is_empty());
    assert!(dir_frames("behind", "backward").contains(&57));
    // Beyond the 10 m half-midplane: no crossing.
    assert!(of(&rows, "bus", "far").is_empty());
    // Walking along the bus's left side 3 m out at 3 m/s: crosses the left half-midplane (x = 0
    // at frame 66.7), never the forward one.
    assert!(dir_frames("along", "left").contains(&67));
    assert!(dir_frames("along", "forward").is_empty());
    // Pushdown of the direction and the category gives the same forward frames.
    let pushed = run(
        &scene,
        &request(
            "crossing",
            vec![
                (3, Constraint::Eq(Value::Str("forward".into()))),
                (1, Constraint::Category("PEDESTRIAN".into())),
                (0, Constraint::Category("BUS".into())),
            ],
        ),
    );
    assert_eq!(frames(&pushed, "bus", "ped"), f);
    // A time constraint inside the span still finds the event that started before it.
    let at60 = run(
        &scene,
        &request("crossing", vec![(2, Constraint::Eq(Value::Time(60)))]),
    );
    assert!(at60.iter().any(|r| r.0 == "bus" && r.1 == "ped"));
}

/// `crossing_detail` on the same scene: the extents are columns a rule compares (RefAV's
/// `forward_thresh` / `lateral_thresh`), and the sense tells the two ways across apart.
#[test]
fn crossing_detail_gives_reach_offset_and_sense() {
    let scene = crossing_scene();
    let rows = all(&scene, "crossing_detail");
    let fixed = all(&scene, "crossing");
    let float = |v: &Value| match v {
        Value::Float(x) => *x,
        other => panic!("not a float: {other:?}"),
    };
    // (frame, sense, reach, off) of one pair in one direction
    let of_dir = |y: &str, dir: &str| -> Vec<(Frame, String, f64, f64)> {
        of(&rows, "bus", y)
            .iter()
            .filter(|r| string(&r.3[0]) == dir)
            .map(|r| {
                (
                    r.2,
                    string(&r.3[1]).to_string(),
                    float(&r.3[2]),
                    float(&r.3[3]),
                )
            })
            .collect()
    };
    // "ped" walks to the bus's left 3 m beyond its front (x = 9, half length 6): counterclockwise.
    let ped = of_dir("ped", "forward");
    assert!(!ped.is_empty());
    assert!(ped.iter().all(|r| r.1 == "counterclockwise"), "{ped:?}");
    assert!(ped.iter().all(|r| (r.2 - 3.0).abs() < 0.05), "{ped:?}");
    // The span now reaches 15 m from the midplane: |y| <= 15 at every frame.
    assert_eq!(ped.len(), 120);
    // Off <= 5 gives back the fixed crossing's frames exactly.
    let within5: Vec<Frame> = ped.iter().filter(|r| r.3 <= 5.0).map(|r| r.0).collect();
    assert_eq!(within5, frames(&fixed, "bus", "ped"));
    // "ped2" crosses the other way: clockwise.
    let ped2 = of_dir("ped2", "forward");
    assert!(
        !ped2.is_empty() && ped2.iter().all(|r| r.1 == "clockwise"),
        "{ped2:?}"
    );
    // "far" crosses 19 m beyond the front: found here, so Reach <= 10 (the fixed crossing) is a
    // near miss while Reach <= 20 holds.
    let far = of_dir("far", "forward");
    assert!(!far.is_empty(), "the far crossing is found up to 30 m");
    assert!(far.iter().all(|r| (r.2 - 19.0).abs() < 0.05), "{far:?}");
    assert!(of(&fixed, "bus", "far").is_empty());
    // "along" passes the bus's left side back to front: clockwise, i.e. overtaking the bus.
    let along = of_dir("along", "left");
    assert!(along.iter().any(|r| r.0 == 67), "{along:?}");
    assert!(along.iter().all(|r| r.1 == "clockwise"), "{along:?}");
    // Pushdown of the sense keeps only that sense.
    let ccw = run(
        &scene,
        &request(
            "crossing_detail",
            vec![(4, Constraint::Eq(Value::Str("counterclockwise".into())))],
        ),
    );
    assert!(ccw.iter().all(|r| string(&r.3[1]) == "counterclockwise"));
    let bus_front: Vec<&Row> = ccw
        .iter()
        .filter(|r| r.0 == "bus" && string(&r.3[0]) == "forward")
        .collect();
    assert!(bus_front.iter().any(|r| r.1 == "ped"));
    assert!(!bus_front.iter().any(|r| r.1 == "ped2"));
}

const ROAD_FRAMES: u32 = 60;

/// Lane 1 (y 0..3.5, +x, x 0..60) continues straight into lane 4 (x 60..200); lane 3 (y -3.5..0,
/// +x) is its right neighbour; lane 2 (y 3.5..7, running -x) is the opposite carriageway.
/// "follower" drives lane 1 at 10 m/s from x 10, "lead" 15 m ahead at the same speed, "far_lead"
/// 40 m ahead; "beside" in lane 3 alongside; "oncoming" in lane 2 at 10 m/s the other way;
/// "parked_opp" parked in lane 2 facing -x; "stopped" stopped in lane 3 at x 45; "cone" a
/// construction cone; "crosser" walking across the road.
fn road_scene() -> Scene {
    let n = ROAD_FRAMES;
    SceneBuilder::new(n as usize)
        .lane(
            1,
            &[[0.0, 3.5], [60.0, 3.5]],
            &[[0.0, 0.0], [60.0, 0.0]],
            &[4],
            Some(2),
            Some(3),
            false,
        )
        .lane(
            4,
            &[[60.0, 3.5], [200.0, 3.5]],
            &[[60.0, 0.0], [200.0, 0.0]],
            &[],
            Some(2),
            None,
            false,
        )
        .lane(
            2,
            &[[200.0, 3.5], [0.0, 3.5]],
            &[[200.0, 7.0], [0.0, 7.0]],
            &[],
            Some(1),
            None,
            false,
        )
        .lane(
            3,
            &[[0.0, 0.0], [200.0, 0.0]],
            &[[0.0, -3.5], [200.0, -3.5]],
            &[],
            Some(1),
            None,
            false,
        )
        .track(
            "follower",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, n, 10.0, 1.75, 0.0, 10.0),
        )
        .track(
            "lead",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, n, 25.0, 1.75, 0.0, 10.0),
        )
        .track(
            "far_lead",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, n, 50.0, 1.75, 0.0, 10.0),
        )
        .track(
            "beside",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, n, 12.0, -1.75, 0.0, 10.0),
        )
        .track(
            "oncoming",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, n, 90.0, 5.25, PI, 10.0),
        )
        .track(
            "parked_opp",
            "REGULAR_VEHICLE",
            CAR,
            still(n, 30.0, 5.25, PI),
        )
        .track(
            "stopped",
            "REGULAR_VEHICLE",
            CAR,
            still(n, 45.0, -1.75, 0.0),
        )
        .track(
            "cone",
            "CONSTRUCTION_CONE",
            [0.4, 0.4, 0.7],
            still(n, 20.0, -4.5, 0.0),
        )
        .track(
            "crosser",
            "PEDESTRIAN",
            PED,
            straight(0, n, 40.0, -10.0, FRAC_PI_2, 1.5),
        )
        .build()
}

#[test]
fn following_a_lead_in_the_same_lane_and_its_successor() {
    let scene = road_scene();
    let rows = all(&scene, "following");
    let f = frames(&rows, "follower", "lead");
    // Lead 15 m ahead (12.75 m beyond the front) at every frame; after frame 35 the lead is in
    // lane 4, the successor, while the follower is still in lane 1 until frame 50.
    assert_eq!(f, (0..ROAD_FRAMES).collect::<Vec<_>>());
    // Not the other way round, not 40 m ahead, not alongside, not oncoming, not a parked car
    // facing the other way.
    assert!(frames(&rows, "lead", "follower").is_empty());
    assert!(frames(&rows, "follower", "far_lead").is_empty());
    assert!(frames(&rows, "follower", "beside").is_empty());
    assert!(frames(&rows, "follower", "oncoming").is_empty());
    assert!(frames(&rows, "follower", "parked_opp").is_empty());
    // The lead follows the far lead (25 m apart: 22.75 m beyond the front).
    assert_eq!(
        frames(&rows, "lead", "far_lead").len(),
        ROAD_FRAMES as usize
    );
}

#[test]
fn same_lane_is_the_lane_as_a_driver_sees_it() {
    let scene = road_scene();
    let rows = all(&scene, "same_lane");
    assert_eq!(
        frames(&rows, "follower", "lead").len(),
        ROAD_FRAMES as usize
    );
    assert_eq!(
        frames(&rows, "lead", "follower").len(),
        ROAD_FRAMES as usize
    );
    // The far lead: same lane chain while within 50 m.
    assert!(!frames(&rows, "follower", "far_lead").is_empty());
    // The neighbour lane and the opposite lane are not the same lane.
    assert!(frames(&rows, "follower", "beside").is_empty());
    assert!(frames(&rows, "follower", "oncoming").is_empty());
    // The pedestrian walking across is in lane 3 from y = -3.4 (frame 44) on: then in the same
    // lane as the car beside, never in the follower's.
    assert_eq!(
        frames(&rows, "crosser", "beside"),
        (44..60).collect::<Vec<_>>()
    );
    assert!(frames(&rows, "crosser", "follower").is_empty());
}

#[test]
fn road_side_same_and_opposite() {
    let scene = road_scene();
    let rows = all(&scene, "road_side");
    let sides = |x: &str, y: &str| -> Vec<String> {
        let mut s: Vec<String> = of(&rows, x, y)
            .iter()
            .map(|r| string(&r.3[0]).to_string())
            .collect();
        s.dedup();
        s
    };
    assert_eq!(sides("follower", "lead"), ["same"]);
    assert_eq!(sides("follower", "beside"), ["same"]);
    assert_eq!(sides("follower", "oncoming"), ["opposite"]);
    assert_eq!(sides("oncoming", "follower"), ["opposite"]);
    assert_eq!(sides("beside", "parked_opp"), ["opposite"]);
    // The cone is off the road: no side.
    assert!(sides("follower", "cone").is_empty());
}

#[test]
fn heading_relative_same_perpendicular_opposite() {
    let scene = road_scene();
    let rows = all(&scene, "heading_relative");
    let rel = |x: &str, y: &str| -> Vec<String> {
        let mut s: Vec<String> = of(&rows, x, y)
            .iter()
            .map(|r| string(&r.3[0]).to_string())
            .collect();
        s.dedup();
        s
    };
    assert_eq!(rel("follower", "lead"), ["same"]);
    assert_eq!(rel("follower", "oncoming"), ["opposite"]);
    assert_eq!(rel("follower", "crosser"), ["perpendicular"]);
    // Parked: its box heading.
    assert_eq!(rel("follower", "parked_opp"), ["opposite"]);
    assert_eq!(rel("stopped", "parked_opp"), ["opposite"]);
    // A cone has no heading.
    assert!(rel("follower", "cone").is_empty());
    assert!(rel("cone", "follower").is_empty());
}

#[test]
fn heading_toward_closes_in_metres_per_second() {
    let scene = road_scene();
    let rows = all(&scene, "heading_toward");
    let f = frames(&rows, "follower", "stopped");
    // Follower at x 10 + t·10 m/s, stopped car 3.5 m to the side at x 45: within 22.5° while
    // 45 - x >= 3.5 / tan 22.5° = 8.45 m, i.e. x <= 36.5: frames 0..=26.
    assert_eq!(f.first(), Some(&0));
    assert_eq!(f.last(), Some(&26), "{f:?}");
    // Moving along with the lead (no closing speed), or away from the follower: no.
    assert!(frames(&rows, "follower", "lead").is_empty());
    assert!(frames(&rows, "lead", "follower").is_empty());
    // The stopped car itself heads toward nothing.
    assert!(rows.iter().all(|r| r.0 != "stopped"));
}

#[test]
fn facing_on_the_road() {
    let scene = road_scene();
    let rows = all(&scene, "facing");
    assert_eq!(
        frames(&rows, "follower", "lead").len(),
        ROAD_FRAMES as usize
    );
    assert!(frames(&rows, "lead", "follower").is_empty());
}

#[test]
fn the_context_and_index_are_sync() {
    fn sync<T: Sync + Send>() {}
    sync::<pairs::PairIndex>();
    sync::<PairContext<'static>>();
}

/// `Constraint::OneOf` (the engine's demand: the tracks or frames another atom binds) on every
/// pair relation of three staged scenes: the answer equals the full relation filtered by the
/// constraints, and never holds a tuple outside the listed values.
#[test]
fn one_of_equals_the_filtered_relation_on_every_pair_relation() {
    let scenes = [direction_scene(0.3), crossing_scene(), road_scene()];
    let mut nonempty = 0;
    let mut cases = 0;
    for scene in &scenes {
        let tracks: Vec<Value> = scene.tracks.iter().map(|t| Value::Track(t.id)).collect();
        // Subjects and objects: every other track; frames: a scattered handful.
        let some: Vec<Value> = tracks.iter().step_by(2).cloned().collect();
        let others: Vec<Value> = tracks.iter().skip(1).step_by(2).cloned().collect();
        let times: Vec<Value> = [0u32, 3, 4, 9, 40, 57].map(Value::Time).to_vec();
        for name in pair_relations() {
            let full = all(scene, name);
            for constraints in [
                vec![(0, Constraint::OneOf(some.clone().into()))],
                vec![(1, Constraint::OneOf(others.clone().into()))],
                vec![(2, Constraint::OneOf(times.clone().into()))],
                vec![
                    (0, Constraint::OneOf(others.clone().into())),
                    (1, Constraint::OneOf(some.clone().into())),
                    (2, Constraint::OneOf(times.clone().into())),
                ],
                vec![(0, Constraint::OneOf(Vec::new().into()))],
            ] {
                let req = request(name, constraints);
                let pushed = run(scene, &req);
                let id = |u: &str| scene.track_by_uuid(u).expect("track").id;
                let filtered: Vec<Row> = full
                    .iter()
                    .filter(|r| {
                        let vals = [
                            Value::Track(id(&r.0)),
                            Value::Track(id(&r.1)),
                            Value::Time(r.2),
                        ];
                        req.constraints.iter().all(|(c, k)| {
                            let Constraint::OneOf(vs) = k else {
                                panic!("only OneOf here")
                            };
                            vs.contains(&vals[*c])
                        })
                    })
                    .cloned()
                    .collect();
                assert_eq!(pushed, filtered, "{req:?}");
                cases += 1;
                nonempty += usize::from(!pushed.is_empty());
            }
        }
    }
    assert_eq!(cases, 3 * pair_relations().len() * 5);
    // Not vacuous: most restricted answers still hold tuples.
    assert!(
        nonempty >= 40,
        "only {nonempty} of {cases} answers were non-empty"
    );
}

#[test]
fn one_of_values_must_fit_the_column() {
    let scene = direction_scene(0.0);
    let ex = Extractor::new(&scene);
    let index = pairs::pair_index(&ex);
    let ctx = PairContext::of(&ex, &index);
    let track = Value::Track(scene.tracks[0].id);
    for (col, values) in [
        (0, vec![track.clone(), Value::Str("x".into())]),
        (2, vec![track.clone()]),
        (3, vec![Value::Time(2)]),
    ] {
        let req = request("direction", vec![(col, Constraint::OneOf(values.into()))]);
        assert!(pair_relation(&ctx, &req).is_err(), "{req:?}");
    }
}

/// The ego's box is the car's body (about -1.0 m to +3.9 m along its heading from the rear axle,
/// where the ego pose is), not a box centred on the rear axle. Pedestrians staged around a still
/// ego whose rear axle is at the origin: "tail" 0.2 m behind the rear bumper, "flank" beside the
/// car with its centre 0.5 m ahead of the axle, "front_flank" beside the car's front half (3.2 m
/// ahead of the axle). With the old axle-centred box, "tail" was inside the ego's box (no
/// direction) and "front_flank" was ahead of it.
#[test]
fn beside_and_behind_the_ego_use_the_cars_real_extent() {
    let peds = [
        ("tail", -1.0 - 0.2 - PED[0] / 2.0, 0.0),
        ("flank", 0.5, 2.0),
        ("front_flank", 3.2, -2.0),
    ];
    let staged = |b: SceneBuilder| {
        peds.iter()
            .fold(b, |b, (n, x, y)| {
                b.track(n, "PEDESTRIAN", PED, still(10, *x, *y, 0.0))
            })
            .build()
    };
    let directions = |scene: &Scene| -> Vec<(String, String, f64)> {
        let req = request(
            "direction",
            vec![(0, Constraint::Eq(Value::Track(scene.ego)))],
        );
        let mut out: Vec<(String, String, f64)> = run(scene, &req)
            .into_iter()
            .filter(|r| r.2 == 0)
            .map(|r| (r.1, string(&r.3[0]).to_string(), float(&r.3[2])))
            .collect();
        out.sort_by(|a, b| (&a.0, &a.1).cmp(&(&b.0, &b.1)));
        out
    };
    let real = directions(&staged(
        SceneBuilder::new(10).ego_at_rear_axle(still(10, 0.0, 0.0, 0.0)),
    ));
    let lat0 = |n: &str, d: &str| (n.to_string(), d.to_string(), 0.0);
    assert_eq!(
        real,
        vec![
            lat0("flank", "left"),
            lat0("front_flank", "right"),
            lat0("tail", "backward"),
        ]
    );
    // The same staging with the box centred on the rear axle (the old ego box) gets the tail
    // and the front flank wrong: the cases discriminate.
    let old = directions(&staged(SceneBuilder::new(10).track(
        "ego",
        "EGO_VEHICLE",
        scenalog_facts::scene::EGO_SIZE,
        still(10, 0.0, 0.0, 0.0),
    )));
    assert!(!old.iter().any(|r| r.0 == "tail"), "{old:?}");
    assert!(
        old.iter().any(|r| r.0 == "front_flank" && r.1 == "forward"),
        "{old:?}"
    );
    assert!(old.contains(&lat0("flank", "left")));
}
