//! RefAV's definitions, where they differ from Scenalog's: the relations `scenalog import refav
//! --semantics refav` targets so an imported program finds what RefAV's own code finds.
//! Each says which RefAV function (CainanD/RefAV 5c5be64, `refAV/atomic_functions.py`) it
//! reproduces; the differences from Scenalog's definitions are listed in `import/README.md`.
//!
//! - **`refav_turning`** (RefAV's `turning`): the yaw rate is RefAV's, unfiltered
//!   ([`rotvec_yaw_rate`]: central differences, one-sided at the ends, of the z component of
//!   the rotation vector of the box's full city-frame rotation, its roll and pitch included,
//!   not of the heading; near a zero rate the two can differ in sign). A run starts at index `s`; it grows while the rate at its end has the sign of
//!   the rate at `s` (a zero rate has no sign), and stops at the first sample that does not (or
//!   at the last sample), which it includes. The run's rates are summed times the track's first
//!   time step; more than 45° is a left turn over the whole run, less than −45° a right turn.
//!   The next run starts at the sample that stopped this one, so that sample belongs to both.
//!   (RefAV's rule for turns cut by the log's ends never adds a frame; it is not reproduced.)
//! - **`refav_turning_filtered`**: the same rule on the yaw rate median-filtered over 3 samples
//!   ([`turning_filtered`]): RefAV's `turning` without the split a one-frame heading spike causes.
//! - **`refav_order`** (the order of RefAV's candidates): the keys of
//!   `get_objects_of_category(Cat)` are the annotation file's `track_uuid.unique()` (each
//!   track's first row), for "VEHICLE" category by category in RefAV's list order (the
//!   catalog's [`VEHICLE_CATEGORIES`]), each in the file's order. A function that loops over
//!   candidates (`being_crossed_by`) depends on it.
//! - **`refav_crosswalk`** (RefAV's `at_pedestrian_crossing`): X's box as RefAV has it (the
//!   annotated row; the ego's at its rear axle) against each pedestrian crossing's polygon
//!   dilated as RefAV's `dilate_convex_polygon` does (every edge moved out by the distance, the
//!   corners mitred: the intersection of the edges' outer half-planes for a convex polygon).
//!   D is the least dilation at which the two touch ([`mitred_distance`]), 0 when they overlap;
//!   C the crossing's map id, so a program can follow which crossing (RefAV's loop defect).

use scenalog_facts::scene::{SUPER_CATEGORIES, VEHICLE_CATEGORIES};
use scenalog_facts::{Frame, Scene, Track, TrackId};

use crate::events::Side;

/// RefAV's turn threshold, degrees over a run.
pub const REFAV_TURN_ANGLE_DEG: f64 = 45.0;

/// The frames of one track's turns as RefAV's `turning` finds them, in frame order (a frame
/// can be both a left and a right turn's, at the sample where the rate changes sign).
pub fn turning(scene: &Scene, track: &Track) -> Vec<(Frame, Side)> {
    let rate: Vec<f64> = rotvec_yaw_rate(scene, track)
        .into_iter()
        .map(f64::to_degrees)
        .collect();
    turning_of(&frames_ns(scene, track), &rate)
}

/// [`turning`] on the yaw rate median-filtered over 3 samples (the ends kept), so a one-frame
/// heading spike, which moves the two rates beside it in opposite directions, does not split a
/// turn: RefAV's rule without its spike defect (`refav_turning_filtered`).
pub fn turning_filtered(scene: &Scene, track: &Track) -> Vec<(Frame, Side)> {
    let v: Vec<f64> = rotvec_yaw_rate(scene, track)
        .into_iter()
        .map(f64::to_degrees)
        .collect();
    let filtered: Vec<f64> = (0..v.len())
        .map(|i| {
            if i == 0 || i + 1 == v.len() {
                return v[i];
            }
            let mut w = [v[i - 1], v[i], v[i + 1]];
            w.sort_by(f64::total_cmp);
            w[1]
        })
        .collect();
    turning_of(&frames_ns(scene, track), &filtered)
}

/// Each box's frame and timestamp (ns; a frame outside the timeline, which a loaded scene does
/// not have, at 10 Hz).
pub(crate) fn frames_ns(scene: &Scene, track: &Track) -> Vec<(Frame, i64)> {
    track
        .boxes
        .iter()
        .map(|b| {
            let ns = scene
                .timeline
                .ns(b.frame)
                .unwrap_or(i64::from(b.frame) * 100_000_000);
            (b.frame, ns)
        })
        .collect()
}

/// RefAV's yaw rate of a track (its `get_nth_yaw_deriv(track, 1, coordinate_frame='self')`),
/// rad/s per box: the z component of the rotation vector (angle in [0, π]) of each box's
/// city-frame rotation, differenced between the boxes before and after (one-sided at the
/// ends), a jump of more than π taken the short way round, over the timestamps' difference.
pub fn rotvec_yaw_rate(scene: &Scene, track: &Track) -> Vec<f64> {
    let z: Vec<f64> = track
        .boxes
        .iter()
        .map(|b| b.city.rotation.scaled_axis().z)
        .collect();
    let ns = frames_ns(scene, track);
    let n = z.len();
    // One box: RefAV takes no difference and returns the angle itself.
    if n == 1 {
        return z;
    }
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            let mut d = z[b] - z[a];
            if d.abs() > std::f64::consts::PI {
                d -= std::f64::consts::TAU.copysign(d);
            }
            1e9 * d / (ns[b].1 - ns[a].1) as f64
        })
        .collect()
}

/// RefAV's run rule on the yaw rates `v` (degrees/s) of a track's samples at `frames` (frame,
/// timestamp in ns).
fn turning_of(frames: &[(Frame, i64)], v: &[f64]) -> Vec<(Frame, Side)> {
    let n = v.len();
    if n < 2 || frames.len() < 2 {
        return Vec::new();
    }
    // RefAV multiplies every rate by the track's first time step.
    let dt = (frames[1].1 - frames[0].1) as f64 / 1e9;
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
    for (i, &(f, _)) in frames.iter().enumerate() {
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

/// The least distance by which `poly` (a convex polygon, either winding, not closed) must be
/// dilated with mitred corners (its edges moved out by the distance) to touch the convex
/// quadrilateral `quad` (either winding), 0 when they overlap or touch. Over the quad, the
/// dilation needed at a point is the largest signed distance past the polygon's edge lines; off
/// the polygon its minimum lies on the quad's boundary, at a corner or where two edge lines'
/// distances are equal along a side. A boundary minimum above 0 with the polygon inside the quad
/// is an overlap too.
pub fn mitred_distance(poly: &[[f64; 2]], quad: &[[f64; 2]; 4]) -> f64 {
    if poly.len() < 3 {
        return f64::INFINITY;
    }
    let n = poly.len();
    let area: f64 = (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    // Outward unit normals and offsets: n·p - c is the signed distance past edge i's line.
    let lines: Vec<([f64; 2], f64)> = (0..n)
        .filter_map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let len = dx.hypot(dy);
            if len <= 0.0 {
                return None;
            }
            let nrm = if area > 0.0 {
                [dy / len, -dx / len]
            } else {
                [-dy / len, dx / len]
            };
            Some((nrm, nrm[0] * a[0] + nrm[1] * a[1]))
        })
        .collect();
    let need = |p: [f64; 2]| {
        lines
            .iter()
            .map(|(m, c)| m[0] * p[0] + m[1] * p[1] - c)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let mut best = quad.iter().map(|&p| need(p)).fold(f64::INFINITY, f64::min);
    for k in 0..4 {
        let (u, v) = (quad[k], quad[(k + 1) % 4]);
        let e = [v[0] - u[0], v[1] - u[1]];
        for i in 0..lines.len() {
            for j in i + 1..lines.len() {
                let (mi, ci) = lines[i];
                let (mj, cj) = lines[j];
                let g = [mi[0] - mj[0], mi[1] - mj[1]];
                let den = g[0] * e[0] + g[1] * e[1];
                if den.abs() < 1e-12 {
                    continue;
                }
                let s = (ci - cj - (g[0] * u[0] + g[1] * u[1])) / den;
                if (0.0..=1.0).contains(&s) {
                    best = best.min(need([u[0] + s * e[0], u[1] + s * e[1]]));
                }
            }
        }
    }
    if best <= 0.0 || convex_contains(quad, poly[0]) {
        0.0
    } else {
        best
    }
}

/// `p` lies in the convex quadrilateral `q` (either winding, boundary included).
fn convex_contains(q: &[[f64; 2]; 4], p: [f64; 2]) -> bool {
    let side = |k: usize| {
        let (a, b) = (q[k], q[(k + 1) % 4]);
        (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
    };
    let s: [f64; 4] = [side(0), side(1), side(2), side(3)];
    s.iter().all(|&v| v >= 0.0) || s.iter().all(|&v| v <= 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RefAV's run rule on these rates (degrees/s) at 10 Hz.
    fn turning(yaw_rate: &[f64]) -> Vec<(Frame, Side)> {
        let frames: Vec<(Frame, i64)> = (0..yaw_rate.len() as Frame)
            .map(|f| (f, i64::from(f) * 100_000_000))
            .collect();
        turning_of(&frames, yaw_rate)
    }

    #[test]
    fn a_one_sample_sign_flip_splits_a_turn() {
        // 30 samples at +20 deg/s (60°) make a left turn over all of them and the sample after.
        let mut w = vec![20.0; 30];
        w.push(-1.0);
        w.extend(vec![0.0; 5]);
        let t = turning(&w);
        assert_eq!(t.len(), 31, "{t:?}");
        assert!(t.iter().all(|&(_, s)| s == Side::Left));
        // One flipped sample in the middle: two runs of 15 samples (30° each), neither a turn.
        w[15] = -1.0;
        assert!(turning(&w).is_empty());
    }

    #[test]
    fn mitred_distance_grows_square_corners() {
        // A 4 m x 2 m crosswalk; a 1 m box 2 m beyond its right edge, and one 2 m beyond its
        // corner along both axes: mitred corners reach a box diagonal from the corner at the
        // same dilation as one straight out (2 m), where a round dilation needs 2.83 m.
        let cw = [[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]];
        let sq = |x: f64, y: f64| [[x, y], [x + 1.0, y], [x + 1.0, y + 1.0], [x, y + 1.0]];
        assert!((mitred_distance(&cw, &sq(6.0, 0.5)) - 2.0).abs() < 1e-12);
        assert!((mitred_distance(&cw, &sq(6.0, 4.0)) - 2.0).abs() < 1e-12);
        // Either winding; overlapping is 0.
        let mut rev = cw;
        rev.reverse();
        assert!((mitred_distance(&rev, &sq(6.0, 4.0)) - 2.0).abs() < 1e-12);
        assert_eq!(mitred_distance(&cw, &sq(1.0, 0.5)), 0.0);
        // Touching, crossing an edge, and the crosswalk inside a large box: all 0.
        assert_eq!(mitred_distance(&cw, &sq(4.0, 0.5)), 0.0);
        assert_eq!(mitred_distance(&cw, &sq(3.5, 1.5)), 0.0);
        let big = [[-1.0, -1.0], [5.0, -1.0], [5.0, 3.0], [-1.0, 3.0]];
        assert_eq!(mitred_distance(&cw, &big), 0.0);
        // A rotated box whose nearest point is on a side, not a corner: the diamond's left
        // corner at (6, 1) faces the edge x = 4 at 2 m.
        let diamond = [[6.0, 1.0], [7.0, 0.0], [8.0, 1.0], [7.0, 2.0]];
        assert!((mitred_distance(&cw, &diamond) - 2.0).abs() < 1e-12);
        // A square rotated 45° beside the corner (4, 2): its side from (5, 4) to (6, 3) meets
        // the corner's bisector at (5.5, 3.5), 1.5 m past both edges.
        let tilted = [[5.0, 4.0], [6.0, 3.0], [7.0, 4.0], [6.0, 5.0]];
        assert!((mitred_distance(&cw, &tilted) - 1.5).abs() < 1e-12);
    }

    #[test]
    fn the_last_sample_ends_a_run() {
        let t = turning(&[-20.0; 30]);
        assert_eq!(t.len(), 30);
        assert!(t.iter().all(|&(_, s)| s == Side::Right));
        assert!(turning(&[-20.0]).is_empty());
    }
}
