//! RefAV's definitions (`refav_*`, for `scenalog import refav --semantics refav`) against
//! Scenalog's on synthetic scenes where the two differ, each way.

use scenalog_extractors::{extract, relation_json};
use scenalog_facts::relation::Request;
use scenalog_facts::Scene;
use scenalog_testkit::{straight, SceneBuilder, Waypoint};
use serde_json::Value as J;

const CAR: [f64; 3] = [4.5, 1.8, 1.5];

fn rows(scene: &Scene, name: &str) -> Vec<J> {
    let data = extract(scene, &Request::all(name)).expect("extract");
    match relation_json(scene, &data) {
        J::Array(v) => v,
        other => panic!("not an array: {other}"),
    }
}

/// The frames and directions of `track` in a (track, time, dir) relation.
fn turns(scene: &Scene, name: &str, track: &str) -> Vec<(u64, String)> {
    rows(scene, name)
        .iter()
        .filter(|r| r[0] == track)
        .map(|r| {
            (
                r[1].as_u64().unwrap_or(0),
                r[2].as_str().unwrap_or("").into(),
            )
        })
        .collect()
}

/// A car at 10 m/s turning left at `rate` deg/s for `frames` frames after 10 straight ones, then
/// 10 more straight; `blip` lowers the heading of one frame by that many degrees.
fn turner(rate: f64, frames: u32, blip: Option<(u32, f64)>) -> Scene {
    let mut way: Vec<Waypoint> = Vec::new();
    let (mut x, mut y, mut h) = (0.0, 0.0, 0.0_f64);
    let total = frames + 20;
    for f in 0..total {
        let shown = match blip {
            Some((b, d)) if b == f => h - d.to_radians(),
            _ => h,
        };
        way.push((f, x, y, shown));
        x += h.cos();
        y += h.sin();
        if (10..10 + frames).contains(&f) {
            h += (rate * 0.1).to_radians();
        }
    }
    SceneBuilder::new(total as usize)
        .track("turner", "REGULAR_VEHICLE", CAR, way)
        .build()
}

#[test]
fn a_one_frame_heading_blip_splits_a_turn_only_in_refav_turning() {
    // 60° at 30 deg/s; the heading of frame 20 (mid-turn) 8° low: the yaw rate's central
    // difference flips sign at frame 19.
    let scene = turner(30.0, 20, Some((20, 8.0)));
    let ours = turns(&scene, "turning", "turner");
    assert!(ours.iter().any(|(f, _)| *f == 19), "{ours:?}");
    assert!(ours.iter().all(|(_, d)| d == "left"));
    // RefAV: two runs of about 30° each, neither a turn.
    assert!(turns(&scene, "refav_turning", "turner").is_empty());
    // Without the blip both find the turn, over about the same frames.
    let clean = turner(30.0, 20, None);
    let (ours, theirs) = (
        turns(&clean, "turning", "turner"),
        turns(&clean, "refav_turning", "turner"),
    );
    assert!(
        ours.len() >= 15 && theirs.len() >= 15,
        "{ours:?} {theirs:?}"
    );
    assert!(theirs.iter().all(|(_, d)| d == "left"));
}

#[test]
fn a_slow_drift_is_a_turn_only_in_refav_turning() {
    // 0.9 deg/s for 60 s: 54° in all, under Scenalog's 1 deg/s dead band at every frame.
    let scene = turner(0.9, 600, None);
    assert!(turns(&scene, "turning", "turner").is_empty());
    let theirs = turns(&scene, "refav_turning", "turner");
    assert!(theirs.len() >= 600, "{}", theirs.len());
    assert!(theirs.iter().all(|(_, d)| d == "left"));
    // 0.7 deg/s (42°): no turn in either.
    assert!(turns(&turner(0.7, 600, None), "refav_turning", "turner").is_empty());
}

/// (X, Y, Dir, Dist) of a direction relation at frame 0.
fn directions(scene: &Scene, name: &str) -> Vec<(String, String, String, f64)> {
    rows(scene, name)
        .iter()
        .filter(|r| r[2] == 0)
        .map(|r| {
            (
                r[0].as_str().unwrap_or("").into(),
                r[1].as_str().unwrap_or("").into(),
                r[3].as_str().unwrap_or("").into(),
                r[4].as_f64().unwrap_or(f64::NAN),
            )
        })
        .collect()
}

fn has(rows: &[(String, String, String, f64)], x: &str, y: &str, dir: &str) -> Option<f64> {
    rows.iter()
        .find(|r| r.0 == x && r.1 == y && r.2 == dir)
        .map(|r| r.3)
}

#[test]
fn refav_direction_places_the_ego_at_its_rear_axle() {
    // The ego's rear axle at the origin heading +x: its body spans x -1.0..3.877. "level" is
    // level with the axle in the lane to the right; "ahead" 29.5 m ahead of the body's front.
    let ahead_x = 3.877 + 29.5 + 2.25;
    let scene = SceneBuilder::new(5)
        .ego_at_rear_axle(straight(0, 5, 0.0, 0.0, 0.0, 0.0))
        .track(
            "level",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 5, 0.0, -3.5, 0.0, 0.0),
        )
        .track(
            "ahead",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 5, ahead_x, 0.0, 0.0, 0.0),
        )
        .build();
    let ours = directions(&scene, "direction");
    let theirs = directions(&scene, "refav_direction");
    // RefAV's back edge of the ego is 1.02 m *ahead* of the axle: a car level with the axle is
    // "behind" it there, only "to the right" in Scenalog.
    assert!(has(&ours, "ego", "level", "right").is_some());
    assert!(has(&ours, "ego", "level", "backward").is_none());
    assert!(has(&theirs, "ego", "level", "right").is_some());
    assert!(has(&theirs, "ego", "level", "backward").is_some());
    // Distances to the ego are from its box at the axle, 1.44 m further from a car ahead:
    // within 30 m in Scenalog, not in RefAV (as the track and as the candidate).
    for (x, y, dir) in [("ego", "ahead", "forward"), ("ahead", "ego", "backward")] {
        let d = has(&ours, x, y, dir).unwrap_or(f64::NAN);
        assert!((d - 29.5).abs() < 1e-3, "{x} {y}: {d}");
        let d = has(&theirs, x, y, dir).unwrap_or(f64::NAN);
        assert!((d - (29.5 + 1.4385)).abs() < 1e-3, "{x} {y}: {d}");
    }
    // Pairs without the ego are the same in both.
    let without_ego = |r: &Vec<(String, String, String, f64)>| -> Vec<(String, String, String)> {
        r.iter()
            .filter(|r| r.0 != "ego" && r.1 != "ego")
            .map(|r| (r.0.clone(), r.1.clone(), r.2.clone()))
            .collect()
    };
    assert_eq!(without_ego(&ours), without_ego(&theirs));
    assert!(!without_ego(&ours).is_empty());
}

/// (X, Y) pairs of a crossing relation in direction "forward", any frame.
fn crossers(scene: &Scene, name: &str) -> Vec<String> {
    let mut ys: Vec<String> = rows(scene, name)
        .iter()
        .filter(|r| r[0] == "car" && r[3] == "forward")
        .map(|r| r[1].as_str().unwrap_or("").to_string())
        .collect();
    ys.dedup();
    ys
}

#[test]
fn refav_crossing_counts_a_side_line_and_scenalog_the_midplane() {
    // A parked car at the origin heading +x (4.5 m by 1.8 m: side lines at y = ±0.9, front at
    // x = 2.25). "grazer" walks in at x = 4 from y = 3 to y = 0.5 and back out: it passes the
    // left side line but never the midplane. "diagonal" walks from (0.27, 3) to (2.98, -0.5):
    // it passes the left side line at x = 1.9 (beside the car, not in front) and the midplane at
    // x = 2.6 (in front), and never reaches the right side line.
    const PED: [f64; 3] = [0.6, 0.6, 1.7];
    let grazer: Vec<Waypoint> = (0..60u32)
        .map(|f| {
            let t = f64::from(f) * 0.1;
            let y = if t < 2.5 { 3.0 - t } else { 0.5 + (t - 2.5) };
            (f, 4.0, y, -std::f64::consts::FRAC_PI_2)
        })
        .collect();
    let diagonal: Vec<Waypoint> = (0..60u32)
        .map(|f| {
            let y = (3.0 - f64::from(f.min(35)) * 0.1).max(-0.5);
            (f, 0.267 + 0.778 * (3.0 - y), y, -1.0)
        })
        .collect();
    let scene = SceneBuilder::new(60)
        .track(
            "car",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 60, 0.0, 0.0, 0.0, 0.0),
        )
        .track("grazer", "PEDESTRIAN", PED, grazer)
        .track("diagonal", "PEDESTRIAN", PED, diagonal)
        .build();
    assert_eq!(crossers(&scene, "crossing"), ["diagonal"]);
    assert_eq!(crossers(&scene, "refav_crossing"), ["grazer"]);
}

#[test]
fn refav_direction_corrected_moves_only_the_ego_back_edge() {
    // As above: "level" is level with the ego's rear axle in the lane to the right; "behind" is
    // 5 m behind the car's back. The corrected box puts the back edge 1.02 m behind the axle:
    // "level" is only to the right, as in Scenalog; "behind" is behind in all three.
    let scene = SceneBuilder::new(5)
        .ego_at_rear_axle(straight(0, 5, 0.0, 0.0, 0.0, 0.0))
        .track(
            "level",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 5, 0.0, -3.5, 0.0, 0.0),
        )
        .track(
            "behind",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 5, -1.02 - 5.0 - 2.25, 0.0, 0.0, 0.0),
        )
        .build();
    let slipped = directions(&scene, "refav_direction");
    let corrected = directions(&scene, "refav_direction_corrected");
    assert!(has(&slipped, "ego", "level", "backward").is_some());
    assert!(has(&corrected, "ego", "level", "backward").is_none());
    assert!(has(&corrected, "ego", "level", "right").is_some());
    for rows in [&slipped, &corrected] {
        let d = has(rows, "ego", "behind", "backward").unwrap_or(f64::NAN);
        // The distance is from the ego's box at the axle (its body 1.44 m behind where it is).
        assert!(d.is_finite() && d > 0.0, "{d}");
    }
    assert_eq!(
        has(&slipped, "ego", "behind", "backward"),
        has(&corrected, "ego", "behind", "backward")
    );
    // Without the ego as X the two are the same relation.
    let not_ego_x = |r: &Vec<(String, String, String, f64)>| -> Vec<(String, String, String)> {
        r.iter()
            .filter(|r| r.0 != "ego")
            .map(|r| (r.0.clone(), r.1.clone(), r.2.clone()))
            .collect()
    };
    assert_eq!(not_ego_x(&slipped), not_ego_x(&corrected));
    assert!(!not_ego_x(&slipped).is_empty());
}

#[test]
fn refav_crossing_event_holds_for_a_crossing_whatever_its_sense() {
    // A parked car at the origin heading +x; "walker" crosses in front of it at x = 4 from the
    // left (y = 3.05) to the right (y = -2.85) at 1 m/s: it passes the left side line (y = 0.9) and
    // the right one (y = -0.9), moving towards -y ("clockwise"). An event is found at each side
    // line, 1.75 m beyond half the car's length, and the spans of refav_crossing contain them.
    const PED: [f64; 3] = [0.6, 0.6, 1.7];
    let walker: Vec<Waypoint> = (0..60u32)
        .map(|f| {
            (
                f,
                4.0,
                3.05 - f64::from(f) * 0.1,
                -std::f64::consts::FRAC_PI_2,
            )
        })
        .collect();
    let scene = SceneBuilder::new(60)
        .track(
            "car",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 60, 0.0, 0.0, 0.0, 0.0),
        )
        .track("walker", "PEDESTRIAN", PED, walker)
        .build();
    let events: Vec<(u64, f64)> = rows(&scene, "refav_crossing_event")
        .iter()
        .filter(|r| r[0] == "car" && r[1] == "walker" && r[3] == "forward")
        .map(|r| {
            (
                r[2].as_u64().unwrap_or(0),
                r[4].as_f64().unwrap_or(f64::NAN),
            )
        })
        .collect();
    assert_eq!(events.len(), 2, "{events:?}");
    for (_, reach) in &events {
        assert!((reach - 1.75).abs() < 1e-6, "{reach}");
    }
    // y = 3.05 - 0.1 f passes 0.9 between frames 21 and 22, -0.9 between 39 and 40.
    assert_eq!(events.iter().map(|e| e.0).collect::<Vec<_>>(), [22, 40]);
    let span_frames: Vec<u64> = rows(&scene, "refav_crossing")
        .iter()
        .filter(|r| r[0] == "car" && r[1] == "walker" && r[3] == "forward")
        .map(|r| r[2].as_u64().unwrap_or(0))
        .collect();
    for (f, _) in &events {
        assert!(span_frames.contains(f), "{f} not in {span_frames:?}");
    }
    // Only "clockwise" spans, but the event carries no sense: a program asking for
    // "counterclockwise" finds no span, while RefAV still overwrites its direction.
    assert!(rows(&scene, "refav_crossing")
        .iter()
        .filter(|r| r[0] == "car" && r[1] == "walker")
        .all(|r| r[4] == "clockwise"));
}

#[test]
fn refav_order_is_the_file_order_and_for_vehicles_category_by_category() {
    // Added (the "file's" order): a pedestrian, a regular vehicle, a bus, another pedestrian,
    // the ego. RefAV's VEHICLE keys: the ego first, then BUS, then REGULAR_VEHICLE.
    let still = |x: f64| straight(0, 3, x, 0.0, 0.0, 0.0);
    let scene = SceneBuilder::new(3)
        .track("p1", "PEDESTRIAN", [0.6, 0.6, 1.7], still(0.0))
        .track("car", "REGULAR_VEHICLE", CAR, still(10.0))
        .track("bus", "BUS", [12.0, 2.5, 3.0], still(30.0))
        .track("p0", "PEDESTRIAN", [0.6, 0.6, 1.7], still(50.0))
        .ego_at_rear_axle(still(-20.0))
        .build();
    let order = |cat: &str| -> Vec<(String, i64)> {
        let mut v: Vec<(String, i64)> = rows(&scene, "refav_order")
            .iter()
            .filter(|r| r[1] == cat)
            .map(|r| {
                (
                    r[0].as_str().unwrap_or("").to_string(),
                    r[2].as_i64().unwrap_or(-1),
                )
            })
            .collect();
        v.sort_by_key(|r| r.1);
        v
    };
    let names = |v: Vec<(String, i64)>| -> Vec<String> { v.into_iter().map(|r| r.0).collect() };
    assert_eq!(names(order("ANY")), ["p1", "car", "bus", "p0", "ego"]);
    assert_eq!(names(order("PEDESTRIAN")), ["p1", "p0"]);
    assert_eq!(names(order("VEHICLE")), ["ego", "bus", "car"]);
    assert_eq!(order("PEDESTRIAN")[0].1, 0);
    assert_eq!(order("VEHICLE")[2].1, 2);
}

#[test]
fn refav_crosswalk_dilates_with_mitred_corners_and_names_the_crossing() {
    // A crosswalk from (0, 0) to (4, 2) (id 7). "beside" is a 0.6 m pedestrian 1.5 m beyond its
    // right edge; "corner" 1.5 m beyond both its right and top edges, diagonal from the corner:
    // RefAV's mitred dilation reaches both at 1.5 m, Scenalog's distance to the corner is
    // 1.5·√2. "on" stands on it (0).
    const PED: [f64; 3] = [0.6, 0.6, 1.7];
    let at = |x: f64, y: f64| straight(0, 2, x, y, 0.0, 0.0);
    let scene = SceneBuilder::new(2)
        .crossing(7, &[[0.0, 0.0], [4.0, 0.0]], &[[0.0, 2.0], [4.0, 2.0]])
        .track("beside", "PEDESTRIAN", PED, at(4.0 + 1.5 + 0.3, 1.0))
        .track(
            "corner",
            "PEDESTRIAN",
            PED,
            at(4.0 + 1.5 + 0.3, 2.0 + 1.5 + 0.3),
        )
        .track("on", "PEDESTRIAN", PED, at(2.0, 1.0))
        .build();
    let refav: Vec<(String, i64, f64)> = rows(&scene, "refav_crosswalk")
        .iter()
        .filter(|r| r[1] == 0)
        .map(|r| {
            (
                r[0].as_str().unwrap_or("").to_string(),
                r[2].as_i64().unwrap_or(-1),
                r[3].as_f64().unwrap_or(f64::NAN),
            )
        })
        .collect();
    let d = |who: &str| {
        refav
            .iter()
            .find(|r| r.0 == who && r.1 == 7)
            .map_or(f64::NAN, |r| r.2)
    };
    assert!((d("beside") - 1.5).abs() < 1e-9, "{refav:?}");
    assert!((d("corner") - 1.5).abs() < 1e-9, "{refav:?}");
    assert_eq!(d("on"), 0.0);
    let ours = |who: &str| {
        rows(&scene, "at_crosswalk")
            .iter()
            .find(|r| r[0] == who && r[1] == 0)
            .map_or(f64::NAN, |r| r[2].as_f64().unwrap_or(f64::NAN))
    };
    assert!((ours("beside") - 1.5).abs() < 1e-6);
    assert!((ours("corner") - 1.5 * 2f64.sqrt()).abs() < 1e-6);
}

#[test]
fn refav_turning_filtered_keeps_a_turn_a_heading_blip_splits() {
    // The blip of `a_one_frame_heading_blip_splits_a_turn_only_in_refav_turning`: RefAV's rule
    // finds no turn; on the 3-sample median of the yaw rate it finds the same turn as without
    // the blip, and it still counts a slow drift, as RefAV's rule does.
    let blip = turner(30.0, 20, Some((20, 8.0)));
    assert!(turns(&blip, "refav_turning", "turner").is_empty());
    let filtered = turns(&blip, "refav_turning_filtered", "turner");
    let clean = turns(&turner(30.0, 20, None), "refav_turning", "turner");
    assert!(filtered.len() >= 15, "{filtered:?}");
    assert!(filtered.iter().all(|(_, d)| d == "left"));
    let frames = |v: &[(u64, String)]| v.iter().map(|r| r.0).collect::<Vec<_>>();
    let (a, b) = (frames(&filtered), frames(&clean));
    let common = a.iter().filter(|f| b.contains(f)).count();
    assert!(common + 2 >= a.len().max(b.len()), "{a:?} vs {b:?}");
    let drift = turner(0.9, 600, None);
    assert_eq!(
        turns(&drift, "refav_turning_filtered", "turner"),
        turns(&drift, "refav_turning", "turner")
    );
}

/// The frames of `track` in a (track, time) relation.
fn frames_of(scene: &Scene, name: &str, track: &str) -> Vec<u64> {
    rows(scene, name)
        .iter()
        .filter(|r| r[0] == track)
        .map(|r| r[1].as_u64().unwrap_or(0))
        .collect()
}

#[test]
fn a_roll_at_one_frame_splits_refav_turning_through_the_rotation_vector() {
    // A left turn of 48° at 16 deg/s from a heading of 90°: RefAV's turn.
    let base = |roll: Option<u32>| {
        let mut scene = turner(16.0, 30, None);
        let i = scene.track_by_uuid["turner"].index();
        for b in &mut scene.tracks[i].boxes {
            let turn = nalgebra::UnitQuaternion::from_euler_angles(0.0, 0.0, 90f64.to_radians());
            b.city.rotation = turn * b.city.rotation;
            b.ego.rotation = b.city.rotation;
        }
        if let Some(f) = roll {
            // The box at frame f rolled 40° about its own x axis: its heading is unchanged.
            let b = &mut scene.tracks[i].boxes[f as usize];
            let tilt = nalgebra::UnitQuaternion::from_euler_angles(40f64.to_radians(), 0.0, 0.0);
            b.city.rotation *= tilt;
            b.ego.rotation = b.city.rotation;
        }
        scene
    };
    let (flat, rolled) = (base(None), base(Some(25)));
    let theirs = turns(&flat, "refav_turning", "turner");
    assert!(theirs.len() >= 30, "{theirs:?}");
    assert!(theirs.iter().all(|(_, d)| d == "left"));
    // The heading, and so Scenalog's turning, does not see the roll.
    assert_eq!(
        turns(&flat, "turning", "turner"),
        turns(&rolled, "turning", "turner")
    );
    assert_eq!(
        rows(&flat, "yaw_rate"),
        rows(&rolled, "yaw_rate"),
        "the heading's rate"
    );
    // The rotation vector's z drops at the rolled frame, so its rate turns negative just
    // before it: two runs of about 24°, neither a turn.
    assert!(
        turns(&rolled, "refav_turning", "turner").is_empty(),
        "{:?}",
        turns(&rolled, "refav_turning", "turner")
    );
}

/// A two-lane road along +x from x = 0 to 200: lane 1 on the right (y from -3.5 to 0), lane
/// 2 on the left (0 to 3.5), lane 1's left neighbour and lane 1 its right one; `oncoming` makes
/// lane 2 run along -x (its boundaries reversed) with lane 1 its left neighbour too, as AV2
/// links the lanes either side of a centre line. A car at 10 m/s
/// moves from lane 1's middle to lane 2's over 3 s, starting at 2.05 s (so no sample lies on the
/// boundary, where RefAV's fraction across the lane is 0, which Python takes as false).
fn lane_changer(oncoming: bool) -> Scene {
    let way: Vec<Waypoint> = (0..80)
        .map(|f| {
            let t = f64::from(f) * 0.1;
            let s = ((t - 2.05) / 3.0).clamp(0.0, 1.0);
            (f, 10.0 * t, -1.75 + 3.5 * s, 0.0)
        })
        .collect();
    // Boundaries with a point every 10 m, as AV2's have several (with only its two ends,
    // RefAV's left-boundary direction near the first point is the zero vector: its
    // `min(0, nearest - 1)` slip takes the last point, which is also the one after).
    let line = |y: f64, back: bool| -> Vec<[f64; 2]> {
        let mut v: Vec<[f64; 2]> = (0..=20).map(|k| [10.0 * f64::from(k), y]).collect();
        if back {
            v.reverse();
        }
        v
    };
    let (left2, right2) = if oncoming {
        (line(0.0, true), line(3.5, true))
    } else {
        (line(3.5, false), line(0.0, false))
    };
    SceneBuilder::new(80)
        .lane(
            1,
            &line(0.0, false),
            &line(-3.5, false),
            &[],
            Some(2),
            None,
            false,
        )
        .lane(
            2,
            &left2,
            &right2,
            &[],
            oncoming.then_some(1),
            (!oncoming).then_some(1),
            false,
        )
        .track("car", "REGULAR_VEHICLE", CAR, way)
        .build()
}

#[test]
fn refav_lane_change_follows_links_across_the_centre_line() {
    // Into a lane running the same way: a left change in both, around the boundary crossing
    // (y = 0 at frame 35).
    let same = lane_changer(false);
    let ours = turns(&same, "lane_change", "car");
    let theirs = turns(&same, "refav_lane_change", "car");
    assert!(ours.iter().any(|(f, _)| *f == 35), "{ours:?}");
    assert!(theirs.iter().any(|(f, _)| *f == 35), "{theirs:?}");
    assert!(theirs.iter().all(|(_, d)| d == "left"), "{theirs:?}");
    // RefAV's span runs while the car keeps moving across its lane: from the change's start
    // (frame 20) to its end (frame 50), not beyond.
    let span: Vec<u64> = theirs.iter().map(|(f, _)| *f).collect();
    assert!(span.iter().all(|f| (20..=51).contains(f)), "{span:?}");
    assert!(span.len() >= 20, "{span:?}");
    // Into the oncoming lane (AV2 links it as the left neighbour): RefAV's lane change, not
    // Scenalog's.
    let oncoming = lane_changer(true);
    assert!(turns(&oncoming, "lane_change", "car").is_empty());
    let theirs = turns(&oncoming, "refav_lane_change", "car");
    assert!(theirs.iter().any(|(f, _)| *f == 35), "{theirs:?}");
}

#[test]
fn refav_on_intersection_is_the_bucketed_lane_not_any_lane_under_the_centre() {
    // A road lane from x = 0 to 200 with an intersection lane over x = 95..105 on top of it.
    // A car driving through at 10 m/s has its centre in the intersection lane for 10 frames,
    // fewer than in the road lane, whose bucket wins them: on an intersection in Scenalog's
    // sense, not in RefAV's.
    let road = |b: SceneBuilder| {
        b.straight_lane(1, 0.0, 200.0, -1.75, 1.75).lane(
            2,
            &[[95.0, 1.75], [105.0, 1.75]],
            &[[95.0, -1.75], [105.0, -1.75]],
            &[],
            None,
            None,
            true,
        )
    };
    let through = road(SceneBuilder::new(150))
        .track(
            "car",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 150, 50.0, 0.0, 0.0, 10.0),
        )
        .build();
    let ours = frames_of(&through, "on_intersection", "car");
    assert!(ours.len() >= 9, "{ours:?}");
    assert!(frames_of(&through, "refav_on_intersection", "car").is_empty());
    // Stopped inside the intersection lane for the whole log: both buckets hold every frame,
    // the tie goes to the earlier bucket (lane 1, by id) unless the intersection lane's turn
    // (straight) agrees with the track's yaw rate (0: it does), so RefAV's answer is yes.
    let stopped = road(SceneBuilder::new(30))
        .track(
            "car",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 30, 100.0, 0.0, 0.0, 0.0),
        )
        .build();
    assert_eq!(
        frames_of(&stopped, "refav_on_intersection", "car").len(),
        30
    );
    assert_eq!(frames_of(&stopped, "on_intersection", "car").len(), 30);
}

#[test]
fn refav_near_measures_from_the_egos_box_at_its_rear_axle() {
    // The ego's rear axle at the origin heading +x: its body spans -1.0 m to +3.877 m, RefAV's
    // box (the annotated row, centred on the axle) -2.44 m to +2.44 m. A 0.5 m cone 9 m past
    // the body's front is within 10 m of the body, 10.44 m from RefAV's box; one 10.5 m behind
    // the body's back is 9.06 m from RefAV's box.
    let cone = [0.5, 0.5, 1.0];
    let scene = SceneBuilder::new(5)
        .ego_at_rear_axle(straight(0, 5, 0.0, 0.0, 0.0, 0.0))
        .track(
            "ahead",
            "CONSTRUCTION_CONE",
            cone,
            straight(0, 5, 3.877 + 9.25, 0.0, 0.0, 0.0),
        )
        .track(
            "behind",
            "CONSTRUCTION_CONE",
            cone,
            straight(0, 5, -1.0 - 10.75, 0.0, 0.0, 0.0),
        )
        .build();
    let dist = |name: &str, y: &str| -> Option<f64> {
        rows(&scene, name)
            .iter()
            .find(|r| r[0] == "ego" && r[1] == y && r[2] == 0)
            .and_then(|r| r[3].as_f64())
    };
    let close = |a: Option<f64>, b: f64| a.is_some_and(|a| (a - b).abs() < 1e-4);
    assert!(
        close(dist("near", "ahead"), 9.0),
        "{:?}",
        dist("near", "ahead")
    );
    assert!(
        close(dist("near", "behind"), 10.5),
        "{:?}",
        dist("near", "behind")
    );
    let half = 4.877 / 2.0;
    assert!(
        close(dist("refav_near", "ahead"), 3.877 + 9.0 - half),
        "{:?}",
        dist("refav_near", "ahead")
    );
    assert!(close(dist("refav_near", "behind"), 1.0 + 10.5 - half));
    // Between two other objects the two agree.
    let (a, b) = (
        rows(&scene, "near")
            .iter()
            .filter(|r| r[0] != "ego" && r[1] != "ego")
            .count(),
        rows(&scene, "refav_near")
            .iter()
            .filter(|r| r[0] != "ego" && r[1] != "ego")
            .count(),
    );
    assert_eq!(a, b);
    assert!(a > 0);
}
