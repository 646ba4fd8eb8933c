//! Events over a track's frames: `turning` and `lane_change`.
//!
//! - **turning**: the yaw rate is median-filtered (`kinematics::median_window`: 0.7 s of samples); maximal runs of boxes whose
//!   filtered rate has one sign and exceeds [`TURN_DEAD_BAND_DEG_S`] are integrated over real time;
//!   every frame of a run turning more than [`TURN_MIN_ANGLE_DEG`] in all is `turning` that way.
//! - **lane_change**: when a track's assigned lane changes from A to B and B is A's left or right
//!   neighbour running the same way (also across a segment joint: a neighbour of A's successor or
//!   predecessor, or of B's; AV2 also links the lanes either side of a centre line as each other's
//!   left neighbour, and moving into oncoming traffic is not a lane change), the move counts when, at the first box in B, the velocity component across the crossed
//!   boundary towards B is at least [`LANE_CHANGE_MIN_LATERAL_SPEED`] and the velocity runs roughly
//!   along the boundary (|cos| ≥ [`LANE_CHANGE_MIN_ABS_COS`]). The event spans the boxes around that
//!   moment over which the smoothed centre keeps moving across the boundary towards B at that
//!   speed or more, between the two lanes' centres ([`LANE_CHANGE_SPAN_WIDTHS`] of a lane width
//!   either side of the boundary, which is followed through the lane chain); turning frames are
//!   removed.
//!
//! "Laterally" is measured across the crossed boundary (the lane's frame), not across the object's
//! own heading: a car's velocity in its own frame is almost purely forward even mid-change (the
//! body yaws into the move), so an object-frame test would miss real lane changes.

use scenalog_facts::{Frame, VectorMap};

use crate::kinematics::{median_filter, TrackKinematics};
use crate::map::geometry::{nearest_on_polyline, Pt};
use crate::map::MapIndex;
use crate::thresholds::{
    LANE_CHANGE_MIN_ABS_COS, LANE_CHANGE_MIN_LATERAL_SPEED, LANE_CHANGE_SPAN_WIDTHS,
    TURN_DEAD_BAND_DEG_S, TURN_MIN_ANGLE_DEG,
};

/// Left or right, for turns and lane changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Side {
    /// Counter-clockwise / to the left.
    Left,
    /// Clockwise / to the right.
    Right,
}

impl Side {
    /// The catalog's name: "left" or "right".
    pub fn as_str(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }
}

/// The frames of one track's turns, in frame order.
pub fn turning(t: &TrackKinematics) -> Vec<(Frame, Side)> {
    let n = t.frames.len();
    let rate = median_filter(&t.yaw_rate, t.window);
    let sign = |w: f64| {
        if w > TURN_DEAD_BAND_DEG_S {
            1
        } else if w < -TURN_DEAD_BAND_DEG_S {
            -1
        } else {
            0
        }
    };
    // Time each box stands for: half the gap to each neighbour.
    let dt = |i: usize| {
        let a = i.saturating_sub(1);
        let b = (i + 1).min(n - 1);
        0.5 * (t.times[b] - t.times[a])
    };
    let mut out = Vec::new();
    let mut i = 0;
    while i < n {
        let s = sign(rate[i]);
        let mut j = i + 1;
        while j < n && sign(rate[j]) == s {
            j += 1;
        }
        if s != 0 {
            let angle: f64 = (i..j).map(|k| rate[k] * dt(k)).sum();
            if angle.abs() > TURN_MIN_ANGLE_DEG {
                let side = if s > 0 { Side::Left } else { Side::Right };
                out.extend(t.frames[i..j].iter().map(|&f| (f, side)));
            }
        }
        i = j;
    }
    out
}

/// The lane whose side boundary is crossed going from lane `a` to lane `b` (lane indices), and
/// the side, when `b` is a neighbour of `a` (directly or across a segment joint).
fn neighbour_link(map: &VectorMap, index: &MapIndex, a: usize, b: usize) -> Option<(usize, Side)> {
    let near_a = std::iter::once(a)
        .chain(index.lanes[a].successors.iter().copied())
        .chain(index.lanes[a].predecessors.iter().copied());
    let near_b: Vec<usize> = std::iter::once(b)
        .chain(index.lanes[b].successors.iter().copied())
        .chain(index.lanes[b].predecessors.iter().copied())
        .collect();
    for p in near_a {
        let seg = &map.lanes[p];
        for (nb, side) in [
            (seg.left_neighbor, Side::Left),
            (seg.right_neighbor, Side::Right),
        ] {
            if let Some(q) = nb.and_then(|id| map.lane_index(id)) {
                if near_b.contains(&q) && same_direction(map, p, q) {
                    return Some((p, side));
                }
            }
        }
    }
    None
}

/// Whether lanes `p` and `q` (indices) run the same way: their overall directions (first to last
/// point of both boundaries) make an acute angle. AV2 marks the lanes on either side of a centre
/// line as each other's left neighbour; moving between those is not a lane change.
fn same_direction(map: &VectorMap, p: usize, q: usize) -> bool {
    let dir = |i: usize| -> [f64; 2] {
        let lane = &map.lanes[i];
        let mut d = [0.0, 0.0];
        for b in [&lane.left_boundary, &lane.right_boundary] {
            if let (Some(first), Some(last)) = (b.first(), b.last()) {
                d[0] += last.x - first.x;
                d[1] += last.y - first.y;
            }
        }
        d
    };
    let (a, b) = (dir(p), dir(q));
    a[0] * b[0] + a[1] * b[1] > 0.0
}

/// Signed distance of `p` across the polyline segment nearest to it, positive towards `side`,
/// with that segment's unit direction; `None` when `p` projects beyond the polyline's ends.
fn offset_across(line: &[Pt], p: Pt, side: Side) -> Option<(f64, Pt)> {
    let (k, _, _) = nearest_on_polyline(line, p)?;
    let (a, b) = (line[k], line[k + 1]);
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    if len <= 0.0 {
        return None;
    }
    let d = [(b[0] - a[0]) / len, (b[1] - a[1]) / len];
    let u = d[0] * (p[0] - a[0]) + d[1] * (p[1] - a[1]);
    if (k == 0 && u < 0.0) || (k + 2 == line.len() && u > len) {
        return None;
    }
    let left = d[0] * (p[1] - a[1]) - d[1] * (p[0] - a[0]);
    Some((if side == Side::Left { left } else { -left }, d))
}

/// The boundary on `side` of lane `p`, continued through the lanes of its chain (the lane as a
/// driver sees it), so a slow change is measured against the road, not a short segment.
fn chain_boundary(map: &VectorMap, index: &MapIndex, p: usize, side: Side) -> Vec<Pt> {
    let mut line: Vec<Pt> = Vec::new();
    for id in index.chains.chain(p) {
        let Some(k) = map.lane_index(*id) else {
            continue;
        };
        let b = match side {
            Side::Left => &index.lanes[k].left,
            Side::Right => &index.lanes[k].right,
        };
        for &q in b {
            if line
                .last()
                .is_none_or(|l| (l[0] - q[0]).hypot(l[1] - q[1]) > 1e-6)
            {
                line.push(q);
            }
        }
    }
    line
}

/// The frames of one track's lane changes, in frame order. `lanes` are the track's assigned lane
/// indices per box.
pub fn lane_changes(
    map: &VectorMap,
    index: &MapIndex,
    t: &TrackKinematics,
    lanes: &[Option<usize>],
    turning_frames: &[(Frame, Side)],
) -> Vec<(Frame, Side)> {
    let n = t.frames.len().min(lanes.len());
    let mut out: Vec<(Frame, Side)> = Vec::new();
    let mut prev: Option<usize> = None;
    for (i, lane) in lanes.iter().enumerate().take(n) {
        let Some(cur) = *lane else { continue };
        let Some(from) = prev.replace(cur) else {
            continue;
        };
        if from == cur {
            continue;
        }
        let Some((p, side)) = neighbour_link(map, index, from, cur) else {
            continue;
        };
        let line = &chain_boundary(map, index, p, side);
        let Some((_, dir)) = offset_across(line, t.pos[i], side) else {
            continue;
        };
        let v = t.vel[i];
        let speed = v[0].hypot(v[1]);
        let along = (v[0] * dir[0] + v[1] * dir[1]).abs();
        let left = dir[0] * v[1] - dir[1] * v[0];
        let across = if side == Side::Left { left } else { -left };
        if speed <= 0.0
            || across < LANE_CHANGE_MIN_LATERAL_SPEED
            || along / speed < LANE_CHANGE_MIN_ABS_COS
        {
            continue;
        }
        // Offsets across the boundary; the span is where they keep growing at the minimum speed,
        // between the old lane's centre line and the new one's (half a lane width either side).
        let half = LANE_CHANGE_SPAN_WIDTHS * index.lanes[p].width.max(index.lanes[cur].width);
        let off: Vec<Option<f64>> = (0..n)
            .map(|k| offset_across(line, t.pos[k], side).map(|o| o.0))
            .collect();
        let moving = |k: usize| -> bool {
            // Moving from box k-1 to box k towards the new lane, between the two lane centres.
            match (off[k - 1], off[k]) {
                (Some(a), Some(b)) => {
                    let dt = t.times[k] - t.times[k - 1];
                    dt > 0.0
                        && (b - a) / dt >= LANE_CHANGE_MIN_LATERAL_SPEED
                        && a >= -half
                        && b <= half
                }
                _ => false,
            }
        };
        let mut lo = i;
        while lo > 0 && moving(lo) {
            lo -= 1;
        }
        let mut hi = i;
        while hi + 1 < n && moving(hi + 1) {
            hi += 1;
        }
        for k in lo..=hi {
            let f = t.frames[k];
            if !turning_frames.iter().any(|&(tf, _)| tf == f) {
                out.push((f, side));
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}
