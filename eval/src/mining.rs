//! The scenario-mining metrics: range filter, per-prompt score thresholds, HOTA-Temporal, HOTA-Track and
//! timestamp-/log-level balanced accuracy, in the order of operations of av2 0.3.6. With
//! [`EvalOptions::roi`], objects outside the drivable-area ROI are dropped after the range filter, as
//! the official `filter_drivable_area` (tracking submissions only).

use crate::classes::{self, Further};
use crate::error::EvalError;
use crate::filters::{referred, Filter};
use crate::hota;
use crate::model::Submission;
use crate::roi::RoiMaps;
use crate::tuning::tune;
pub use crate::tuning::PromptHota;
use std::collections::BTreeMap;
use std::sync::Arc;

/// Options of [`evaluate`].
#[derive(Debug, Clone)]
pub struct EvalOptions {
    /// Objects farther than this from the ego (x-y) are dropped; 50 m officially.
    pub max_range_m: f64,
    /// The drivable-area ROI of every log (the official `--dataset_dir`); `None` evaluates without it.
    pub roi: Option<Arc<RoiMaps>>,
}

impl Default for EvalOptions {
    fn default() -> Self {
        EvalOptions {
            max_range_m: 50.0,
            roi: None,
        }
    }
}

/// The evaluation result.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// Mean HOTA-Temporal over prompts.
    pub hota_temporal: f64,
    /// Mean HOTA-Track over prompts.
    pub hota_track: f64,
    /// Mean timestamp-level balanced accuracy over prompts.
    pub timestamp_ba: f64,
    /// Mean log-level balanced accuracy over prompts.
    pub log_ba: f64,
    /// Whether the predictions carried tracks (otherwise classification only, HOTA 0).
    pub contains_tracking: bool,
    /// HOTA-Temporal per prompt.
    pub hota_temporal_by_prompt: BTreeMap<String, PromptHota>,
    /// HOTA-Track per prompt.
    pub hota_track_by_prompt: BTreeMap<String, PromptHota>,
    /// Timestamp balanced accuracy per prompt.
    pub timestamp_ba_by_prompt: BTreeMap<String, f64>,
    /// Log balanced accuracy per prompt.
    pub log_ba_by_prompt: BTreeMap<String, f64>,
    /// HOTA-Temporal of the related and of the other objects and the tracker's HOTA
    /// ([`crate::classes`]).
    pub further: Further,
}

fn ferr(msg: String) -> EvalError {
    EvalError::Format(msg)
}

/// Checks that predictions and ground truth hold the same sequences and timestamps, in increasing order.
fn check_alignment(
    pred: &Submission,
    gt: &Submission,
    contains_tracking: bool,
) -> Result<(), EvalError> {
    for key in gt.sequences.keys() {
        if !pred.sequences.contains_key(key) {
            return Err(ferr(format!(
                "sequence {key:?} is in the ground truth but not in the predictions"
            )));
        }
    }
    for (what, sub) in [("predictions", pred), ("ground truth", gt)] {
        for (key, frames) in &sub.sequences {
            for (i, f) in frames.iter().enumerate() {
                let n = f.translation_m.len();
                let lens = [
                    ("label", f.label.len()),
                    ("track_id", f.track_id.len()),
                    ("score", f.score.as_ref().map_or(n, |s| s.len())),
                ];
                for (field, l) in lens {
                    if l != n {
                        return Err(ferr(format!(
                            "{what}: sequence {key:?} frame {i}: field {field:?} has {l} entries but translation_m has {n}"
                        )));
                    }
                }
            }
        }
    }
    for (key, pframes) in &pred.sequences {
        let Some(gframes) = gt.sequences.get(key) else {
            return Err(ferr(format!(
                "sequence {key:?} is in the predictions but not in the ground truth"
            )));
        };
        for (what, frames) in [("predictions", pframes), ("ground truth", gframes)] {
            for (i, w) in frames.windows(2).enumerate() {
                if w[1].timestamp_ns <= w[0].timestamp_ns {
                    return Err(ferr(format!(
                        "{what}: sequence {key:?} frame {}: timestamp_ns {} does not follow {}",
                        i + 1,
                        w[1].timestamp_ns,
                        w[0].timestamp_ns
                    )));
                }
            }
        }
        if pframes.len() != gframes.len() {
            return Err(ferr(format!(
                "sequence {key:?}: {} prediction frames but {} ground-truth frames",
                pframes.len(),
                gframes.len()
            )));
        }
        for (i, (p, g)) in pframes.iter().zip(gframes).enumerate() {
            if p.timestamp_ns != g.timestamp_ns {
                return Err(ferr(format!(
                    "sequence {key:?} frame {i}: prediction timestamp_ns {} but ground truth {}",
                    p.timestamp_ns, g.timestamp_ns
                )));
            }
            if contains_tracking && p.score.is_none() && !p.is_empty() {
                return Err(ferr(format!(
                    "predictions: sequence {key:?} frame {i}: field \"score\" missing"
                )));
            }
        }
    }
    Ok(())
}

/// Drops objects farther than `max_range_m` from the ego in x-y (inclusive), as `filter_max_dist`.
pub fn filter_range(sub: &mut Submission, max_range_m: f64) {
    for frames in sub.sequences.values_mut() {
        for f in frames {
            let e = f.ego_translation_m;
            let mask: Vec<bool> = f
                .translation_m
                .iter()
                .map(|t| {
                    let dx = t[0] - e[0];
                    let dy = t[1] - e[1];
                    (dx * dx + dy * dy).sqrt() <= max_range_m
                })
                .collect();
            f.retain(&mask);
        }
    }
}

/// Drops objects with no box corner in the drivable-area ROI of their log, as `filter_drivable_area`.
/// Errors when a log has no raster or a frame lacks sizes or yaws.
pub fn filter_roi(sub: &mut Submission, maps: &RoiMaps) -> Result<(), EvalError> {
    check_roi_sub("submission", sub, maps)?;
    for (key, frames) in sub.sequences.iter_mut() {
        let Some(r) = maps.get(&key.0) else { continue };
        for f in frames {
            let mask: Vec<bool> = (0..f.len())
                .map(|i| r.box_in_roi(f.translation_m[i], f.size[i], f.yaw[i]))
                .collect();
            f.retain(&mask);
        }
    }
    Ok(())
}

#[derive(Default, Clone, Copy)]
struct Confusion {
    tp: u64,
    fp: u64,
    tn: u64,
    fn_: u64,
}

fn safe_rate(n: u64, d: u64) -> f64 {
    if d == 0 {
        1.0
    } else {
        n as f64 / d as f64
    }
}

fn ba(c: Confusion) -> f64 {
    (safe_rate(c.tp, c.tp + c.fn_) + safe_rate(c.tn, c.tn + c.fp)) / 2.0
}

/// Timestamp- and log-level balanced accuracy per prompt (`compute_temporal_metrics`); `thresholds` filters
/// prediction objects by score when given.
fn temporal(
    pred: &Submission,
    gt: &Submission,
    thresholds: Option<&BTreeMap<String, PromptHota>>,
) -> (BTreeMap<String, f64>, BTreeMap<String, f64>) {
    let mut ts: BTreeMap<String, Confusion> = BTreeMap::new();
    let mut sc: BTreeMap<String, Confusion> = BTreeMap::new();
    for (key, gframes) in &gt.sequences {
        let prompt = &key.1;
        ts.entry(prompt.clone()).or_default();
        sc.entry(prompt.clone()).or_default();
        let th = thresholds.and_then(|t| t.get(prompt)).map(|p| p.threshold);
        let pframes = pred.sequences.get(key);
        let mut any_gt = false;
        let mut any_pred = false;
        let mut all_ambiguous = true;
        let mut c = Confusion::default();
        for (j, g) in gframes.iter().enumerate() {
            let gt_pos = match g.is_positive {
                Some(None) => None,
                Some(Some(b)) => Some(b),
                None => Some(g.label.contains(&0)),
            };
            let p = pframes.and_then(|f| f.get(j));
            let pred_pos = p.is_some_and(|p| {
                p.is_positive == Some(Some(true))
                    || p.label.iter().enumerate().any(|(i, &l)| {
                        l == 0
                            && match (th, &p.score) {
                                (Some(th), Some(s)) => s[i] as f64 >= th,
                                _ => true,
                            }
                    })
            });
            any_pred |= pred_pos;
            let Some(gp) = gt_pos else { continue };
            all_ambiguous = false;
            any_gt |= gp;
            match (gp, pred_pos) {
                (true, true) => c.tp += 1,
                (false, true) => c.fp += 1,
                (true, false) => c.fn_ += 1,
                (false, false) => c.tn += 1,
            }
        }
        if all_ambiguous {
            continue;
        }
        let t = ts.entry(prompt.clone()).or_default();
        t.tp += c.tp;
        t.fp += c.fp;
        t.fn_ += c.fn_;
        t.tn += c.tn;
        let s = sc.entry(prompt.clone()).or_default();
        match (any_pred, any_gt) {
            (true, true) => s.tp += 1,
            (true, false) => s.fp += 1,
            (false, true) => s.fn_ += 1,
            (false, false) => s.tn += 1,
        }
    }
    (
        ts.into_iter().map(|(k, c)| (k, ba(c))).collect(),
        sc.into_iter().map(|(k, c)| (k, ba(c))).collect(),
    )
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let v: Vec<f64> = v.collect();
    if v.is_empty() {
        return f64::NAN;
    }
    hota::np_sum(&v) / v.len() as f64
}

/// Checks that every log has an ROI raster and every frame the box sizes and yaws the ROI test needs.
fn check_roi_inputs(pred: &Submission, gt: &Submission, maps: &RoiMaps) -> Result<(), EvalError> {
    check_roi_sub("ground truth", gt, maps)?;
    check_roi_sub("predictions", pred, maps)
}

fn check_roi_sub(what: &str, sub: &Submission, maps: &RoiMaps) -> Result<(), EvalError> {
    for (key, frames) in &sub.sequences {
        if maps.get(&key.0).is_none() {
            return Err(ferr(format!(
                    "{what}: sequence {key:?}: log {} has no drivable-area map (not in the dataset directory)",
                    key.0
                )));
        }
        for (i, f) in frames.iter().enumerate() {
            let n = f.translation_m.len();
            for (field, l) in [("size", f.size.len()), ("yaw", f.yaw.len())] {
                if l != n {
                    return Err(ferr(format!(
                            "{what}: sequence {key:?} frame {i}: field {field:?} has {l} entries but translation_m has {n} (the ROI filter needs it)"
                        )));
                }
            }
        }
    }
    Ok(())
}

/// Evaluates predictions against ground truth as `av2.evaluation.scenario_mining.eval.evaluate`
/// (objective HOTA; the drivable-area filter when [`EvalOptions::roi`] is given).
pub fn evaluate(
    pred: &Submission,
    gt: &Submission,
    opts: &EvalOptions,
) -> Result<Report, EvalError> {
    let contains_tracking = pred
        .sequences
        .values()
        .flatten()
        .any(|f| f.is_positive.is_none() || !f.track_id.is_empty());
    check_alignment(pred, gt, contains_tracking)?;
    if !contains_tracking {
        let (ts, sc) = temporal(
            &referred(pred, &Filter::Range(f64::INFINITY), false),
            &referred(gt, &Filter::Range(f64::INFINITY), false),
            None,
        );
        // No objects predicted: 0 where the ground truth holds the class (within range; the ROI
        // is not applied, as the predictions carry no boxes to check it with).
        let range = Filter::Range(opts.max_range_m);
        let further = classes::further(pred, gt, &range, &range);
        return Ok(Report {
            hota_temporal: 0.0,
            hota_track: 0.0,
            timestamp_ba: mean(ts.values().copied()),
            log_ba: mean(sc.values().copied()),
            contains_tracking,
            hota_temporal_by_prompt: BTreeMap::new(),
            hota_track_by_prompt: BTreeMap::new(),
            timestamp_ba_by_prompt: ts,
            log_ba_by_prompt: sc,
            further,
        });
    }
    let r = opts.max_range_m;
    let roi = opts.roi.as_deref();
    if let Some(maps) = roi {
        check_roi_inputs(pred, gt, maps)?;
    }
    let (fp, fg) = (Filter::new(pred, r, roi), Filter::new(gt, r, roi));
    let (pr, gr) = (referred(pred, &fp, false), referred(gt, &fg, false));
    let temporal_h = tune(&pr, &gr);
    let (ts, sc) = temporal(&pr, &gr, Some(&temporal_h));
    let (pf, gf) = (referred(pred, &fp, true), referred(gt, &fg, true));
    let track_h = tune(&pf, &gf);
    let further = classes::further(pred, gt, &fp, &fg);
    Ok(Report {
        hota_temporal: mean(temporal_h.values().map(|h| h.value)),
        hota_track: mean(track_h.values().map(|h| h.value)),
        timestamp_ba: mean(ts.values().copied()),
        log_ba: mean(sc.values().copied()),
        contains_tracking,
        hota_temporal_by_prompt: temporal_h,
        hota_track_by_prompt: track_h,
        timestamp_ba_by_prompt: ts,
        log_ba_by_prompt: sc,
        further,
    })
}

impl Report {
    /// The report as JSON: the four headline numbers (`hota_temporal`, `hota_track`, `timestamp_ba`,
    /// `log_ba`), the further three (`hota_temporal_related`, `hota_temporal_other`, `hota`; `null`
    /// where the ground truth holds no such object), `hota_mean_over_thresholds` (the tracker's
    /// HOTA averaged over the 10 score thresholds, as av2's tracking evaluation has it, where
    /// `hota` takes the best), per-prompt values and `warnings`.
    pub fn to_json(&self) -> serde_json::Value {
        let hota = |m: &BTreeMap<String, PromptHota>| -> serde_json::Value {
            m.iter()
                .map(|(k, v)| {
                    (
                        k.clone(),
                        serde_json::json!({ "value": v.value, "score_threshold": v.threshold }),
                    )
                })
                .collect::<serde_json::Map<_, _>>()
                .into()
        };
        serde_json::json!({
            "hota_temporal": self.hota_temporal,
            "hota_track": self.hota_track,
            "timestamp_ba": self.timestamp_ba,
            "log_ba": self.log_ba,
            "contains_tracking": self.contains_tracking,
            "hota_temporal_by_prompt": hota(&self.hota_temporal_by_prompt),
            "hota_track_by_prompt": hota(&self.hota_track_by_prompt),
            "timestamp_ba_by_prompt": self.timestamp_ba_by_prompt,
            "log_ba_by_prompt": self.log_ba_by_prompt,
            "hota_temporal_related": self.further.related.value(),
            "hota_temporal_other": self.further.other.value(),
            "hota": self.further.tracker.value(),
            "hota_mean_over_thresholds": self.further.tracker.overall.as_ref().map(|h| h.mean_over_thresholds),
            "hota_temporal_related_by_prompt": self.further.related.by_prompt_json(),
            "hota_temporal_other_by_prompt": self.further.other.by_prompt_json(),
            "hota_by_prompt": self.further.tracker.by_prompt_json(),
            "warnings": self.further.warnings,
        })
    }

    /// The further columns as `--out` writes them (`paper_metrics.json`): the three values and
    /// `{prompt: value | null}` for each.
    pub fn paper_json(&self) -> serde_json::Value {
        let f = &self.further;
        serde_json::json!({
            "hota_temporal_related": f.related.value(),
            "hota_temporal_other": f.other.value(),
            "hota": f.tracker.value(),
            "hota_temporal_related_by_prompt": f.related.values_json(),
            "hota_temporal_other_by_prompt": f.other.values_json(),
            "hota_by_prompt": f.tracker.values_json(),
        })
    }
}

impl Report {
    /// The official output files' content: (`temporal_metrics.json`, `spatiotemporal_metrics.json`, the
    /// latter only when the predictions carried tracks).
    pub fn official_json(&self) -> (serde_json::Value, Option<serde_json::Value>) {
        let temporal = serde_json::json!({
            "timestamp_balanced_accuracy_class_avg": self.timestamp_ba,
            "scenario_balanced_accuracy_class_avg": self.log_ba,
            "timestamp_balanced_accuracy_by_class": self.timestamp_ba_by_prompt,
            "scenario_balanced_accuracy_by_class": self.log_ba_by_prompt,
        });
        let by = |m: &BTreeMap<String, PromptHota>| -> BTreeMap<String, f64> {
            m.iter().map(|(k, v)| (k.clone(), v.value)).collect()
        };
        let spatio = self.contains_tracking.then(|| {
            serde_json::json!({
                "hota_temporal_class_avg": self.hota_temporal,
                "hota_track_class_avg": self.hota_track,
                "hota_temporal_by_class": by(&self.hota_temporal_by_prompt),
                "hota_track_by_class": by(&self.hota_track_by_prompt),
            })
        });
        (temporal, spatio)
    }
}
