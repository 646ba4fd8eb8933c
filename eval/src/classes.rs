//! The paper's further tracking columns: HOTA-Temporal of the related objects (label 1) and of the
//! other objects (label 2), and the tracker's plain HOTA over every object, labels ignored.
//!
//! Related and other objects are scored as av2 scored its `RELATED_OBJECT` and `OTHER_OBJECT`
//! classes until February 2026 (`evaluate_scenario_mining` with `classes = AV2_CATEGORIES`, the
//! code the RefAV paper's tables were made with): one class pooled over every (log, prompt)
//! sequence, its score threshold tuned over the 10 recall levels, HOTA combined over the
//! sequences. The per-prompt values are the same computation on one prompt's sequences. The
//! tracker's HOTA is the same again over every object, each log counted once (its first prompt's
//! sequence: a tracker's output is the same under every prompt of a log), as a tracking benchmark
//! scores a tracker with the classes merged. The official code never computed that one; it is
//! defined here as the paper describes it. `eval/README.md` says which is which.
//!
//! Objects are classed by their `label` (0 referred, 1 related, 2 other), as the current
//! official code reads a submission; the older code that computed the related and other columns
//! classed them by `name` (`RELATED_OBJECT`, `OTHER_OBJECT`). Where a file's name and label
//! disagree the two give different values, so every such file gets a warning
//! ([`label_name_mismatches`]).

use crate::filters::{pick, Filter, Pick};
use crate::model::{FrameData, Submission};
use crate::tuning::{tune, PromptHota};
use std::collections::BTreeMap;

/// One class's HOTA: pooled over every sequence, and per prompt. `None` where the ground truth
/// holds no object of the class (after the range and ROI filters).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ClassHota {
    /// Over every sequence (for the tracker's HOTA: every log once).
    pub overall: Option<PromptHota>,
    /// Per prompt of the ground truth.
    pub by_prompt: BTreeMap<String, Option<PromptHota>>,
}

impl ClassHota {
    /// The overall value, `None` where the class is absent from the ground truth.
    pub fn value(&self) -> Option<f64> {
        self.overall.as_ref().map(|h| h.value)
    }

    /// The per-prompt values as JSON: `{prompt: {"value", "score_threshold"} | null}`.
    pub fn by_prompt_json(&self) -> serde_json::Value {
        self.by_prompt
            .iter()
            .map(|(k, v)| {
                let v = match v {
                    Some(h) => {
                        serde_json::json!({ "value": h.value, "score_threshold": h.threshold })
                    }
                    None => serde_json::Value::Null,
                };
                (k.clone(), v)
            })
            .collect::<serde_json::Map<_, _>>()
            .into()
    }

    /// The per-prompt values alone: `{prompt: value | null}`.
    pub fn values_json(&self) -> serde_json::Value {
        self.by_prompt
            .iter()
            .map(|(k, v)| (k.clone(), serde_json::json!(v.as_ref().map(|h| h.value))))
            .collect::<serde_json::Map<_, _>>()
            .into()
    }
}

/// The three further columns of an evaluation, and what was noticed computing them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Further {
    /// HOTA-Temporal of the related objects (label 1).
    pub related: ClassHota,
    /// HOTA-Temporal of the other objects (label 2).
    pub other: ClassHota,
    /// The tracker's HOTA over every object, labels ignored.
    pub tracker: ClassHota,
    /// Things the caller should be told (e.g. a log whose sequences hold different objects).
    pub warnings: Vec<String>,
}

/// Computes the further columns; `fp` and `fg` are the filters of the predictions and the
/// ground truth.
pub(crate) fn further(pred: &Submission, gt: &Submission, fp: &Filter, fg: &Filter) -> Further {
    let score = |which: Pick| {
        let (p, g) = (pick(pred, fp, which), pick(gt, fg, which));
        class_hota(&p, &g, &pooled(&p), &pooled(&g))
    };
    let related = score(Pick::Label(1));
    let other = score(Pick::Label(2));
    let (p, g) = (pick(pred, fp, Pick::Every), pick(gt, fg, Pick::Every));
    let mut warnings = Vec::new();
    for (sub, what) in [(pred, "predictions"), (gt, "ground truth")] {
        if let Some(w) = label_name_mismatches(sub, what) {
            warnings.push(w);
        }
    }
    let (pl, gl) = (
        one_per_log(&p, "predictions", &mut warnings),
        one_per_log(&g, "ground truth", &mut warnings),
    );
    let tracker = class_hota(&p, &g, &pl, &gl);
    Further {
        related,
        other,
        tracker,
        warnings,
    }
}

/// The `name` av2 gives each `label` of a scenario-mining object.
pub const LABEL_NAMES: [&str; 3] = ["REFERRED_OBJECT", "RELATED_OBJECT", "OTHER_OBJECT"];

/// A warning when some of `sub`'s objects carry a `name` other than their `label`'s
/// ([`LABEL_NAMES`]): how many, and the first (log, prompt, timestamp, label, name).
pub fn label_name_mismatches(sub: &Submission, what: &str) -> Option<String> {
    let mut n = 0usize;
    let mut first = None;
    for ((log, prompt), frames) in &sub.sequences {
        for f in frames {
            for (l, name) in f.label.iter().zip(&f.name) {
                let want = usize::try_from(*l).ok().and_then(|i| LABEL_NAMES.get(i));
                if want != Some(&name.as_str()) {
                    n += 1;
                    first.get_or_insert_with(|| {
                        format!(
                            "log {log}, prompt {prompt:?}, {} ns: label {l}, name {name:?}",
                            f.timestamp_ns
                        )
                    });
                }
            }
        }
    }
    first.map(|f| {
        format!(
            "{what}: {n} object(s) whose name is not their label's (first: {f}); HOTA-Temporal of related and other objects classes them by label, where av2's older code classed them by name"
        )
    })
}

/// Per prompt of `gt` and overall (on `pooled_pred`/`pooled_gt`, whose sequences all carry the
/// prompt `""`), `None` where the ground truth holds no object.
fn class_hota(
    pred: &Submission,
    gt: &Submission,
    pooled_pred: &Submission,
    pooled_gt: &Submission,
) -> ClassHota {
    let present = objects_by_prompt(gt);
    let tuned = tune(pred, gt);
    let by_prompt = present
        .iter()
        .map(|(prompt, &n)| {
            let h = if n > 0 {
                tuned.get(prompt).cloned()
            } else {
                None
            };
            (prompt.clone(), h)
        })
        .collect();
    let any = present.values().any(|&n| n > 0);
    let overall = if any {
        tune(pooled_pred, pooled_gt).into_values().next()
    } else {
        None
    };
    ClassHota { overall, by_prompt }
}

/// Objects per prompt.
fn objects_by_prompt(sub: &Submission) -> BTreeMap<String, usize> {
    let mut n: BTreeMap<String, usize> = BTreeMap::new();
    for (k, frames) in &sub.sequences {
        *n.entry(k.1.clone()).or_default() += frames.iter().map(FrameData::len).sum::<usize>();
    }
    n
}

/// The same sequences under one prompt, `""`, so [`tune`] scores them as one class; the prompt
/// moves into the log id's slot so the keys stay distinct.
fn pooled(sub: &Submission) -> Submission {
    let sequences = sub
        .sequences
        .iter()
        .map(|((log, prompt), frames)| {
            (
                (format!("{log}\u{0}{prompt}"), String::new()),
                frames.clone(),
            )
        })
        .collect();
    Submission { sequences }
}

/// Every log once, under the prompt `""`: its first prompt's sequence. A later prompt of the same
/// log holding different objects (timestamps, track ids or positions) is reported in `warnings`.
fn one_per_log(sub: &Submission, what: &str, warnings: &mut Vec<String>) -> Submission {
    let mut out: BTreeMap<(String, String), Vec<FrameData>> = BTreeMap::new();
    let mut first_prompt: BTreeMap<&str, &str> = BTreeMap::new();
    for ((log, prompt), frames) in &sub.sequences {
        let key = (log.clone(), String::new());
        match out.get(&key) {
            None => {
                out.insert(key, frames.clone());
                first_prompt.insert(log, prompt);
            }
            Some(kept) => {
                if !same_objects(kept, frames) {
                    warnings.push(format!(
                        "{what}: log {log}: the sequence of prompt {prompt:?} holds other objects than that of {:?}; the tracker's HOTA uses the latter",
                        first_prompt.get(log.as_str()).copied().unwrap_or("")
                    ));
                }
            }
        }
    }
    Submission { sequences: out }
}

/// Whether two sequences hold the same frames and objects (timestamps, track ids, positions).
fn same_objects(a: &[FrameData], b: &[FrameData]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.timestamp_ns == y.timestamp_ns
                && x.track_id == y.track_id
                && x.translation_m == y.translation_m
                && x.score == y.score
        })
}
