//! The road across a lane: how many lanes run each way beside it, counted along a line square to
//! the lane at its middle, from kerb to kerb (`road_lanes`).
//!
//! AV2's neighbour links often stop at the centre line (two lanes of opposite directions are
//! neighbours in some maps and not in others), so the count is taken from the geometry: the
//! line is walked in steps of [`STEP_M`] each way from the lane's middle until it leaves the
//! drivable area (a kerb or a median that is not paved) or reaches [`REACH_M`]; each run of
//! steps inside the same lanes (a lane and the lanes overlapping it where the road splits) is
//! one lane, counted for the direction it runs.

use super::geometry::{heading, nearest_on_polyline, polyline_length, Pt};
use super::index::MapIndex;
use crate::kinematics::wrap_angle;

/// The step along the cross line, metres (lanes are 2.5-4 m wide).
const STEP_M: f64 = 0.25;

/// How far either way from the lane's middle the cross line reaches, metres (eight lanes of
/// 3.75 m).
const REACH_M: f64 = 30.0;

/// A lane runs the same way when its direction at the cross line is within this of the lane's,
/// the opposite way within this of the reverse, degrees.
const PARALLEL_MAX_DEG: f64 = 30.0;

/// Lanes across the road at lane `i`'s middle: (same direction, opposite direction), lane `i`
/// included; `None` for an intersection lane (no road runs one way through an intersection) or a
/// lane without a centre line.
pub fn lanes_across(index: &MapIndex, i: usize, is_intersection: &[bool]) -> Option<(i64, i64)> {
    if is_intersection.get(i).copied().unwrap_or(true) {
        return None;
    }
    let line = &index.lanes[i].centerline;
    let (mid, dir) = middle(line)?;
    let normal = [-dir.sin(), dir.cos()];
    let (mut same, mut opposite) = (1, 0);
    for sign in [1.0, -1.0] {
        // The lanes at the previous step, and the run they belong to.
        let mut prev: Vec<usize> = vec![i];
        let steps = (REACH_M / STEP_M) as usize;
        for k in 1..=steps {
            let d = sign * STEP_M * k as f64;
            let p = [mid[0] + normal[0] * d, mid[1] + normal[1] * d];
            let here: Vec<usize> = index
                .lanes_containing(p)
                .into_iter()
                .filter(|&j| !is_intersection.get(j).copied().unwrap_or(true))
                .collect();
            if here.is_empty() {
                if !index.in_drivable_area(p) {
                    break;
                }
                prev.clear();
                continue;
            }
            if here.iter().any(|j| prev.contains(j)) {
                prev = here;
                continue;
            }
            // A new lane begins: counted for the way the first of them runs here.
            match way(index, here[0], p, dir) {
                Some(true) => same += 1,
                Some(false) => opposite += 1,
                None => {}
            }
            prev = here;
        }
    }
    Some((same, opposite))
}

/// The middle point of a centre line and the line's heading there.
fn middle(line: &[Pt]) -> Option<(Pt, f64)> {
    if line.len() < 2 {
        return None;
    }
    let mut left = polyline_length(line) / 2.0;
    for w in line.windows(2) {
        let len = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
        if left <= len && len > 0.0 {
            let f = left / len;
            let p = [
                w[0][0] + f * (w[1][0] - w[0][0]),
                w[0][1] + f * (w[1][1] - w[0][1]),
            ];
            return Some((p, heading(w[0], w[1])));
        }
        left -= len;
    }
    None
}

/// Whether lane `j` runs the same way as `dir` at `p` (`Some(true)`), the opposite way
/// (`Some(false)`), or crosswise (`None`).
fn way(index: &MapIndex, j: usize, p: Pt, dir: f64) -> Option<bool> {
    let line = &index.lanes[j].centerline;
    let (s, _, _) = nearest_on_polyline(line, p)?;
    let diff = wrap_angle(heading(line[s], line[s + 1]) - dir)
        .to_degrees()
        .abs();
    if diff <= PARALLEL_MAX_DEG {
        Some(true)
    } else if diff >= 180.0 - PARALLEL_MAX_DEG {
        Some(false)
    } else {
        None
    }
}
