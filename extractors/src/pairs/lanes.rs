//! Relations through the lanes the objects are in: `same_lane`, `following`, `road_side`.
//!
//! They use the lane assignment (one lane per track box, [`crate::lanes`]) and the map's lane
//! chains (the lane as a driver sees it, [`crate::map::chain`]) and road sides
//! ([`crate::map::sides`]). An object in no lane has none of these relations.

use scenalog_facts::relation::RelationData;
use scenalog_facts::{Frame, TrackId};

use super::spatial::key3;
use super::{
    for_each_pair, for_each_pair_searching, radius, str_values, text_ranks, wanted, ObjBox,
    PairContext,
};
use crate::map::RoadSide;
use crate::query::Query;
use crate::rows::relation;
use crate::thresholds::{
    FOLLOWING_HEADING_MIN_SPEED_M_S, FOLLOWING_MAX_AHEAD_M, FOLLOWING_MAX_LATERAL_M,
    FOLLOWING_MIN_HEADING_COS,
};

/// The values of `road_side`'s Side column, in catalog order.
pub const SIDES: [&str; 2] = ["same", "opposite"];

/// Whether lane `ly` (a map lane index) is in lane `lx`'s chain (the lane as a driver sees it,
/// `lx` itself included).
pub fn in_chain(ctx: &PairContext, lx: usize, ly: usize) -> bool {
    lx == ly || {
        let id = ctx.map.lanes[ly].id;
        ctx.map.chains.chain(lx).contains(&id)
    }
}

/// `same_lane(X, Y, T)`: Y's lane at T is in X's lane as a driver sees it ([`in_chain`]: X's lane
/// and the predecessors and successors that continue it straight). Not symmetric at the chain's
/// reach or where chains fork.
pub(crate) fn same_lane(ctx: &PairContext, q: &Query) -> RelationData {
    let rows = for_each_pair(ctx, q, radius(q, None), key3, |f, x, y, d, out| {
        let (Some(lx), Some(ly)) = (ctx.lane_index(x.track, x.k), ctx.lane_index(y.track, y.k))
        else {
            return;
        };
        if in_chain(ctx, lx, ly) && d.within() {
            out.push((x.track, y.track, f));
        }
    });
    relation(q, rows)
}

/// The unit heading of box `b` for `following`: along its smoothed velocity when faster than
/// [`FOLLOWING_HEADING_MIN_SPEED_M_S`], else along its box.
fn follow_heading(ctx: &PairContext, b: &ObjBox) -> [f64; 2] {
    let v = ctx
        .kin
        .tracks
        .get(b.track.index())
        .and_then(|k| k.vel.get(b.k).copied())
        .unwrap_or([0.0, 0.0]);
    let s = (v[0] * v[0] + v[1] * v[1]).sqrt();
    if s > FOLLOWING_HEADING_MIN_SPEED_M_S {
        [v[0] / s, v[1] / s]
    } else {
        [b.cos, b.sin]
    }
}

/// Y's smoothed centre in X's frame (X's smoothed centre, X's box heading): (forward, left).
fn smoothed_local(ctx: &PairContext, x: &ObjBox, y: &ObjBox) -> Option<[f64; 2]> {
    let px = *ctx.kin.tracks.get(x.track.index())?.pos.get(x.k)?;
    let py = *ctx.kin.tracks.get(y.track.index())?.pos.get(y.k)?;
    let (dx, dy) = (py[0] - px[0], py[1] - px[1]);
    Some([dx * x.cos + dy * x.sin, -dx * x.sin + dy * x.cos])
}

/// Whether X (box `x`) follows lead Y (box `y`): both are in lanes; Y's centre is ahead of X's
/// front by more than 0 and less than [`FOLLOWING_MAX_AHEAD_M`]; their headings (velocity, or box
/// when slow) are within 60° (cosine above [`FOLLOWING_MIN_HEADING_COS`]); and either
/// - Y's lane is X's lane, one of its successors, or ahead of it in X's lane as a driver sees it,
///   and Y's centre is less than [`FOLLOWING_MAX_LATERAL_M`] to either side of X's axis; or
/// - Y's lane is a left/right neighbour of X's and Y's box overlaps X's width (a lead straddling
///   the lane line; RefAV's second case, with Y's own width where RefAV used X's).
pub fn follows(ctx: &PairContext, x: &ObjBox, y: &ObjBox) -> bool {
    let (Some(lx), Some(ly)) = (ctx.lane_index(x.track, x.k), ctx.lane_index(y.track, y.k)) else {
        return false;
    };
    let Some([fwd, lat]) = smoothed_local(ctx, x, y) else {
        return false;
    };
    let ahead = fwd - x.half_len;
    if !(ahead > 0.0 && ahead < FOLLOWING_MAX_AHEAD_M) {
        return false;
    }
    let (hx, hy) = (follow_heading(ctx, x), follow_heading(ctx, y));
    if hx[0] * hy[0] + hx[1] * hy[1] <= FOLLOWING_MIN_HEADING_COS {
        return false;
    }
    let geom = &ctx.map.lanes[lx];
    let ly_id = ctx.map.lanes[ly].id;
    let same_or_ahead =
        lx == ly || geom.successors.contains(&ly) || ctx.map.chains.ahead(lx).contains(&ly_id);
    if same_or_ahead && lat.abs() < FOLLOWING_MAX_LATERAL_M {
        return true;
    }
    let seg = &ctx.scene.map.lanes[lx];
    let neighbour = seg.left_neighbor == Some(ly_id) || seg.right_neighbor == Some(ly_id);
    neighbour && lat.abs() < x.half_wid + y.half_wid
}

/// `following(X, Y, T)`: X follows lead Y at T ([`follows`]; RefAV's `following`).
pub(crate) fn following(ctx: &PairContext, q: &Query) -> RelationData {
    let r = radius(q, None);
    let reach = FollowingReach::of(ctx);
    let region = |x: &ObjBox| reach.ahead_of(x);
    let rows = for_each_pair_searching(
        ctx,
        q,
        (r, reach.search()),
        Some(&region),
        key3,
        |f, x, y, d, out| {
            if follows(ctx, x, y) && d.within() {
                out.push((x.track, y.track, f));
            }
        },
    );
    relation(q, rows)
}

/// Where a lead Y can be when X [`follows`] it, as the candidate search measures (raw centres
/// and boxes). In X's frame, from X's smoothed centre, Y's smoothed centre is ahead of X's front
/// by less than [`FOLLOWING_MAX_AHEAD_M`], and less than the larger of
/// [`FOLLOWING_MAX_LATERAL_M`] and the two half widths to the side; a raw centre is at most the
/// scene's largest smoothing offset (`drift`) from the smoothed one, so measured from the raw
/// centres each coordinate moves by at most twice that. The search therefore finds every pair
/// `follows` accepts, among far fewer candidates than the 50 m pair radius gives.
struct FollowingReach {
    /// The scene's largest distance between a box's raw and smoothed centres.
    drift: f64,
    /// The scene's largest half box width.
    half_width: f64,
}

impl FollowingReach {
    fn of(ctx: &PairContext) -> FollowingReach {
        let finite_max = |it: &mut dyn Iterator<Item = f64>| {
            it.filter(|d| d.is_finite()).fold(0.0_f64, f64::max)
        };
        let drift = finite_max(
            &mut ctx
                .kin
                .tracks
                .iter()
                .flat_map(|k| k.pos.iter().zip(&k.center))
                .map(|(p, c)| (p[0] - c[0]).hypot(p[1] - c[1])),
        );
        let half_width = finite_max(
            &mut ctx
                .scene
                .tracks
                .iter()
                .flat_map(|t| &t.boxes)
                .map(|b| 0.5 * b.size[1]),
        );
        FollowingReach { drift, half_width }
    }

    /// An upper bound on the distance from a lead's raw centre to X's raw box.
    fn search(&self) -> f64 {
        FOLLOWING_MAX_AHEAD_M.hypot(FOLLOWING_MAX_LATERAL_M.max(self.half_width))
            + 2.0 * self.drift
            + 1e-6
    }

    /// The city-frame envelope of the rectangle ahead of X's box `x` that holds every lead's raw
    /// centre.
    fn ahead_of(&self, x: &ObjBox) -> ([f64; 2], [f64; 2]) {
        let slack = 2.0 * self.drift + 1e-6;
        let (f0, f1) = (
            x.half_len - slack,
            x.half_len + FOLLOWING_MAX_AHEAD_M + slack,
        );
        let side = FOLLOWING_MAX_LATERAL_M.max(x.half_wid + self.half_width) + slack;
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for (f, l) in [(f0, -side), (f0, side), (f1, -side), (f1, side)] {
            let p = [
                x.center[0] + f * x.cos - l * x.sin,
                x.center[1] + f * x.sin + l * x.cos,
            ];
            for i in 0..2 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
        (lo, hi)
    }
}

/// The road side of lane `ly` relative to lane `lx` (map lane indices): the road-side groups'
/// answer for `lx`, or else for the nearest lane of `lx`'s chain that has one (road-side groups
/// join neighbours across the road, chains join segments along it).
pub fn lane_side(ctx: &PairContext, lx: usize, ly: usize) -> Option<RoadSide> {
    if let Some(s) = ctx.map.sides.side(lx, ly) {
        return Some(s);
    }
    let chain = ctx.map.chains.chain(lx);
    let p = ctx.map.chains.position.get(lx).copied().unwrap_or(0);
    let mut order: Vec<usize> = (0..chain.len()).filter(|&i| i != p).collect();
    order.sort_by_key(|&i| (i.abs_diff(p), i));
    order
        .into_iter()
        .filter_map(|i| ctx.scene.map.lane_index(chain[i]))
        .find_map(|c| ctx.map.sides.side(c, ly))
}

/// `road_side(X, Y, T, Side)`: Y's lane at T is on the "same" or "opposite" side of the road as
/// X's lane ([`lane_side`]: same-direction neighbours are the same side, a neighbour whose shared
/// boundary runs the other way and everything on its side is opposite). No tuple when either is
/// in no lane or the map does not relate their lanes.
pub(crate) fn road_side(ctx: &PairContext, q: &Query) -> RelationData {
    let want = wanted(q, 3, &SIDES);
    let names = str_values(&SIDES);
    let ranks = text_ranks(&SIDES);
    let rows = for_each_pair(
        ctx,
        q,
        radius(q, None),
        |r: &(TrackId, TrackId, Frame, usize)| (r.0, r.1, r.2, ranks[r.3]),
        |f, x, y, d, out| {
            let (Some(lx), Some(ly)) = (ctx.lane_index(x.track, x.k), ctx.lane_index(y.track, y.k))
            else {
                return;
            };
            if let Some(side) = lane_side(ctx, lx, ly) {
                let k = usize::from(side == RoadSide::Opposite);
                if want.contains(&SIDES[k]) && d.within() {
                    out.push((x.track, y.track, f, k));
                }
            }
        },
    );
    let rows = rows.into_iter();
    relation(q, rows.map(|(x, y, t, k)| (x, y, t, names[k].clone())))
}
