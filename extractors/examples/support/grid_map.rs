//! Synthetic maps of many lanes, for measuring how map indexing grows (`examples/map_scale.rs`,
//! `tests/map_scale.rs`).

use scenalog_facts::Scene;
use scenalog_testkit::SceneBuilder;

/// A scene whose map has about `n` lanes in rows of `per_row` lanes, each `length` metres long and
/// 3.5 m wide, along +x: each lane's successor is the next in its row, its left neighbour the lane
/// beside it in the row above and its right neighbour the one below (all one
/// way). Short lanes make long chains of successors within the chain's reach.
pub fn grid_scene(n: usize, per_row: usize, length: f64) -> Scene {
    let rows = n.div_ceil(per_row);
    let id = |r: usize, c: usize| (r * per_row + c) as i64 + 1;
    let mut b = SceneBuilder::new(2);
    for r in 0..rows {
        let (y_right, y_left) = (r as f64 * 3.5, r as f64 * 3.5 + 3.5);
        for c in 0..per_row {
            let (x0, x1) = (c as f64 * length, (c + 1) as f64 * length);
            let succ: Vec<i64> = if c + 1 < per_row {
                vec![id(r, c + 1)]
            } else {
                Vec::new()
            };
            b = b.lane(
                id(r, c),
                &[[x0, y_left], [x1, y_left]],
                &[[x0, y_right], [x1, y_right]],
                &succ,
                (r + 1 < rows).then(|| id(r + 1, c)),
                (r > 0).then(|| id(r - 1, c)),
                false,
            );
        }
    }
    b.build()
}

/// A scene of `n` lanes that all lead into one hub lane (each a successor-less 10 m lane across
/// the hub's start, with the hub as its only successor), and the hub leading on to a row of 10 m
/// lanes: one lane with `n` predecessors.
pub fn hub_scene(n: usize) -> Scene {
    let mut b = SceneBuilder::new(2);
    let hub = 1;
    b = b.lane(
        hub,
        &[[0.0, 3.5], [10.0, 3.5]],
        &[[0.0, 0.0], [10.0, 0.0]],
        &[2],
        None,
        None,
        true,
    );
    b = b.lane(
        2,
        &[[10.0, 3.5], [20.0, 3.5]],
        &[[10.0, 0.0], [20.0, 0.0]],
        &[],
        None,
        None,
        false,
    );
    for i in 0..n {
        let y = i as f64 * 0.01;
        b = b.lane(
            i as i64 + 3,
            &[[-10.0, y + 3.5], [0.0, 3.5]],
            &[[-10.0, y], [0.0, 0.0]],
            &[hub],
            None,
            None,
            false,
        );
    }
    b.build()
}

/// A scene of one row of `n` lanes of 1 mm each (successor to successor): no chain reaches its
/// 60 m within the row's first 60,000 lanes, so only a limit on the chain's segments bounds it.
pub fn tiny_lanes_scene(n: usize) -> Scene {
    let mut b = SceneBuilder::new(2);
    for i in 0..n {
        let (x0, x1) = (i as f64 * 0.001, (i + 1) as f64 * 0.001);
        let succ: Vec<i64> = if i + 1 < n {
            vec![i as i64 + 2]
        } else {
            Vec::new()
        };
        b = b.lane(
            i as i64 + 1,
            &[[x0, 3.5], [x1, 3.5]],
            &[[x0, 0.0], [x1, 0.0]],
            &succ,
            None,
            None,
            false,
        );
    }
    b.build()
}

/// A scene of `n` lanes all over the same 10 m × 3.5 m of road (a corrupt or hostile map):
/// every lane's box overlaps every other's.
pub fn overlapping_scene(n: usize) -> Scene {
    let mut b = SceneBuilder::new(2);
    for i in 0..n {
        b = b.lane(
            i as i64 + 1,
            &[[0.0, 3.5], [10.0, 3.5]],
            &[[0.0, 0.0], [10.0, 0.0]],
            &[],
            None,
            None,
            false,
        );
    }
    b.build()
}
