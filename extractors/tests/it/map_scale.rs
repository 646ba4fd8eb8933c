//! Map indexing grows near-linearly with the number of lanes: doubling a synthetic map
//! (`examples/support/grid_map.rs`: rows of 1 m lanes, one lane with thousands of predecessors, a
//! row of 1 mm lanes, lanes all over one stretch of road) about doubles the time of `MapIndex::new`. The ratio is asserted, not the times: a pairwise step
//! makes it about 4, linear about 2, and the bound of 3 leaves room for a busy machine.

use std::time::{Duration, Instant};

use scenalog_extractors::map::MapIndex;
use scenalog_facts::Scene;

#[path = "../../examples/support/grid_map.rs"]
mod grid_map;

/// The fastest of three builds of the map of `scene` (the least disturbed by other work), and
/// the index of the last.
fn fastest(scene: &scenalog_facts::Scene) -> (Duration, MapIndex) {
    let mut best = Duration::MAX;
    let mut index = MapIndex::new(&scene.map);
    for _ in 0..3 {
        let t = Instant::now();
        index = MapIndex::new(&scene.map);
        best = best.min(t.elapsed());
    }
    (best, index)
}

/// The ratio of the fastest build of the map of `2n` lanes to that of `n`, and both indexes.
fn doubling(make: fn(usize) -> Scene, n: usize) -> (f64, MapIndex, MapIndex) {
    let (small, big) = (make(n), make(2 * n));
    let (mut t1, i1) = fastest(&small);
    let (mut t2, i2) = fastest(&big);
    // A measurement disturbed by other work is taken again, up to three times: a linear build
    // doubles every time, a pairwise one quadruples every time.
    for _ in 0..2 {
        if t2.as_secs_f64() < 3.0 * t1.as_secs_f64() {
            break;
        }
        t1 = t1.min(fastest(&small).0);
        t2 = t2.min(fastest(&big).0);
    }
    (t2.as_secs_f64() / t1.as_secs_f64().max(1e-9), i1, i2)
}

fn assert_linear(name: &str, ratio: f64) {
    assert!(
        ratio < 3.0,
        "{name}: indexing twice the lanes took {ratio:.2} times as long (linear: about 2)"
    );
}

#[test]
fn map_indexing_time_about_doubles_with_the_lanes() {
    // Rows of 1 m lanes: every lane's chain is 60 lanes long each way.
    let (ratio, i1, i2) = doubling(|n| grid_map::grid_scene(n, 1_000, 1.0), 4_000);
    assert_linear("grid", ratio);
    // The indexes are real: every lane has its chain (60 m of 1 m lanes each way, cut at the
    // ends of its row) and its road-side group.
    assert_eq!(i1.lanes.len(), 4_000);
    assert_eq!(i2.lanes.len(), 8_000);
    let middle = 500; // row 0, lane 500: 60 behind, itself, 60 ahead
    assert_eq!(i2.chains.chain(middle).len(), 121);
    assert_eq!(i2.chains.behind(middle).len(), 60);
    // Neighbours link the lanes side by side across the rows: one same-side group per column.
    assert_eq!(i1.sides.members.len(), 1_000);
    assert!(i1.sides.members.iter().all(|g| g.len() == 4));
    assert!(i2.sides.members.iter().all(|g| g.len() == 8));

    // One lane with thousands of predecessors.
    let (ratio, _, hub) = doubling(grid_map::hub_scene, 4_000);
    assert_linear("hub", ratio);
    assert_eq!(hub.lanes[0].predecessors.len(), 8_000);

    // A row of 1 mm lanes: chains cut at their most segments, not the row's length.
    let (ratio, _, tiny) = doubling(grid_map::tiny_lanes_scene, 4_000);
    assert_linear("tiny", ratio);
    let most = scenalog_extractors::thresholds::LANE_CHAIN_MAX_SEGMENTS;
    assert_eq!(tiny.chains.chain(4_000).len(), 2 * most + 1);
    assert_eq!(tiny.chains.ahead(4_000).len(), most);

    // Every lane over the same stretch of road (issue #42): still linear.
    let (ratio, _, _) = doubling(grid_map::overlapping_scene, 4_000);
    assert_linear("overlap", ratio);
}
