//! The per-prompt score-threshold tuning of the scenario-mining metrics: the ten thresholds at
//! recall levels 1.0 down to 0.1, HOTA at each, the best kept ([`tune`], [`PromptHota`]).

use std::collections::BTreeMap;

use rayon::prelude::*;

use crate::hota::{self, ClassFrame, Hota};
use crate::model::{FrameData, SeqKey, Submission};

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
