//! Kinematics and events: `speed`, `accel`, `lat_accel`, `yaw_rate`, `forward_speed` (signed
//! along the heading), `total_turn` (the heading turned so far, unwrapped), `stationary`,
//! `turning`, `lane_change`.

use std::borrow::Cow;
use std::f64::consts::{PI, TAU};

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
    per_box_values(ex, q, |k| Cow::Borrowed(field(k)))
}

/// `forward_speed(X, T, V)`: the smoothed velocity projected on the box's heading, so a vehicle
/// moving backwards has a negative V. (The box heading is the annotated one; a box annotated
/// facing the wrong way reads as reversing: `reversing` asks for it to last.)
pub fn forward_speed(ex: &Extractor, q: &Query) -> RelationData {
    per_box_values(ex, q, |k| {
        let along = k.vel.iter().zip(&k.yaw);
        Cow::Owned(
            along
                .map(|(v, y)| v[0] * y.cos() + v[1] * y.sin())
                .collect(),
        )
    })
}

/// `total_turn(X, T, A)`: how far X's box heading has turned since its first box, in degrees,
/// counter-clockwise positive and unwrapped: each step between two boxes is taken the short way
/// round (at most 180°), so a U-turn changes it by about 180° and a full circle by 360°.
pub fn total_turn(ex: &Extractor, q: &Query) -> RelationData {
    per_box_values(ex, q, |k| {
        let mut turned = Vec::with_capacity(k.yaw.len());
        let mut sum = 0.0;
        for (i, y) in k.yaw.iter().enumerate() {
            if i > 0 {
                let step = (y - k.yaw[i - 1]).rem_euclid(TAU);
                sum += if step > PI { step - TAU } else { step };
            }
            turned.push(sum.to_degrees());
        }
        Cow::Owned(turned)
    })
}

/// `(X, T, v)` for every box the query allows, `v` the box's entry in `values(k)` (one per box
/// of the track, `k` its kinematics).
fn per_box_values<'k>(
    ex: &'k Extractor,
    q: &Query,
    values: impl Fn(&'k TrackKinematics) -> Cow<'k, [f64]>,
) -> RelationData {
    let kin = ex.kinematics();
    let mut rows = Vec::new();
    for t in q.tracks(ex.scene(), 0) {
        let Some(k) = kin.tracks.get(t.index()) else {
            continue;
        };
        let r = q.box_range(1, ex.scene().num_frames(), &k.frames);
        let values = values(k);
        rows.extend(r.filter_map(|i| Some((t, *k.frames.get(i)?, *values.get(i)?))));
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
