//! The road's structure: which way a lane turns (`lane_turn`), how many lanes the road has each
//! way (`road_lanes`), where a box sits in its lane (`lane_offset`), the painted line it is over
//! (`over_marking`) and how far it is from the road's edge (`road_edge`).

use scenalog_facts::relation::RelationData;

use super::s;
use crate::cache::Extractor;
use crate::map::cross_section::lanes_across;
use crate::map::geometry::{box_corners, lateral_offset};
use crate::query::Query;
use crate::rows::relation;
use crate::thresholds::LANE_TURN_CLASS_DEG;

/// `lane_turn(L, Dir, A)`: each lane's heading change from its start to its end, "left" or
/// "right" past [`LANE_TURN_CLASS_DEG`], "straight" otherwise.
pub fn lane_turn(ex: &Extractor, q: &Query) -> RelationData {
    let (left, right, straight) = (s("left"), s("right"), s("straight"));
    let rows = ex.map_index().lanes.iter().map(|l| {
        let dir = if l.turn_deg > LANE_TURN_CLASS_DEG {
            &left
        } else if l.turn_deg < -LANE_TURN_CLASS_DEG {
            &right
        } else {
            &straight
        };
        (l.id, dir.clone(), l.turn_deg)
    });
    relation(q, rows.collect::<Vec<_>>())
}

/// `road_lanes(L, Same, Opposite)`: the lanes across the road at L's middle
/// ([`crate::map::cross_section`]); intersection lanes have none.
pub fn road_lanes(ex: &Extractor, q: &Query) -> RelationData {
    let index = ex.map_index();
    let is_intersection: Vec<bool> = ex
        .scene()
        .map
        .lanes
        .iter()
        .map(|l| l.is_intersection)
        .collect();
    let rows = (0..index.lanes.len()).filter_map(|i| {
        let (same, opposite) = lanes_across(index, i, &is_intersection)?;
        Some((index.lanes[i].id, same, opposite))
    });
    relation(q, rows.collect::<Vec<_>>())
}

/// `lane_offset(X, T, Off, W)`: X's centre measured across its assigned lane: from the centre
/// line (+ left), and the lane's width there (between its two boundaries' lines).
pub fn lane_offset(ex: &Extractor, q: &Query) -> RelationData {
    let (kin, index, lanes) = (ex.kinematics(), ex.map_index(), ex.lane_indices());
    let n = ex.scene().num_frames();
    let mut rows = Vec::new();
    for t in q.tracks(ex.scene(), 0) {
        let k = &kin.tracks[t.index()];
        for i in q.box_range(1, n, &k.frames) {
            let Some(l) = lanes[t.index()][i].map(|l| &index.lanes[l]) else {
                continue;
            };
            let c = k.center[i];
            let (Some(off), Some(to_left), Some(to_right)) = (
                lateral_offset(&l.centerline, c),
                lateral_offset(&l.left, c),
                lateral_offset(&l.right, c),
            ) else {
                continue;
            };
            rows.push((t, k.frames[i], off, to_right - to_left));
        }
    }
    relation(q, rows)
}

/// `over_marking(X, T, Side, Mark, D)`: how far the farthest corner of X's box lies past each
/// boundary of its assigned lane (square to the boundary's nearest segment), when it does.
pub fn over_marking(ex: &Extractor, q: &Query) -> RelationData {
    let (scene, kin, index, lanes) = (
        ex.scene(),
        ex.kinematics(),
        ex.map_index(),
        ex.lane_indices(),
    );
    let n = scene.num_frames();
    let (left, right) = (s("left"), s("right"));
    let mut rows = Vec::new();
    for t in q.tracks(scene, 0) {
        let k = &kin.tracks[t.index()];
        let boxes = &scene.track(t).boxes;
        for i in q.box_range(1, n, &k.frames) {
            let Some(li) = lanes[t.index()][i] else {
                continue;
            };
            let (geom, seg) = (&index.lanes[li], &scene.map.lanes[li]);
            let corners = box_corners(k.center[i], k.yaw[i], boxes[i].size[0], boxes[i].size[1]);
            // Past the left boundary is its left (+), past the right one its right (-).
            let past = |line: &[[f64; 2]], sign: f64| {
                corners
                    .iter()
                    .filter_map(|&c| lateral_offset(line, c))
                    .map(|o| sign * o)
                    .fold(f64::NEG_INFINITY, f64::max)
            };
            for (side, line, sign, mark) in [
                (&left, &geom.left, 1.0, &seg.left_mark_type),
                (&right, &geom.right, -1.0, &seg.right_mark_type),
            ] {
                let d = past(line, sign);
                if d > 0.0 {
                    rows.push((t, k.frames[i], side.clone(), s(mark), d));
                }
            }
        }
    }
    relation(q, rows)
}

/// `road_edge(X, T, D)`: from X's ground box to the nearest outer edge of the drivable area.
pub fn road_edge(ex: &Extractor, q: &Query) -> RelationData {
    let index = ex.map_index();
    super::map::box_distance(ex, q, |shape, max| index.road_edge_distance(shape, max))
}
