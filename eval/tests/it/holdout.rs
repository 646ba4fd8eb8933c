//! The five holdout submissions (tests/data/av2/holdout/) evaluate against the real ground truth without
//! error, with and without the drivable-area ROI, and their results follow from how each was derived from
//! the base submission (`eval/combined_predictions_dev.pkl`). Official scores are not known for these;
//! the checks are relations to the base that hold by construction.

use scenalog_eval::{evaluate, read_pickle, EvalOptions, Report, RoiMaps, SeqKey, Submission};
use std::collections::BTreeSet;
use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

fn path(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/av2")
        .join(rel)
}

fn load(rel: &str) -> Submission {
    read_pickle(&path(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

fn gt() -> Submission {
    load("eval/combined_gt_dev.pkl")
}

fn base() -> Submission {
    load("eval/combined_predictions_dev.pkl")
}

fn holdout(name: &str) -> Submission {
    load(&format!("holdout/holdout_{name}.pkl"))
}

fn roi_maps() -> Arc<RoiMaps> {
    static MAPS: OnceLock<Arc<RoiMaps>> = OnceLock::new();
    MAPS.get_or_init(|| {
        let g = gt();
        let ids: Vec<&str> = g.sequences.keys().map(|k| k.0.as_str()).collect();
        Arc::new(RoiMaps::load(&path("logs"), ids).expect("roi maps"))
    })
    .clone()
}

fn run(pred: &Submission, gt: &Submission, roi: bool) -> Report {
    let opts = EvalOptions {
        roi: roi.then(roi_maps),
        ..EvalOptions::default()
    };
    let r = evaluate(pred, gt, &opts).expect("evaluate");
    for v in [r.hota_temporal, r.hota_track, r.timestamp_ba, r.log_ba] {
        assert!(
            (0.0..=1.0).contains(&v),
            "headline value {v} outside [0, 1]"
        );
    }
    r
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// The objects the evaluation keeps (range, then ROI filter).
fn kept(sub: &Submission, roi: bool) -> Submission {
    let mut sub = sub.clone();
    scenalog_eval::mining::filter_range(&mut sub, 50.0);
    if roi {
        scenalog_eval::mining::filter_roi(&mut sub, &roi_maps()).expect("roi filter");
    }
    sub
}

/// Referred track ids of one sequence.
fn referred_tracks(frames: &[scenalog_eval::FrameData]) -> BTreeSet<i32> {
    frames
        .iter()
        .flat_map(|f| {
            f.label
                .iter()
                .zip(&f.track_id)
                .filter(|(l, _)| **l == 0)
                .map(|(_, t)| *t)
        })
        .collect()
}

/// The highest score of any object of the given tracks.
fn max_score(frames: &[scenalog_eval::FrameData], tracks: &BTreeSet<i32>) -> f64 {
    frames
        .iter()
        .flat_map(|f| {
            let s = f.score.clone().unwrap_or_default();
            f.track_id
                .iter()
                .zip(s)
                .filter(|(t, _)| tracks.contains(t))
                .map(|(_, s)| f64::from(s))
                .collect::<Vec<_>>()
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Positions moved: every prompt's HOTA falls, and so does its localisation accuracy.
#[test]
fn jitter_lowers_hota_and_localisation() {
    let (g, b, h) = (gt(), base(), holdout("jitter"));
    for roi in [false, true] {
        let (rb, rh) = (run(&b, &g, roi), run(&h, &g, roi));
        assert!(rh.hota_temporal < rb.hota_temporal && rh.hota_track < rb.hota_track);
        for (p, hb) in &rb.hota_temporal_by_prompt {
            let hh = &rh.hota_temporal_by_prompt[p];
            assert!(hh.value < hb.value, "{p}");
            assert!(mean(&hh.detail.loc_a) < mean(&hb.detail.loc_a), "{p} LocA");
            if hh.threshold == hb.threshold {
                // labels and scores are the base's: same threshold, same classification
                assert_eq!(rh.timestamp_ba_by_prompt[p], rb.timestamp_ba_by_prompt[p]);
                assert_eq!(rh.log_ba_by_prompt[p], rb.log_ba_by_prompt[p]);
            }
        }
    }
}

/// Referred labels removed from some frames: HOTA-Temporal and timestamp BA fall for every prompt.
/// HOTA-Track changes only through the tracks that lost every kept referred object: when none did, or
/// when all their objects score below the (unchanged) threshold, it is the base's exactly; otherwise it
/// differs (and may rise, if those tracks were false positives).
#[test]
fn dropped_referred_frames_lower_hota_temporal() {
    let (g, b, h) = (gt(), base(), holdout("drop_frames"));
    let (mut same, mut changed) = (0, 0);
    for roi in [false, true] {
        let (kb, kh) = (kept(&b, roi), kept(&h, roi));
        let (rb, rh) = (run(&b, &g, roi), run(&h, &g, roi));
        assert!(rh.hota_temporal < rb.hota_temporal);
        assert!(rh.timestamp_ba < rb.timestamp_ba);
        for (p, hb) in &rb.hota_temporal_by_prompt {
            assert!(rh.hota_temporal_by_prompt[p].value < hb.value, "{p}");
            assert!(
                rh.timestamp_ba_by_prompt[p] < rb.timestamp_ba_by_prompt[p],
                "{p}"
            );
        }
        for (k, fb) in &kb.sequences {
            let (ib, ih) = (referred_tracks(fb), referred_tracks(&kh.sequences[k]));
            assert!(ih.is_subset(&ib), "{k:?}");
            let lost: BTreeSet<i32> = ib.difference(&ih).copied().collect();
            let (tb, th) = (
                &rb.hota_track_by_prompt[&k.1],
                &rh.hota_track_by_prompt[&k.1],
            );
            let invisible = th.threshold == tb.threshold && max_score(fb, &lost) < tb.threshold;
            if lost.is_empty() || invisible {
                same += 1;
                // the candidates may differ (the lost objects' scores are gone), the result not
                assert_eq!((th.value, &th.detail), (tb.value, &tb.detail), "{k:?}");
            } else {
                changed += 1;
                assert_ne!(th.detail, tb.detail, "{k:?}");
            }
        }
    }
    assert!(
        same > 0 && changed > 0,
        "{same} unchanged, {changed} changed"
    );
}

/// Scores replaced: where the chosen threshold keeps every prediction, the result is that of the base
/// with its score threshold removed (all scores 1).
#[test]
fn replaced_scores_only_move_the_threshold() {
    let (g, b, h) = (gt(), base(), holdout("scores"));
    let mut all = b.clone();
    for f in all.sequences.values_mut().flatten() {
        f.score = Some(vec![1.0; f.len()]);
    }
    let mut checked = 0;
    for roi in [false, true] {
        let (rh, ra) = (run(&h, &g, roi), run(&all, &g, roi));
        for (p, hh) in &rh.hota_temporal_by_prompt {
            let min_score = h
                .sequences
                .iter()
                .filter(|(k, _)| &k.1 == p)
                .flat_map(|(_, fs)| fs.iter().flat_map(|f| f.score.clone().unwrap_or_default()))
                .fold(f32::INFINITY, f32::min);
            if hh.threshold <= f64::from(min_score) {
                checked += 1;
                assert_eq!(hh.detail, ra.hota_temporal_by_prompt[p].detail, "{p}");
                assert_eq!(rh.timestamp_ba_by_prompt[p], ra.timestamp_ba_by_prompt[p]);
                assert_eq!(rh.log_ba_by_prompt[p], ra.log_ba_by_prompt[p]);
            }
        }
    }
    assert!(checked > 0);
}

/// Track ids switched halfway: association accuracy and HOTA fall for every prompt; the HOTA-Temporal
/// candidate thresholds (per-frame matching, which ignores ids) are the base's.
#[test]
fn id_switch_lowers_association() {
    let (g, b, h) = (gt(), base(), holdout("id_switch"));
    for roi in [false, true] {
        let (rb, rh) = (run(&b, &g, roi), run(&h, &g, roi));
        for (by_b, by_h) in [
            (&rb.hota_temporal_by_prompt, &rh.hota_temporal_by_prompt),
            (&rb.hota_track_by_prompt, &rh.hota_track_by_prompt),
        ] {
            for (p, hb) in by_b {
                let hh = &by_h[p];
                assert!(hh.value < hb.value, "{p}");
                assert!(mean(&hh.detail.ass_a) < mean(&hb.detail.ass_a), "{p} AssA");
            }
        }
        for (p, hb) in &rb.hota_temporal_by_prompt {
            assert_eq!(
                rh.hota_temporal_by_prompt[p].candidates, hb.candidates,
                "{p}"
            );
            if rh.hota_temporal_by_prompt[p].threshold == hb.threshold {
                assert_eq!(rh.timestamp_ba_by_prompt[p], rb.timestamp_ba_by_prompt[p]);
                assert_eq!(rh.log_ba_by_prompt[p], rb.log_ba_by_prompt[p]);
            }
        }
    }
}

/// One sequence without referred objects: its prompt scores HOTA 0 and balanced accuracy (0 + 1) / 2
/// (every frame predicted negative: no true positive, every negative frame a true negative); the other
/// prompt is the base's exactly.
#[test]
fn emptied_sequence_scores_zero_for_its_prompt() {
    let (g, b, h) = (gt(), base(), holdout("empty_seq"));
    let emptied: Vec<&SeqKey> = h
        .sequences
        .iter()
        .filter(|(_, fs)| fs.iter().all(|f| !f.label.contains(&0)))
        .map(|(k, _)| k)
        .collect();
    assert_eq!(emptied.len(), 1);
    let prompt = &emptied[0].1;
    let gframes = &g.sequences[emptied[0]];
    assert!(gframes.iter().any(|f| f.label.contains(&0)));
    for roi in [false, true] {
        let (rb, rh) = (run(&b, &g, roi), run(&h, &g, roi));
        assert!(rh.hota_temporal < rb.hota_temporal && rh.hota_track < rb.hota_track);
        assert!(rh.timestamp_ba < rb.timestamp_ba && rh.log_ba < rb.log_ba);
        for (p, hb) in &rb.hota_temporal_by_prompt {
            let (ht, hk) = (&rh.hota_temporal_by_prompt[p], &rh.hota_track_by_prompt[p]);
            if p == prompt {
                assert_eq!((ht.value, hk.value), (0.0, 0.0));
                assert_eq!(ht.detail.tp, [0.0; 19]);
                assert_eq!(rh.timestamp_ba_by_prompt[p], 0.5);
                assert_eq!(rh.log_ba_by_prompt[p], 0.5);
            } else {
                assert_eq!(ht, hb);
                assert_eq!(hk, &rb.hota_track_by_prompt[p]);
                assert_eq!(rh.timestamp_ba_by_prompt[p], rb.timestamp_ba_by_prompt[p]);
            }
        }
    }
}

/// Related and other objects are classed by label; a file whose names disagree with its labels
/// is named in a warning (the value would differ under av2's older classing by name).
#[test]
fn a_name_that_disagrees_with_its_label_is_warned_of() {
    use scenalog_eval::classes::label_name_mismatches;
    let g = gt();
    assert_eq!(label_name_mismatches(&g, "ground truth"), None);
    let mut h = base();
    assert_eq!(label_name_mismatches(&h, "predictions"), None);
    let Some(frame) = h
        .sequences
        .values_mut()
        .flat_map(|f| f.iter_mut())
        .find(|f| !f.label.is_empty())
    else {
        panic!("no object in the base submission")
    };
    let label = frame.label[0];
    let wrong = if label == 2 {
        "RELATED_OBJECT"
    } else {
        "OTHER_OBJECT"
    };
    frame.name[0] = wrong.into();
    let w = label_name_mismatches(&h, "predictions").unwrap_or_default();
    assert!(
        w.contains("1 object(s)")
            && w.contains(&format!("label {label}, name \"{wrong}\""))
            && w.contains("by label"),
        "{w}"
    );
    let names: Vec<&str> = ["drop_frames", "empty_seq", "id_switch", "jitter", "scores"]
        .into_iter()
        .filter(|n| label_name_mismatches(&holdout(n), "predictions").is_some())
        .collect();
    // Two of the five carry names that disagree with their labels.
    assert_eq!(names, ["drop_frames", "empty_seq"]);
}
