//! `scenalog eval` on the real scenario-mining fixture.

use std::path::PathBuf;
use std::process::Command;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/av2/eval")
        .join(name)
}

fn scenalog() -> Command {
    crate::util::scenalog()
}

#[test]
fn json_headline_numbers() {
    let out = scenalog()
        .args(["eval", "--json", "--pred"])
        .arg(data("combined_predictions_dev.pkl"))
        .arg("--gt")
        .arg(data("combined_gt_dev.pkl"))
        .output()
        .expect("run scenalog");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let close = |k: &str, want: f64| {
        let got = v[k].as_f64().unwrap_or(f64::NAN);
        assert!((got - want).abs() <= 1e-9, "{k}: {got} vs {want}");
    };
    close("hota_temporal", 0.3795501973683041);
    close("hota_track", 0.3941392002747208);
    close("timestamp_ba", 0.85);
    close("log_ba", 1.0);
}

#[test]
fn text_output_and_bad_input() {
    let out = scenalog()
        .args(["eval", "--per-prompt", "--pred"])
        .arg(data("combined_predictions_dev.pkl"))
        .arg("--gt")
        .arg(data("combined_gt_dev.pkl"))
        .output()
        .expect("run scenalog");
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("HOTA-Temporal: 0.37955"), "{text}");
    assert!(text.contains("stopped car"), "{text}");

    // Arrow tables are read too and give the same numbers.
    let out = scenalog()
        .args(["eval", "--json", "--pred"])
        .arg(data("combined_predictions_dev.feather"))
        .arg("--gt")
        .arg(data("combined_gt_dev.feather"))
        .output()
        .expect("run scenalog");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert!((v["hota_track"].as_f64().unwrap_or(0.0) - 0.3941392002747208).abs() <= 1e-9);

    // A file that is neither: exit 2 with a message naming the file.
    let out = scenalog()
        .args(["eval", "--pred"])
        .arg(data("../README.md"))
        .arg("--gt")
        .arg(data("combined_gt_dev.pkl"))
        .output()
        .expect("run scenalog");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("README.md"), "{err}");
}

#[test]
fn out_writes_official_json_files() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = scenalog()
        .args(["eval", "--pred"])
        .arg(data("combined_predictions_dev.pkl"))
        .arg("--gt")
        .arg(data("combined_gt_dev.pkl"))
        .arg("--out")
        .arg(dir.path())
        .output()
        .expect("run scenalog");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for (ours, official) in [
        (
            "temporal_metrics.json",
            "official_noroi_temporal_metrics.json",
        ),
        (
            "spatiotemporal_metrics.json",
            "official_noroi_spatiotemporal_metrics.json",
        ),
    ] {
        let read = |p: PathBuf| -> serde_json::Value {
            serde_json::from_str(&std::fs::read_to_string(&p).expect("read")).expect("json")
        };
        let got = read(dir.path().join(ours));
        let want = read(data("expected").join(official));
        let want = want.as_object().expect("object");
        assert_eq!(got.as_object().expect("object").len(), want.len(), "{ours}");
        for (k, w) in want {
            match w {
                serde_json::Value::Object(m) => {
                    for (p, v) in m {
                        let g = got[k][p].as_f64().unwrap_or(f64::NAN);
                        assert!(
                            (g - v.as_f64().unwrap()).abs() <= 1e-9,
                            "{ours} {k} {p}: {g}"
                        );
                    }
                }
                v => {
                    let g = got[k].as_f64().unwrap_or(f64::NAN);
                    assert!((g - v.as_f64().unwrap()).abs() <= 1e-9, "{ours} {k}: {g}");
                }
            }
        }
    }
}

fn logs_dir() -> PathBuf {
    scenalog_testkit::sample_logs_dir()
}

/// `--dataset-dir` turns the drivable-area ROI filter on: the official `|roi` numbers and JSON files.
#[test]
fn dataset_dir_gives_the_roi_numbers() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = scenalog()
        .args(["eval", "--json", "--pred"])
        .arg(data("combined_predictions_dev.pkl"))
        .arg("--gt")
        .arg(data("combined_gt_dev.feather"))
        .arg("--dataset-dir")
        .arg(logs_dir())
        .arg("--out")
        .arg(dir.path())
        .output()
        .expect("run scenalog");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let read = |p: PathBuf| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(&p).expect("read")).expect("json")
    };
    let want = read(data("expected").join("official_roi_spatiotemporal_metrics.json"));
    let got = read(dir.path().join("spatiotemporal_metrics.json"));
    let close = |g: &serde_json::Value, w: &serde_json::Value, what: &str| {
        let (g, w) = (g.as_f64().unwrap_or(f64::NAN), w.as_f64().unwrap_or(0.0));
        assert!((g - w).abs() <= 1e-9, "{what}: {g} vs {w}");
    };
    close(
        &v["hota_temporal"],
        &want["hota_temporal_class_avg"],
        "hota_temporal",
    );
    close(
        &v["hota_track"],
        &want["hota_track_class_avg"],
        "hota_track",
    );
    for key in ["hota_temporal_by_class", "hota_track_by_class"] {
        for (prompt, w) in want[key].as_object().expect("by class") {
            close(&got[key][prompt], w, &format!("{key} {prompt}"));
        }
    }
    let want = read(data("expected").join("official_roi_temporal_metrics.json"));
    let got = read(dir.path().join("temporal_metrics.json"));
    close(
        &v["timestamp_ba"],
        &want["timestamp_balanced_accuracy_class_avg"],
        "timestamp_ba",
    );
    close(
        &v["log_ba"],
        &want["scenario_balanced_accuracy_class_avg"],
        "log_ba",
    );
    for key in [
        "timestamp_balanced_accuracy_by_class",
        "scenario_balanced_accuracy_by_class",
    ] {
        for (prompt, w) in want[key].as_object().expect("by class") {
            close(&got[key][prompt], w, &format!("{key} {prompt}"));
        }
    }
}

/// A log of the submission missing from the dataset directory is an error naming it; so is a log
/// directory without a vector map.
#[test]
fn dataset_dir_missing_log_or_map_is_an_error() {
    let dir = tempfile::tempdir().expect("tempdir");
    let kept = "3b3570b4-7b0b-3268-a571-b0889dbf40b6";
    let missing = "3bffdcff-c3a7-38b6-a0f2-64196d130958";
    let map = dir.path().join(kept).join("map");
    std::fs::create_dir_all(&map).expect("mkdir");
    for entry in std::fs::read_dir(logs_dir().join(kept).join("map")).expect("map dir") {
        let entry = entry.expect("entry");
        std::fs::copy(entry.path(), map.join(entry.file_name())).expect("copy");
    }
    let run = || {
        scenalog()
            .args(["eval", "--pred"])
            .arg(data("combined_predictions_dev.pkl"))
            .arg("--gt")
            .arg(data("combined_gt_dev.pkl"))
            .arg("--dataset-dir")
            .arg(dir.path())
            .output()
            .expect("run scenalog")
    };
    let out = run();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(missing) && !err.contains("panicked"), "{err}");

    // the log directory exists but holds no vector map
    std::fs::create_dir_all(dir.path().join(missing).join("map")).expect("mkdir");
    let out = run();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("log_map_archive") && err.contains(missing),
        "{err}"
    );
}

/// Runs `scenalog eval` on the fixture with `extra` arguments.
fn eval_fixture(extra: &[&str]) -> std::process::Output {
    scenalog()
        .args(["eval", "--pred"])
        .arg(data("combined_predictions_dev.pkl"))
        .arg("--gt")
        .arg(data("combined_gt_dev.pkl"))
        .args(extra)
        .output()
        .expect("run scenalog")
}

#[test]
fn related_other_and_tracker_hota_in_text_json_and_out() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = eval_fixture(&["--json", "--out", dir.path().to_str().expect("utf-8")]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    // The fixture's ground truth labels no object related: null, overall and per prompt.
    assert!(v["hota_temporal_related"].is_null(), "{v:#}");
    assert!(v["hota_temporal_related_by_prompt"]["stopped car"].is_null());
    let other = v["hota_temporal_other"].as_f64().expect("other");
    let hota = v["hota"].as_f64().expect("hota");
    assert!((other - 0.5807763575364608).abs() <= 1e-12, "{other}");
    assert!((hota - 0.7466950270710451).abs() <= 1e-12, "{hota}");
    assert!(v["hota_by_prompt"]["stopped car"]["score_threshold"].is_number());
    let paper: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("paper_metrics.json")).expect("paper_metrics"),
    )
    .expect("json");
    assert_eq!(paper["hota_temporal_other"], v["hota_temporal_other"]);
    assert_eq!(paper["hota"], v["hota"]);
    assert!(paper["hota_temporal_related"].is_null());
    assert_eq!(
        paper["hota_by_prompt"]["stopped car"],
        v["hota_by_prompt"]["stopped car"]["value"]
    );
    let text = eval_fixture(&["--per-prompt"]);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("HOTA-Temporal (related objects): - (no related object in the ground truth)"),
        "{text}"
    );
    assert!(
        text.contains(&format!("HOTA-Temporal (other objects): {other}")),
        "{text}"
    );
    assert!(
        text.contains(&format!("HOTA (tracker, every object): {hota}")),
        "{text}"
    );
    assert!(
        text.contains("\tHOTA-Temporal related\tHOTA-Temporal other\tHOTA\n"),
        "{text}"
    );
}

#[test]
fn rate_and_timestamps() {
    let json = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec!["--json"];
        args.extend_from_slice(extra);
        let out = eval_fixture(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).expect("json")
    };
    // The fixture is at 2 Hz: --rate 2 changes nothing, --rate 10 is refused.
    assert_eq!(json(&["--rate", "2"]), json(&[]));
    let out = eval_fixture(&["--rate", "10"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("cannot be sampled at 10 Hz"), "{err}");
    // Listed timestamps: the first frame of each log only.
    let gt = scenalog_eval::read_pickle(&data("combined_gt_dev.pkl")).expect("gt");
    let first: serde_json::Map<String, serde_json::Value> = gt
        .sequences
        .iter()
        .map(|(k, f)| (k.0.clone(), serde_json::json!([f[0].timestamp_ns])))
        .collect();
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("ts.json");
    std::fs::write(&file, serde_json::Value::Object(first).to_string()).expect("write");
    let one = json(&["--timestamps", file.to_str().expect("utf-8")]);
    assert_ne!(one["hota_temporal"], json(&[])["hota_temporal"]);
    std::fs::write(&file, "{\"x\": [1]}").expect("write");
    let out = eval_fixture(&["--timestamps", file.to_str().expect("utf-8")]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("is not listed"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
