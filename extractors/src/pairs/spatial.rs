//! Relations about where the boxes are: `near`, `direction`, `facing` (raw annotated boxes).

use scenalog_facts::relation::RelationData;
use scenalog_facts::{Frame, TrackId};

use super::{
    for_each_pair, radius, str_values, text_ranks, wanted, ObjBox, PairContext, PairDistance,
    RowKey,
};
use crate::query::Query;
use crate::rows::relation;
use crate::thresholds::FACING_MAX_ANGLE_DEG;

/// The directions of `direction` (and `crossing`), in catalog order.
pub const DIRECTIONS: [&str; 4] = ["forward", "backward", "left", "right"];

/// The sort key of an `(X, Y, T)` row.
pub(crate) fn key3(r: &(TrackId, TrackId, Frame)) -> RowKey {
    (r.0, r.1, r.2, 0)
}

/// `near(X, Y, T, D)`: D is the distance between X's and Y's ground rectangles at T (0 when they
/// overlap), for every pair within [`crate::thresholds::PAIR_MAX_DISTANCE_M`] (or the request's
/// tighter bound on D). Symmetric: `near(X, Y, T, D)` iff `near(Y, X, T, D)`, the same D.
pub(crate) fn near(ctx: &PairContext, q: &Query) -> RelationData {
    let r = radius(q, Some(3));
    let rows = for_each_pair(
        ctx,
        q,
        r,
        |r: &(TrackId, TrackId, Frame, f64)| (r.0, r.1, r.2, 0),
        |f, x, y, d, out| {
            let d = d.value();
            if d <= r {
                out.push((x.track, y.track, f, d));
            }
        },
    );
    relation(q, rows)
}

/// Which of X's four regions hold Y's centre, with the lateral offset for each: `local` is Y's
/// centre in X's box frame (forward, left). "forward": ahead of X's front; "backward": behind its
/// rear; "left"/"right": beyond its left/right side. The regions overlap at the corners (a centre
/// ahead and to the left is both "forward" and "left"); a centre inside X's box is in none.
/// Lat: for forward/backward, how far the centre lies beyond X's sides; for left/right, beyond its
/// front or rear; 0 when within.
pub fn regions(x: &ObjBox, local: [f64; 2]) -> [Option<f64>; 4] {
    regions_within([x.half_len, -x.half_len, x.half_wid], local)
}

/// [`regions`] of a box whose front and back lie at `front` and `back` along its axis and whose
/// sides lie `half_wid` either side of it, in the frame `local` is given in.
pub fn regions_within([front, back, half_wid]: [f64; 3], local: [f64; 2]) -> [Option<f64>; 4] {
    let [fx, ly] = local;
    let lat_fb = (ly.abs() - half_wid).max(0.0);
    let lat_lr = (fx - front).max(back - fx).max(0.0);
    [
        (fx > front).then_some(lat_fb),
        (fx < back).then_some(lat_fb),
        (ly > half_wid).then_some(lat_lr),
        (ly < -half_wid).then_some(lat_lr),
    ]
}

/// `direction(X, Y, T, Dir, Dist, Lat)`: Y's centre lies in X's Dir region ([`regions`]), Dist the
/// box-to-box distance (as `near`), Lat the lateral offset. RefAV's
/// `get_objects_in_relative_direction` with its default unlimited lateral threshold (bound Lat in
/// the rule to narrow it).
pub(crate) fn direction(ctx: &PairContext, q: &Query) -> RelationData {
    let bound = radius(q, Some(4));
    direction_by(
        ctx,
        q,
        bound,
        |x, y| regions(x, x.to_local(y.center)),
        |_, _, d| d.value(),
    )
}

/// The body of `direction` and its variants: `place(x, y)` gives X's four regions holding Y (as
/// [`regions`]), `dist(x, y, d)` the distance, asked only when Y is in a wanted region; pairs are
/// searched within `search` and kept within the request's bound on Dist.
pub(crate) fn direction_by(
    ctx: &PairContext,
    q: &Query,
    search: f64,
    place: impl Fn(&ObjBox, &ObjBox) -> [Option<f64>; 4] + Sync,
    dist: impl Fn(&ObjBox, &ObjBox, &PairDistance) -> f64 + Sync,
) -> RelationData {
    let ranks = text_ranks(&DIRECTIONS);
    let mut want: Vec<usize> = wanted(q, 3, &DIRECTIONS)
        .iter()
        .filter_map(|w| DIRECTIONS.iter().position(|d| d == w))
        .collect();
    // Rows of one pair in text order of the direction, as the output is sorted.
    want.sort_by_key(|&w| ranks[w]);
    let names = str_values(&DIRECTIONS);
    let bound = radius(q, Some(4));
    let rows = for_each_pair(
        ctx,
        q,
        search,
        |r: &(TrackId, TrackId, Frame, usize, f64, f64)| (r.0, r.1, r.2, ranks[r.3]),
        |f, x, y, d, out| {
            let r = place(x, y);
            if want.iter().all(|&w| r[w].is_none()) {
                return;
            }
            let d = dist(x, y, d);
            if d > bound {
                return;
            }
            for &w in &want {
                if let Some(lat) = r[w] {
                    out.push((x.track, y.track, f, w, d, lat));
                }
            }
        },
    );
    let rows = rows.into_iter();
    relation(
        q,
        rows.map(|(x, y, t, w, d, lat)| (x, y, t, names[w].clone(), d, lat)),
    )
}

/// `facing(X, Y, T)`: the bearing of Y's centre from X's centre is within
/// [`FACING_MAX_ANGLE_DEG`] of X's forward axis (RefAV's `facing_toward`).
pub(crate) fn facing(ctx: &PairContext, q: &Query) -> RelationData {
    let rows = for_each_pair(ctx, q, radius(q, None), key3, |f, x, y, d, out| {
        let [fx, ly] = x.to_local(y.center);
        if ly.atan2(fx).to_degrees().abs() <= FACING_MAX_ANGLE_DEG && d.within() {
            out.push((x.track, y.track, f));
        }
    });
    relation(q, rows)
}
