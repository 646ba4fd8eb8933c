//! The relations for concepts descriptions name (issue #14): `towing`, `in_between`,
//! `lane_direction` and the "CONSTRUCTION" super-category of `category`, on small synthetic
//! scenes whose answer is known by construction: each with a staged positive case and near-misses
//! that break one condition (a threshold just crossed, the wrong category, the wrong side).

use std::f64::consts::FRAC_PI_2;

use scenalog_extractors::Extractor;
use scenalog_facts::relation::{Constraint, Request, Value};
use scenalog_facts::Scene;
use scenalog_testkit::{straight, SceneBuilder, Waypoint};

const CAR: [f64; 3] = [4.5, 1.8, 1.5];
const CAB: [f64; 3] = [6.0, 2.5, 3.0];
const TRAILER: [f64; 3] = [12.0, 2.5, 4.0];
const PED: [f64; 3] = [0.6, 0.6, 1.7];
const CONE: [f64; 3] = [0.4, 0.4, 0.7];
const FRAMES: u32 = 10;

/// One track of a test scene: uuid, category, size, waypoints.
type Spec<'a> = (&'a str, &'a str, [f64; 3], Vec<Waypoint>);

/// `b` with the ego parked far from everything and the given tracks.
fn with_tracks(b: SceneBuilder, tracks: &[Spec]) -> Scene {
    let ego = straight(0, FRAMES, 500.0, 500.0, 0.0, 0.0);
    let mut b = b.track("ego", "EGO_VEHICLE", CAR, ego);
    for (uuid, cat, size, way) in tracks {
        b = b.track(uuid, cat, *size, way.clone());
    }
    b.build()
}

/// A scene without a map, with the given tracks.
fn scene(tracks: &[Spec]) -> Scene {
    with_tracks(SceneBuilder::new(FRAMES as usize), tracks)
}

/// An object standing at (x, y) with heading `yaw` for the whole scene.
fn still(x: f64, y: f64, yaw: f64) -> Vec<Waypoint> {
    straight(0, FRAMES, x, y, yaw, 0.0)
}

/// The rows of `name` under `constraints`, tracks as uuids and other values as text.
fn rows_with(s: &Scene, name: &str, constraints: Vec<(usize, Constraint)>) -> Vec<Vec<String>> {
    let req = Request {
        name: name.into(),
        constraints,
    };
    let data = Extractor::new(s)
        .extract_uncached(&req)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    (0..data.len())
        .map(|i| {
            data.row(i)
                .expect("row in range")
                .iter()
                .map(|v| match v {
                    Value::Track(t) => s.track(*t).uuid.clone(),
                    Value::Time(t) => t.to_string(),
                    Value::Str(x) => x.to_string(),
                    other => format!("{other:?}"),
                })
                .collect()
        })
        .collect()
}

fn rows(s: &Scene, name: &str) -> Vec<Vec<String>> {
    rows_with(s, name, Vec::new())
}

/// The distinct leading columns (all but the time and what follows it) of `rows`.
fn keys(rows: &[Vec<String>], width: usize) -> Vec<Vec<String>> {
    let mut k: Vec<Vec<String>> = rows.iter().map(|r| r[..width].to_vec()).collect();
    k.dedup();
    k
}

fn v(items: &[&str]) -> Vec<String> {
    items.iter().map(|s| s.to_string()).collect()
}

// ---- towing ------------------------------------------------------------------------------------

/// A cab driving +x at 10 m/s from x = 20, and a trailer whose centre is `back` m behind the
/// cab's centre and `side` m to its left, heading `yaw`, moving with it.
fn rig(trailer_category: &str, back: f64, side: f64, yaw: f64) -> Scene {
    let trailer: Vec<Waypoint> = straight(0, FRAMES, 20.0, 0.0, 0.0, 10.0)
        .into_iter()
        .map(|(f, x, y, _)| (f, x - back, y + side, yaw))
        .collect();
    scene(&[
        (
            "cab",
            "TRUCK_CAB",
            CAB,
            straight(0, FRAMES, 20.0, 0.0, 0.0, 10.0),
        ),
        ("trailer", trailer_category, TRAILER, trailer),
    ])
}

#[test]
fn towing_pairs_a_cab_with_the_trailer_hanging_behind_it() {
    // Cab rear at -3, a 0.5 m gap, the trailer's front at -3.5 and its centre at -9.5.
    let s = rig("VEHICULAR_TRAILER", 9.5, 0.0, 0.0);
    let r = rows(&s, "towing");
    assert_eq!(r.len(), FRAMES as usize, "{r:?}");
    assert_eq!(keys(&r, 2), vec![v(&["cab", "trailer"])]);
    // Swung out behind a cab turning left: the trailer 40° to the right of the cab, its centre
    // 1.95 m outside the cab's left side and its front at the cab's rear, still in tow.
    let r = rows(&s_swung(1.25 + 1.95, (-40f64).to_radians()), "towing");
    assert_eq!(keys(&r, 2), vec![v(&["cab", "trailer"])]);
    // The category is pushed down: a "VEHICULAR_TRAILER" constraint on Y keeps it, "BUS" on X not.
    let only = rows_with(
        &s,
        "towing",
        vec![(1, Constraint::Category("VEHICULAR_TRAILER".into()))],
    );
    assert_eq!(only.len(), FRAMES as usize);
    assert!(rows_with(&s, "towing", vec![(0, Constraint::Category("BUS".into()))]).is_empty());
}

fn s_swung(side: f64, yaw: f64) -> Scene {
    rig("VEHICULAR_TRAILER", 9.5, side, yaw)
}

#[test]
fn towing_near_misses_find_nothing() {
    // A gap of 3.5 m (> 3): the trailer stands behind, it is not hitched.
    assert!(rows(&rig("VEHICULAR_TRAILER", 13.0, 0.0, 0.0), "towing").is_empty());
    // The same box, but a car: only trailers are towed.
    assert!(rows(&rig("REGULAR_VEHICLE", 9.5, 0.0, 0.0), "towing").is_empty());
    // 2.05 m outside the cab's side (> 2), the gap under 1 m.
    assert!(rows(&s_swung(1.25 + 2.05, 0.0), "towing").is_empty());
    // Across the cab's rear (90° > 60°), 0.5 m behind it.
    assert!(rows(
        &rig("VEHICULAR_TRAILER", 3.0 + 0.5 + 1.25, 0.0, FRAC_PI_2),
        "towing"
    )
    .is_empty());
    // In front of the cab: the cab does not tow it (nor does it tow the cab, a truck).
    assert!(rows(&rig("VEHICULAR_TRAILER", -9.5, 0.0, 0.0), "towing").is_empty());
}

// ---- in_between --------------------------------------------------------------------------------

/// A pedestrian at the origin and two cars at `a` and `b`.
fn trio(a: [f64; 2], b: [f64; 2]) -> Scene {
    scene(&[
        ("ped", "PEDESTRIAN", PED, still(0.0, 0.0, 0.0)),
        ("a", "REGULAR_VEHICLE", CAR, still(a[0], a[1], 0.0)),
        ("b", "REGULAR_VEHICLE", CAR, still(b[0], b[1], 0.0)),
    ])
}

#[test]
fn in_between_finds_a_pedestrian_between_two_cars_in_both_orders() {
    let r = rows(&trio([0.0, 3.0], [0.0, -3.0]), "in_between");
    assert_eq!(r.len(), 2 * FRAMES as usize, "{r:?}");
    let mut k = keys(&r, 3);
    k.sort();
    k.dedup();
    assert_eq!(k, vec![v(&["ped", "a", "b"]), v(&["ped", "b", "a"])]);
    // 1.9 m off the segment joining the cars (<= 2) still counts.
    let r = rows(&trio([1.9, 3.0], [1.9, -3.0]), "in_between");
    assert_eq!(r.len(), 2 * FRAMES as usize);
    // Pushdown: Y fixed to car a.
    let s = trio([0.0, 3.0], [0.0, -3.0]);
    let a = s.track_by_uuid("a").expect("track a").id;
    let r = rows_with(&s, "in_between", vec![(1, Constraint::Eq(Value::Track(a)))]);
    assert_eq!(keys(&r, 3), vec![v(&["ped", "a", "b"])]);
}

#[test]
fn in_between_near_misses_find_nothing() {
    // Both cars on the same side of the pedestrian.
    assert!(rows(&trio([-2.5, 3.0], [2.5, 3.0]), "in_between").is_empty());
    // 2.5 m off the segment joining the cars (> 2).
    assert!(rows(&trio([2.5, 3.0], [2.5, -3.0]), "in_between").is_empty());
    // One car 5.8 m away box to box (> 5).
    assert!(rows(&trio([0.0, 3.0], [0.0, -7.0]), "in_between").is_empty());
}

// ---- lane_direction ----------------------------------------------------------------------------

/// Lane 1 along +x (x 0..100, y 0..3.5) and the given tracks.
fn road(tracks: &[Spec]) -> Scene {
    let b = SceneBuilder::new(FRAMES as usize).straight_lane(1, 0.0, 100.0, 0.0, 3.5);
    with_tracks(b, tracks)
}

/// The distinct (uuid, Rel) of `lane_direction` on `s`.
fn directions(s: &Scene) -> Vec<Vec<String>> {
    let mut k: Vec<Vec<String>> = rows(s, "lane_direction")
        .into_iter()
        .map(|r| vec![r[0].clone(), r[2].clone()])
        .collect();
    k.sort();
    k.dedup();
    k
}

#[test]
fn lane_direction_tells_with_from_against_traffic() {
    let s = road(&[
        (
            "with",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, FRAMES, 20.0, 1.75, 0.0, 10.0),
        ),
        (
            "against",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, FRAMES, 80.0, 1.75, std::f64::consts::PI, 10.0),
        ),
        // Slow and parked facing the wrong way: its box heading counts.
        (
            "parked",
            "REGULAR_VEHICLE",
            CAR,
            still(50.0, 1.75, std::f64::consts::PI),
        ),
        // 44° and 46° to the lane at 2 m/s: the "same" threshold is 45°.
        (
            "d44",
            "BICYCLIST",
            PED,
            straight(0, FRAMES, 30.0, 0.5, 44f64.to_radians(), 2.0),
        ),
        (
            "d46",
            "BICYCLIST",
            PED,
            straight(0, FRAMES, 60.0, 0.5, 46f64.to_radians(), 2.0),
        ),
        // A cone has no direction of travel; a car off the road has no lane.
        ("cone", "CONSTRUCTION_CONE", CONE, still(40.0, 1.75, 0.0)),
        (
            "off",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, FRAMES, 20.0, 20.0, 0.0, 10.0),
        ),
    ]);
    assert_eq!(
        directions(&s),
        vec![
            v(&["against", "opposite"]),
            v(&["d44", "same"]),
            v(&["d46", "perpendicular"]),
            v(&["parked", "opposite"]),
            v(&["with", "same"]),
        ]
    );
    // The Rel column is pushed down.
    let r = rows_with(
        &s,
        "lane_direction",
        vec![(2, Constraint::Eq(Value::Str("opposite".into())))],
    );
    assert!(
        r.iter().all(|r| r[2] == "opposite") && r.len() == 2 * FRAMES as usize,
        "{r:?}"
    );
}

// ---- the CONSTRUCTION super-category ---------------------------------------------------------

#[test]
fn construction_is_a_super_category_of_road_works_objects() {
    let s = scene(&[
        ("cone", "CONSTRUCTION_CONE", CONE, still(0.0, 0.0, 0.0)),
        ("barrel", "CONSTRUCTION_BARREL", CONE, still(2.0, 0.0, 0.0)),
        ("board", "MESSAGE_BOARD_TRAILER", CAR, still(6.0, 0.0, 0.0)),
        ("sign", "SIGN", CONE, still(9.0, 0.0, 0.0)),
        ("bollard", "BOLLARD", CONE, still(11.0, 0.0, 0.0)),
    ]);
    let construction = rows_with(
        &s,
        "category",
        vec![(1, Constraint::Eq(Value::Str("CONSTRUCTION".into())))],
    );
    let mut got: Vec<&str> = construction.iter().map(|r| r[0].as_str()).collect();
    got.sort_unstable();
    assert_eq!(got, ["barrel", "board", "cone"]);
    // As a category constraint pushed into a pair relation.
    let near = rows_with(
        &s,
        "near",
        vec![(0, Constraint::Category("CONSTRUCTION".into()))],
    );
    assert!(!near.is_empty());
    assert!(near
        .iter()
        .all(|r| ["cone", "barrel", "board"].contains(&r[0].as_str())));
}
