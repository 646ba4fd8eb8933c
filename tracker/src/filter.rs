//! The confidence filter for spurious tracks, applied before mining.

use std::collections::{BTreeMap, BTreeSet};

use crate::frames::Detections;

/// A track seen in one frame only is dropped when its score is at most this (RefAV's value).
pub const SINGLE_FRAME_MIN_SCORE: f32 = 0.05;
/// A longer track is dropped when its lowest score is at most this (RefAV's value).
pub const TRACK_MIN_SCORE: f32 = 0.005;

/// Which tracks to keep.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Filter {
    /// RefAV's: drop one-frame tracks scoring at most [`SINGLE_FRAME_MIN_SCORE`] and longer
    /// tracks whose lowest score is at most [`TRACK_MIN_SCORE`].
    #[default]
    RefAv,
    /// Keep every track.
    None,
}

/// The track ids of `frames` the filter keeps.
pub fn kept_tracks(frames: &[Detections], filter: Filter) -> BTreeSet<i64> {
    // Per track: frames seen, lowest score.
    let mut stats: BTreeMap<i64, (usize, f32)> = BTreeMap::new();
    for f in frames {
        for (&t, &s) in f.track_id.iter().zip(&f.score) {
            let e = stats.entry(t).or_insert((0, f32::INFINITY));
            e.0 += 1;
            e.1 = e.1.min(s);
        }
    }
    stats
        .into_iter()
        .filter(|&(_, (n, low))| match filter {
            Filter::None => true,
            Filter::RefAv if n == 1 => low > SINGLE_FRAME_MIN_SCORE,
            Filter::RefAv => low > TRACK_MIN_SCORE,
        })
        .map(|(t, _)| t)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(ids: &[i64], scores: &[f32]) -> Detections {
        Detections {
            track_id: ids.to_vec(),
            score: scores.to_vec(),
            ..Detections::default()
        }
    }

    #[test]
    fn refav_thresholds_at_their_boundaries() {
        let frames = [
            // 1: one frame at 0.05 (dropped); 2: one frame at 0.051 (kept);
            // 3: two frames, lowest 0.005 (dropped); 4: two frames, lowest 0.006 (kept).
            frame(&[1, 2, 3, 4], &[0.05, 0.051, 0.9, 0.9]),
            frame(&[3, 4], &[0.005, 0.006]),
        ];
        let kept = kept_tracks(&frames, Filter::RefAv);
        assert_eq!(kept.into_iter().collect::<Vec<_>>(), vec![2, 4]);
        let all = kept_tracks(&frames, Filter::None);
        assert_eq!(all.len(), 4);
    }
}
