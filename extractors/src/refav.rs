//! RefAV's definitions, where they differ from Scenalog's: the relations `scenalog import refav
//! --semantics refav` targets so an imported program finds what RefAV's own code finds.
//! Each says which RefAV function (CainanD/RefAV 5c5be64, `refAV/atomic_functions.py`) it
//! reproduces; the differences from Scenalog's definitions are listed in `import/README.md`.
//!
//! - **`refav_turning`** (RefAV's `turning`): the yaw rate is RefAV's, unfiltered (central
//!   differences of the heading over real time, one-sided at the ends: the kinematics'
//!   `yaw_rate`). A run starts at index `s`; it grows while the rate at its end has the sign of
//!   the rate at `s` (a zero rate has no sign), and stops at the first sample that does not (or
//!   at the last sample), which it includes. The run's rates are summed times the track's first
//!   time step; more than 45° is a left turn over the whole run, less than −45° a right turn.
//!   The next run starts at the sample that stopped this one, so that sample belongs to both.
//!   (RefAV's rule for turns cut by the log's ends never adds a frame; it is not reproduced.)
//! - **`refav_order`** (the order of RefAV's candidates): the keys of
//!   `get_objects_of_category(Cat)` are the annotation file's `track_uuid.unique()` (each
//!   track's first row), for "VEHICLE" category by category in RefAV's list order (the
//!   catalog's [`VEHICLE_CATEGORIES`]), each in the file's order. A function that loops over
//!   candidates (`being_crossed_by`) depends on it.

use scenalog_facts::scene::{SUPER_CATEGORIES, VEHICLE_CATEGORIES};
use scenalog_facts::{Frame, Scene, TrackId};

use crate::events::Side;
use crate::kinematics::TrackKinematics;

/// RefAV's turn threshold, degrees over a run.
pub const REFAV_TURN_ANGLE_DEG: f64 = 45.0;

/// The frames of one track's turns as RefAV's `turning` finds them, in frame order (a frame
/// can be both a left and a right turn's, at the sample where the rate changes sign).
pub fn turning(t: &TrackKinematics) -> Vec<(Frame, Side)> {
    let v = &t.yaw_rate;
    let n = v.len();
    if n < 2 || t.times.len() < 2 {
        return Vec::new();
    }
    // RefAV multiplies every rate by the track's first time step.
    let dt = t.times[1] - t.times[0];
    let same_sign = |a: f64, b: f64| (a > 0.0 && b > 0.0) || (a < 0.0 && b < 0.0);
    let (mut left, mut right) = (vec![false; n], vec![false; n]);
    let (mut s, mut e) = (0, 0);
    while s < n - 1 {
        if same_sign(v[s], v[e]) && e < n - 1 {
            e += 1;
            continue;
        }
        let angle: f64 = v[s..=e].iter().map(|w| w * dt).sum();
        if angle > REFAV_TURN_ANGLE_DEG {
            left[s..=e].iter_mut().for_each(|b| *b = true);
        } else if angle < -REFAV_TURN_ANGLE_DEG {
            right[s..=e].iter_mut().for_each(|b| *b = true);
        }
        s = e;
        e += 1;
    }
    let mut out = Vec::new();
    for (i, &f) in t.frames.iter().enumerate() {
        if left[i] {
            out.push((f, Side::Left));
        }
        if right[i] {
            out.push((f, Side::Right));
        }
    }
    out
}

/// `refav_order(X, Cat, R)` rows: X's position (0 first) among the keys of RefAV's
/// `get_objects_of_category(Cat)` for Cat = X's category, "VEHICLE" (for a vehicle) and "ANY".
pub fn order(scene: &Scene) -> Vec<(TrackId, &str, i64)> {
    let mut by_file: Vec<&scenalog_facts::Track> = scene.tracks.iter().collect();
    by_file.sort_by_key(|t| t.file_order);
    let mut rows = Vec::with_capacity(scene.tracks.len() * 3);
    let mut per_category: std::collections::HashMap<&str, i64> = Default::default();
    for (i, t) in by_file.iter().enumerate() {
        let own = per_category.entry(t.category.as_str()).or_insert(0);
        rows.push((t.id, t.category.as_str(), *own));
        *own += 1;
        rows.push((t.id, SUPER_CATEGORIES[1], i as i64));
    }
    let vehicles = VEHICLE_CATEGORIES
        .iter()
        .flat_map(|c| by_file.iter().filter(move |t| t.category == *c));
    for (i, t) in vehicles.enumerate() {
        rows.push((t.id, SUPER_CATEGORIES[0], i as i64));
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    fn track(yaw_rate: Vec<f64>) -> TrackKinematics {
        let n = yaw_rate.len();
        TrackKinematics {
            frames: (0..n as Frame).collect(),
            times: (0..n).map(|i| i as f64 * 0.1).collect(),
            yaw_rate,
            ..TrackKinematics::default()
        }
    }

    #[test]
    fn a_one_sample_sign_flip_splits_a_turn() {
        // 30 samples at +20 deg/s (60°) make a left turn over all of them and the sample after.
        let mut w = vec![20.0; 30];
        w.push(-1.0);
        w.extend(vec![0.0; 5]);
        let t = turning(&track(w.clone()));
        assert_eq!(t.len(), 31, "{t:?}");
        assert!(t.iter().all(|&(_, s)| s == Side::Left));
        // One flipped sample in the middle: two runs of 15 samples (30° each), neither a turn.
        w[15] = -1.0;
        assert!(turning(&track(w)).is_empty());
    }

    #[test]
    fn the_last_sample_ends_a_run() {
        let t = turning(&track(vec![-20.0; 30]));
        assert_eq!(t.len(), 30);
        assert!(t.iter().all(|&(_, s)| s == Side::Right));
        assert!(turning(&track(vec![-20.0])).is_empty());
    }
}
