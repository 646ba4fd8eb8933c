//! Time: a log's annotation timestamps as frame indices 0..N and back to nanoseconds.

use crate::scene::Frame;

/// The annotation timestamps of a log, sorted ascending and distinct; frame `i` is `timestamps_ns[i]`.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Timeline {
    timestamps_ns: Vec<i64>,
}

impl Timeline {
    /// Builds a timeline from timestamps in any order; duplicates are merged.
    pub fn new(mut timestamps_ns: Vec<i64>) -> Self {
        timestamps_ns.sort_unstable();
        timestamps_ns.dedup();
        Timeline { timestamps_ns }
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.timestamps_ns.len()
    }

    /// Whether the log has no frame.
    pub fn is_empty(&self) -> bool {
        self.timestamps_ns.is_empty()
    }

    /// The frame of an annotation timestamp, if it is one.
    pub fn frame_of(&self, ns: i64) -> Option<Frame> {
        self.timestamps_ns
            .binary_search(&ns)
            .ok()
            .map(|i| i as Frame)
    }

    /// The timestamp (ns) of a frame.
    pub fn ns(&self, frame: Frame) -> Option<i64> {
        self.timestamps_ns.get(frame as usize).copied()
    }

    /// Seconds from the log's first timestamp to `frame`.
    pub fn seconds(&self, frame: Frame) -> Option<f64> {
        let first = *self.timestamps_ns.first()?;
        Some((self.ns(frame)? - first) as f64 * 1e-9)
    }

    /// All timestamps, in frame order.
    pub fn timestamps_ns(&self) -> &[i64] {
        &self.timestamps_ns
    }
}
