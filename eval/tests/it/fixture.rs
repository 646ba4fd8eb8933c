//! Reproduces the official numbers in tests/data/av2/eval/expected/ on the real fixture.

use scenalog_eval::{evaluate, read_pickle, EvalOptions, RoiMaps, Submission};
use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/av2/eval")
        .join(name)
}

/// The ROI rasters of the fixture's logs, built once per test binary from tests/data/av2/logs.
fn roi_maps() -> Arc<RoiMaps> {
    static MAPS: OnceLock<Arc<RoiMaps>> = OnceLock::new();
    MAPS.get_or_init(|| {
        let dir = scenalog_testkit::sample_logs_dir();
        let (pred, gt) = load();
        let ids: Vec<String> = gt
            .sequences
            .keys()
            .chain(pred.sequences.keys())
            .map(|k| k.0.clone())
            .collect();
        Arc::new(RoiMaps::load(&dir, ids.iter().map(|s| s.as_str())).expect("roi maps"))
    })
    .clone()
}

fn opts(roi: bool) -> EvalOptions {
    EvalOptions {
        roi: roi.then(roi_maps),
        ..EvalOptions::default()
    }
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
fn range_and_roi_filter_counts_match() {
    let (mut pred, mut gt) = load();
    let maps = roi_maps();
    for sub in [&mut pred, &mut gt] {
        scenalog_eval::mining::filter_range(sub, 50.0);
        scenalog_eval::mining::filter_roi(sub, &maps).expect("roi filter");
    }
    let counts = expected("scenario_mining_filter_counts.json");
    for (file, sub) in [
        ("combined_gt_dev.pkl", &gt),
        ("combined_predictions_dev.pkl", &pred),
    ] {
        for (key, frames) in &sub.sequences {
            let name = format!("('{}', '{}')", key.0, key.1);
            let c = &counts[file][&name];
            let per_frame: Vec<u64> = frames.iter().map(|f| f.len() as u64).collect();
            let want: Vec<u64> = c["objects_per_frame_after_50m_and_roi"]
                .as_array()
                .expect("per-frame counts")
                .iter()
                .map(|v| v.as_u64().expect("count"))
                .collect();
            assert_eq!(per_frame, want, "{file} {name} per frame");
            let total: u64 = per_frame.iter().sum();
            let referred: usize = frames
                .iter()
                .map(|f| f.label.iter().filter(|&&l| l == 0).count())
                .sum();
            assert_eq!(total, c["objects_after_50m_and_roi"].as_u64().unwrap());
            assert_eq!(
                referred as u64,
                c["referred_after_50m_and_roi"].as_u64().unwrap(),
                "{file} {name}"
            );
            // the ROI drops something in this fixture
            assert!(total < c["objects_after_50m"].as_u64().unwrap());
        }
    }
}

/// The rasters equal the official ones in size, placement and cell counts.
#[test]
fn roi_rasters_match() {
    let maps = roi_maps();
    let exp = expected("scenario_mining_expected_results.json");
    let rasters = exp["roi_rasters"].as_object().expect("roi_rasters");
    assert_eq!(rasters.len(), 2);
    let int = |v: &serde_json::Value| v.as_i64().expect("integer");
    for (log, e) in rasters {
        let r = maps.get(log).expect("raster of the log");
        let b: Vec<i64> = e["bounds_xmin_ymin_xmax_ymax"]
            .as_array()
            .unwrap()
            .iter()
            .map(int)
            .collect();
        assert_eq!(r.bounds().to_vec(), b, "{log} bounds");
        let shape = &e["da_shape_h_w"];
        assert_eq!(
            (r.shape().0 as i64, r.shape().1 as i64),
            (int(&shape[0]), int(&shape[1])),
            "{log} shape"
        );
        assert_eq!(r.drivable_cells() as i64, int(&e["da_ones"]), "{log} da");
        assert_eq!(r.roi_cells() as i64, int(&e["roi_ones"]), "{log} roi");
        assert_eq!(r.polygons() as i64, int(&e["n_drivable_areas"]), "{log}");
        let sim = &e["da_Sim2"];
        assert_eq!(sim["s"].as_f64(), Some(scenalog_eval::roi::CELLS_PER_M));
        assert_eq!((int(&sim["t"][0]), int(&sim["t"][1])), (-b[0], -b[1]));
    }
}

#[test]
fn headline_numbers_without_roi() {
    let (pred, gt) = load();
    let r = evaluate(&pred, &gt, &opts(false)).expect("evaluate");
    check_headline(&r, &variant("base|no_roi"), "base|no_roi");
}

#[test]
fn headline_numbers_with_roi() {
    let (pred, gt) = load();
    let r = evaluate(&pred, &gt, &opts(true)).expect("evaluate");
    check_headline(&r, &variant("base|roi"), "base|roi");
    // the filter matters here: the two differ
    let without = evaluate(&pred, &gt, &opts(false)).expect("evaluate");
    assert!((r.hota_temporal - without.hota_temporal).abs() > 1e-3);
}

fn arr(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

/// Chosen thresholds, tuned values and per-alpha detail of both HOTA variants, and the official JSON
/// files, with (`roi`) or without the drivable-area filter.
fn check_per_prompt(roi: bool) {
    let (pred, gt) = load();
    let r = evaluate(&pred, &gt, &opts(roi)).expect("evaluate");
    let detail = expected("scenario_mining_hota_detail.json");
    let tag = if roi { "roi" } else { "noroi" };
    let spatio = expected(&format!("official_{tag}_spatiotemporal_metrics.json"));
    let temporal = expected(&format!("official_{tag}_temporal_metrics.json"));
    let prefix = if roi { "roi" } else { "no_roi" };
    close(
        r.hota_temporal,
        spatio["hota_temporal_class_avg"].as_f64().unwrap(),
        "hota_temporal_class_avg",
    );
    close(
        r.hota_track,
        spatio["hota_track_class_avg"].as_f64().unwrap(),
        "hota_track_class_avg",
    );
    close(
        r.timestamp_ba,
        temporal["timestamp_balanced_accuracy_class_avg"]
            .as_f64()
            .unwrap(),
        "timestamp ba avg",
    );
    close(
        r.log_ba,
        temporal["scenario_balanced_accuracy_class_avg"]
            .as_f64()
            .unwrap(),
        "log ba avg",
    );
    for (variant, by_prompt, spatio_key) in [
        (
            "hota_temporal",
            &r.hota_temporal_by_prompt,
            "hota_temporal_by_class",
        ),
        ("hota_track", &r.hota_track_by_prompt, "hota_track_by_class"),
    ] {
        let variant = format!("{prefix}|{variant}");
        let exp = detail[&variant].as_object().expect("variant");
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
            close(
                d.mean(),
                e["hota_mean_over_alphas"].as_f64().unwrap(),
                &format!("{what} mean over alphas"),
            );
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
                assert_eq!(vals.len(), 19);
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

#[test]
fn per_prompt_thresholds_and_per_alpha_detail_without_roi() {
    check_per_prompt(false);
}

#[test]
fn per_prompt_thresholds_and_per_alpha_detail_with_roi() {
    check_per_prompt(true);
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
    for roi in [false, true] {
        let r = evaluate(&pred, &gt, &opts(roi)).expect("evaluate");
        let name = format!("perfect|{}", if roi { "roi" } else { "no_roi" });
        check_headline(&r, &variant(&name), &name);
    }
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
    for (roi, tag) in [(false, "no_roi"), (true, "roi")] {
        let r = evaluate(&cls, &gt, &opts(roi)).expect("evaluate");
        assert!(!r.contains_tracking);
        let name = format!("classification_only|{tag}");
        check_headline(&r, &variant(&name), &name);
    }

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
    for (roi, tag) in [(false, "no_roi"), (true, "roi")] {
        let r = evaluate(&pred, &gtp, &opts(roi)).expect("evaluate");
        let name = format!("gt_with_is_positive|{tag}");
        check_headline(&r, &variant(&name), &name);
        let r = evaluate(&cls, &gtp, &opts(roi)).expect("evaluate");
        let name = format!("gt_with_is_positive+classification_only|{tag}");
        check_headline(&r, &variant(&name), &name);
    }

    let even = classification_only(&gt, true);
    let all = expected("scenario_mining_expected_results.json");
    for (gt_variant, g) in [("gt_legacy", &gt), ("gt_with_is_positive", &gtp)] {
        let v = &all["variants_classification_even_frames"]
            [format!("classification_even_frames|{gt_variant}")];
        let r = evaluate(&even, g, &opts(false)).expect("evaluate");
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
