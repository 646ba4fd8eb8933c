//! Kinematics and events: `speed`, `accel`, `lat_accel`, `yaw_rate`, `stationary`, `turning`,
//! `lane_change`.

use scenalog_facts::relation::RelationData;
use scenalog_facts::Frame;

use super::s;
use crate::cache::Extractor;
use crate::events::Side;
use crate::kinematics::TrackKinematics;
use crate::query::Query;
use crate::rows::relation;

/// A per-box float of the kinematics (`speed`, `accel`, `lat_accel`, `yaw_rate`).
pub fn per_box(ex: &Extractor, q: &Query, field: fn(&TrackKinematics) -> &[f64]) -> RelationData {
    per_box_value(ex, q, |k, i| field(k)[i])
}

/// `forward_speed(X, T, V)`: the smoothed velocity projected on the box's heading, so a vehicle
/// moving backwards has a negative V. (The box heading is the annotated one; a box annotated
/// facing the wrong way reads as reversing: `reversing` asks for it to last.)
pub fn forward_speed(ex: &Extractor, q: &Query) -> RelationData {
    per_box_value(ex, q, |k, i| {
        let (v, yaw) = (k.vel[i], k.yaw[i]);
        v[0] * yaw.cos() + v[1] * yaw.sin()
    })
}

/// `(X, T, value(k, i))` for every box `i` the query allows, `k` its track's kinematics.
fn per_box_value(
    ex: &Extractor,
    q: &Query,
    value: impl Fn(&TrackKinematics, usize) -> f64,
) -> RelationData {
    let kin = ex.kinematics();
    let mut rows = Vec::new();
    for t in q.tracks(ex.scene(), 0) {
        let Some(k) = kin.tracks.get(t.index()) else {
            continue;
        };
        let r = q.box_range(1, ex.scene().num_frames(), &k.frames);
        rows.extend(r.map(|i| (t, k.frames[i], value(k, i))));
    }
    relation(q, rows)
}

/// `stationary(X)`.
pub fn stationary(ex: &Extractor, q: &Query) -> RelationData {
    let kin = ex.kinematics();
    let xs = q
        .tracks(ex.scene(), 0)
        .filter(|t| kin.tracks.get(t.index()).is_some_and(|k| k.stationary));
    relation(q, xs.map(|x| (x,)))
}

/// An event relation (`turning`, `lane_change`) from per-track (frame, side) lists.
pub fn events(ex: &Extractor, q: &Query, per_track: &[Vec<(Frame, Side)>]) -> RelationData {
    let (left, right) = (s("left"), s("right"));
    let mut rows = Vec::new();
    for t in q.tracks(ex.scene(), 0) {
        for &(f, side) in per_track.get(t.index()).map_or(&[][..], Vec::as_slice) {
            let side = match side {
                Side::Left => left.clone(),
                Side::Right => right.clone(),
            };
            rows.push((t, f, side));
        }
    }
    relation(q, rows)
}
