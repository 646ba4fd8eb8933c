//! Lane assignment: which lane segment each track's centre is in at each of its frames.
//!
//! The types here are the contract between map extraction and pair extraction.

use scenalog_facts::{LaneId, Scene};

use crate::kinematics::{Kinematics, TrackKinematics};
use crate::map::index::MapIndex;
use crate::thresholds::{LANE_TURN_MIN_DEG, TRACK_TURN_MIN_YAW_RATE_DEG_S};

/// Per track (indexed by `TrackId::index()`), per box (same order as `Track::boxes`): the lane the
/// track is assigned to at that frame, if its centre is in any lane.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LaneAssignment {
    /// `lanes[track][box]`.
    pub lanes: Vec<Vec<Option<LaneId>>>,
}

/// Assigns lanes to every track (builds the map index; see [`assign_with`] to reuse one).
pub fn assign(scene: &Scene, kin: &Kinematics) -> LaneAssignment {
    assign_with(&MapIndex::new(&scene.map), kin)
}

/// Assigns lanes to every track of `kin` using a prepared map index.
///
/// Per box, the candidates are the lanes whose polygon contains the raw city-frame centre. A track
/// keeps its current lane while that lane is a candidate; otherwise it takes the candidate that
/// stays a candidate for the most consecutive boxes, ties broken by the lane's turn direction
/// (left/right/straight, [`LANE_TURN_MIN_DEG`]) agreeing with the track's mean yaw rate over that
/// run ([`TRACK_TURN_MIN_YAW_RATE_DEG_S`]), then by the lower lane id.
pub fn assign_with(index: &MapIndex, kin: &Kinematics) -> LaneAssignment {
    use rayon::prelude::*;
    let lanes = kin
        .tracks
        .par_iter()
        .map(|t| assign_track(index, t))
        .collect();
    LaneAssignment { lanes }
}

fn turn_class(value: f64, threshold: f64) -> i8 {
    if value > threshold {
        1
    } else if value < -threshold {
        -1
    } else {
        0
    }
}

/// Lane indices (into the map's lanes) per box of one track.
pub fn assign_track_indices(index: &MapIndex, t: &TrackKinematics) -> Vec<Option<usize>> {
    let n = t.center.len();
    let cands: Vec<Vec<usize>> = t
        .center
        .iter()
        .map(|&c| index.lanes_containing(c))
        .collect();
    // run[i][k]: how many consecutive boxes from i lane cands[i][k] stays a candidate.
    let mut run: Vec<Vec<usize>> = vec![Vec::new(); n];
    for i in (0..n).rev() {
        run[i] = cands[i]
            .iter()
            .map(|l| {
                let next = (i + 1 < n)
                    .then(|| cands[i + 1].iter().position(|m| m == l))
                    .flatten()
                    .map_or(0, |k| run[i + 1][k]);
                1 + next
            })
            .collect();
    }
    let mut out = Vec::with_capacity(n);
    let mut cur: Option<usize> = None;
    for i in 0..n {
        if let Some(c) = cur.filter(|c| cands[i].contains(c)) {
            out.push(Some(c));
            continue;
        }
        let best = cands[i]
            .iter()
            .zip(&run[i])
            .map(|(&l, &len)| {
                let end = (i + len).min(n);
                let mean_rate = t.yaw_rate[i..end].iter().sum::<f64>() / len.max(1) as f64;
                let agree = turn_class(index.lanes[l].turn_deg, LANE_TURN_MIN_DEG)
                    == turn_class(mean_rate, TRACK_TURN_MIN_YAW_RATE_DEG_S);
                (l, len, agree)
            })
            .max_by(|a, b| {
                a.1.cmp(&b.1)
                    .then(a.2.cmp(&b.2))
                    .then(index.lanes[b.0].id.cmp(&index.lanes[a.0].id))
            })
            .map(|(l, _, _)| l);
        if best.is_some() {
            cur = best;
        }
        out.push(best);
    }
    out
}

fn assign_track(index: &MapIndex, t: &TrackKinematics) -> Vec<Option<LaneId>> {
    assign_track_indices(index, t)
        .into_iter()
        .map(|l| l.map(|k| index.lanes[k].id))
        .collect()
}
