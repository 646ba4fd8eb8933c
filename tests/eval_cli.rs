//! `scenalog eval` on the real scenario-mining fixture.

use std::path::PathBuf;
use std::process::Command;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/av2/eval")
        .join(name)
}

fn scenalog() -> Command {
    Command::new(env!("CARGO_BIN_EXE_scenalog"))
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
