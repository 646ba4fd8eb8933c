//! Lane chains (the lane as a driver sees it) and road sides on synthetic maps.

use scenalog_extractors::map::{MapIndex, RoadSide};
use scenalog_facts::LaneId;
use scenalog_testkit::SceneBuilder;

fn ids(v: &[LaneId]) -> Vec<i64> {
    v.iter().map(|l| l.0).collect()
}

#[test]
fn chain_goes_straight_through_an_intersection() {
    // 1 -> 2 -> {3 straight, 4 left turn, 5 right turn}; 3 -> 6. Lane 7 is unconnected.
    let quarter = |cx: f64, cy: f64, r: f64, from: f64, to: f64| -> Vec<[f64; 2]> {
        (0..=8)
            .map(|k| {
                let a = from + (to - from) * k as f64 / 8.0;
                [cx + r * a.cos(), cy + r * a.sin()]
            })
            .collect()
    };
    use std::f64::consts::FRAC_PI_2 as H;
    let scene = SceneBuilder::new(1)
        .lane(
            1,
            &[[0.0, 3.5], [30.0, 3.5]],
            &[[0.0, 0.0], [30.0, 0.0]],
            &[2],
            None,
            None,
            false,
        )
        .lane(
            2,
            &[[30.0, 3.5], [60.0, 3.5]],
            &[[30.0, 0.0], [60.0, 0.0]],
            &[3, 4, 5, 99],
            None,
            None,
            false,
        )
        .lane(
            3,
            &[[60.0, 3.5], [80.0, 3.5]],
            &[[60.0, 0.0], [80.0, 0.0]],
            &[6],
            None,
            None,
            true,
        )
        // Left turn about (60, 13.5): from heading +x to heading +y.
        .lane(
            4,
            &quarter(60.0, 13.5, 10.0, -H, 0.0),
            &quarter(60.0, 13.5, 13.5, -H, 0.0),
            &[],
            None,
            None,
            true,
        )
        // Right turn about (60, -10): from heading +x to heading -y.
        .lane(
            5,
            &quarter(60.0, -10.0, 13.5, H, 0.0),
            &quarter(60.0, -10.0, 10.0, H, 0.0),
            &[],
            None,
            None,
            true,
        )
        .lane(
            6,
            &[[80.0, 3.5], [120.0, 3.5]],
            &[[80.0, 0.0], [120.0, 0.0]],
            &[],
            None,
            None,
            false,
        )
        .straight_lane(7, 0.0, 10.0, 50.0, 53.5)
        .build();
    let index = MapIndex::new(&scene.map);
    let at = |id: i64| scene.map.lane_index(LaneId(id)).expect("lane");
    assert!(index.lanes[at(4)].turn_deg > 70.0 && index.lanes[at(5)].turn_deg < -70.0);
    assert_eq!(ids(index.chains.chain(at(2))), vec![1, 2, 3, 6]);
    assert_eq!(ids(index.chains.chain(at(1))), vec![1, 2, 3, 6]);
    assert_eq!(ids(index.chains.ahead(at(2))), vec![3, 6]);
    assert_eq!(ids(index.chains.behind(at(3))), vec![1, 2]);
    // A turn lane's chain continues back through its only predecessor, not into the other turns.
    assert_eq!(ids(index.chains.chain(at(4))), vec![1, 2, 4]);
    assert_eq!(ids(index.chains.chain(at(7))), vec![7]);
    // Predecessors are derived from successors (AV2 files leave them empty).
    assert_eq!(index.lanes[at(3)].predecessors, vec![at(2)]);
}

#[test]
fn road_sides_follow_the_shared_boundary() {
    // 1 (right) and 2 (left) run +x; 3 runs -x beyond 2's left boundary; 4 runs -x next to 3.
    let scene = SceneBuilder::new(1)
        .lane(
            1,
            &[[0.0, 3.5], [50.0, 3.5]],
            &[[0.0, 0.0], [50.0, 0.0]],
            &[],
            Some(2),
            None,
            false,
        )
        .lane(
            2,
            &[[0.0, 7.0], [50.0, 7.0]],
            &[[0.0, 3.5], [50.0, 3.5]],
            &[],
            Some(3),
            Some(1),
            false,
        )
        .lane(
            3,
            &[[50.0, 7.0], [0.0, 7.0]],
            &[[50.0, 10.5], [0.0, 10.5]],
            &[],
            Some(2),
            Some(4),
            false,
        )
        .lane(
            4,
            &[[50.0, 10.5], [0.0, 10.5]],
            &[[50.0, 14.0], [0.0, 14.0]],
            &[],
            Some(3),
            None,
            false,
        )
        .straight_lane(5, 0.0, 10.0, 50.0, 53.5)
        .build();
    let index = MapIndex::new(&scene.map);
    let at = |id: i64| scene.map.lane_index(LaneId(id)).expect("lane");
    assert_eq!(index.sides.side(at(1), at(2)), Some(RoadSide::Same));
    assert_eq!(index.sides.side(at(1), at(1)), Some(RoadSide::Same));
    assert_eq!(index.sides.side(at(1), at(3)), Some(RoadSide::Opposite));
    assert_eq!(index.sides.side(at(4), at(1)), Some(RoadSide::Opposite));
    assert_eq!(index.sides.side(at(3), at(4)), Some(RoadSide::Same));
    assert_eq!(index.sides.side(at(1), at(5)), None);
    assert_eq!(ids(&index.sides.same_side(at(2))), vec![1, 2]);
    assert_eq!(ids(&index.sides.opposite_side(at(1))), vec![3, 4]);
}
