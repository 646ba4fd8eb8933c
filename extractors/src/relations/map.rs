//! Map relations: lanes of the map (`lane_type`, `intersection_lane`, `lane_successor`,
//! `lane_neighbor`) and of objects (`in_lane`, `on_road`, `in_drivable_area`, `on_intersection`,
//! `near_intersection`, `at_crosswalk`, `at_stop_sign`).

use scenalog_facts::relation::RelationData;
use scenalog_facts::{Frame, LaneId, TrackId};

use super::s;
use crate::cache::Extractor;
use crate::map::geometry::{box_corners, Polygon};
use crate::map::stop_signs::STOP_SIGN_CATEGORY;
use crate::query::Query;
use crate::rows::relation;
use crate::thresholds::MAP_DISTANCE_MAX_M;

/// `in_lane(X, T, L)`: the assigned lane per box.
pub fn in_lane(ex: &Extractor, q: &Query) -> RelationData {
    let (kin, lanes) = (ex.kinematics(), ex.lanes());
    let n = ex.scene().num_frames();
    let mut rows = Vec::new();
    for t in q.tracks(ex.scene(), 0) {
        let i = t.index();
        let k = &kin.tracks[i];
        let r = q.box_range(1, n, &k.frames);
        for (&f, l) in k.frames[r.clone()].iter().zip(&lanes.lanes[i][r]) {
            if let Some(l) = l {
                rows.push((t, f, *l));
            }
        }
    }
    relation(q, rows)
}

/// `on_road(X, T)`: the box has an assigned lane.
pub fn on_road(ex: &Extractor, q: &Query) -> RelationData {
    let (kin, lanes) = (ex.kinematics(), ex.lanes());
    let n = ex.scene().num_frames();
    let mut rows = Vec::new();
    for t in q.tracks(ex.scene(), 0) {
        let i = t.index();
        let k = &kin.tracks[i];
        let r = q.box_range(1, n, &k.frames);
        for (&f, l) in k.frames[r.clone()].iter().zip(&lanes.lanes[i][r]) {
            if l.is_some() {
                rows.push((t, f));
            }
        }
    }
    relation(q, rows)
}

/// A per-box test on the raw centre (`in_drivable_area`, `on_intersection`).
pub fn centre_test(ex: &Extractor, q: &Query, test: impl Fn([f64; 2]) -> bool) -> RelationData {
    let kin = ex.kinematics();
    let n = ex.scene().num_frames();
    let mut rows = Vec::new();
    for t in q.tracks(ex.scene(), 0) {
        let k = &kin.tracks[t.index()];
        let r = q.box_range(1, n, &k.frames);
        for (&f, &c) in k.frames[r.clone()].iter().zip(&k.center[r]) {
            if test(c) {
                rows.push((t, f));
            }
        }
    }
    relation(q, rows)
}

/// The distance bound for a `D` column: the request's upper bound, never above
/// [`MAP_DISTANCE_MAX_M`].
fn distance_bound(q: &Query, col: usize) -> f64 {
    q.upper_bound(col)
        .map_or(MAP_DISTANCE_MAX_M, |b| b.min(MAP_DISTANCE_MAX_M))
}

/// `near_intersection(X, T, D)`.
pub fn near_intersection(ex: &Extractor, q: &Query) -> RelationData {
    let (kin, index) = (ex.kinematics(), ex.map_index());
    let n = ex.scene().num_frames();
    let max = distance_bound(q, 2);
    let mut rows = Vec::new();
    for t in q.tracks(ex.scene(), 0) {
        let k = &kin.tracks[t.index()];
        let mut hint = None;
        let r = q.box_range(1, n, &k.frames);
        for (&f, &c) in k.frames[r.clone()].iter().zip(&k.center[r]) {
            if let Some(d) = index.intersection_distance_hinted(c, max, &mut hint) {
                rows.push((t, f, d));
            }
        }
    }
    relation(q, rows)
}

/// `at_crosswalk(X, T, D)`: distance from the object's ground rectangle to the nearest crossing.
pub fn at_crosswalk(ex: &Extractor, q: &Query) -> RelationData {
    let index = ex.map_index();
    box_distance(ex, q, |shape, max| index.crossing_distance(shape, max))
}

/// `(X, T, D)` for every box the query allows, D `distance(box, max)` from X's ground rectangle
/// to a map feature, up to the query's bound on D (at most [`MAP_DISTANCE_MAX_M`]).
pub(crate) fn box_distance(
    ex: &Extractor,
    q: &Query,
    distance: impl Fn(&Polygon, f64) -> Option<f64>,
) -> RelationData {
    let (scene, kin) = (ex.scene(), ex.kinematics());
    let n = scene.num_frames();
    let max = distance_bound(q, 2);
    let mut rows = Vec::new();
    for t in q.tracks(scene, 0) {
        let k = &kin.tracks[t.index()];
        let boxes = &scene.track(t).boxes;
        for i in q.box_range(1, n, &k.frames) {
            let b = &boxes[i];
            let shape =
                Polygon::new(box_corners(k.center[i], k.yaw[i], b.size[0], b.size[1]).to_vec());
            if let Some(d) = distance(&shape, max) {
                rows.push((t, b.frame, d));
            }
        }
    }
    relation(q, rows)
}

/// `refav_crosswalk(X, T, C, D)`: see [`crate::refav`]: X's box as RefAV has it at T, pedestrian
/// crossing C (map id), D the mitred dilation at which they touch (0 overlapping), up to the
/// query's bound on D (at most [`MAP_DISTANCE_MAX_M`]).
pub fn refav_crosswalk(ex: &Extractor, q: &Query) -> RelationData {
    let (scene, index) = (ex.scene(), ex.map_index());
    let n = scene.num_frames();
    let max = distance_bound(q, 3);
    let ids: Vec<i64> = scene.map.crossings.iter().map(|c| c.id).collect();
    let mut rows = Vec::new();
    for t in q.tracks(scene, 0) {
        let track = scene.track(t);
        let ego = t == scene.ego;
        let r = q.frames(1, n);
        for b in track.boxes.iter().filter(|b| r.contains(&b.frame)) {
            let (c, yaw) = crate::pairs::refav::placed_centre(b, ego);
            // Relative to the box's centre, so city coordinates lose no precision.
            let quad = box_corners([0.0, 0.0], yaw, b.size[0], b.size[1]);
            for (k, poly) in index.crossings.iter().enumerate() {
                let local: Vec<[f64; 2]> = poly
                    .pts
                    .iter()
                    .map(|p| [p[0] - c[0], p[1] - c[1]])
                    .collect();
                let d = crate::refav::mitred_distance(&local, &quad);
                if d <= max {
                    rows.push((t, b.frame, ids[k], d));
                }
            }
        }
    }
    relation(q, rows)
}

/// `at_stop_sign(X, S, T)`.
pub fn at_stop_sign(ex: &Extractor, q: &Query) -> RelationData {
    let (scene, kin, lanes) = (ex.scene(), ex.kinematics(), ex.lane_indices());
    let n = scene.num_frames();
    let signs: Vec<_> = ex
        .stop_signs()
        .iter()
        .filter(|s| q.allows_track(1, s.track))
        .collect();
    let mut rows: Vec<(TrackId, TrackId, Frame)> = Vec::new();
    if !signs.is_empty() {
        for t in q.tracks(scene, 0) {
            if scene.track(t).category == STOP_SIGN_CATEGORY {
                continue;
            }
            let k = &kin.tracks[t.index()];
            for i in q.box_range(2, n, &k.frames) {
                let f = k.frames[i];
                for sign in &signs {
                    if crate::map::stop_signs::at_sign(
                        sign,
                        k.center[i],
                        k.yaw[i],
                        lanes[t.index()][i],
                    ) {
                        rows.push((t, sign.track, f));
                    }
                }
            }
        }
    }
    relation(q, rows)
}

/// `lane_type(L, Ty)`.
pub fn lane_type(ex: &Extractor, q: &Query) -> RelationData {
    let lanes = &ex.scene().map.lanes;
    relation(q, lanes.iter().map(|l| (l.id, s(l.lane_type.as_str()))))
}

/// `intersection_lane(L)`.
pub fn intersection_lane(ex: &Extractor, q: &Query) -> RelationData {
    let lanes = ex.scene().map.lanes.iter();
    relation(q, lanes.filter(|l| l.is_intersection).map(|l| (l.id,)))
}

/// `lane_successor(L, L2)`: successors present in the map (dangling ids are left out).
pub fn lane_successor(ex: &Extractor, q: &Query) -> RelationData {
    let map = &ex.scene().map;
    let mut rows: Vec<(LaneId, LaneId)> = Vec::new();
    for l in &map.lanes {
        for &s in &l.successors {
            if map.lane(s).is_some() {
                rows.push((l.id, s));
            }
        }
    }
    relation(q, rows)
}

/// `lane_neighbor(L, L2, Side)`: neighbours present in the map.
pub fn lane_neighbor(ex: &Extractor, q: &Query) -> RelationData {
    let map = &ex.scene().map;
    let (left, right) = (s("left"), s("right"));
    let mut rows = Vec::new();
    for l in &map.lanes {
        for (n, side) in [(l.left_neighbor, &left), (l.right_neighbor, &right)] {
            if let Some(n) = n.filter(|&n| map.lane(n).is_some()) {
                rows.push((l.id, n, side.clone()));
            }
        }
    }
    relation(q, rows)
}
