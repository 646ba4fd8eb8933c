//! Time: a log's timestamps as frames on its 10 Hz grid and back to nanoseconds.
//!
//! A frame is a fixed unit of time in rules, 0.1 s, whatever the rate of the input: the first
//! timestamp is frame 0 and each next one is as many frames later as whole tenths of a second
//! have passed (the gap to the previous timestamp rounded to 0.1 s, at least one frame). A 10 Hz
//! log's frames are 0, 1, 2, … as they always were; a 2 Hz tracker's (boxes every fifth sweep)
//! are 0, 5, 10, …, so `T + 10` is one second later in both. Frames between two timestamps hold
//! no data: [`Timeline::frames`] lists the ones that do.

use crate::ids::Frame;

/// One frame on the grid, in nanoseconds.
pub const FRAME_NS: i64 = 100_000_000;

/// The timestamps of a log, sorted ascending and distinct, and the frame of each.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Timeline {
    timestamps_ns: Vec<i64>,
    /// `frames[i]` is the frame of `timestamps_ns[i]`, strictly increasing from 0.
    frames: Vec<Frame>,
}

impl Timeline {
    /// Builds a timeline from timestamps in any order; duplicates are merged.
    pub fn new(mut timestamps_ns: Vec<i64>) -> Self {
        timestamps_ns.sort_unstable();
        timestamps_ns.dedup();
        let mut frames = Vec::with_capacity(timestamps_ns.len());
        let mut frame: Frame = 0;
        for (i, &ts) in timestamps_ns.iter().enumerate() {
            if i > 0 {
                let gap = ts.saturating_sub(timestamps_ns[i - 1]);
                // Rounded to whole frames, at least one (timestamps are distinct).
                let steps = (gap.saturating_add(FRAME_NS / 2) / FRAME_NS).max(1);
                frame = frame.saturating_add(Frame::try_from(steps).unwrap_or(Frame::MAX));
            }
            frames.push(frame);
        }
        Timeline {
            timestamps_ns,
            frames,
        }
    }

    /// Number of timestamps (frames that hold data).
    pub fn len(&self) -> usize {
        self.timestamps_ns.len()
    }

    /// Whether the log has no timestamp.
    pub fn is_empty(&self) -> bool {
        self.timestamps_ns.is_empty()
    }

    /// The length of the grid: the last frame plus one (equal to [`Timeline::len`] for a log
    /// with a timestamp every 0.1 s). Per-frame tables are sized by this.
    pub fn frame_count(&self) -> usize {
        self.frames.last().map_or(0, |&f| f as usize + 1)
    }

    /// The frames that hold data, ascending (`0..len` for a 10 Hz log).
    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// The frame of a timestamp, if it is one.
    pub fn frame_of(&self, ns: i64) -> Option<Frame> {
        self.timestamps_ns
            .binary_search(&ns)
            .ok()
            .map(|i| self.frames[i])
    }

    /// The timestamp (ns) of a frame, if the frame holds data.
    pub fn ns(&self, frame: Frame) -> Option<i64> {
        self.frames
            .binary_search(&frame)
            .ok()
            .map(|i| self.timestamps_ns[i])
    }

    /// Seconds from the log's first timestamp to `frame`, if the frame holds data.
    pub fn seconds(&self, frame: Frame) -> Option<f64> {
        let first = *self.timestamps_ns.first()?;
        Some((self.ns(frame)? - first) as f64 * 1e-9)
    }

    /// The frame that holds data before `frame`, if any.
    pub fn previous(&self, frame: Frame) -> Option<Frame> {
        let i = self.frames.partition_point(|&f| f < frame);
        i.checked_sub(1).map(|i| self.frames[i])
    }

    /// The frame that holds data after `frame`, if any.
    pub fn next(&self, frame: Frame) -> Option<Frame> {
        let i = self.frames.partition_point(|&f| f <= frame);
        self.frames.get(i).copied()
    }

    /// One value per frame of the grid from one per timestamp: a frame without data takes the
    /// value of the frame before it (so a per-frame table, e.g. the ego poses, is indexed by
    /// frame whatever the input's rate).
    pub fn per_frame<T: Clone>(&self, per_timestamp: &[T]) -> Vec<T> {
        let mut out = Vec::with_capacity(self.frame_count());
        for (i, &f) in self.frames.iter().enumerate() {
            let Some(v) = per_timestamp.get(i) else { break };
            while out.len() < f as usize {
                let fill = out.last().cloned().unwrap_or_else(|| v.clone());
                out.push(fill);
            }
            out.push(v.clone());
        }
        out
    }

    /// All timestamps, in frame order.
    pub fn timestamps_ns(&self) -> &[i64] {
        &self.timestamps_ns
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ten_hertz_frames_are_indices_and_two_hertz_frames_keep_tenths() {
        // AV2 sweeps are not exactly 0.1 s apart.
        let ten: Vec<i64> = (0..40).map(|i| 1_000 + i * 99_700_000).collect();
        let t = Timeline::new(ten.clone());
        assert_eq!(t.frames(), (0..40).collect::<Vec<Frame>>());
        assert_eq!(t.frame_count(), 40);
        let two: Vec<i64> = ten.iter().copied().step_by(5).collect();
        let t2 = Timeline::new(two.clone());
        assert_eq!(t2.frames(), [0, 5, 10, 15, 20, 25, 30, 35]);
        assert_eq!(t2.frame_count(), 36);
        assert_eq!(t2.len(), 8);
        assert_eq!(t2.frame_of(two[3]), Some(15));
        assert_eq!(t2.ns(15), Some(two[3]));
        assert_eq!(t2.ns(16), None);
        assert_eq!(t2.previous(15), Some(10));
        assert_eq!(t2.previous(12), Some(10));
        assert_eq!(t2.next(15), Some(20));
        assert_eq!(t2.next(35), None);
        assert!((t2.seconds(10).unwrap() - 0.997).abs() < 1e-9);
        let per = t2.per_frame(&two);
        assert_eq!(per.len(), 36);
        assert_eq!(per[15], two[3]);
        assert_eq!(per[17], two[3]);
        // A dropped 10 Hz frame leaves its frame empty.
        let dropped = Timeline::new(vec![0, FRAME_NS, 3 * FRAME_NS]);
        assert_eq!(dropped.frames(), [0, 1, 3]);
    }
}
