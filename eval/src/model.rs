//! The plain data model of a scenario-mining submission or ground truth.

use std::collections::BTreeMap;

/// One sequence key: (log id, prompt).
pub type SeqKey = (String, String);

/// One frame (timestamp) of a sequence: per-object arrays of equal length.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FrameData {
    /// Frame time in nanoseconds.
    pub timestamp_ns: i64,
    /// Ego position in the city frame.
    pub ego_translation_m: [f64; 3],
    /// The prompt text stored with the frame, if any.
    pub description: Option<String>,
    /// Box centres in the city frame.
    pub translation_m: Vec<[f64; 3]>,
    /// Box sizes (length, width, height).
    pub size: Vec<[f32; 3]>,
    /// Yaw in the city frame.
    pub yaw: Vec<f32>,
    /// Velocities.
    pub velocity_m_per_s: Vec<[f64; 3]>,
    /// 0 referred, 1 related, 2 other.
    pub label: Vec<i32>,
    /// Category names.
    pub name: Vec<String>,
    /// Track ids.
    pub track_id: Vec<i32>,
    /// Confidence scores (predictions only).
    pub score: Option<Vec<f32>>,
    /// Frame-level classification: `None` key absent, `Some(None)` ambiguous, `Some(Some(b))` a verdict.
    pub is_positive: Option<Option<bool>>,
}

impl FrameData {
    /// Number of objects in the frame.
    pub fn len(&self) -> usize {
        self.translation_m.len()
    }

    /// Whether the frame holds no objects.
    pub fn is_empty(&self) -> bool {
        self.translation_m.is_empty()
    }

    /// Keeps only the objects whose mask entry is true.
    pub fn retain(&mut self, mask: &[bool]) {
        fn keep<T: Clone>(v: &mut Vec<T>, mask: &[bool]) {
            let mut i = 0;
            v.retain(|_| {
                let k = mask.get(i).copied().unwrap_or(false);
                i += 1;
                k
            });
        }
        keep(&mut self.translation_m, mask);
        keep(&mut self.size, mask);
        keep(&mut self.yaw, mask);
        keep(&mut self.velocity_m_per_s, mask);
        keep(&mut self.label, mask);
        keep(&mut self.name, mask);
        keep(&mut self.track_id, mask);
        if let Some(s) = &mut self.score {
            keep(s, mask);
        }
    }
}

/// A whole submission or ground truth: sequences keyed by (log id, prompt), frames in time order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Submission {
    /// The sequences.
    pub sequences: BTreeMap<SeqKey, Vec<FrameData>>,
}
