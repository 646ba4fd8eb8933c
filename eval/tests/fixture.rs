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
