//! From derived `referred` / `related` tuples to labelled objects per output frame.
//!
//! The rules: every run of consecutive referred frames of a track is dilated symmetrically until
//! it lasts at least [`MIN_RUN_SECONDS`] (only over frames where the track is annotated, and within
//! the log); a related object farther than [`MAX_RELATED_DISTANCE_M`] from its referred object at
//! that frame is dropped; frames are emitted at the benchmark's 2 Hz timestamps (the frames
//! holding data that are a multiple of [`EVAL_STRIDE`] on the 10 Hz grid: every fifth of a 10 Hz
//! log, every one of a 2 Hz tracker's, never a second down-sampling) or at a given list.

use std::collections::{BTreeMap, BTreeSet};

use scenalog_facts::{Frame, Scene, Timeline, TrackId};

/// A referred run shorter than this (seconds) is dilated symmetrically to this length.
pub const MIN_RUN_SECONDS: f64 = 1.5;
/// Related objects farther than this (metres, centre to centre) from their referred object are dropped.
pub const MAX_RELATED_DISTANCE_M: f64 = 50.0;
/// The benchmark's 2 Hz output: every 5th frame of the 10 Hz grid, from the first.
pub const EVAL_STRIDE: usize = 5;

/// The label of an object in a prediction frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Label {
    /// The object the description is about.
    Referred = 0,
    /// An object the referred one interacts with.
    Related = 1,
    /// Any other annotated object.
    Other = 2,
}

/// One output frame: every object annotated there, with its label.
#[derive(Debug, Clone, PartialEq)]
pub struct LabelledFrame {
    /// The frame.
    pub frame: Frame,
    /// Every track annotated at this frame, sorted by track id, with its label.
    pub objects: Vec<(TrackId, Label)>,
}

/// The default output frames of a scene: the frames holding data on the 2 Hz grid (a multiple
/// of [`EVAL_STRIDE`]): every 5th frame of a 10 Hz log, each frame of a 2 Hz input.
pub fn eval_frames(scene: &Scene) -> Vec<Frame> {
    scene
        .timeline
        .frames()
        .iter()
        .copied()
        .filter(|f| (*f as usize).is_multiple_of(EVAL_STRIDE))
        .collect()
}

/// Dilates the referred frames of one track: every run of consecutive frames (frames of the
/// timeline with none between them that holds data) lasting less than [`MIN_RUN_SECONDS`] grows
/// one frame of the timeline at a time on alternate sides (over frames where the track is
/// `present`) until it lasts that long or cannot grow.
pub fn dilate(
    frames: &BTreeSet<Frame>,
    present: &BTreeSet<Frame>,
    timeline: &Timeline,
) -> BTreeSet<Frame> {
    let ts = |f: Frame| timeline.ns(f);
    let mut out = frames.clone();
    let mut runs: Vec<(Frame, Frame)> = Vec::new();
    for &f in frames {
        match runs.last_mut() {
            Some((_, end)) if timeline.next(*end) == Some(f) => *end = f,
            _ => runs.push((f, f)),
        }
    }
    let min_ns = (MIN_RUN_SECONDS * 1e9).round() as i64;
    for (mut a, mut b) in runs {
        let mut left_turn = true;
        while let (Some(ta), Some(tb)) = (ts(a), ts(b)) {
            if tb - ta >= min_ns {
                break;
            }
            let left = timeline.previous(a).filter(|f| present.contains(f));
            let right = timeline.next(b).filter(|f| present.contains(f));
            match (left_turn, left, right) {
                (true, Some(l), _) | (false, Some(l), None) => a = l,
                (false, _, Some(r)) | (true, None, Some(r)) => b = r,
                _ => break,
            }
            left_turn = !left_turn;
        }
        out.extend(timeline.frames().iter().filter(|f| (a..=b).contains(*f)));
    }
    out
}

/// Turns derived tuples into labelled output frames.
///
/// `referred` holds `(track, frame)`, `related` holds `(referred track, related track, frame)`.
pub fn label_frames(
    scene: &Scene,
    referred: &[(TrackId, Frame)],
    related: &[(TrackId, TrackId, Frame)],
    output_frames: &[Frame],
) -> Vec<LabelledFrame> {
    let mut by_track: BTreeMap<TrackId, BTreeSet<Frame>> = BTreeMap::new();
    for &(t, f) in referred {
        by_track.entry(t).or_default().insert(f);
    }
    let mut referred_at: BTreeSet<(Frame, TrackId)> = BTreeSet::new();
    for (&track, frames) in &by_track {
        let present: BTreeSet<Frame> = scene.track(track).boxes.iter().map(|b| b.frame).collect();
        for f in dilate(frames, &present, &scene.timeline) {
            referred_at.insert((f, track));
        }
    }
    let mut related_at: BTreeSet<(Frame, TrackId)> = BTreeSet::new();
    for &(r, o, f) in related {
        let (Some(rb), Some(ob)) = (scene.track(r).box_at(f), scene.track(o).box_at(f)) else {
            continue;
        };
        let d = (rb.city_center() - ob.city_center()).xy().norm();
        if d <= MAX_RELATED_DISTANCE_M {
            related_at.insert((f, o));
        }
    }
    output_frames
        .iter()
        .map(|&frame| {
            let objects = scene
                .tracks
                .iter()
                .filter(|t| t.box_at(frame).is_some())
                .map(|t| {
                    let label = if referred_at.contains(&(frame, t.id)) {
                        Label::Referred
                    } else if related_at.contains(&(frame, t.id)) {
                        Label::Related
                    } else {
                        Label::Other
                    };
                    (t.id, label)
                })
                .collect();
            LabelledFrame { frame, objects }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ts(n: usize) -> Timeline {
        Timeline::new((0..n as i64).map(|i| i * 100_000_000).collect())
    }

    #[test]
    fn short_run_grows_symmetrically_to_one_and_a_half_seconds() {
        let present: BTreeSet<Frame> = (0..100).collect();
        let got = dilate(&[50].into_iter().collect(), &present, &ts(100));
        // 1.5 s at 10 Hz is 15 intervals: 16 frames, 8 on the left and 7 on the right.
        assert_eq!(got.len(), 16);
        assert_eq!(got.first(), Some(&42));
        assert_eq!(got.last(), Some(&57));
    }

    #[test]
    fn long_runs_are_unchanged_and_edges_push_to_the_other_side() {
        let present: BTreeSet<Frame> = (0..100).collect();
        let long: BTreeSet<Frame> = (10..40).collect();
        assert_eq!(dilate(&long, &present, &ts(100)), long);
        let got = dilate(&[0].into_iter().collect(), &present, &ts(100));
        assert_eq!(got, (0..16).collect());
    }

    #[test]
    fn dilation_stays_where_the_track_is_present() {
        let present: BTreeSet<Frame> = (48..53).collect();
        let got = dilate(&[50].into_iter().collect(), &present, &ts(100));
        assert_eq!(got, present);
    }
}
