//! A 2 Hz tracker: the sample logs' tracker input (`tests/data/av2/tracker/exact.pkl`, the
//! annotations in the 3D-tracking format at 10 Hz) with only the boxes at the evaluation's
//! timestamps (every fifth sweep, as the paper's sampling-rate table uses), mined with the library
//! and scored beside the 10 Hz run. Time in rules is a fixed 0.1 s frame on the log's 10 Hz grid,
//! so the 2 Hz frames are 0, 5, 10, … and the submission has exactly the tracker's frames, which
//! are the ground truth's.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use scenalog_eval::{read_pickle, PyValue as P};
use scenalog_tracker::TrackerPickle;

fn data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/av2")
        .join(rel)
}

/// Writes `exact.pkl` with only every `stride`th frame of each log (from the first) to `out`.
fn every_nth_frame(stride: usize, out: &Path) {
    let tracks = TrackerPickle::open(&data("tracker/exact.pkl")).expect("exact.pkl");
    let s = |x: &str| P::Str(x.to_string());
    let mut logs = Vec::new();
    for log in tracks.log_ids() {
        let frames = tracks.frames(log).expect("frames");
        let kept: Vec<P> = frames
            .iter()
            .step_by(stride)
            .map(|d| {
                let n = d.len();
                P::Dict(vec![
                    (s("timestamp_ns"), P::I64(d.timestamp_ns)),
                    (
                        s("translation_m"),
                        P::F64Array(vec![n, 3], d.translation_m.concat()),
                    ),
                    (s("size"), P::F64Array(vec![n, 3], d.size.concat())),
                    (s("yaw"), P::F64Array(vec![n], d.yaw.clone())),
                    (s("name"), P::StrArray(d.name.clone())),
                    (s("score"), P::F32Array(vec![n], d.score.clone())),
                    (s("track_id"), P::I64Array(d.track_id.clone())),
                ])
            })
            .collect();
        logs.push((s(log), P::List(kept)));
    }
    std::fs::write(out, scenalog_eval::encode_value(&P::Dict(logs))).expect("write");
}

/// `scenalog mine --log-prompts` on the fixture's pairs with `tracks`, then `scenalog eval
/// --json` of its submission: (the submission's timestamps by sequence, the report).
fn mine_and_score(tracks: &Path, out: &Path) -> (BTreeMap<String, Vec<i64>>, serde_json::Value) {
    let o = crate::util::scenalog()
        .arg("mine")
        .arg("--log-prompts")
        .arg(data("tracker/log_prompt_pairs_fixture.json"))
        .arg("--dataset-dir")
        .arg(data("logs"))
        .arg("--tracks")
        .arg(tracks)
        .arg("--out")
        .arg(out)
        .args(["--threads", "2"])
        .output()
        .expect("scenalog runs");
    assert!(
        o.status.success(),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    let sub = read_pickle(&out.join("submission.pkl")).expect("submission");
    let stamps = sub
        .sequences
        .iter()
        .map(|((log, prompt), frames)| {
            (
                format!("{log}/{prompt}"),
                frames.iter().map(|f| f.timestamp_ns).collect(),
            )
        })
        .collect();
    let e = crate::util::scenalog()
        .arg("eval")
        .arg("--pred")
        .arg(out.join("submission.pkl"))
        .arg("--gt")
        .arg(data("eval/combined_gt_dev.pkl"))
        .arg("--dataset-dir")
        .arg(data("logs"))
        .arg("--json")
        .output()
        .expect("scenalog eval runs");
    assert!(
        e.status.success(),
        "eval refused the submission: {}",
        String::from_utf8_lossy(&e.stderr)
    );
    let report = serde_json::from_slice(&e.stdout).expect("eval --json");
    (stamps, report)
}

#[test]
fn a_two_hertz_tracker_is_mined_and_scored_beside_ten_hertz() {
    let dir = tempfile::tempdir().expect("tempdir");
    let two_hz = dir.path().join("exact_2hz.pkl");
    every_nth_frame(5, &two_hz);
    let (stamps_10, report_10) = mine_and_score(&data("tracker/exact.pkl"), &dir.path().join("10"));
    let (stamps_2, report_2) = mine_and_score(&two_hz, &dir.path().join("2"));

    // Exactly the tracker's frames, which are the ground truth's: no second down-sampling.
    let gt = read_pickle(&data("eval/combined_gt_dev.pkl")).expect("ground truth");
    for (key, stamps) in &stamps_2 {
        let (log, prompt) = key.split_once('/').expect("log/prompt");
        let want: Vec<i64> = gt.sequences[&(log.to_string(), prompt.to_string())]
            .iter()
            .map(|f| f.timestamp_ns)
            .collect();
        assert_eq!(stamps, &want, "{key}");
        assert_eq!(stamps, &stamps_10[key], "{key}");
    }
    let figure = |r: &serde_json::Value, k: &str| r[k].as_f64().unwrap_or(f64::NAN);
    for k in ["hota_temporal", "hota_track", "timestamp_ba", "log_ba"] {
        eprintln!(
            "{k}: 10 Hz {:.4}, 2 Hz {:.4}",
            figure(&report_10, k),
            figure(&report_2, k)
        );
    }
    let (t10, t2) = (
        figure(&report_10, "hota_temporal"),
        figure(&report_2, "hota_temporal"),
    );
    assert!(t10 > 0.5, "10 Hz HOTA-Temporal {t10}");
    // Comparable answers: the paper finds RefProg robust to 2 Hz input.
    assert!((t2 - t10).abs() < 0.1, "2 Hz {t2} vs 10 Hz {t10}");
}
