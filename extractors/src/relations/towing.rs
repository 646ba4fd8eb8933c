//! `towing(X, Y, T)`: vehicle X tows trailer Y (AV2 annotates a semi's tractor as `TRUCK_CAB` and
//! what it pulls as `VEHICULAR_TRAILER`, two tracks).

use scenalog_facts::relation::RelationData;
use scenalog_facts::scene::is_vehicle_category;

use crate::cache::Extractor;
use crate::kinematics::wrap_angle;
use crate::pairs::{box_distance, pair_index, ObjBox};
use crate::query::Query;
use crate::rows::relation;
use crate::thresholds::{TOWING_MAX_GAP_M, TOWING_MAX_HEADING_DEG, TOWING_MAX_LATERAL_M};

/// The category of a towed trailer.
pub const TRAILER_CATEGORY: &str = "VEHICULAR_TRAILER";

/// Whether a track of category `category` can tow: a vehicle, or a trailer (a second trailer of a
/// road train hangs on the first).
pub fn can_tow(category: &str) -> bool {
    is_vehicle_category(category) || category == TRAILER_CATEGORY
}

/// Whether `trailer`'s box hangs behind `tower`'s: its centre behind the tower's rear, at most
/// [`TOWING_MAX_LATERAL_M`] outside its sides, the rectangles at most [`TOWING_MAX_GAP_M`] apart
/// and the headings within [`TOWING_MAX_HEADING_DEG`].
pub fn hangs_behind(tower: &ObjBox, trailer: &ObjBox) -> bool {
    let [fwd, left] = tower.to_local(trailer.center);
    fwd < -tower.half_len
        && left.abs() - tower.half_wid <= TOWING_MAX_LATERAL_M
        && wrap_angle(trailer.yaw - tower.yaw).abs().to_degrees() <= TOWING_MAX_HEADING_DEG
        && box_distance(tower, trailer) <= TOWING_MAX_GAP_M
}

/// `towing(X, Y, T)`: per trailer Y and frame, every vehicle X its box hangs behind.
pub fn towing(ex: &Extractor, q: &Query) -> RelationData {
    let (scene, kin) = (ex.scene(), ex.kinematics());
    let index = pair_index(ex);
    let frames = q.frames(2, scene.num_frames());
    let mut rows = Vec::new();
    for y in q.tracks(scene, 1) {
        if scene.track(y).category != TRAILER_CATEGORY {
            continue;
        }
        let Some(ky) = kin.tracks.get(y.index()) else {
            continue;
        };
        for &f in ky.frames.iter().filter(|f| frames.contains(f)) {
            let Some(fb) = index.frame(kin, f) else {
                continue;
            };
            let Some(yb) = fb.of(y) else {
                continue;
            };
            let mut towers: Vec<_> = fb
                .candidates(yb, TOWING_MAX_GAP_M)
                .map(|i| &fb.boxes[i])
                .filter(|xb| {
                    xb.track != y
                        && q.allows_track(0, xb.track)
                        && can_tow(&scene.track(xb.track).category)
                        && hangs_behind(xb, yb)
                })
                .map(|xb| xb.track)
                .collect();
            towers.sort_unstable();
            rows.extend(towers.into_iter().map(|x| (x, y, f)));
        }
    }
    relation(q, rows)
}
