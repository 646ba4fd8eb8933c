//! Pickles written by Python the ordinary way, in every protocol (0-5) and array layout (C and
//! Fortran order, non-contiguous views, big-endian, float16 and narrow integers, `<U`, `|S` and
//! object string arrays): the committed fixtures of `tests/data/pickles` (made by its
//! `make_pickles.py`), and the same files made again live when `python3` with numpy is present.
//! Both formats: the scenario-mining submission (`scenalog_eval::read_pickle`) and the 3D-tracking
//! input (`TrackerPickle`). Every file must decode to `expected.json`, frame by frame.

use std::path::{Path, PathBuf};

use scenalog_tracker::TrackerPickle;
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/pickles")
}

fn floats(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(items) => items.iter().flat_map(floats).collect(),
        Value::Number(n) => vec![n.as_f64().expect("a number")],
        other => panic!("not numbers: {other}"),
    }
}

fn strings(v: &Value) -> Vec<String> {
    v.as_array()
        .expect("an array")
        .iter()
        .map(|s| s.as_str().expect("a string").to_string())
        .collect()
}

/// Checks every pickle of `dir` against its `expected.json`; returns how many files were read.
fn check_dir(dir: &Path) -> usize {
    let expected: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("expected.json")).expect("expected.json"),
    )
    .expect("expected.json is JSON");
    let log = expected["log_id"].as_str().expect("log_id");
    let prompt = expected["prompt"].as_str().expect("prompt");
    let layouts = strings(&expected["layouts"]);
    let stamps: Vec<i64> = expected["timestamps_ns"]
        .as_array()
        .expect("timestamps")
        .iter()
        .map(|t| t.as_i64().expect("an integer"))
        .collect();
    let names = strings(&expected["name"]);
    let translation = floats(&expected["translation_m"]);
    let size = floats(&expected["size"]);
    let yaw = floats(&expected["yaw"]);
    let score = floats(&expected["score"]);
    let track_id = floats(&expected["track_id"]);
    let label = floats(&expected["label"]);
    let velocity = floats(&expected["velocity_m_per_s"]);
    let mut read = 0;
    for protocol in 0..=5 {
        let path = dir.join(format!("submission_p{protocol}.pkl"));
        let sub = scenalog_eval::read_pickle(&path)
            .unwrap_or_else(|e| panic!("protocol {protocol}: {e}"));
        let frames = &sub.sequences[&(log.to_string(), prompt.to_string())];
        assert_eq!(frames.len(), layouts.len());
        for (i, f) in frames.iter().enumerate() {
            let at = format!("submission protocol {protocol} frame {i} ({})", layouts[i]);
            assert_eq!(f.timestamp_ns, stamps[i], "{at}");
            assert_eq!(f.ego_translation_m, [1.0, 2.0, 3.0], "{at}");
            assert_eq!(f.description.as_deref(), Some(prompt), "{at}");
            let t: Vec<f64> = f.translation_m.iter().flatten().copied().collect();
            assert_eq!(t, translation, "{at}");
            let s: Vec<f64> = f.size.iter().flatten().map(|&x| f64::from(x)).collect();
            assert_eq!(s, size, "{at}");
            let v: Vec<f64> = f.velocity_m_per_s.iter().flatten().copied().collect();
            assert_eq!(v, velocity, "{at}");
            let y: Vec<f64> = f.yaw.iter().map(|&x| f64::from(x)).collect();
            assert_eq!(y, yaw, "{at}");
            let sc: Vec<f64> = f.score.iter().flatten().map(|&x| f64::from(x)).collect();
            assert_eq!(sc, score, "{at}");
            let ids: Vec<f64> = f.track_id.iter().map(|&x| f64::from(x)).collect();
            assert_eq!(ids, track_id, "{at}");
            let l: Vec<f64> = f.label.iter().map(|&x| f64::from(x)).collect();
            assert_eq!(l, label, "{at}");
            assert_eq!(f.name, names, "{at}");
        }
        read += 1;

        let path = dir.join(format!("tracks_p{protocol}.pkl"));
        let tracks =
            TrackerPickle::open(&path).unwrap_or_else(|e| panic!("protocol {protocol}: {e}"));
        let frames = tracks
            .frames(log)
            .unwrap_or_else(|e| panic!("protocol {protocol}: {e}"));
        assert_eq!(frames.len(), layouts.len());
        for (i, d) in frames.iter().enumerate() {
            let at = format!("tracks protocol {protocol} frame {i} ({})", layouts[i]);
            assert_eq!(d.timestamp_ns, stamps[i], "{at}");
            let t: Vec<f64> = d.translation_m.iter().flatten().copied().collect();
            assert_eq!(t, translation, "{at}");
            let s: Vec<f64> = d.size.iter().flatten().copied().collect();
            assert_eq!(s, size, "{at}");
            assert_eq!(d.yaw, yaw, "{at}");
            let sc: Vec<f64> = d.score.iter().map(|&x| f64::from(x)).collect();
            assert_eq!(sc, score, "{at}");
            let ids: Vec<f64> = d.track_id.iter().map(|&x| x as f64).collect();
            assert_eq!(ids, track_id, "{at}");
            assert_eq!(d.name, names, "{at}");
        }
        read += 1;
    }
    read
}

#[test]
fn committed_python_pickles_decode_in_every_protocol_and_layout() {
    assert_eq!(check_dir(&fixtures()), 12);
}

#[test]
fn python_pickles_made_live_decode_when_numpy_is_present() {
    let has_numpy = std::process::Command::new("python3")
        .args(["-c", "import numpy"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_numpy {
        eprintln!("skipped: python3 with numpy is not available (the committed fixtures are)");
        return;
    }
    let dir = tempfile::tempdir().expect("tempdir");
    let made = std::process::Command::new("python3")
        .arg(fixtures().join("make_pickles.py"))
        .arg(dir.path())
        .output()
        .expect("run make_pickles.py");
    assert!(
        made.status.success(),
        "make_pickles.py failed: {}",
        String::from_utf8_lossy(&made.stderr)
    );
    assert_eq!(check_dir(dir.path()), 12);
}

/// The 3D-tracking pickles Python wrote, in every protocol and layout, made into the sample log's
/// scene (their frames moved to the log's first timestamps, where it has ego poses): tracks
/// come in RefAV's order of objects (`Track::file_order`) by their first frame, then tracker id
/// (all four first appear in the first frame: ids 7, 8, 300, 40000), the added ego last;
/// `refav_order` over "ANY" follows it.
#[test]
fn python_tracker_pickles_order_their_tracks_by_first_frame_then_id() {
    use scenalog_extractors::{extract, relation_json};
    use scenalog_facts::relation::Request;
    use scenalog_tracker::{tracked_log, Filter};
    let log_dir = scenalog_testkit::sample_log(scenalog_testkit::SAMPLE_LOGS[0]);
    for protocol in 0..=5 {
        let path = fixtures().join(format!("tracks_p{protocol}.pkl"));
        let pickle = TrackerPickle::open(&path).unwrap_or_else(|e| panic!("{e}"));
        let log = pickle.log_ids().next().expect("a log").to_string();
        let mut frames = pickle.frames(&log).unwrap_or_else(|e| panic!("{e}"));
        let stamps = scenalog_facts::read::load_scene(&log_dir)
            .unwrap_or_else(|e| panic!("{e}"))
            .timeline
            .timestamps_ns()
            .to_vec();
        for (f, &t) in frames.iter_mut().zip(&stamps) {
            f.timestamp_ns = t;
        }
        let tracked = tracked_log(&log, &frames, &log_dir, Filter::None, pickle.file())
            .unwrap_or_else(|e| panic!("protocol {protocol}: {e}"));
        let scene = &tracked.scene;
        let mut by_order: Vec<(u32, Option<i64>)> = scene
            .tracks
            .iter()
            .map(|t| (t.file_order, tracked.tracker_ids[t.id.index()]))
            .collect();
        by_order.sort_unstable();
        let ids: Vec<Option<i64>> = by_order.iter().map(|r| r.1).collect();
        assert_eq!(
            ids,
            [Some(7), Some(8), Some(300), Some(40000), None],
            "protocol {protocol}"
        );
        let data = extract(scene, &Request::all("refav_order")).expect("refav_order");
        let rows = relation_json(scene, &data);
        let mut any: Vec<(i64, String)> = rows
            .as_array()
            .expect("rows")
            .iter()
            .filter(|r| r[1] == "ANY")
            .map(|r| {
                (
                    r[2].as_i64().unwrap_or(-1),
                    r[0].as_str().unwrap_or("").to_string(),
                )
            })
            .collect();
        any.sort();
        let uuids: Vec<String> = by_order
            .iter()
            .map(|&(o, _)| {
                let t = scene
                    .tracks
                    .iter()
                    .find(|t| t.file_order == o)
                    .expect("a track");
                t.uuid.clone()
            })
            .collect();
        assert_eq!(any.into_iter().map(|r| r.1).collect::<Vec<_>>(), uuids);
    }
}
