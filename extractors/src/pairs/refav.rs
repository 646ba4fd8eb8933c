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

use scenalog_facts::relation::RelationData;
use scenalog_facts::scene::{EGO_CATEGORY, EGO_CENTRE_AHEAD_OF_AXLE_M, EGO_SIZE};
use scenalog_facts::TrackId;

use super::spatial::{direction_by, regions, regions_within};
use super::{box_distance, radius, ObjBox, PairContext};
use crate::query::Query;
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
pub fn refav_direction(ctx: &PairContext, q: &Query) -> RelationData {
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
                let bounds = [REFAV_EGO_FRONT_M, REFAV_EGO_BACK_M, REFAV_EGO_HALF_WIDTH_M];
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
