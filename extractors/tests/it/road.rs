//! The road's structure on built scenes whose answers are known by construction (`lane_turn`,
//! `road_lanes`, `lane_offset`, `over_marking`, `road_edge`), and on the real logs.

use std::f64::consts::FRAC_PI_2;

use scenalog_extractors::map::geometry::box_corners;
use scenalog_extractors::{extract, relation_json, Extractor};
use scenalog_facts::relation::{Column, Request};
use scenalog_facts::Scene;
use scenalog_testkit::{sample_scenes, straight, SceneBuilder};
use serde_json::Value as J;

const CAR: [f64; 3] = [4.5, 1.8, 1.5];
const BUS: [f64; 3] = [12.0, 2.6, 3.2];

fn rows(scene: &Scene, name: &str) -> Vec<Vec<J>> {
    let data = extract(scene, &Request::all(name)).expect("extract");
    match relation_json(scene, &data) {
        J::Array(v) => v
            .into_iter()
            .map(|r| r.as_array().cloned().expect("a row"))
            .collect(),
        other => panic!("not an array: {other}"),
    }
}

fn num(v: &J) -> f64 {
    v.as_f64().expect("a number")
}

/// A quarter circle of radius `r` turning left (`sign` 1) or right (-1) from heading +x at the
/// origin, as 10 points.
fn arc(r: f64, sign: f64) -> Vec<[f64; 2]> {
    (0..10)
        .map(|i| {
            let a = FRAC_PI_2 * i as f64 / 9.0;
            [r * a.sin(), sign * r * (1.0 - a.cos())]
        })
        .collect()
}

/// A straight lane, one turning left and one right by 90°, and one bending 30° (straight on).
#[test]
fn lane_turn_classifies_lanes_by_their_heading_change() {
    let bend: Vec<[f64; 2]> = (0..10)
        .map(|i| {
            let a = (30.0f64).to_radians() * i as f64 / 9.0;
            [20.0 * a.sin(), 20.0 * (1.0 - a.cos())]
        })
        .collect();
    // The boundaries 1.75 m either side of each centre line (left is +y before the turn).
    let side = |line: &[[f64; 2]], d: f64| -> Vec<[f64; 2]> {
        line.iter()
            .enumerate()
            .map(|(i, p)| {
                let j = if i + 1 < line.len() { i + 1 } else { i };
                let k = if j == i { i - 1 } else { i };
                let (dx, dy) = (line[j][0] - line[k][0], line[j][1] - line[k][1]);
                let n = dx.hypot(dy);
                [p[0] - dy / n * d, p[1] + dx / n * d]
            })
            .collect()
    };
    let mut b = SceneBuilder::new(5).straight_lane(1, 0.0, 30.0, -1.75, 1.75);
    for (id, line) in [(2, arc(12.0, 1.0)), (3, arc(12.0, -1.0)), (4, bend)] {
        b = b.lane(
            id,
            &side(&line, 1.75),
            &side(&line, -1.75),
            &[],
            None,
            None,
            true,
        );
    }
    let got = rows(&b.build(), "lane_turn");
    let want = [(1, "straight", 0.0), (2, "left", 90.0), (3, "right", -90.0)];
    for (id, dir, a) in want {
        let r = got.iter().find(|r| r[0] == id).expect("a row a lane");
        assert_eq!(r[1], dir, "lane {id}");
        // The end segments' headings, not the tangents: within about one of the 9 steps of 10° (resampled).
        assert!((num(&r[2]) - a).abs() <= 12.0, "lane {id}: {r:?}");
    }
    let bend = got.iter().find(|r| r[0] == 4).expect("the bend");
    assert_eq!(bend[1], "straight", "{bend:?}");
    assert!(num(&bend[2]) > 20.0 && num(&bend[2]) < 30.0, "{bend:?}");
}

/// A road of two lanes east and one west (no neighbour links between them, as many AV2 maps
/// have), a one-way road of one lane, a divided road whose two carriageways are separate
/// drivable areas, and an intersection lane.
#[test]
fn road_lanes_counts_the_lanes_across_the_road() {
    let scene = SceneBuilder::new(5)
        .drivable_area(1, &[[0.0, -7.0], [100.0, -7.0], [100.0, 3.5], [0.0, 3.5]])
        .straight_lane(1, 0.0, 100.0, -7.0, -3.5)
        .straight_lane(2, 0.0, 100.0, -3.5, 0.0)
        .straight_lane(3, 100.0, 0.0, 3.5, 0.0)
        .drivable_area(2, &[[0.0, 50.0], [100.0, 50.0], [100.0, 54.0], [0.0, 54.0]])
        .straight_lane(4, 0.0, 100.0, 50.25, 53.75)
        // Divided: east at y 100..103.5, a 3 m unpaved median, west at y 106.5..110.
        .drivable_area(
            3,
            &[[0.0, 100.0], [100.0, 100.0], [100.0, 103.5], [0.0, 103.5]],
        )
        .drivable_area(
            4,
            &[[0.0, 106.5], [100.0, 106.5], [100.0, 110.0], [0.0, 110.0]],
        )
        .straight_lane(5, 0.0, 100.0, 100.0, 103.5)
        .straight_lane(6, 100.0, 0.0, 110.0, 106.5)
        .lane(
            7,
            &[[200.0, 1.75], [230.0, 1.75]],
            &[[200.0, -1.75], [230.0, -1.75]],
            &[],
            None,
            None,
            true,
        )
        .build();
    let got = rows(&scene, "road_lanes");
    let count = |id: i64| -> Option<(i64, i64)> {
        got.iter()
            .find(|r| r[0] == id)
            .map(|r| (r[1].as_i64().expect("int"), r[2].as_i64().expect("int")))
    };
    assert_eq!(count(1), Some((2, 1)));
    assert_eq!(count(2), Some((2, 1)));
    assert_eq!(count(3), Some((1, 2)));
    assert_eq!(count(4), Some((1, 0)), "one-way");
    assert_eq!(count(5), Some((1, 0)), "a carriageway of a divided road");
    assert_eq!(count(6), Some((1, 0)), "a carriageway of a divided road");
    assert_eq!(
        count(7),
        None,
        "no road runs one way through an intersection"
    );
}

/// Lanes east at y -3.5..0 (left line dashed white, right solid white): a car 0.75 m left of
/// the centre, a bus whose box reaches 0.8 m over the dashed line, and a car in the middle.
fn lane_scene() -> Scene {
    SceneBuilder::new(40)
        .drivable_area(1, &[[-50.0, -7.0], [50.0, -7.0], [50.0, 0.0], [-50.0, 0.0]])
        .drivable_area(2, &[[50.0, -7.0], [150.0, -7.0], [150.0, 0.0], [50.0, 0.0]])
        .straight_lane(1, -50.0, 150.0, -3.5, 0.0)
        .straight_lane(2, -50.0, 150.0, -7.0, -3.5)
        .track(
            "offset",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 40, 0.0, -1.0, 0.0, 5.0),
        )
        .track("bus", "BUS", BUS, straight(0, 40, 0.0, -0.5, 0.0, 5.0))
        .track(
            "middle",
            "REGULAR_VEHICLE",
            CAR,
            straight(0, 40, 30.0, -5.25, 0.0, 5.0),
        )
        .track(
            "walker",
            "PEDESTRIAN",
            [0.5, 0.5, 1.7],
            straight(0, 40, 40.0, -9.0, 0.0, 0.0),
        )
        .build()
}

fn values_of(got: &[Vec<J>], track: &str, col: usize) -> Vec<f64> {
    got.iter()
        .filter(|r| r[0] == track)
        .map(|r| num(&r[col]))
        .collect()
}

#[test]
fn lane_offset_measures_from_the_centre_line() {
    let got = rows(&lane_scene(), "lane_offset");
    let off = values_of(&got, "offset", 2);
    assert_eq!(off.len(), 40);
    assert!(off.iter().all(|o| (o - 0.75).abs() < 1e-6), "{off:?}");
    assert!(values_of(&got, "offset", 3)
        .iter()
        .all(|w| (w - 3.5).abs() < 1e-6));
    let middle = values_of(&got, "middle", 2);
    assert!(middle.iter().all(|o| o.abs() < 1e-6), "{middle:?}");
    assert!(values_of(&got, "walker", 2).is_empty(), "not in a lane");
}

#[test]
fn over_marking_names_the_line_a_box_is_over_and_how_far() {
    let got = rows(&lane_scene(), "over_marking");
    let bus: Vec<&Vec<J>> = got.iter().filter(|r| r[0] == "bus").collect();
    assert_eq!(bus.len(), 40, "{bus:?}");
    for r in bus {
        assert_eq!((&r[2], &r[3]), (&J::from("left"), &J::from("DASHED_WHITE")));
        assert!((num(&r[4]) - 0.8).abs() < 1e-6, "{r:?}");
    }
    for track in ["offset", "middle", "walker"] {
        assert!(values_of(&got, track, 4).is_empty(), "{track}");
    }
}

/// The road (two tiles meeting at x = 50) is bounded by y = -7 and y = 0: the car in the middle
/// of the right lane is 0.85 m from the kerb all the way, also where it drives over the tiles'
/// shared edge (x 30 to 50), which is no kerb; the pedestrian is 1.75 m off the road, the bus
/// over its edge.
#[test]
fn road_edge_measures_to_the_kerb_not_between_tiles() {
    let got = rows(&lane_scene(), "road_edge");
    let d = |t: &str| values_of(&got, t, 2);
    assert!(
        d("middle").iter().all(|v| (v - 0.85).abs() < 1e-6),
        "{:?}",
        d("middle")
    );
    assert!(
        d("walker").iter().all(|v| (v - 1.75).abs() < 1e-6),
        "{:?}",
        d("walker")
    );
    assert!(d("bus").iter().all(|&v| v == 0.0), "{:?}", d("bus"));
    // The car 0.75 m left of its lane's centre (y = -1): its left side at y = -0.1.
    assert!(
        d("offset").iter().all(|v| (v - 0.1).abs() < 1e-6),
        "{:?}",
        d("offset")
    );
}

/// On the real logs: almost every `lane_offset` lies within its lane's half width plus a little
/// (the centre is in the lane), `over_marking` distances are positive,
/// side, a box `road_edge` puts away from every edge lies wholly on the drivable area or wholly
/// off it, and every lane outside intersections has a count.
#[test]
fn road_relations_agree_with_the_map_on_the_real_logs() {
    for scene in sample_scenes() {
        let ex = Extractor::new(scene);
        let off = ex
            .extract(&Request::all("lane_offset"))
            .expect("lane_offset");
        let (Column::Float(o), Column::Float(w)) = (&off.columns[2], &off.columns[3]) else {
            panic!("lane_offset columns")
        };
        assert!(!o.is_empty(), "{}", scene.log_id);
        let outside = o
            .iter()
            .zip(w)
            .filter(|(o, w)| o.abs() > 0.5 * **w + 0.5)
            .count();
        // The centre is in the lane; a curved lane's boundary lines may tilt off the centre line.
        assert!(
            outside * 100 < o.len(),
            "{}: {outside} of {}",
            scene.log_id,
            o.len()
        );
        let marks = ex
            .extract(&Request::all("over_marking"))
            .expect("over_marking");
        let Column::Float(d) = &marks.columns[4] else {
            panic!("over_marking columns")
        };
        assert!(
            !d.is_empty() && d.iter().all(|&d| d > 0.0),
            "{}",
            scene.log_id
        );
        let lanes = ex.extract(&Request::all("road_lanes")).expect("road_lanes");
        let plain = scene
            .map
            .lanes
            .iter()
            .filter(|l| !l.is_intersection)
            .count();
        assert_eq!(lanes.len(), plain, "{}", scene.log_id);
        let edge = ex.extract(&Request::all("road_edge")).expect("road_edge");
        let Column::Float(e) = &edge.columns[2] else {
            panic!("road_edge columns")
        };
        assert!(e.iter().all(|&e| (0.0..=50.0).contains(&e)));
        // A box at some distance from every edge lies wholly on the road or wholly off it.
        let (Column::Track(xs), Column::Time(ts)) = (&edge.columns[0], &edge.columns[1]) else {
            panic!("road_edge columns")
        };
        let index = ex.map_index();
        let mut checked = 0;
        for i in (0..e.len()).step_by(7).filter(|&i| e[i] > 0.05) {
            let b = scene.track(xs[i]).box_at(ts[i]).expect("a box");
            let c = b.city_center();
            let corners = box_corners([c.x, c.y], b.city_yaw(), b.size[0], b.size[1]);
            let on: Vec<bool> = corners.iter().map(|&p| index.in_drivable_area(p)).collect();
            assert!(
                on.iter().all(|&x| x == on[0]),
                "{}: row {i} at {} m from the edge: {on:?}",
                scene.log_id,
                e[i]
            );
            checked += 1;
        }
        assert!(checked > 100, "{}: {checked}", scene.log_id);
        println!(
            "{}: lane_offset {}, over_marking {}, road_lanes {}, road_edge {}",
            scene.log_id,
            o.len(),
            d.len(),
            lanes.len(),
            e.len()
        );
    }
}
