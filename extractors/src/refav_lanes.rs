//! RefAV's lane assignment and what it decides: `refav_lane_change` (RefAV's `changing_lanes`)
//! and `refav_on_intersection` (RefAV's `on_intersection`), for `scenalog import refav
//! --semantics refav`. Read from CainanD/RefAV 5c5be64 (`refAV/utils.py`:
//! `get_scenario_lanes`, `get_pos_within_lane`, `get_turn_direction`, `is_point_in_polygon`;
//! `refAV/atomic_functions.py`: `changing_lanes`, `on_intersection`); the differences from
//! Scenalog's definitions are listed in `import/README.md`.
//!
//! - **Positions** are RefAV's: each box's city centre (the ego's at its rear axle, as its
//!   annotated row), median-filtered over 7 samples with the ends repeated; velocities the
//!   central differences of the raw centres, filtered the same way (`get_nth_pos_deriv`).
//! - **Lane buckets** ([`scenario_lanes`]): every lane whose polygon (right boundary, left
//!   boundary reversed, closed) contains a sample's position, by RefAV's ray casting, gets that
//!   sample in its bucket; buckets are kept in the order they were opened (sample by sample,
//!   lanes in the map file's order, which is ascending id in AV2's files). Then, while buckets
//!   remain, the one with most samples wins its samples (on a tie the earlier bucket, unless a
//!   later tied one is an intersection lane whose turn agrees with the track's mean yaw rate
//!   over the bucket's samples — left above 0.15 rad/s, right below −0.15, straight between —
//!   which then wins, the last such), and its samples leave every other bucket. A sample in no
//!   lane has none. (AV2's `get_nearby_lane_segments`, which RefAV asks first, also needs one of
//!   the lane's boundary points, interpolated to 50 a side, within 5 m in the max norm: a lane
//!   that contains the point passes it unless one side is over about 400 m long; not
//!   reproduced.)
//! - **Lane changes** ([`lane_changes`]): at sample `i` whose lane is the previous sample's
//!   right (left) neighbour by AV2's links — across a centre line too —, with the city-frame `y`
//!   velocity at least 0.1 m/s in size and the velocity within 60° of the previous lane's right
//!   (left) boundary direction near the position (`|cos| >= 0.5`; for a left change RefAV's
//!   boundary direction runs from the boundary's first point, or its last when the nearest
//!   point is the first, to the point after the nearest — its `min(0, …)` slip). The change
//!   spans `i-1` and `i`, then back and forward while the position's fraction across its lane
//!   from the left boundary ([`pos_within_lane`]) keeps falling (left) or rising (right) between
//!   samples (a fraction of exactly 0 stops it, as Python's truth test does); `i-1` is kept only
//!   when it is not the first sample. Turning frames (RefAV's `turning`, either way) are
//!   removed.

use std::sync::Arc;

use scenalog_facts::relation::RelationData;
use scenalog_facts::scene::EGO_CATEGORY;
use scenalog_facts::{Frame, LaneSegment, Scene, Track};

use crate::cache::Extractor;
use crate::events::Side;
use crate::map::MapIndex;
use crate::pairs::refav::{median_nearest, placed_centre};
use crate::query::Query;
use crate::rows::relation;

/// RefAV's least sideways speed (city `y`) of a lane change, m/s (`SIDEWAYS_VEL_THRESH`).
pub const REFAV_LANE_CHANGE_MIN_Y_SPEED: f64 = 0.1;
/// RefAV's least `|cos|` between the velocity and the crossed boundary (`COS_SIMILARITY_THRESH`).
pub const REFAV_LANE_CHANGE_MIN_ABS_COS: f64 = 0.5;
/// The yaw rate, rad/s, above which a track's samples in a bucket agree with a left-turning
/// intersection lane (below minus it: right; between: straight) in RefAV's tie-break.
pub const REFAV_LANE_TIE_YAW_RATE: f64 = 0.15;

/// One track's samples as RefAV's lane functions see them.
pub struct RefavSamples {
    /// The boxes' frames.
    pub frames: Vec<Frame>,
    /// Median-filtered city centres (the ego's at its rear axle).
    pub pos: Vec<[f64; 2]>,
    /// Median-filtered central differences of the raw centres, m/s.
    pub vel: Vec<[f64; 2]>,
    /// RefAV's yaw rate, rad/s ([`crate::refav::rotvec_yaw_rate`]).
    pub yaw_rate: Vec<f64>,
}

/// RefAV's positions, velocities and yaw rate of one track.
pub fn samples(scene: &Scene, track: &Track) -> RefavSamples {
    let ego = track.category == EGO_CATEGORY;
    let fns = crate::refav::frames_ns(scene, track);
    let raw: Vec<[f64; 2]> = track
        .boxes
        .iter()
        .map(|b| placed_centre(b, ego).0)
        .collect();
    let n = raw.len();
    let d: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
            let dt = (fns[b].1 - fns[a].1) as f64;
            if dt == 0.0 {
                // One box: RefAV takes no difference (the "velocity" is the position).
                return raw[k];
            }
            [
                1e9 * (raw[b][0] - raw[a][0]) / dt,
                1e9 * (raw[b][1] - raw[a][1]) / dt,
            ]
        })
        .collect();
    RefavSamples {
        frames: fns.iter().map(|&(f, _)| f).collect(),
        pos: filter_2d(&raw),
        vel: filter_2d(&d),
        yaw_rate: crate::refav::rotvec_yaw_rate(scene, track),
    }
}

fn filter_2d(p: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let xs: Vec<f64> = p.iter().map(|q| q[0]).collect();
    let ys: Vec<f64> = p.iter().map(|q| q[1]).collect();
    median_nearest(&xs)
        .into_iter()
        .zip(median_nearest(&ys))
        .map(|(a, b)| [a, b])
        .collect()
}

/// RefAV's `is_point_in_polygon`: ray casting to +x over the closed polygon `poly`, a point on
/// a rising or falling edge's left counted inside as RefAV counts it.
pub fn refav_point_in_polygon(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let n = poly.len();
    if n == 0 {
        return false;
    }
    let [x, y] = p;
    let mut inside = false;
    let mut p1 = poly[0];
    let mut xinters = f64::NAN;
    for i in 1..=n {
        let p2 = poly[i % n];
        if y > p1[1].min(p2[1]) && y <= p1[1].max(p2[1]) && x <= p1[0].max(p2[0]) {
            if p1[1] != p2[1] {
                xinters = (y - p1[1]) * (p2[0] - p1[0]) / (p2[1] - p1[1]) + p1[0];
            }
            if p1[0] == p2[0] || x <= xinters {
                inside = !inside;
            }
        }
        p1 = p2;
    }
    inside
}

/// AV2's lane polygon: the right boundary, the left boundary reversed, the first point again.
pub fn lane_polygon(lane: &LaneSegment) -> Vec<[f64; 2]> {
    let mut poly: Vec<[f64; 2]> = lane
        .right_boundary
        .iter()
        .chain(lane.left_boundary.iter().rev())
        .map(|p| [p.x, p.y])
        .collect();
    if let Some(&first) = poly.first() {
        poly.push(first);
    }
    poly
}

/// RefAV's `get_turn_direction` of an intersection lane: the angle between its first and last
/// right-to-left cross vectors (`arctan2(dx, dy)`), right above 30°, left below −30°; `None`
/// for a lane outside intersections.
fn turn_direction(lane: &LaneSegment) -> Option<Option<Side>> {
    if !lane.is_intersection {
        return None;
    }
    let (r0, l0) = (lane.right_boundary.first()?, lane.left_boundary.first()?);
    let (r1, l1) = (lane.right_boundary.last()?, lane.left_boundary.last()?);
    let start = (r0.x - l0.x).atan2(r0.y - l0.y);
    let end = (r1.x - l1.x).atan2(r1.y - l1.y);
    let mut change = end - start;
    if change.abs() > std::f64::consts::PI {
        change -= std::f64::consts::TAU.copysign(change);
    }
    let sixth = std::f64::consts::PI / 6.0;
    Some(if change > sixth {
        Some(Side::Right)
    } else if change < -sixth {
        Some(Side::Left)
    } else {
        None
    })
}

/// RefAV's lane of each sample (an index into the map's lanes), by its lane buckets (see the
/// module doc).
pub fn scenario_lanes(scene: &Scene, index: &MapIndex, s: &RefavSamples) -> Vec<Option<usize>> {
    let lanes = &scene.map.lanes;
    let n = s.pos.len();
    // Buckets in the order they were opened: (lane, samples).
    let mut buckets: Vec<(usize, Vec<usize>)> = Vec::new();
    for (i, &p) in s.pos.iter().enumerate() {
        for l in index.lanes_near(p, 0.0) {
            if !refav_point_in_polygon(p, &lane_polygon(&lanes[l])) {
                continue;
            }
            match buckets.iter_mut().find(|(b, _)| *b == l) {
                Some((_, v)) => v.push(i),
                None => buckets.push((l, vec![i])),
            }
        }
    }
    let mut out = vec![None; n];
    while !buckets.is_empty() {
        let mut most = 0;
        let mut best = 0;
        for (k, (l, v)) in buckets.iter().enumerate() {
            if v.len() > most {
                most = v.len();
                best = k;
            } else if v.len() == most {
                let Some(turn) = turn_direction(&lanes[*l]) else {
                    continue;
                };
                let mean = v.iter().map(|&i| s.yaw_rate[i]).sum::<f64>() / v.len() as f64;
                let agrees = match turn {
                    Some(Side::Left) => mean > REFAV_LANE_TIE_YAW_RATE,
                    Some(Side::Right) => mean < -REFAV_LANE_TIE_YAW_RATE,
                    None => -REFAV_LANE_TIE_YAW_RATE < mean && mean < REFAV_LANE_TIE_YAW_RATE,
                };
                if agrees {
                    best = k;
                }
            }
        }
        let (lane, won) = buckets.remove(best);
        for &i in &won {
            out[i] = Some(lane);
        }
        for (_, v) in buckets.iter_mut() {
            v.retain(|i| !won.contains(i));
        }
        buckets.retain(|(_, v)| !v.is_empty());
    }
    out
}

/// RefAV's `get_pos_within_lane(pos, lane)`'s second value: how far across the lane `p` lies,
/// from the left boundary (0) towards the right (1), measured between the points RefAV takes
/// on each boundary (its projections, including its slips: a point before a segment's start
/// projects onto the segment's line behind it); `None` outside the lane's polygon.
pub fn pos_within_lane(p: [f64; 2], lane: &LaneSegment) -> Option<f64> {
    if !refav_point_in_polygon(p, &lane_polygon(lane)) {
        return None;
    }
    let nearest = |line: &[nalgebra::Point3<f64>]| -> Option<[f64; 2]> {
        let mut best = f64::INFINITY;
        let mut point = None;
        for w in line.windows(2) {
            let (s, e) = ([w[0].x, w[0].y], [w[1].x, w[1].y]);
            let len = (e[0] - s[0]).hypot(e[1] - s[1]);
            let dir = [(e[0] - s[0]) / len, (e[1] - s[1]) / len];
            let dot = (p[0] - s[0]) * dir[0] + (p[1] - s[1]) * dir[1];
            let proj = [dot * dir[0], dot * dir[1]];
            let proj_len = proj[0].hypot(proj[1]);
            let at = if (0.0..=len).contains(&proj_len) {
                [s[0] + proj[0], s[1] + proj[1]]
            } else {
                e
            };
            let dist = (p[0] - at[0]).hypot(p[1] - at[1]);
            if dist < best {
                best = dist;
                point = Some([s[0] + proj[0], s[1] + proj[1]]);
            }
        }
        point
    };
    let (l, r) = (
        nearest(&lane.left_boundary)?,
        nearest(&lane.right_boundary)?,
    );
    let width = (l[0] - r[0]).hypot(l[1] - r[1]);
    let dir = [(l[0] - r[0]) / width, (l[1] - r[1]) / width];
    let dot = (p[0] - l[0]) * dir[0] + (p[1] - l[1]) * dir[1];
    Some((dot * dir[0]).hypot(dot * dir[1]) / width)
}

/// The direction of a boundary near `p` as RefAV's `changing_lanes` takes it (see the module
/// doc), normalised as RefAV does (by the norm of the vector plus 1e-8 in each component).
fn boundary_direction(line: &[nalgebra::Point3<f64>], p: [f64; 2], side: Side) -> Option<[f64; 2]> {
    let n = line.len();
    let nearest = (0..n).min_by(|&a, &b| {
        let d = |k: usize| (line[k].x - p[0]).hypot(line[k].y - p[1]);
        d(a).total_cmp(&d(b))
    })?;
    let start = match side {
        Side::Right => nearest.saturating_sub(1),
        // RefAV's `min(0, nearest - 1)`: the first point, or (Python's -1) the last.
        Side::Left if nearest == 0 => n - 1,
        Side::Left => 0,
    };
    let end = (nearest + 1).min(n - 1);
    let v = [line[end].x - line[start].x, line[end].y - line[start].y];
    let norm = (v[0] + 1e-8).hypot(v[1] + 1e-8);
    Some([v[0] / norm, v[1] / norm])
}

/// RefAV's lane-change frames of one track (see the module doc), turning frames removed, in
/// frame order (a frame may be both a left and a right change's).
pub fn lane_changes(
    scene: &Scene,
    s: &RefavSamples,
    lanes: &[Option<usize>],
    turning: &[(Frame, Side)],
) -> Vec<(Frame, Side)> {
    let map = &scene.map.lanes;
    let n = s.pos.len();
    let lane = |i: usize| lanes[i].map(|l| &map[l]);
    let mut exact: Vec<(usize, Side)> = Vec::new();
    for i in 1..n {
        let (Some(prev), Some(cur)) = (lane(i - 1), lane(i)) else {
            continue;
        };
        if s.vel[i][1].abs() < REFAV_LANE_CHANGE_MIN_Y_SPEED {
            continue;
        }
        let (side, line) = if prev.right_neighbor == Some(cur.id) {
            (Side::Right, &prev.right_boundary)
        } else if prev.left_neighbor == Some(cur.id) {
            (Side::Left, &prev.left_boundary)
        } else {
            continue;
        };
        let Some(b) = boundary_direction(line, s.pos[i], side) else {
            continue;
        };
        let v = s.vel[i];
        let speed = v[0].hypot(v[1]);
        let cos = ((b[0] * v[0] + b[1] * v[1]) / speed).abs();
        if cos >= REFAV_LANE_CHANGE_MIN_ABS_COS {
            exact.push((i, side));
        }
    }
    // Python's truth test of a fraction: None and 0.0 are false.
    let width = |k: usize| lane(k).and_then(|l| pos_within_lane(s.pos[k], l));
    let moving = |a: usize, b: usize, side: Side| match (width(a), width(b)) {
        (Some(w0), Some(w1)) if w0 != 0.0 && w1 != 0.0 => match side {
            Side::Left => w0 > w1,
            Side::Right => w0 < w1,
        },
        _ => false,
    };
    let mut frames: Vec<(Frame, Side)> = Vec::new();
    for &(i, side) in &exact {
        let mut start = i - 1;
        while start > 0 {
            if start == i - 1 || moving(start, start + 1, side) {
                frames.push((s.frames[start], side));
                start -= 1;
            } else {
                break;
            }
        }
        let mut end = i;
        while end < n {
            if end == i || moving(end - 1, end, side) {
                frames.push((s.frames[end], side));
                end += 1;
            } else {
                break;
            }
        }
    }
    // `turning` is in frame order.
    frames.retain(|&(f, _)| turning.binary_search_by_key(&f, |&(g, _)| g).is_err());
    frames.sort_unstable();
    frames.dedup();
    frames
}

/// Per track (by `TrackId::index()`): RefAV's lane per box and its lane-change frames.
pub struct RefavLaneData {
    /// Per track, per box: the lane's index in the map's lanes.
    pub lanes: Vec<Vec<Option<usize>>>,
    /// Per track: its lane-change frames, RefAV's `turning` frames removed.
    pub changes: Vec<Vec<(Frame, Side)>>,
}

/// One track's lane per box and its lane-change frames.
type TrackLanes = (Vec<Option<usize>>, Vec<(Frame, Side)>);

/// RefAV's lanes and lane changes of every track, computed once per scene.
pub fn lane_data(ex: &Extractor) -> Arc<RefavLaneData> {
    ex.cached(|ex| {
        use rayon::prelude::*;
        let (scene, index, turning) = (ex.scene(), ex.map_index(), ex.refav_turning());
        let per: Vec<TrackLanes> = scene
            .tracks
            .par_iter()
            .map(|t| {
                let s = samples(scene, t);
                let lanes = scenario_lanes(scene, index, &s);
                let changes = lane_changes(scene, &s, &lanes, &turning[t.id.index()]);
                (lanes, changes)
            })
            .collect();
        let (lanes, changes) = per.into_iter().unzip();
        RefavLaneData { lanes, changes }
    })
}

/// `refav_lane_change(X, T, Dir)`: RefAV's `changing_lanes` (see the module doc).
pub(crate) fn refav_lane_change(ex: &Extractor, q: &Query) -> RelationData {
    crate::relations::motion::events(ex, q, &lane_data(ex).changes)
}

/// `refav_on_intersection(X, T)`: RefAV's `on_intersection`: the lane RefAV assigns X at T is
/// an intersection lane.
pub(crate) fn refav_on_intersection(ex: &Extractor, q: &Query) -> RelationData {
    let (scene, data) = (ex.scene(), lane_data(ex));
    let n = scene.num_frames();
    let mut rows = Vec::new();
    for t in q.tracks(scene, 0) {
        let r = q.frames(1, n);
        let boxes = &scene.track(t).boxes;
        for (b, l) in boxes.iter().zip(&data.lanes[t.index()]) {
            if r.contains(&b.frame) && l.is_some_and(|l| scene.map.lanes[l].is_intersection) {
                rows.push((t, b.frame));
            }
        }
    }
    relation(q, rows)
}
