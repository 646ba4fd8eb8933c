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

impl Submission {
    /// Checks what every reader of a submission or ground truth must refuse, naming the place:
    /// a log id that is not a plain directory name ([`scenalog_input::check_log_id`]: the
    /// evaluation joins ids to `--dataset-dir`), and NaN or infinite numbers in a box, a score
    /// or the ego's position (they would shift the scores in silence). `what` names the file.
    pub fn validate(&self, what: &str) -> Result<(), crate::EvalError> {
        for ((log, prompt), frames) in &self.sequences {
            scenalog_input::check_log_id(log)
                .map_err(|e| crate::EvalError::Format(format!("{what}: {e}")))?;
            for (i, f) in frames.iter().enumerate() {
                if let Some((field, object)) = f.first_non_finite() {
                    let at = match object {
                        Some(j) => format!(" object {j}"),
                        None => String::new(),
                    };
                    return Err(crate::EvalError::Format(format!(
                        "{what}: sequence ({log:?}, {prompt:?}) frame {i} (timestamp_ns {}) \
                         field {field:?}{at}: NaN or infinite value (every number of a box must \
                         be finite)",
                        f.timestamp_ns
                    )));
                }
            }
        }
        Ok(())
    }
}

impl FrameData {
    /// The first field (and object index) holding a NaN or an infinity, if any.
    fn first_non_finite(&self) -> Option<(&'static str, Option<usize>)> {
        if self.ego_translation_m.iter().any(|x| !x.is_finite()) {
            return Some(("ego_translation_m", None));
        }
        let rows3 = |v: &[[f64; 3]]| v.iter().position(|r| r.iter().any(|x| !x.is_finite()));
        let rows = |v: &[f32]| v.iter().position(|x| !x.is_finite());
        if let Some(j) = rows3(&self.translation_m) {
            return Some(("translation_m", Some(j)));
        }
        if let Some(j) = self
            .size
            .iter()
            .position(|r| r.iter().any(|x| !x.is_finite()))
        {
            return Some(("size", Some(j)));
        }
        if let Some(j) = rows(&self.yaw) {
            return Some(("yaw", Some(j)));
        }
        if let Some(j) = rows3(&self.velocity_m_per_s) {
            return Some(("velocity_m_per_s", Some(j)));
        }
        if let Some(j) = self.score.as_deref().and_then(rows) {
            return Some(("score", Some(j)));
        }
        None
    }
}
