//! Kinematics and events: `speed`, `accel`, `lat_accel`, `yaw_rate`, `stationary`, `turning`,
//! `lane_change`.

use scenalog_facts::relation::{Column, RelationData};
use scenalog_facts::Frame;

use super::s;
use crate::cache::Extractor;
use crate::events::Side;
use crate::kinematics::TrackKinematics;
use crate::query::Query;

/// A per-box float of the kinematics (`speed`, `accel`, `lat_accel`, `yaw_rate`).
pub fn per_box(ex: &Extractor, q: &Query, field: fn(&TrackKinematics) -> &[f64]) -> RelationData {
    let kin = ex.kinematics();
    let (mut xs, mut ts, mut vs) = (Vec::new(), Vec::new(), Vec::new());
    for t in q.tracks(ex.scene(), 0) {
        let Some(k) = kin.tracks.get(t.index()) else {
            continue;
        };
        let r = q.box_range(1, ex.scene().num_frames(), &k.frames);
        for (&f, &v) in k.frames[r.clone()].iter().zip(&field(k)[r]) {
            xs.push(t);
            ts.push(f);
            vs.push(v);
        }
    }
    RelationData {
        name: q.spec.name.into(),
        columns: vec![Column::Track(xs), Column::Time(ts), Column::Float(vs)],
    }
}

/// `stationary(X)`.
pub fn stationary(ex: &Extractor, q: &Query) -> RelationData {
    let kin = ex.kinematics();
    let xs = q
        .tracks(ex.scene(), 0)
        .filter(|t| kin.tracks.get(t.index()).is_some_and(|k| k.stationary))
        .collect();
    RelationData {
        name: q.spec.name.into(),
        columns: vec![Column::Track(xs)],
    }
}

/// An event relation (`turning`, `lane_change`) from per-track (frame, side) lists.
pub fn events(ex: &Extractor, q: &Query, per_track: &[Vec<(Frame, Side)>]) -> RelationData {
    let (left, right) = (s("left"), s("right"));
    let (mut xs, mut ts, mut ds) = (Vec::new(), Vec::new(), Vec::new());
    for t in q.tracks(ex.scene(), 0) {
        for &(f, side) in per_track.get(t.index()).map_or(&[][..], Vec::as_slice) {
            xs.push(t);
            ts.push(f);
            ds.push(match side {
                Side::Left => left.clone(),
                Side::Right => right.clone(),
            });
        }
    }
    RelationData {
        name: q.spec.name.into(),
        columns: vec![Column::Track(xs), Column::Time(ts), Column::Str(ds)],
    }
}
