//! Reproduces the official numbers in tests/data/av2/eval/expected/ on the real fixture.

use scenalog_eval::{evaluate, read_pickle, EvalOptions, Submission};
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/av2/eval")
        .join(name)
}

fn load() -> (Submission, Submission) {
    let pred = read_pickle(&data("combined_predictions_dev.pkl")).expect("predictions");
    let gt = read_pickle(&data("combined_gt_dev.pkl")).expect("ground truth");
    (pred, gt)
}

fn expected(name: &str) -> serde_json::Value {
    let text = std::fs::read_to_string(data("expected").join(name)).expect("expected json");
    // the filter-counts file starts with a stray warning line
    let start = text.find('{').expect("json object");
    serde_json::from_str(&text[start..]).expect("valid json")
}

fn close(a: f64, b: f64, what: &str) {
    assert!((a - b).abs() <= 1e-9, "{what}: got {a}, expected {b}");
}

#[test]
fn reads_the_fixture() {
    let (pred, gt) = load();
    assert_eq!(pred.sequences.len(), 2);
    let key = (
        "3bffdcff-c3a7-38b6-a0f2-64196d130958".to_string(),
        "stopped car".to_string(),
    );
    let frames = &gt.sequences[&key];
    assert_eq!(frames.len(), 32);
    let total: usize = frames.iter().map(|f| f.len()).sum();
    let referred: usize = frames
        .iter()
        .map(|f| f.label.iter().filter(|&&l| l == 0).count())
        .sum();
    let counts = expected("scenario_mining_filter_counts.json");
    let c =
        &counts["combined_gt_dev.pkl"]["('3bffdcff-c3a7-38b6-a0f2-64196d130958', 'stopped car')"];
    assert_eq!(total as u64, c["objects_total"].as_u64().unwrap());
    assert_eq!(referred as u64, c["referred_total"].as_u64().unwrap());
    assert!(pred.sequences.values().flatten().all(|f| f.score.is_some()));
}

#[test]
fn range_filter_counts_match() {
    let (mut pred, mut gt) = load();
    scenalog_eval::mining::filter_range(&mut pred, 50.0);
    scenalog_eval::mining::filter_range(&mut gt, 50.0);
    let counts = expected("scenario_mining_filter_counts.json");
    for (file, sub) in [
        ("combined_gt_dev.pkl", &gt),
        ("combined_predictions_dev.pkl", &pred),
    ] {
        for (key, frames) in &sub.sequences {
            let name = format!("('{}', '{}')", key.0, key.1);
            let c = &counts[file][&name];
            let total: usize = frames.iter().map(|f| f.len()).sum();
            let referred: usize = frames
                .iter()
                .map(|f| f.label.iter().filter(|&&l| l == 0).count())
                .sum();
            assert_eq!(
                total as u64,
                c["objects_after_50m"].as_u64().unwrap(),
                "{file} {name}"
            );
            assert_eq!(
                referred as u64,
                c["referred_after_50m"].as_u64().unwrap(),
                "{file} {name}"
            );
        }
    }
}

#[test]
fn headline_numbers_without_roi() {
    let (pred, gt) = load();
    let r = evaluate(&pred, &gt, &EvalOptions::default()).expect("evaluate");
    let exp = expected("scenario_mining_expected_results.json");
    let v = &exp["variants"]["base|no_roi"];
    close(
        r.hota_temporal,
        v["hota_temporal"].as_f64().unwrap(),
        "hota_temporal",
    );
    close(
        r.hota_track,
        v["hota_track"].as_f64().unwrap(),
        "hota_track",
    );
    close(
        r.timestamp_ba,
        v["timestamp_ba"].as_f64().unwrap(),
        "timestamp_ba",
    );
    close(r.log_ba, v["scenario_ba"].as_f64().unwrap(), "log_ba");
}

fn arr(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

#[test]
fn per_prompt_thresholds_and_per_alpha_detail_without_roi() {
    let (pred, gt) = load();
    let r = evaluate(&pred, &gt, &EvalOptions::default()).expect("evaluate");
    let detail = expected("scenario_mining_hota_detail.json");
    let spatio = expected("official_noroi_spatiotemporal_metrics.json");
    let temporal = expected("official_noroi_temporal_metrics.json");
    for (variant, by_prompt, spatio_key) in [
        (
            "no_roi|hota_temporal",
            &r.hota_temporal_by_prompt,
            "hota_temporal_by_class",
        ),
        (
            "no_roi|hota_track",
            &r.hota_track_by_prompt,
            "hota_track_by_class",
        ),
    ] {
        let exp = detail[variant].as_object().expect("variant");
        assert_eq!(exp.len(), by_prompt.len());
        for (prompt, e) in exp {
            let got = &by_prompt[prompt];
            let what = format!("{variant} {prompt}");
            close(
                got.threshold,
                e["best_score_threshold"].as_f64().unwrap(),
                &format!("{what} threshold"),
            );
            close(
                got.value,
                e["tuned_value"].as_f64().unwrap(),
                &format!("{what} value"),
            );
            close(
                got.value,
                spatio[spatio_key][prompt].as_f64().unwrap(),
                &format!("{what} official json"),
            );
            let d = &got.detail;
            for (field, vals) in [
                ("HOTA", &d.hota),
                ("DetA", &d.det_a),
                ("AssA", &d.ass_a),
                ("LocA", &d.loc_a),
                ("HOTA_TP", &d.tp),
                ("HOTA_FN", &d.fn_),
                ("HOTA_FP", &d.fp),
            ] {
                let want = arr(&e[field]);
                assert_eq!(want.len(), 19);
                for (a, (g, w)) in vals.iter().zip(&want).enumerate() {
                    close(*g, *w, &format!("{what} {field}[{a}]"));
                }
            }
        }
    }
    for (prompt, v) in temporal["timestamp_balanced_accuracy_by_class"]
        .as_object()
        .unwrap()
    {
        close(
            r.timestamp_ba_by_prompt[prompt],
            v.as_f64().unwrap(),
            &format!("timestamp BA {prompt}"),
        );
    }
    for (prompt, v) in temporal["scenario_balanced_accuracy_by_class"]
        .as_object()
        .unwrap()
    {
        close(
            r.log_ba_by_prompt[prompt],
            v.as_f64().unwrap(),
            &format!("log BA {prompt}"),
        );
    }
}

fn variant(name: &str) -> serde_json::Value {
    expected("scenario_mining_expected_results.json")["variants"][name].clone()
}

fn check_headline(r: &scenalog_eval::Report, v: &serde_json::Value, what: &str) {
    close(
        r.hota_temporal,
        v["hota_temporal"].as_f64().unwrap(),
        &format!("{what} hota_temporal"),
    );
    close(
        r.hota_track,
        v["hota_track"].as_f64().unwrap(),
        &format!("{what} hota_track"),
    );
    close(
        r.timestamp_ba,
        v["timestamp_ba"].as_f64().unwrap(),
        &format!("{what} timestamp_ba"),
    );
    close(
        r.log_ba,
        v["scenario_ba"].as_f64().unwrap(),
        &format!("{what} log_ba"),
    );
}

/// Perfect predictions: the ground truth itself with score 1.
#[test]
fn perfect_predictions_score_one() {
    let (_, gt) = load();
    let mut pred = gt.clone();
    for f in pred.sequences.values_mut().flatten() {
        f.score = Some(vec![1.0; f.len()]);
    }
    let r = evaluate(&pred, &gt, &EvalOptions::default()).expect("evaluate");
    check_headline(&r, &variant("perfect|no_roi"), "perfect");
}

/// Classification-only predictions: each frame carries only `is_positive` (referred object present).
fn classification_only(gt: &Submission, even_frames: bool) -> Submission {
    let mut pred = Submission::default();
    for (k, frames) in &gt.sequences {
        let out = frames
            .iter()
            .enumerate()
            .map(|(i, f)| scenalog_eval::FrameData {
                timestamp_ns: f.timestamp_ns,
                ego_translation_m: f.ego_translation_m,
                is_positive: Some(Some(if even_frames {
                    i % 2 == 0
                } else {
                    f.label.contains(&0)
                })),
                ..Default::default()
            })
            .collect();
        pred.sequences.insert(k.clone(), out);
    }
    pred
}

/// Ground truth with `is_positive`: true when a referred object is within 50 m, ambiguous (None) when
/// referred objects exist only beyond it, false otherwise.
fn gt_with_is_positive(gt: &Submission) -> Submission {
    let mut out = gt.clone();
    for f in out.sequences.values_mut().flatten() {
        let e = f.ego_translation_m;
        let near = f.label.iter().zip(&f.translation_m).any(|(&l, t)| {
            l == 0 && ((t[0] - e[0]).powi(2) + (t[1] - e[1]).powi(2)).sqrt() <= 50.0
        });
        f.is_positive = Some(if near {
            Some(true)
        } else if f.label.contains(&0) {
            None
        } else {
            Some(false)
        });
    }
    out
}

#[test]
fn classification_only_variants() {
    let (pred, gt) = load();
    let cls = classification_only(&gt, false);
    let r = evaluate(&cls, &gt, &EvalOptions::default()).expect("evaluate");
    assert!(!r.contains_tracking);
    check_headline(
        &r,
        &variant("classification_only|no_roi"),
        "classification_only",
    );

    let gtp = gt_with_is_positive(&gt);
    let counts =
        &expected("scenario_mining_expected_results.json")["variants"]["gt_is_positive_counts"];
    for (k, frames) in &gtp.sequences {
        let c = &counts[format!("('{}', '{}')", k.0, k.1)];
        let n = |v: Option<bool>| frames.iter().filter(|f| f.is_positive == Some(v)).count() as u64;
        assert_eq!(n(Some(true)), c["True"].as_u64().unwrap(), "{k:?} True");
        assert_eq!(n(Some(false)), c["False"].as_u64().unwrap(), "{k:?} False");
        assert_eq!(n(None), c["None"].as_u64().unwrap(), "{k:?} None");
    }
    let r = evaluate(&pred, &gtp, &EvalOptions::default()).expect("evaluate");
    check_headline(
        &r,
        &variant("gt_with_is_positive|no_roi"),
        "gt_with_is_positive",
    );
    let r = evaluate(&cls, &gtp, &EvalOptions::default()).expect("evaluate");
    check_headline(
        &r,
        &variant("gt_with_is_positive+classification_only|no_roi"),
        "gt_is_positive+cls",
    );

    let even = classification_only(&gt, true);
    let all = expected("scenario_mining_expected_results.json");
    for (gt_variant, g) in [("gt_legacy", &gt), ("gt_with_is_positive", &gtp)] {
        let v = &all["variants_classification_even_frames"]
            [format!("classification_even_frames|{gt_variant}")];
        let r = evaluate(&even, g, &EvalOptions::default()).expect("evaluate");
        check_headline(&r, v, gt_variant);
        for (prompt, want) in v["by_class"]["timestamp_balanced_accuracy_by_class"]
            .as_object()
            .unwrap()
        {
            close(
                r.timestamp_ba_by_prompt[prompt],
                want.as_f64().unwrap(),
                &format!("{gt_variant} {prompt}"),
            );
        }
    }
}
