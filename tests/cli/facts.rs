//! `scenalog facts` end to end: the built binary on the real logs in `tests/data/av2/logs/`.
//!
//! Expected figures were computed independently with pyarrow (see `facts/tests/verify_figures.py`).

use std::path::PathBuf;
use std::process::Output;

fn log_dir(id: &str) -> PathBuf {
    scenalog_testkit::sample_logs_dir().join(id)
}

fn scenalog(args: &[&str]) -> Output {
    crate::util::scenalog()
        .args(args)
        .output()
        .expect("run scenalog")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn text_summary_of_the_mia_log() {
    let dir = log_dir("3b3570b4-7b0b-3268-a571-b0889dbf40b6");
    let out = scenalog(&["facts", dir.to_str().expect("utf8 path")]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = stdout(&out);
    for want in [
        "log 3b3570b4-7b0b-3268-a571-b0889dbf40b6 (city MIA)",
        "timestamps  157 over 15.60 s",
        "boxes       13820",
        "tracks      120",
        "REGULAR_VEHICLE      84",
        "PEDESTRIAN           12",
        "lane segments 150 (150 VEHICLE; 48 in intersections; 22 dangling ids)",
        "pedestrian crossings 6",
        "drivable areas 5",
        "loaded in",
    ] {
        assert!(text.contains(want), "missing {want:?} in:\n{text}");
    }
}

#[test]
fn json_summary_of_each_log() {
    // (log, city, timestamps, tracks, boxes, REGULAR_VEHICLE tracks, lanes, crossings, areas, ego uuid)
    let cases = [
        (
            "3b3570b4-7b0b-3268-a571-b0889dbf40b6",
            "MIA",
            157,
            120,
            13_820,
            84,
            150,
            6,
            5,
            "9d57813a-2d04-40e6-9694-20dfa13295dc",
        ),
        (
            "3bffdcff-c3a7-38b6-a0f2-64196d130958",
            "PIT",
            156,
            116,
            12_342,
            98,
            211,
            14,
            15,
            "27c6325e-81c4-458a-8e45-628550c80da3",
        ),
        // The plain log: 146 tracks in the file + the added ego; 12,078 rows + 156 ego boxes.
        (
            "adcf7d18-0510-35b0-a2fa-b4cea13a6d76",
            "PIT",
            156,
            147,
            12_234,
            47,
            199,
            11,
            8,
            "ego",
        ),
    ];
    for (id, city, ts, tracks, boxes, cars, lanes, crossings, areas, ego) in cases {
        let dir = log_dir(id);
        let out = scenalog(&["facts", "--json", dir.to_str().expect("utf8 path")]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
        assert_eq!(v["log_id"], id);
        assert_eq!(v["city"], city);
        assert_eq!(v["timestamps"], ts);
        assert_eq!(v["tracks"], tracks);
        assert_eq!(v["boxes"], boxes);
        assert_eq!(v["tracks_by_category"]["REGULAR_VEHICLE"], cars);
        assert_eq!(v["tracks_by_category"]["EGO_VEHICLE"], 1);
        let sum: u64 = v["tracks_by_category"]
            .as_object()
            .expect("object")
            .values()
            .filter_map(|n| n.as_u64())
            .sum();
        assert_eq!(sum, tracks);
        assert_eq!(v["lane_segments"], lanes);
        assert_eq!(v["pedestrian_crossings"], crossings);
        assert_eq!(v["drivable_areas"], areas);
        assert_eq!(v["ego_uuid"], ego);
        assert!(v["load_ms"].as_f64().is_some_and(|ms| ms > 0.0));
    }
}

#[test]
fn unreadable_log_exits_2_with_the_path_on_stderr() {
    let out = scenalog(&["facts", "/nonexistent/scenalog-log"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("/nonexistent/scenalog-log"), "{err}");

    // A directory that is not a log (the map folder of a real one).
    let dir = log_dir("3b3570b4-7b0b-3268-a571-b0889dbf40b6").join("map");
    let out = scenalog(&["facts", "--json", dir.to_str().expect("utf8 path")]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("annotations"), "{err}");
}

#[test]
fn facts_help_describes_the_arguments() {
    let out = scenalog(&["facts", "--help"]);
    assert!(out.status.success());
    let text = stdout(&out);
    assert!(
        text.contains("LOG_DIR") && text.contains("--json"),
        "{text}"
    );
}

#[test]
fn facts_relation_prints_count_and_json_tuples() {
    let log = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/av2/logs/3b3570b4-7b0b-3268-a571-b0889dbf40b6"
    );
    let out = crate::util::scenalog()
        .args(["facts", log, "--relation", "in_lane", "--json"])
        .output()
        .expect("run scenalog");
    assert!(out.status.success());
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON array");
    let rows = rows.as_array().expect("array");
    assert!(!rows.is_empty());
    for row in rows {
        let row = row.as_array().expect("tuple");
        assert_eq!(row.len(), 3);
        assert!(row[0].is_string(), "track as uuid");
        assert!(row[1].as_u64().is_some_and(|f| f < 157), "frame index");
        assert!(row[2].as_i64().is_some(), "lane map id");
    }
    let text = crate::util::scenalog()
        .args(["facts", log, "--relation", "in_lane"])
        .output()
        .expect("run scenalog");
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(text.contains(&format!("{} tuples", rows.len())), "{text}");
    let bad = crate::util::scenalog()
        .args(["facts", log, "--relation", "no_such_relation"])
        .output()
        .expect("run scenalog");
    assert_eq!(bad.status.code(), Some(2));
}

/// `facts --relation` extracts within `mine`'s limits: a relation past `--max-tuples` or a
/// `--timeout-ms` is an error naming it (exit 2), the same relation within them is counted.
#[test]
fn a_relation_is_extracted_within_the_limits() {
    let dir = log_dir("3b3570b4-7b0b-3268-a571-b0889dbf40b6");
    let dir = dir.to_str().expect("utf8 path");
    let ok = scenalog(&["facts", dir, "--relation", "near"]);
    assert!(ok.status.success(), "{:?}", ok);
    let count: usize = stdout(&ok)
        .split(": near: ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|n| n.parse().ok())
        .expect("a count");
    assert!(count > 100, "{count}");
    let small = (count / 2).to_string();
    let over = scenalog(&["facts", dir, "--relation", "near", "--max-tuples", &small]);
    assert_eq!(over.status.code(), Some(2));
    let err = String::from_utf8_lossy(&over.stderr);
    assert!(err.contains("near") && err.contains(&small), "{err}");
    let late = scenalog(&["facts", dir, "--relation", "near", "--timeout-ms", "1"]);
    assert_eq!(late.status.code(), Some(2));
    let err = String::from_utf8_lossy(&late.stderr);
    assert!(
        err.contains("near") && err.contains("time limit of 1 ms"),
        "{err}"
    );
}

/// `facts --relation R --json --columns` names the columns from the catalog (as the Python
/// package's tables) around the same tuples the bare `--json` prints, which is unchanged.
#[test]
fn facts_relation_json_names_its_columns_from_the_catalog() {
    let log = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/av2/logs/3b3570b4-7b0b-3268-a571-b0889dbf40b6"
    );
    let run = |extra: &[&str]| {
        let out = crate::util::scenalog()
            .args(["facts", log, "--relation", "near", "--json"])
            .args(extra)
            .output()
            .expect("run scenalog");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice::<serde_json::Value>(&out.stdout).expect("JSON")
    };
    let bare = run(&[]);
    let named = run(&["--columns"]);
    assert_eq!(named["relation"], "near");
    let names: Vec<&str> = named["columns"]
        .as_array()
        .expect("columns")
        .iter()
        .map(|c| c["name"].as_str().expect("name"))
        .collect();
    let spec = scenalog_facts::catalog::relation("near").expect("near");
    assert_eq!(names, spec.column_names());
    assert_eq!(names.len(), spec.columns.len());
    assert_eq!(named["columns"][0]["type"], "track");
    assert_eq!(named["tuples"], bare, "the same tuples");
    assert!(
        bare.as_array().is_some_and(|a| !a.is_empty()),
        "bare array unchanged"
    );
}
