//! The road's structure: which way a lane turns (`lane_turn`), how many lanes the road has each
//! way (`road_lanes`), where a box sits in its lane (`lane_offset`), the painted line it is over
//! (`over_marking`) and how far it is from the road's edge (`road_edge`).

use scenalog_facts::relation::RelationData;
use scenalog_facts::TrackId;

use super::s;
use crate::cache::Extractor;
use crate::kinematics::TrackKinematics;
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

/// Calls `each(t, k, i, lane)` for every box `i` the query allows whose object has an assigned
/// lane there (`in_lane`'s), `k` the track's kinematics, `lane` the lane's index in the map.
fn boxes_in_lanes(
    ex: &Extractor,
    q: &Query,
    mut each: impl FnMut(TrackId, &TrackKinematics, usize, usize),
) {
    let (kin, lanes) = (ex.kinematics(), ex.lane_indices());
    let n = ex.scene().num_frames();
    for t in q.tracks(ex.scene(), 0) {
        let k = &kin.tracks[t.index()];
        for i in q.box_range(1, n, &k.frames) {
            if let Some(lane) = lanes[t.index()][i] {
                each(t, k, i, lane);
            }
        }
    }
}

/// `lane_offset(X, T, Off, W)`: X's centre measured across its assigned lane: from the centre
/// line (+ left), and the lane's width there (between its two boundaries' lines).
pub fn lane_offset(ex: &Extractor, q: &Query) -> RelationData {
    let index = ex.map_index();
    let mut rows = Vec::new();
    boxes_in_lanes(ex, q, |t, k, i, lane| {
        let (l, c) = (&index.lanes[lane], k.center[i]);
        if let (Some(off), Some(to_left), Some(to_right)) = (
            lateral_offset(&l.centerline, c),
            lateral_offset(&l.left, c),
            lateral_offset(&l.right, c),
        ) {
            rows.push((t, k.frames[i], off, to_right - to_left));
        }
    });
    relation(q, rows)
}

/// `over_marking(X, T, Side, Mark, D)`: how far the farthest corner of X's box lies past each
/// boundary of its assigned lane (square to the boundary's nearest segment), when it does.
pub fn over_marking(ex: &Extractor, q: &Query) -> RelationData {
    let (scene, index) = (ex.scene(), ex.map_index());
    let (left, right) = (s("left"), s("right"));
    let mut rows = Vec::new();
    boxes_in_lanes(ex, q, |t, k, i, lane| {
        let (geom, seg) = (&index.lanes[lane], &scene.map.lanes[lane]);
        let size = scene.track(t).boxes[i].size;
        let corners = box_corners(k.center[i], k.yaw[i], size[0], size[1]);
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
    });
    relation(q, rows)
}

/// `road_edge(X, T, D)`: from X's ground box to the nearest outer edge of the drivable area.
pub fn road_edge(ex: &Extractor, q: &Query) -> RelationData {
    let index = ex.map_index();
    super::map::box_distance(ex, q, |shape, max| index.road_edge_distance(shape, max))
}
