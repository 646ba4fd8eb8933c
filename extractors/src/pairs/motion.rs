//! Relations about how the objects move relative to each other: `heading_relative`,
//! `heading_toward`, `crossing` (smoothed positions and velocities).

use std::collections::BTreeSet;
use std::sync::Arc;

use scenalog_facts::catalog::SENSES;
use scenalog_facts::relation::RelationData;
use scenalog_facts::{Frame, TrackId};

use super::spatial::{key3, DIRECTIONS};
use super::{
    box_distance, for_each_pair, for_each_pair_in, frame_range, radius, str_values, text_ranks,
    wanted, ObjBox, PairContext,
};
use crate::kinematics::TrackKinematics;
use crate::query::Query;
use crate::rows::relation;
use crate::thresholds::{
    CROSSING_DETAIL_MAX_OFF_M, CROSSING_DETAIL_MAX_REACH_M, CROSSING_MIN_SPEED_M_S,
    CROSSING_REACH_M, CROSSING_SPAN_M, HEADING_MIN_SPEED_M_S, HEADING_OPPOSITE_MIN_DEG,
    HEADING_SAME_MAX_DEG, HEADING_TOWARD_MAX_ANGLE_DEG, HEADING_TOWARD_MIN_CLOSING_M_S,
    HEADING_TOWARD_MIN_SPEED_M_S, PAIR_MAX_DISTANCE_M,
};

/// The values of `heading_relative`'s Rel column, in catalog order.
pub const HEADINGS: [&str; 3] = ["same", "perpendicular", "opposite"];

/// Categories of objects that move by themselves (RefAV's `has_free_will`, with the ego): a slow
/// one of these is headed along its box; a slow sign, cone or bollard has no heading.
pub const SELF_MOVING_CATEGORIES: &[&str] = &[
    "ANIMAL",
    "ARTICULATED_BUS",
    "BICYCLIST",
    "BOX_TRUCK",
    "BUS",
    "EGO_VEHICLE",
    "LARGE_VEHICLE",
    "MOTORCYCLE",
    "MOTORCYCLIST",
    "OFFICIAL_SIGNALER",
    "PEDESTRIAN",
    "RAILED_VEHICLE",
    "REGULAR_VEHICLE",
    "SCHOOL_BUS",
    "TRUCK",
    "TRUCK_CAB",
    "VEHICULAR_TRAILER",
    "WHEELED_RIDER",
];

/// Whether objects of `category` move by themselves.
pub fn moves_by_itself(category: &str) -> bool {
    SELF_MOVING_CATEGORIES.contains(&category)
}

fn norm(v: [f64; 2]) -> f64 {
    (v[0] * v[0] + v[1] * v[1]).sqrt()
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn track_kin<'a>(ctx: &PairContext<'a>, t: TrackId) -> Option<&'a TrackKinematics> {
    ctx.kin.tracks.get(t.index())
}

/// The unit heading of box `b` for `heading_relative`: along its smoothed velocity when at least
/// [`HEADING_MIN_SPEED_M_S`] fast, else along its box if it moves by itself, else none.
pub fn travel_heading(ctx: &PairContext, b: &ObjBox) -> Option<[f64; 2]> {
    let k = track_kin(ctx, b.track)?;
    let v = *k.vel.get(b.k)?;
    let s = norm(v);
    if s >= HEADING_MIN_SPEED_M_S {
        Some([v[0] / s, v[1] / s])
    } else if moves_by_itself(&ctx.scene.track(b.track).category) {
        Some([b.cos, b.sin])
    } else {
        None
    }
}

/// The angle between two unit vectors, degrees in [0, 180].
fn angle_deg(a: [f64; 2], b: [f64; 2]) -> f64 {
    dot(a, b).clamp(-1.0, 1.0).acos().to_degrees()
}

/// The heading class of an angle (degrees) between two headings: 0 "same", 1 "perpendicular",
/// 2 "opposite".
pub fn heading_class(angle: f64) -> usize {
    if angle <= HEADING_SAME_MAX_DEG {
        0
    } else if angle >= HEADING_OPPOSITE_MIN_DEG {
        2
    } else {
        1
    }
}

/// `heading_relative(X, Y, T, Rel)`: the angle between X's and Y's headings ([`travel_heading`]):
/// "same" when at most [`HEADING_SAME_MAX_DEG`], "opposite" when at least
/// [`HEADING_OPPOSITE_MIN_DEG`], "perpendicular" between. No tuple when either has no heading.
/// (RefAV's `heading_in_relative_direction_to`; unlike RefAV both may be slow, each then using its
/// box heading.)
pub(crate) fn heading_relative(ctx: &PairContext, q: &Query) -> RelationData {
    let want: Vec<usize> = wanted(q, 3, &HEADINGS)
        .iter()
        .filter_map(|w| HEADINGS.iter().position(|h| h == w))
        .collect();
    let names = str_values(&HEADINGS);
    let ranks = text_ranks(&HEADINGS);
    let rows = for_each_pair(
        ctx,
        q,
        radius(q, None),
        |r: &(TrackId, TrackId, Frame, usize)| (r.0, r.1, r.2, ranks[r.3]),
        |f, x, y, d, out| {
            let (Some(hx), Some(hy)) = (travel_heading(ctx, x), travel_heading(ctx, y)) else {
                return;
            };
            let c = heading_class(angle_deg(hx, hy));
            if want.contains(&c) && d.within() {
                out.push((x.track, y.track, f, c));
            }
        },
    );
    let rows = rows.into_iter();
    relation(q, rows.map(|(x, y, t, c)| (x, y, t, names[c].clone())))
}

/// Whether X (box `x`) heads toward Y (box `y`): X moves at least
/// [`HEADING_TOWARD_MIN_SPEED_M_S`], its velocity points within [`HEADING_TOWARD_MAX_ANGLE_DEG`]
/// of the direction from its centre to Y's, and the distance between the centres shrinks at
/// least [`HEADING_TOWARD_MIN_CLOSING_M_S`] (m/s: the relative velocity along that direction).
pub fn heads_toward(ctx: &PairContext, x: &ObjBox, y: &ObjBox) -> bool {
    let (Some(kx), Some(ky)) = (track_kin(ctx, x.track), track_kin(ctx, y.track)) else {
        return false;
    };
    let (Some(&px), Some(&vx), Some(&py), Some(&vy)) = (
        kx.pos.get(x.k),
        kx.vel.get(x.k),
        ky.pos.get(y.k),
        ky.vel.get(y.k),
    ) else {
        return false;
    };
    let r = [py[0] - px[0], py[1] - px[1]];
    let (dist, speed) = (norm(r), norm(vx));
    if dist <= f64::EPSILON || speed < HEADING_TOWARD_MIN_SPEED_M_S {
        return false;
    }
    let cos = dot(vx, r) / (dist * speed);
    let closing = dot(r, [vx[0] - vy[0], vx[1] - vy[1]]) / dist;
    cos >= HEADING_TOWARD_MAX_ANGLE_DEG.to_radians().cos()
        && closing >= HEADING_TOWARD_MIN_CLOSING_M_S
}

/// `heading_toward(X, Y, T)`: see [`heads_toward`] (RefAV's `heading_toward`, with the closing
/// speed in m/s instead of metres per frame).
pub(crate) fn heading_toward(ctx: &PairContext, q: &Query) -> RelationData {
    let rows = for_each_pair(ctx, q, radius(q, None), key3, |f, x, y, d, out| {
        if heads_toward(ctx, x, y) && d.within() {
            out.push((x.track, y.track, f));
        }
    });
    relation(q, rows)
}

/// How far beyond [`CROSSING_REACH_M`] (box-to-box) a pair may be at some frame to be examined
/// for crossings: covers one frame of relative motion at up to 50 m/s, since the crossing itself
/// is interpolated between two frames.
const CROSSING_CANDIDATE_MARGIN_M: f64 = 5.0;

/// One common frame of X and Y in the crossing frame of a direction: Y's centre `u` along the
/// direction axis and `v` across the midplane (metres from X's centre), and Y's velocity across
/// the midplane relative to X, `dv` (m/s).
#[derive(Debug, Clone, Copy)]
struct Sample {
    frame: Frame,
    u: f64,
    v: f64,
    dv: f64,
}

/// Y (track `y`) relative to X over the frames both are present: the frame, Y's centre in X's
/// frame (forward, left) and Y's velocity relative to X in X's frame (forward, left).
fn relative_motion(ctx: &PairContext, x: TrackId, y: TrackId) -> Vec<(Frame, [f64; 4])> {
    let (Some(kx), Some(ky)) = (track_kin(ctx, x), track_kin(ctx, y)) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (j, &frame) in ky.frames.iter().enumerate() {
        let Some(i) = kx.index_of(frame) else {
            continue;
        };
        let (Some(&px), Some(&vx), Some(&yaw)) = (kx.pos.get(i), kx.vel.get(i), kx.yaw.get(i))
        else {
            continue;
        };
        let (Some(&py), Some(&vy)) = (ky.pos.get(j), ky.vel.get(j)) else {
            continue;
        };
        let (s, c) = yaw.sin_cos();
        let (dx, dy) = (py[0] - px[0], py[1] - px[1]);
        let (rvx, rvy) = (vy[0] - vx[0], vy[1] - vx[1]);
        let m = [
            dx * c + dy * s,
            -dx * s + dy * c,
            rvx * c + rvy * s,
            -rvx * s + rvy * c,
        ];
        if m.iter().all(|v| v.is_finite()) {
            out.push((frame, m));
        }
    }
    out
}

/// The samples of a relative motion ([`relative_motion`]) for direction `dir` (index into
/// [`DIRECTIONS`]): rotated so the direction is +u and v is across the midplane.
fn samples(motion: &[(Frame, [f64; 4])], dir: usize) -> Vec<Sample> {
    motion
        .iter()
        .map(|&(frame, [fx, ly, fv, lv])| {
            let (u, v, dv) = match dir {
                0 => (fx, ly, lv),
                1 => (-fx, -ly, -lv),
                2 => (ly, -fx, -fv),
                _ => (-ly, fx, fv),
            };
            Sample { frame, u, v, dv }
        })
        .collect()
}

/// One crossing event of Y over a half-midplane of X: how far beyond X's side Y crossed, the
/// sense (+1: `v` increasing, counterclockwise about X seen from above), and its frames with Y's
/// distance from the midplane at each.
#[derive(Debug, Clone)]
struct CrossingEvent {
    reach: f64,
    sense: f64,
    frames: Vec<(Frame, f64)>,
}

/// Every crossing event in `s` (a direction's samples) for an object whose extent along the
/// direction from its centre is `reach0` (half its length or width), with the half-midplane
/// extending `max_reach` beyond it and the span bounded by `max_off`.
///
/// A crossing happens between consecutive samples whose `v` changes sign, both within `max_off`
/// of the midplane (so a box heading flipping by 180° does not swing a distant object across),
/// where the interpolated crossing point lies on the half-midplane
/// (`reach0 <= u <= reach0 + max_reach`) and Y moves across it in that sense faster than
/// [`CROSSING_MIN_SPEED_M_S`]. The event spans the two samples and extends each way while Y keeps
/// moving across that fast and stays within `max_off` of the midplane.
fn crossing_events(s: &[Sample], reach0: f64, max_reach: f64, max_off: f64) -> Vec<CrossingEvent> {
    let mut events = Vec::new();
    let moving = |k: usize, sign: f64| sign * s[k].dv > CROSSING_MIN_SPEED_M_S;
    let near_plane = |k: usize| s[k].v.abs() <= max_off;
    for j in 1..s.len() {
        let (a, b) = (&s[j - 1], &s[j]);
        if (a.v < 0.0) == (b.v < 0.0) || !near_plane(j - 1) || !near_plane(j) {
            continue;
        }
        let t = a.v / (a.v - b.v);
        let u = a.u + t * (b.u - a.u);
        if !(reach0..=reach0 + max_reach).contains(&u) {
            continue;
        }
        let sign = if b.v > a.v { 1.0 } else { -1.0 };
        if !moving(j, sign) {
            continue;
        }
        let mut frames = vec![(a.frame, a.v.abs()), (b.frame, b.v.abs())];
        let mut k = j - 1;
        while k > 0 && near_plane(k - 1) && moving(k - 1, sign) {
            k -= 1;
            frames.push((s[k].frame, s[k].v.abs()));
        }
        let mut k = j;
        while k + 1 < s.len() && near_plane(k + 1) && moving(k + 1, sign) {
            k += 1;
            frames.push((s[k].frame, s[k].v.abs()));
        }
        frames.sort_by_key(|f| f.0);
        events.push(CrossingEvent {
            reach: u - reach0,
            sense: sign,
            frames,
        });
    }
    events
}

/// The frames of every crossing event in `s` with the catalog's fixed extents
/// ([`CROSSING_REACH_M`], [`CROSSING_SPAN_M`]).
fn crossing_frames(s: &[Sample], reach0: f64) -> BTreeSet<Frame> {
    crossing_events(s, reach0, CROSSING_REACH_M, CROSSING_SPAN_M)
        .into_iter()
        .flat_map(|e| e.frames.into_iter().map(|f| f.0))
        .collect()
}

/// The (X, Y) pairs that come within `reach` (plus the candidate margin) of each other at some
/// frame of the whole log, sorted and distinct: an event may start before the requested frames.
fn crossing_candidates(ctx: &PairContext, q: &Query, reach: f64) -> Vec<(TrackId, TrackId)> {
    let all_frames = 0..ctx.index.num_frames() as Frame;
    let mut pairs = for_each_pair_in(
        ctx,
        q,
        all_frames,
        reach + CROSSING_CANDIDATE_MARGIN_M,
        |r: &(TrackId, TrackId)| (r.0, r.1, 0, 0),
        |_, x, y, d, out| {
            // A pair is a candidate once: its later frames need no distance.
            if out.last() != Some(&(x.track, y.track)) && d.within() {
                out.push((x.track, y.track));
            }
        },
    );
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// `crossing(X, Y, T, Dir)`: Y's centre crosses the half-midplane of X that extends
/// [`CROSSING_REACH_M`] beyond X's Dir side (forward: the plane through X's length axis in front
/// of X; left: the plane through its width axis beside it; ...), and T lies in the event's span.
/// A crossing is a sign change of Y's offset across the plane between two consecutive common
/// frames, both within [`CROSSING_SPAN_M`] of the plane, the interpolated crossing point on the
/// half-plane, and Y moving across faster than [`CROSSING_MIN_SPEED_M_S`]; the span extends each
/// way while Y keeps moving across that fast and within [`CROSSING_SPAN_M`] of the plane.
/// Motion is relative to X (Y's velocity minus X's, in X's frame), so a
/// pedestrian standing still while a car turns past is not crossing. Every pair that comes within
/// [`CROSSING_REACH_M`] (plus a margin) at some frame is examined, in every requested direction
/// (RefAV's `being_crossed_by` overwrote its direction argument after the first crossing, and
/// bounded the span only on the far side). Tuples only at frames where the boxes are within
/// [`PAIR_MAX_DISTANCE_M`].
pub(crate) fn crossing(ctx: &PairContext, q: &Query) -> RelationData {
    use rayon::prelude::*;
    let want: Vec<usize> = wanted(q, 3, &DIRECTIONS)
        .iter()
        .filter_map(|w| DIRECTIONS.iter().position(|d| d == w))
        .collect();
    let names = str_values(&DIRECTIONS);
    let out_frames = frame_range(q, 2, ctx.index.num_frames());
    if want.is_empty() || out_frames.is_empty() {
        return relation::<(TrackId, TrackId, Frame, Arc<str>)>(q, []);
    }
    let pairs = crossing_candidates(ctx, q, CROSSING_REACH_M);
    let ranks = text_ranks(&DIRECTIONS);
    let mut rows: Vec<(TrackId, TrackId, Frame, usize)> = pairs
        .par_iter()
        .flat_map_iter(|&(x, y)| {
            let mut rows = Vec::new();
            let motion = relative_motion(ctx, x, y);
            for &dir in &want {
                let s = samples(&motion, dir);
                let frames = crossing_frames(&s, reach0(ctx, x, dir, &s));
                for f in frames.into_iter().filter(|f| out_frames.contains(f)) {
                    if within_pair_distance(ctx, x, y, f) {
                        rows.push((x, y, f, dir));
                    }
                }
            }
            rows
        })
        .collect();
    rows.sort_unstable_by_key(|r| (r.0, r.1, r.2, ranks[r.3]));
    let rows = rows.into_iter();
    relation(q, rows.map(|(x, y, t, d)| (x, y, t, names[d].clone())))
}

/// A row of `crossing_detail`: X, Y, T, Dir, Sense, Reach, Off.
type DetailRow = (TrackId, TrackId, Frame, Arc<str>, Arc<str>, f64, f64);

/// `crossing_detail(X, Y, T, Dir, Sense, Reach, Off)`: the crossings of [`crossing`] with their
/// extents as columns instead of fixed: events are found with the half-midplane reaching
/// [`CROSSING_DETAIL_MAX_REACH_M`] beyond X's side and spans bounded by
/// [`CROSSING_DETAIL_MAX_OFF_M`]; `Reach` is how far beyond X's Dir side Y crossed (one value per
/// event), `Off` Y's distance from the midplane at T, and `Sense` "counterclockwise" when Y's
/// offset across the plane grows (in front of X: moving to X's left; on X's left: moving
/// backwards), "clockwise" otherwise (on X's left: back to front, overtaking X). RefAV's
/// `being_crossed_by(forward_thresh=F, lateral_thresh=L, in_direction=S)` is
/// `Reach <= F, Off <= L, Sense = S`. Because Y moves monotonically across during an event,
/// bounding `Off` per frame gives the event's span for a smaller bound, except that an event
/// whose first sample past the plane is already farther than the bound is kept from the frames
/// within it (the fixed-extent [`crossing`] drops such an event).
pub(crate) fn crossing_detail(ctx: &PairContext, q: &Query) -> RelationData {
    use rayon::prelude::*;
    let want: Vec<usize> = wanted(q, 3, &DIRECTIONS)
        .iter()
        .filter_map(|w| DIRECTIONS.iter().position(|d| d == w))
        .collect();
    let names = str_values(&DIRECTIONS);
    let senses = str_values(SENSES);
    let out_frames = frame_range(q, 2, ctx.index.num_frames());
    if want.is_empty() || out_frames.is_empty() {
        return relation::<DetailRow>(q, []);
    }
    let pairs = crossing_candidates(ctx, q, CROSSING_DETAIL_MAX_REACH_M);
    let dir_ranks = text_ranks(&DIRECTIONS);
    let mut rows: Vec<(TrackId, TrackId, Frame, usize, usize, f64, f64)> = pairs
        .par_iter()
        .flat_map_iter(|&(x, y)| {
            let mut rows = Vec::new();
            let motion = relative_motion(ctx, x, y);
            for &dir in &want {
                let s = samples(&motion, dir);
                let r0 = reach0(ctx, x, dir, &s);
                for e in crossing_events(
                    &s,
                    r0,
                    CROSSING_DETAIL_MAX_REACH_M,
                    CROSSING_DETAIL_MAX_OFF_M,
                ) {
                    let sense = usize::from(e.sense > 0.0); // SENSES[1] is counterclockwise
                    for (f, off) in e.frames {
                        if out_frames.contains(&f) && within_pair_distance(ctx, x, y, f) {
                            rows.push((x, y, f, dir, sense, e.reach, off));
                        }
                    }
                }
            }
            rows
        })
        .collect();
    rows.sort_unstable_by(|a, b| {
        (a.0, a.1, a.2, dir_ranks[a.3], a.4)
            .cmp(&(b.0, b.1, b.2, dir_ranks[b.3], b.4))
            .then(a.5.total_cmp(&b.5))
            .then(a.6.total_cmp(&b.6))
    });
    rows.dedup_by(|a, b| {
        (a.0, a.1, a.2, a.3, a.4) == (b.0, b.1, b.2, b.3, b.4)
            && a.5.to_bits() == b.5.to_bits()
            && a.6.to_bits() == b.6.to_bits()
    });
    let rows = rows.into_iter().map(|(x, y, t, d, sense, reach, off)| {
        let (d, sense) = (names[d].clone(), senses[sense].clone());
        (x, y, t, d, sense, reach, off)
    });
    relation(q, rows)
}

/// X's extent from its centre along direction `dir`: half its length (forward/backward) or width
/// (left/right), from its first box in the samples' frames (box sizes are constant per track).
fn reach0(ctx: &PairContext, x: TrackId, dir: usize, s: &[Sample]) -> f64 {
    let size = s
        .first()
        .and_then(|first| ctx.scene.track(x).box_at(first.frame))
        .map_or([0.0; 3], |b| b.size);
    let half = if dir < 2 { size[0] } else { size[1] };
    0.5 * half.max(0.0)
}

fn within_pair_distance(ctx: &PairContext, x: TrackId, y: TrackId, f: Frame) -> bool {
    let Some(fb) = ctx.index.frame(ctx.kin, f) else {
        return false;
    };
    match (fb.of(x), fb.of(y)) {
        (Some(bx), Some(by)) => box_distance(bx, by) <= PAIR_MAX_DISTANCE_M,
        _ => false,
    }
}
