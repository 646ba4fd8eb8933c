//! Stop signs: each STOP_SIGN track's lane, and whether an object stands before it facing it.
//!
//! A stop sign's lane is the nearest non-intersection lane within [`STOP_SIGN_LANE_SEARCH_M`] of the
//! sign (its mean annotated centre; signs do not move) such that the sign stands on the lane's
//! right-hand side or over it, and the lane ends (its stop line) within
//! [`STOP_SIGN_LANE_SEARCH_M`] past the sign. An object X is `at_stop_sign` at T when its assigned
//! lane is the sign's lane or one of the lanes behind it in the lane chain, the sign lies
//! 0..[`STOP_SIGN_FORWARD_MAX_M`] ahead of X's centre along X's heading and at most
//! [`STOP_SIGN_LATERAL_MAX_M`] to its side, and X's heading is within [`STOP_SIGN_HEADING_MAX_DEG`]
//! of the lane's direction at the sign (X faces the sign rather than driving away from it).

use scenalog_facts::{LaneType, Scene, TrackId, VectorMap};

use super::geometry::{heading, nearest_on_polyline, polyline_length, Pt};
use super::index::MapIndex;
use crate::kinematics::{wrap_angle, Kinematics};
use crate::thresholds::{
    STOP_SIGN_FORWARD_MAX_M, STOP_SIGN_HEADING_MAX_DEG, STOP_SIGN_LANE_SEARCH_M,
    STOP_SIGN_LATERAL_MAX_M,
};

/// The category of stop-sign tracks.
pub const STOP_SIGN_CATEGORY: &str = "STOP_SIGN";

/// A stop sign with its lane.
#[derive(Debug, Clone, PartialEq)]
pub struct StopSign {
    /// The sign's track.
    pub track: TrackId,
    /// Its position (mean annotated centre), city frame.
    pub pos: Pt,
    /// Index of its lane in the map's lanes.
    pub lane: usize,
    /// The lane's direction of travel at the sign, radians.
    pub lane_heading: f64,
    /// The lane and the lanes behind it in its chain (lane indices), ascending.
    pub approach: Vec<usize>,
}

/// Finds every stop sign's lane; signs without a lane are left out.
pub fn stop_signs(scene: &Scene, kin: &Kinematics, index: &MapIndex) -> Vec<StopSign> {
    let mut out = Vec::new();
    for t in &scene.tracks {
        if t.category != STOP_SIGN_CATEGORY {
            continue;
        }
        let Some(k) = kin.tracks.get(t.id.index()) else {
            continue;
        };
        if k.center.is_empty() {
            continue;
        }
        let m = k.center.len() as f64;
        let pos = [
            k.center.iter().map(|c| c[0]).sum::<f64>() / m,
            k.center.iter().map(|c| c[1]).sum::<f64>() / m,
        ];
        if let Some((lane, lane_heading)) = sign_lane(&scene.map, index, pos) {
            let mut approach: Vec<usize> = index
                .chains
                .behind(lane)
                .iter()
                .filter_map(|&id| scene.map.lane_index(id))
                .collect();
            approach.push(lane);
            approach.sort_unstable();
            approach.dedup();
            out.push(StopSign {
                track: t.id,
                pos,
                lane,
                lane_heading,
                approach,
            });
        }
    }
    out
}

/// The lane a sign at `pos` governs, with the lane's heading at the sign.
fn sign_lane(map: &VectorMap, index: &MapIndex, pos: Pt) -> Option<(usize, f64)> {
    let mut best: Option<(f64, usize, f64)> = None;
    for i in index.lanes_near(pos, STOP_SIGN_LANE_SEARCH_M) {
        let seg = &map.lanes[i];
        if seg.is_intersection || seg.lane_type != LaneType::Vehicle {
            continue;
        }
        let g = &index.lanes[i];
        let d = g.polygon.distance_to_point(pos);
        if d > STOP_SIGN_LANE_SEARCH_M {
            continue;
        }
        let Some((k, q, _)) = nearest_on_polyline(&g.centerline, pos) else {
            continue;
        };
        let (a, b) = (g.centerline[k], g.centerline[k + 1]);
        let right_side = (b[0] - a[0]) * (pos[1] - a[1]) - (b[1] - a[1]) * (pos[0] - a[0]) <= 0.0;
        let mut rest = vec![q];
        rest.extend_from_slice(&g.centerline[k + 1..]);
        let to_end = polyline_length(&rest);
        if (d == 0.0 || right_side) && to_end <= STOP_SIGN_LANE_SEARCH_M {
            let h = heading(a, b);
            if best.is_none_or(|(bd, bi, _)| (d, g.id) < (bd, index.lanes[bi].id)) {
                best = Some((d, i, h));
            }
        }
    }
    best.map(|(_, i, h)| (i, h))
}

/// Whether an object at `center` with heading `yaw`, assigned to lane `lane`, is at `sign`.
pub fn at_sign(sign: &StopSign, center: Pt, yaw: f64, lane: Option<usize>) -> bool {
    let Some(l) = lane else { return false };
    if sign.approach.binary_search(&l).is_err() {
        return false;
    }
    let (s, c) = yaw.sin_cos();
    let d = [sign.pos[0] - center[0], sign.pos[1] - center[1]];
    let forward = d[0] * c + d[1] * s;
    let lateral = -d[0] * s + d[1] * c;
    let facing =
        wrap_angle(yaw - sign.lane_heading).to_degrees().abs() <= STOP_SIGN_HEADING_MAX_DEG;
    (0.0..=STOP_SIGN_FORWARD_MAX_M).contains(&forward)
        && lateral.abs() <= STOP_SIGN_LATERAL_MAX_M
        && facing
}
