//! Evaluating at a chosen sampling rate (`scenalog eval --rate 2|10`) or at given timestamps
//! (`--timestamps FILE`), so one submission can be scored at 10 Hz and at 2 Hz.
//!
//! The ground truth decides the frames: at a rate, every k-th frame of each ground-truth sequence
//! from its first, k being the sequence's rate over the one asked for (10 Hz to 2 Hz: every 5th,
//! as RefAV's `get_eval_timestamps` takes `log_timestamps[::5]`); at given timestamps, the frames
//! listed for the sequence's log (RefAV's `eval_timestamps.json`: `{log_id: [timestamp_ns, …]}`).
//! The predictions keep the frames at the kept timestamps of their sequence, and must have every
//! one of them.

use crate::error::EvalError;
use crate::model::{FrameData, Submission};
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Which frames to evaluate.
#[derive(Debug, Clone, PartialEq)]
pub enum Sampling {
    /// Every frame of the ground truth at this rate (Hz); the ground truth's own rate must be a
    /// whole multiple of it.
    Rate(u32),
    /// The timestamps (ns) listed per log id.
    Timestamps(BTreeMap<String, BTreeSet<i64>>),
}

fn ferr(msg: String) -> EvalError {
    EvalError::Format(msg)
}

/// Reads a timestamps file: a JSON object of log id to a list of integer nanosecond timestamps.
pub fn read_timestamps(path: &Path) -> Result<BTreeMap<String, BTreeSet<i64>>, EvalError> {
    let name = path.display().to_string();
    // Through the one input reader: a FIFO or a device is an error naming it, not a hang, and
    // nothing is read past the text limit.
    let text = scenalog_input::read_text_file(path, scenalog_input::TEXT_LIMIT)
        .map_err(|p| EvalError::File(name.clone(), p))?;
    parse_timestamps(&text, &name)
}

/// Parses timestamps given as JSON text (see [`read_timestamps`]); `name` says where they came
/// from in errors.
pub fn parse_timestamps(
    text: &str,
    name: &str,
) -> Result<BTreeMap<String, BTreeSet<i64>>, EvalError> {
    let v: serde_json::Value =
        serde_json::from_str(text).map_err(|e| ferr(format!("{name}: not JSON: {e}")))?;
    let obj = v.as_object().ok_or_else(|| {
        ferr(format!(
            "{name}: expected an object of log id to a list of timestamps (ns)"
        ))
    })?;
    let mut out = BTreeMap::new();
    for (log, list) in obj {
        let list = list.as_array().ok_or_else(|| {
            ferr(format!(
                "{name}: log {log}: expected a list of timestamps (ns), got {list}"
            ))
        })?;
        let mut set = BTreeSet::new();
        for (i, t) in list.iter().enumerate() {
            let ns = t.as_i64().ok_or_else(|| {
                ferr(format!(
                    "{name}: log {log} entry {i}: expected an integer timestamp (ns), got {t}"
                ))
            })?;
            set.insert(ns);
        }
        out.insert(log.clone(), set);
    }
    Ok(out)
}

/// The frames per second of a sequence: one over its median frame gap; `None` below two frames.
fn rate_hz(frames: &[FrameData]) -> Option<f64> {
    let mut gaps: Vec<i64> = frames
        .windows(2)
        .map(|w| w[1].timestamp_ns - w[0].timestamp_ns)
        .collect();
    if gaps.is_empty() {
        return None;
    }
    gaps.sort_unstable();
    let median = gaps[gaps.len() / 2];
    (median > 0).then(|| 1e9 / median as f64)
}

/// The kept timestamps of one ground-truth sequence.
fn kept_timestamps(
    key: &(String, String),
    frames: &[FrameData],
    sampling: &Sampling,
) -> Result<BTreeSet<i64>, EvalError> {
    match sampling {
        Sampling::Rate(hz) => {
            if *hz == 0 {
                return Err(ferr("a sampling rate must be at least 1 Hz".into()));
            }
            let Some(have) = rate_hz(frames) else {
                return Ok(frames.iter().map(|f| f.timestamp_ns).collect());
            };
            let ratio = have / f64::from(*hz);
            let k = ratio.round();
            if k < 1.0 || (ratio - k).abs() > 0.2 {
                return Err(ferr(format!(
                    "ground truth: sequence {key:?} is at {have:.2} Hz, which cannot be sampled at {hz} Hz (its rate must be a whole multiple of it)"
                )));
            }
            let k = k as usize;
            Ok(frames.iter().step_by(k).map(|f| f.timestamp_ns).collect())
        }
        Sampling::Timestamps(by_log) => {
            let listed = by_log.get(&key.0).ok_or_else(|| {
                ferr(format!(
                    "timestamps: log {} of the ground truth's sequence {key:?} is not listed",
                    key.0
                ))
            })?;
            let have: BTreeSet<i64> = frames.iter().map(|f| f.timestamp_ns).collect();
            if let Some(missing) = listed.iter().find(|t| !have.contains(t)) {
                return Err(ferr(format!(
                    "ground truth: sequence {key:?} has no frame at listed timestamp {missing}"
                )));
            }
            Ok(listed.clone())
        }
    }
}

/// Keeps the frames `sampling` selects in both submissions (see the module comment). On an error
/// neither is changed; errors name the sequence and timestamp: a ground truth that cannot be sampled at the rate, a log or
/// timestamp missing, predictions without a frame at a kept timestamp.
pub fn resample(
    pred: &mut Submission,
    gt: &mut Submission,
    sampling: &Sampling,
) -> Result<(), EvalError> {
    let mut kept: BTreeMap<(String, String), BTreeSet<i64>> = BTreeMap::new();
    for (key, frames) in &gt.sequences {
        kept.insert(key.clone(), kept_timestamps(key, frames, sampling)?);
    }
    // Checked before anything is dropped, so an error leaves both submissions as they were.
    for (key, frames) in &pred.sequences {
        let Some(times) = kept.get(key) else {
            continue; // the evaluation reports sequences missing from the ground truth
        };
        let have: BTreeSet<i64> = frames.iter().map(|f| f.timestamp_ns).collect();
        if let Some(missing) = times.iter().find(|t| !have.contains(t)) {
            return Err(ferr(format!(
                "predictions: sequence {key:?} has no frame at timestamp {missing} (kept from the ground truth)"
            )));
        }
    }
    for (key, frames) in pred.sequences.iter_mut() {
        if let Some(times) = kept.get(key) {
            frames.retain(|f| times.contains(&f.timestamp_ns));
        }
    }
    for (key, frames) in gt.sequences.iter_mut() {
        if let Some(times) = kept.get(key) {
            frames.retain(|f| times.contains(&f.timestamp_ns));
        }
    }
    Ok(())
}
