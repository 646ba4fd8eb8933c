//! `in_between(X, Y, Z, T)`: X is between Y and Z (a pedestrian between two parked cars, a
//! motorcycle between two lanes of traffic).

use scenalog_facts::relation::RelationData;

use crate::cache::Extractor;
use crate::pairs::{box_distance, pair_index, ObjBox};
use crate::query::Query;
use crate::rows::relation;
use crate::thresholds::{BETWEEN_MAX_GAP_M, BETWEEN_MAX_OFFSET_M};

/// Whether the point `c` lies between `a` and `b`: its projection on the segment `a`–`b` falls
/// strictly inside it and it is at most [`BETWEEN_MAX_OFFSET_M`] from the segment.
pub fn lies_between(c: [f64; 2], a: [f64; 2], b: [f64; 2]) -> bool {
    let (ab, ac) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    if len2 <= 0.0 {
        return false;
    }
    let s = (ac[0] * ab[0] + ac[1] * ab[1]) / len2;
    let off = (ab[0] * ac[1] - ab[1] * ac[0]).abs() / len2.sqrt();
    s > 0.0 && s < 1.0 && off <= BETWEEN_MAX_OFFSET_M
}

/// `in_between(X, Y, Z, T)`: per X and frame, every ordered pair (Y, Z) of other objects at most
/// [`BETWEEN_MAX_GAP_M`] from X whose centres X's centre lies between.
pub fn in_between(ex: &Extractor, q: &Query) -> RelationData {
    let (scene, kin) = (ex.scene(), ex.kinematics());
    let index = pair_index(ex);
    let frames = q.frames(3, scene.num_frames());
    let mut rows = Vec::new();
    for x in q.tracks(scene, 0) {
        let Some(kx) = kin.tracks.get(x.index()) else {
            continue;
        };
        for &f in kx.frames.iter().filter(|f| frames.contains(f)) {
            let Some(fb) = index.frame(kin, f) else {
                continue;
            };
            let Some(xb) = fb.of(x) else {
                continue;
            };
            let mut close: Vec<&ObjBox> = fb
                .candidates(xb, BETWEEN_MAX_GAP_M)
                .map(|i| &fb.boxes[i])
                .filter(|b| b.track != x && box_distance(xb, b) <= BETWEEN_MAX_GAP_M)
                .collect();
            close.sort_unstable_by_key(|b| b.track);
            for yb in close.iter().filter(|b| q.allows_track(1, b.track)) {
                for zb in close.iter().filter(|b| q.allows_track(2, b.track)) {
                    if yb.track != zb.track && lies_between(xb.center, yb.center, zb.center) {
                        rows.push((x, yb.track, zb.track, f));
                    }
                }
            }
        }
    }
    relation(q, rows)
}
