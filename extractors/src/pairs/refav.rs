//! RefAV's definitions of pair relations where they differ from Scenalog's, for programs
//! imported with `scenalog import refav --semantics refav` (see [`crate::refav`] for the
//! per-object ones).
//!
//! - **`refav_direction`** (RefAV's `has_objects_in_relative_direction`): `direction` with the
//!   ego placed as RefAV places it. As the track, its regions are those of a fixed box about the
//!   rear axle (the ego pose): front [`REFAV_EGO_FRONT_M`], back [`REFAV_EGO_BACK_M`] — *ahead*
//!   of the axle, RefAV's sign slip, reproduced — and sides ±[`REFAV_EGO_HALF_WIDTH_M`]. As the
//!   track or the candidate, its position and its box for distances are the annotated row centred
//!   on the rear axle, not the car's body Scenalog uses (1.44 m further ahead). As every pair
//!   relation, it holds only for boxes within 50 m of each other (the ego's body).
//! - **`refav_crossing`** (RefAV's `being_crossed_by`): at the frames X and Y share, Y's centre
//!   and velocity (central differences) each median-filtered over 7 samples with the ends
//!   repeated, in X's frame (the ego at its rear axle), turned to RefAV's axes for the direction.
//!   A crossing is a sample `i` where Y passes either of X's side lines `y = ±width/2` (X's
//!   first box's size, also for "left" and "right") between `i-1` and `i`, moving across faster
//!   than [`REFAV_CROSSING_MIN_SPEED`], with its `x` at least half X's length: Reach is that `x`
//!   less half the length. The crossing's span runs from `i-1` back and from `i` on while Y keeps
//!   moving that way faster than the threshold; Off is the farthest Y has got beyond the midplane
//!   on the far side along the way (RefAV extends while it is under `lateral_thresh`; the near
//!   side is unbounded). Sense is "counterclockwise" towards +y, "clockwise" towards −y.
//!   Computed over every shared frame (not only within 50 m) for pairs that come within 50 m at
//!   some frame. RefAV's overwrite of its `direction` with ±1 after the first crossing it finds
//!   (later candidates tested against the forward plane) is the importer's, over
//!   **`refav_crossing_event`** (each crossing at the frame it passes the line, whatever its
//!   sense and span) and `refav_order` (RefAV's order of candidates, [`crate::refav`]).
//! - **`refav_near`** (RefAV's `near_objects`' distance): `near` with the ego's box at its
//!   rear axle.
//! - **`refav_direction_corrected`**: `refav_direction` with the ego's back edge where RefAV
//!   means it (−[`REFAV_EGO_BACK_M`]), for imports that do not reproduce the sign slip.

use scenalog_facts::catalog::{DIRECTIONS, SENSES};
use scenalog_facts::relation::RelationData;
use scenalog_facts::scene::{EGO_CATEGORY, EGO_CENTRE_AHEAD_OF_AXLE_M, EGO_SIZE};
use scenalog_facts::{Frame, Scene, Track, TrackBox, TrackId};

use super::spatial::{direction_by, regions, regions_within};
use super::{box_distance, radius, str_values, wanted, ObjBox, PairContext};
use crate::query::Query;
use crate::rows::relation;
use crate::thresholds::PAIR_MAX_DISTANCE_M;

/// RefAV's front edge of the ego as a track, metres ahead of the rear axle (`4.877/2 + 1.422`).
pub const REFAV_EGO_FRONT_M: f64 = EGO_SIZE[0] / 2.0 + 1.422;
/// RefAV's back edge of the ego as a track, metres ahead of the rear axle
/// (`4.877 - (4.877/2 + 1.422)`: +1.02 m where the car's back is at −1.02 m).
pub const REFAV_EGO_BACK_M: f64 = EGO_SIZE[0] - REFAV_EGO_FRONT_M;
/// RefAV's half-width of the ego as a track, metres.
pub const REFAV_EGO_HALF_WIDTH_M: f64 = 1.0;

/// The ego's box moved from the car's body back to the rear axle, where RefAV has it.
fn at_axle(b: &ObjBox) -> ObjBox {
    ObjBox {
        center: [
            b.center[0] - EGO_CENTRE_AHEAD_OF_AXLE_M * b.cos,
            b.center[1] - EGO_CENTRE_AHEAD_OF_AXLE_M * b.sin,
        ],
        ..*b
    }
}

/// `refav_direction(X, Y, T, Dir, Dist, Lat)`: `direction` with the ego as RefAV places it (see
/// the module doc); the same columns and meaning otherwise.
pub(crate) fn refav_direction(ctx: &PairContext, q: &Query) -> RelationData {
    refav_direction_with(ctx, q, REFAV_EGO_BACK_M)
}

/// `refav_direction_corrected(X, Y, T, Dir, Dist, Lat)`: `refav_direction` with the ego's back
/// edge where RefAV means it, [`REFAV_EGO_BACK_M`] behind the rear axle (the sign slip fixed).
pub(crate) fn refav_direction_corrected(ctx: &PairContext, q: &Query) -> RelationData {
    refav_direction_with(ctx, q, -REFAV_EGO_BACK_M)
}

/// `refav_direction` with the ego's back edge at `back` metres ahead of its rear axle.
fn refav_direction_with(ctx: &PairContext, q: &Query, back: f64) -> RelationData {
    let ego: Option<TrackId> = ctx
        .scene
        .tracks
        .iter()
        .find(|t| t.category == EGO_CATEGORY)
        .map(|t| t.id);
    let is_ego = |b: &ObjBox| Some(b.track) == ego;
    let placed = |b: &ObjBox| if is_ego(b) { at_axle(b) } else { *b };
    // The ego's box moves by up to EGO_CENTRE_AHEAD_OF_AXLE_M: search that much further.
    let search = (radius(q, Some(4)) + EGO_CENTRE_AHEAD_OF_AXLE_M).min(PAIR_MAX_DISTANCE_M);
    direction_by(
        ctx,
        q,
        search,
        |x, y| {
            let yc = placed(y).center;
            if is_ego(x) {
                let bounds = [REFAV_EGO_FRONT_M, back, REFAV_EGO_HALF_WIDTH_M];
                regions_within(bounds, at_axle(x).to_local(yc))
            } else {
                regions(x, x.to_local(yc))
            }
        },
        |x, y, d| {
            if !(is_ego(x) || is_ego(y)) {
                d.value()
            } else if d.value() > PAIR_MAX_DISTANCE_M {
                // Like every pair relation, only pairs within 50 m of each other (the car's body).
                f64::INFINITY
            } else {
                box_distance(&placed(x), &placed(y))
            }
        },
    )
}

/// `refav_near(X, Y, T, D)`: `near` with the ego's box where RefAV has it, the annotated row
/// centred on the rear axle (its `cuboid_distance`), not the car's body 1.44 m further ahead:
/// D is the distance between the two boxes so placed. As every pair relation, only up to 50 m.
pub(crate) fn refav_near(ctx: &PairContext, q: &Query) -> RelationData {
    let ego = ctx.scene.ego;
    let placed = |b: &ObjBox| if b.track == ego { at_axle(b) } else { *b };
    let r = radius(q, Some(3));
    // The ego's box moves back by up to EGO_CENTRE_AHEAD_OF_AXLE_M: search that much further.
    let search = (r + EGO_CENTRE_AHEAD_OF_AXLE_M).min(PAIR_MAX_DISTANCE_M);
    let rows = super::for_each_pair(
        ctx,
        q,
        search,
        |r: &(TrackId, TrackId, Frame, f64)| (r.0, r.1, r.2, 0),
        |f, x, y, d, out| {
            // Like every pair relation, only pairs within 50 m of each other (the car's body).
            if d.value() > PAIR_MAX_DISTANCE_M {
                return;
            }
            let d = if x.track == ego || y.track == ego {
                box_distance(&placed(x), &placed(y))
            } else {
                d.value()
            };
            if d <= r {
                out.push((x.track, y.track, f, d));
            }
        },
    );
    relation(q, rows)
}

/// RefAV's speed across the plane below which a sample neither crosses nor extends a crossing
/// (`VELOCITY_THRESH`, m/s).
pub const REFAV_CROSSING_MIN_SPEED: f64 = 0.2;

/// One object's samples for RefAV's `being_crossed_by`, in the track's frame: centre and
/// velocity (both median-filtered as RefAV's `get_nth_pos_deriv` does), at the frames the two
/// objects share.
struct Relative {
    frames: Vec<Frame>,
    pos: Vec<[f64; 2]>,
    vel: Vec<[f64; 2]>,
}

/// scipy's `median_filter(x, size=min(7, n), mode="nearest")` on one series: a centred window
/// (for an even size, one more sample behind than ahead), edges repeated, the middle order
/// statistic (the upper one for an even size).
pub(crate) fn median_nearest(x: &[f64]) -> Vec<f64> {
    let n = x.len();
    let w = n.min(7);
    if w == 0 {
        return Vec::new();
    }
    let mut buf = Vec::with_capacity(w);
    (0..n)
        .map(|i| {
            buf.clear();
            for j in 0..w {
                // i - w/2 + j, clamped to the series (scipy's "nearest").
                let k = (i + j).saturating_sub(w / 2).min(n - 1);
                buf.push(x[k]);
            }
            buf.sort_by(f64::total_cmp);
            buf[w / 2]
        })
        .collect()
}

/// Filters both coordinates of a series with [`median_nearest`].
fn median_nearest_2d(p: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let xs: Vec<f64> = p.iter().map(|q| q[0]).collect();
    let ys: Vec<f64> = p.iter().map(|q| q[1]).collect();
    median_nearest(&xs)
        .into_iter()
        .zip(median_nearest(&ys))
        .map(|(a, b)| [a, b])
        .collect()
}

/// A box's city centre (at the rear axle for the ego) and heading.
pub(crate) fn placed_centre(b: &TrackBox, ego: bool) -> ([f64; 2], f64) {
    let c = b.city_center();
    let h = b.city_yaw();
    let a = if ego { EGO_CENTRE_AHEAD_OF_AXLE_M } else { 0.0 };
    ([c.x - a * h.cos(), c.y - a * h.sin()], h)
}

/// Y relative to X as RefAV's `being_crossed_by` sees it (before the rotation for the direction).
fn relative(scene: &Scene, x: &Track, y: &Track, ego: Option<TrackId>) -> Option<Relative> {
    let (mut i, mut j) = (0, 0);
    let mut common = Vec::new();
    while i < x.boxes.len() && j < y.boxes.len() {
        match x.boxes[i].frame.cmp(&y.boxes[j].frame) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                common.push((i, j));
                i += 1;
                j += 1;
            }
        }
    }
    if common.len() < 2 {
        return None;
    }
    // Only pairs that come within the pair relations' range (plus X's length) at a shared frame.
    let reach = PAIR_MAX_DISTANCE_M + x.boxes[0].size[0];
    let close = common.iter().any(|&(i, j)| {
        let (a, b) = (x.boxes[i].city_center(), y.boxes[j].city_center());
        (a.x - b.x).hypot(a.y - b.y) <= reach
    });
    if !close {
        return None;
    }
    let frames: Vec<Frame> = common.iter().map(|&(i, _)| x.boxes[i].frame).collect();
    let secs: Vec<f64> = frames
        .iter()
        .map(|&f| scene.timeline.seconds(f).unwrap_or(f64::from(f) * 0.1))
        .collect();
    let (xe, ye) = (Some(x.id) == ego, Some(y.id) == ego);
    let raw: Vec<[f64; 2]> = common
        .iter()
        .map(|&(_, j)| placed_centre(&y.boxes[j], ye).0)
        .collect();
    let n = raw.len();
    let d: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
            let dt = secs[b] - secs[a];
            if dt <= 0.0 {
                return [0.0, 0.0];
            }
            [(raw[b][0] - raw[a][0]) / dt, (raw[b][1] - raw[a][1]) / dt]
        })
        .collect();
    let (pos_city, vel_city) = (median_nearest_2d(&raw), median_nearest_2d(&d));
    let mut pos = Vec::with_capacity(n);
    let mut vel = Vec::with_capacity(n);
    for (k, &(i, _)) in common.iter().enumerate() {
        let (c, h) = placed_centre(&x.boxes[i], xe);
        let (s, co) = h.sin_cos();
        let (dx, dy) = (pos_city[k][0] - c[0], pos_city[k][1] - c[1]);
        pos.push([dx * co + dy * s, -dx * s + dy * co]);
        let v = vel_city[k];
        vel.push([v[0] * co + v[1] * s, -v[0] * s + v[1] * co]);
    }
    Some(Relative { frames, pos, vel })
}

/// A point of X's frame in RefAV's axes for a direction (its `get_nth_pos_deriv(direction=…)`).
fn rotate(dir: usize, p: [f64; 2]) -> [f64; 2] {
    match DIRECTIONS[dir] {
        "left" => [p[1], -p[0]],
        "right" => [-p[1], p[0]],
        "backward" => [-p[0], -p[1]],
        _ => p,
    }
}

/// One row of `refav_crossing`.
type CrossRow = (TrackId, TrackId, Frame, usize, usize, f64, f64);

/// The crossings of Y over X's `dir` side lines, as RefAV's `being_crossed_by` finds them, with
/// every frame of each crossing's span; with `events`, one row per crossing at the frame it
/// passes the line (Off 0), spans or not.
fn crossings(
    r: &Relative,
    dims: [f64; 2],
    dir: usize,
    ids: (TrackId, TrackId),
    events: bool,
    out: &mut Vec<CrossRow>,
) {
    let [half_len, half_wid] = [dims[0] / 2.0, dims[1] / 2.0];
    let (lb, rb) = (-half_wid, half_wid);
    let p: Vec<[f64; 2]> = r.pos.iter().map(|&q| rotate(dir, q)).collect();
    let v: Vec<[f64; 2]> = r.vel.iter().map(|&q| rotate(dir, q)).collect();
    for i in 1..p.len() {
        let (y0, y1) = (p[i - 1][1], p[i][1]);
        let crosses = (y0 < lb && lb < y1)
            || (y1 < rb && rb < y0)
            || (y0 < rb && rb < y1)
            || (y1 < lb && lb < y0);
        if !crosses || v[i][1].abs() <= REFAV_CROSSING_MIN_SPEED || p[i][0] < half_len {
            continue;
        }
        let reach = p[i][0] - half_len;
        let s = if y1 > y0 { 1.0 } else { -1.0 };
        // Sense: RefAV's in_direction "clockwise" keeps the crossings towards -y.
        let sense = usize::from(s > 0.0);
        if events {
            out.push((ids.0, ids.1, r.frames[i], dir, sense, reach, 0.0));
            continue;
        }
        let mut visit = |k: usize, off: &mut f64| -> bool {
            if s * v[k][1] <= REFAV_CROSSING_MIN_SPEED {
                return false;
            }
            *off = off.max(s * p[k][1]);
            out.push((ids.0, ids.1, r.frames[k], dir, sense, reach, *off));
            true
        };
        let mut off = f64::NEG_INFINITY;
        for k in (0..i).rev() {
            if !visit(k, &mut off) {
                break;
            }
        }
        let mut off = f64::NEG_INFINITY;
        for k in i..p.len() {
            if !visit(k, &mut off) {
                break;
            }
        }
    }
}

/// `refav_crossing(X, Y, T, Dir, Sense, Reach, Off)`: RefAV's `being_crossed_by(X, Y, direction=
/// Dir, in_direction=Sense, forward_thresh >= Reach, lateral_thresh > Off)` holds at T (see
/// the module doc; the direction overwrite is the importer's, with `refav_crossing_event`).
pub(crate) fn refav_crossing(scene: &Scene, q: &Query) -> RelationData {
    let rows = crossing_rows(scene, q, false);
    let senses = str_values(SENSES);
    let names = str_values(DIRECTIONS);
    let rows = rows.into_iter().map(|(x, y, t, d, s, reach, off)| {
        (x, y, t, names[d].clone(), senses[s].clone(), reach, off)
    });
    relation(q, rows)
}

/// `refav_crossing_event(X, Y, T, Dir, Reach)`: Y's median-filtered centre passes one of X's side
/// lines extended in direction Dir between the frame before T and T, Reach m beyond half X's
/// length, moving across faster than [`REFAV_CROSSING_MIN_SPEED`]: a crossing RefAV's
/// `being_crossed_by` finds (whatever its sense, and whether or not a span follows), the event
/// after which it overwrites its `direction` argument.
pub(crate) fn refav_crossing_event(scene: &Scene, q: &Query) -> RelationData {
    let rows = crossing_rows(scene, q, true);
    let names = str_values(DIRECTIONS);
    let rows = rows.into_iter();
    relation(
        q,
        rows.map(|(x, y, t, d, _, reach, _)| (x, y, t, names[d].clone(), reach)),
    )
}

/// The rows of `refav_crossing` (spans) or `refav_crossing_event` (`events`) for a query.
fn crossing_rows(scene: &Scene, q: &Query, events: bool) -> Vec<CrossRow> {
    let ego = scene
        .tracks
        .iter()
        .find(|t| t.category == EGO_CATEGORY)
        .map(|t| t.id);
    let dirs: Vec<usize> = wanted(q, 3, DIRECTIONS)
        .iter()
        .filter_map(|w| DIRECTIONS.iter().position(|d| d == w))
        .collect();
    let ys: Vec<TrackId> = q.tracks(scene, 1).collect();
    let xs: Vec<TrackId> = q.tracks(scene, 0).collect();
    use rayon::prelude::*;
    let rows: Vec<CrossRow> = xs
        .par_iter()
        .flat_map_iter(|&xt| {
            let x = scene.track(xt);
            let mut out = Vec::new();
            let Some(first) = x.boxes.first() else {
                return out.into_iter();
            };
            let dims = [first.size[0], first.size[1]];
            for &yt in &ys {
                if yt == xt {
                    continue;
                }
                let Some(r) = relative(scene, x, scene.track(yt), ego) else {
                    continue;
                };
                // Only pairs that come within the pair relations' range at some shared frame.
                if r.pos
                    .iter()
                    .all(|p| p[0].hypot(p[1]) > PAIR_MAX_DISTANCE_M + dims[0])
                {
                    continue;
                }
                for &d in &dirs {
                    crossings(&r, dims, d, (xt, yt), events, &mut out);
                }
            }
            out.into_iter()
        })
        .collect();
    rows
}
