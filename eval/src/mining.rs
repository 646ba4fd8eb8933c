//! The scenario-mining metrics: range filter, per-prompt score thresholds, HOTA-Temporal, HOTA-Track and
//! timestamp-/log-level balanced accuracy, in the order of operations of av2 0.3.6. With
//! [`EvalOptions::roi`], objects outside the drivable-area ROI are dropped after the range filter, as
//! the official `filter_drivable_area` (tracking submissions only).

use crate::classes::{self, Further};
use crate::error::EvalError;
use crate::hota::{self, ClassFrame, Hota};
use crate::model::{FrameData, SeqKey, Submission};
use crate::roi::{RoiMaps, RoiRaster};
use rayon::prelude::*;
use std::collections::{BTreeMap, BTreeSet};
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

/// Per-prompt results of one HOTA variant.
#[derive(Debug, Clone, PartialEq)]
pub struct PromptHota {
    /// The chosen score threshold.
    pub threshold: f64,
    /// max(0, best mean HOTA over the thresholds).
    pub value: f64,
    /// The detail at the chosen threshold.
    pub detail: Hota,
    /// The 10 candidate thresholds (recall 1.0 down to 0.1).
    pub candidates: Vec<f64>,
    /// max(0, the mean HOTA over the 10 candidate thresholds, each counted once a candidate):
    /// how av2's tracking evaluation summarises its score thresholds, where [`Self::value`]
    /// takes the best (the scenario-mining metrics' tuning).
    pub mean_over_thresholds: f64,
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

/// Copies of the frames holding only the objects `keep(frame, object)` selects.
fn select(frames: &[FrameData], keep: impl Fn(usize, &FrameData, usize) -> bool) -> Vec<FrameData> {
    frames
        .iter()
        .enumerate()
        .map(|(j, f)| {
            let idx: Vec<usize> = (0..f.len()).filter(|&i| keep(j, f, i)).collect();
            FrameData {
                timestamp_ns: f.timestamp_ns,
                ego_translation_m: f.ego_translation_m,
                description: None,
                translation_m: idx.iter().map(|&i| f.translation_m[i]).collect(),
                size: idx.iter().filter_map(|&i| f.size.get(i).copied()).collect(),
                yaw: idx.iter().filter_map(|&i| f.yaw.get(i).copied()).collect(),
                velocity_m_per_s: Vec::new(),
                label: idx.iter().map(|&i| f.label[i]).collect(),
                name: Vec::new(),
                track_id: idx.iter().map(|&i| f.track_id[i]).collect(),
                score: f
                    .score
                    .as_ref()
                    .map(|s| idx.iter().map(|&i| s[i]).collect()),
                is_positive: f.is_positive,
            }
        })
        .collect()
}

/// Whether object `i` survives the range filter and, when given, the ROI filter.
fn kept(f: &FrameData, i: usize, max_range_m: f64, roi: Option<&RoiRaster>) -> bool {
    let e = f.ego_translation_m;
    let t = f.translation_m[i];
    let dx = t[0] - e[0];
    let dy = t[1] - e[1];
    if (dx * dx + dy * dy).sqrt() > max_range_m {
        return false;
    }
    match roi {
        // sizes and yaws were checked to be present when the ROI is on
        Some(r) => r.box_in_roi(t, f.size[i], f.yaw[i]),
        None => true,
    }
}

/// Which objects the filters keep.
pub(crate) enum Filter<'a> {
    /// The range filter alone, tested inline.
    Range(f64),
    /// Range and ROI, per sequence, frame and object: computed once, as the box test is the costly part.
    Masks(BTreeMap<&'a SeqKey, Vec<Vec<bool>>>),
}

impl<'a> Filter<'a> {
    pub(crate) fn new(sub: &'a Submission, max_range_m: f64, roi: Option<&RoiMaps>) -> Filter<'a> {
        let Some(maps) = roi else {
            return Filter::Range(max_range_m);
        };
        let masks = sub
            .sequences
            .par_iter()
            .map(|(k, frames)| {
                let r = maps.get(&k.0);
                let m = frames
                    .iter()
                    .map(|f| (0..f.len()).map(|i| kept(f, i, max_range_m, r)).collect())
                    .collect();
                (k, m)
            })
            .collect();
        Filter::Masks(masks)
    }
}

/// Which objects of a frame [`pick`] keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Pick {
    /// The objects carrying this label (0 referred, 1 related, 2 other).
    Label(i32),
    /// Every object of a track referred in any kept object (`referred_full_tracks`).
    ReferredTracks,
    /// Every object, labels ignored.
    Every,
}

/// The referred objects kept by the filters (`filter_max_dist`, `filter_drivable_area`, then
/// `classify_referred_objects`); with `full_tracks`, every kept object of a track referred in any kept
/// object (`referred_full_tracks`).
fn referred(sub: &Submission, filter: &Filter, full_tracks: bool) -> Submission {
    let which = if full_tracks {
        Pick::ReferredTracks
    } else {
        Pick::Label(0)
    };
    pick(sub, filter, which)
}

/// The objects kept by the filters that `which` selects, in copies of every sequence.
pub(crate) fn pick(sub: &Submission, filter: &Filter, which: Pick) -> Submission {
    let sequences = sub
        .sequences
        .iter()
        .map(|(k, frames)| {
            let masks = match filter {
                Filter::Masks(m) => m.get(k),
                Filter::Range(_) => None,
            };
            let keep = |j: usize, f: &FrameData, i: usize| match (filter, masks) {
                (Filter::Range(r), _) => kept(f, i, *r, None),
                (Filter::Masks(_), m) => m.is_some_and(|m| m[j][i]),
            };
            let out = match which {
                Pick::ReferredTracks => {
                    let ids: BTreeSet<i32> = frames
                        .iter()
                        .enumerate()
                        .flat_map(|(j, f)| {
                            (0..f.len())
                                .filter(move |&i| f.label[i] == 0 && keep(j, f, i))
                                .map(move |i| f.track_id[i])
                        })
                        .collect();
                    select(frames, |j, f, i| {
                        ids.contains(&f.track_id[i]) && keep(j, f, i)
                    })
                }
                Pick::Label(l) => select(frames, |j, f, i| f.label[i] == l && keep(j, f, i)),
                Pick::Every => select(frames, keep),
            };
            (k.clone(), out)
        })
        .collect();
    Submission { sequences }
}

fn class_frames(frames: &[FrameData], threshold: Option<f64>) -> Vec<ClassFrame> {
    frames
        .iter()
        .map(|f| {
            let mut cf = ClassFrame::default();
            for i in 0..f.len() {
                if let (Some(th), Some(s)) = (threshold, &f.score) {
                    if (s[i] as f64) < th {
                        continue;
                    }
                }
                cf.ids.push(f.track_id[i]);
                cf.xy.push([f.translation_m[i][0], f.translation_m[i][1]]);
            }
            cf
        })
        .collect()
}

/// The 10 recall levels 1.0, 0.9, ... 0.1 as `np.linspace(0.1, 1, 10).round(12)[::-1]`.
fn recall_levels() -> [f64; 10] {
    let mut r = [0.0; 10];
    let step = (1.0 - 0.1) / 9.0;
    for (i, x) in r.iter_mut().enumerate() {
        let v = if i == 9 { 1.0 } else { i as f64 * step + 0.1 };
        *x = ((v * 1e12).round_ties_even()) / 1e12;
    }
    r.reverse();
    r
}

/// numpy's `interp(x, xp, fp, right=0)` for increasing xp.
fn interp(x: f64, xp: &[f64], fp: &[f64]) -> f64 {
    let n = xp.len();
    if x.is_nan() {
        return x;
    }
    if x < xp[0] {
        return fp[0];
    }
    if x > xp[n - 1] {
        return 0.0;
    }
    // j with xp[j] <= x < xp[j+1], or n-1 when x == xp[n-1]
    let j = xp.partition_point(|&v| v <= x).saturating_sub(1);
    if j == n - 1 || xp[j] == x {
        return fp[j];
    }
    let slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j]);
    let mut r = slope * (x - xp[j]) + fp[j];
    if r.is_nan() {
        r = slope * (x - xp[j + 1]) + fp[j + 1];
        if r.is_nan() && fp[j] == fp[j + 1] {
            r = fp[j];
        }
    }
    r
}

/// Candidate score thresholds of one prompt (`_calculate_score_thresholds`).
fn score_thresholds(seqs: &[(&Vec<FrameData>, &Vec<FrameData>)]) -> Vec<f64> {
    let mut scores: Vec<f32> = Vec::new();
    let mut n_gt = 0usize;
    for (g, p) in seqs {
        for (gf, pf) in g.iter().zip(p.iter()) {
            let gxy: Vec<[f64; 2]> = gf.translation_m.iter().map(|t| [t[0], t[1]]).collect();
            let pxy: Vec<[f64; 2]> = pf.translation_m.iter().map(|t| [t[0], t[1]]).collect();
            let sim = hota::similarity(&gxy, &pxy);
            let (_, cols) = hota::max_assignment(&sim);
            if let Some(s) = &pf.score {
                scores.extend(cols.iter().map(|&c| s[c]));
            }
            n_gt += gf.len();
        }
    }
    let levels = recall_levels();
    if scores.is_empty() || n_gt == 0 {
        return vec![0.0; 10];
    }
    scores.sort_by(|a, b| a.total_cmp(b));
    scores.reverse();
    let fp: Vec<f64> = scores.iter().map(|&s| s as f64).collect();
    let xp: Vec<f64> = (1..=fp.len()).map(|i| i as f64 / n_gt as f64).collect();
    let max_recall = xp[xp.len() - 1];
    levels
        .iter()
        .map(|&r| {
            let v = interp(r, &xp, &fp);
            if r > max_recall || v.is_nan() {
                0.0
            } else {
                v
            }
        })
        .collect()
}

/// HOTA with threshold tuning for every prompt of referred-only data (`_tune_score_thresholds`).
pub(crate) fn tune(pred: &Submission, gt: &Submission) -> BTreeMap<String, PromptHota> {
    let mut by_prompt: BTreeMap<&str, Vec<&SeqKey>> = BTreeMap::new();
    for k in gt.sequences.keys() {
        by_prompt.entry(k.1.as_str()).or_default().push(k);
    }
    let empty = Vec::new();
    let work: Vec<(&str, Vec<&SeqKey>)> = by_prompt.into_iter().collect();
    work.into_par_iter()
        .filter_map(|(prompt, keys)| {
            let pairs: Vec<(&Vec<FrameData>, &Vec<FrameData>)> = keys
                .iter()
                .map(|k| (&gt.sequences[*k], pred.sequences.get(*k).unwrap_or(&empty)))
                .collect();
            let candidates = score_thresholds(&pairs);
            let gt_frames: Vec<Vec<ClassFrame>> =
                pairs.iter().map(|(g, _)| class_frames(g, None)).collect();
            // Equal candidates score equally, and np.argmax keeps the first maximum, so each distinct
            // threshold is scored once (in parallel: a pooled class is one large group).
            let mut distinct: Vec<f64> = Vec::new();
            for &th in &candidates {
                if !distinct.iter().any(|d| d.to_bits() == th.to_bits()) {
                    distinct.push(th);
                }
            }
            let scored: Vec<(f64, f64, Hota)> = distinct
                .par_iter()
                .map(|&th| {
                    let seqs: Vec<(&[ClassFrame], Vec<ClassFrame>)> = pairs
                        .iter()
                        .zip(&gt_frames)
                        .map(|((_, p), g)| (g.as_slice(), class_frames(p, Some(th))))
                        .collect();
                    let h = hota::hota(&seqs);
                    (th, h.mean(), h)
                })
                .collect();
            let mean_over = candidates
                .iter()
                .filter_map(|c| scored.iter().find(|s| s.0.to_bits() == c.to_bits()))
                .map(|s| s.1)
                .sum::<f64>()
                / candidates.len().max(1) as f64;
            let mut best: Option<(f64, f64, Hota)> = None;
            for (th, m, h) in scored {
                // np.argmax: the first maximum wins
                if best.as_ref().is_none_or(|b| m > b.1) {
                    best = Some((th, m, h));
                }
            }
            best.map(|(threshold, m, detail)| {
                (
                    prompt.to_string(),
                    PromptHota {
                        threshold,
                        value: m.max(0.0),
                        detail,
                        candidates,
                        mean_over_thresholds: mean_over.max(0.0),
                    },
                )
            })
        })
        .collect()
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
