//! `scenalog explain --rerun OUT.rrd`: the recording read back with Rerun's own Python SDK (the
//! crate's version, `rerun-sdk` 0.36.3; `SCENALOG_RERUN_PYTHON` names a Python that has it, else
//! `python3`), and what it holds checked against `explain`'s own answers. Built with the `rerun`
//! feature (`.ci/run` runs this module so); without it, the flag is an error that says how to get
//! it.

use std::path::Path;

const LOG: &str = "tests/data/av2/logs/3b3570b4-7b0b-3268-a571-b0889dbf40b6";
const RULES: &str = "rules/library/vehicle_with_bicycle_to_its_right.dl";
const TRACK: &str = "2f09a161";

fn explain_rerun(out: &Path) -> std::process::Output {
    crate::util::scenalog()
        .args([
            "explain", "--rules", RULES, "--log", LOG, "--track", TRACK, "--at", "8", "--rerun",
        ])
        .arg(out)
        .output()
        .expect("run explain")
}

#[test]
fn rerun_wants_an_rrd_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let o = explain_rerun(&dir.path().join("x.png"));
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--rerun") && err.contains(".rrd"), "{err}");
}

/// `scenalog mine --rerun` of the bicycle program and the stopped-car one on the test's log.
fn mine_rerun(out: &Path) -> std::process::Output {
    crate::util::scenalog()
        .args([
            "mine",
            "--rules",
            RULES,
            "rules/library/stopped_car.dl",
            "--logs",
            LOG,
            "--threads",
            "1",
            "--rerun",
            "--out",
        ])
        .arg(out)
        .output()
        .expect("run mine")
}

#[cfg(not(feature = "rerun"))]
#[test]
fn rerun_without_the_feature_says_how_to_get_it() {
    let dir = tempfile::tempdir().expect("tempdir");
    let o = mine_rerun(&dir.path().join("out"));
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--rerun") && err.contains("--features rerun"),
        "{err}"
    );
    assert!(!dir.path().join("out/matches.rrd").exists());

    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("x.rrd");
    let o = explain_rerun(&out);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--features rerun"), "{err}");
    assert!(!out.exists());
}

/// The recording at `out` as `tests/support/read_rrd.py` reads it with rerun-sdk.
#[cfg(feature = "rerun")]
fn read_back(out: &Path) -> serde_json::Value {
    const SDK: &str = "0.36.3";
    let python = std::env::var("SCENALOG_RERUN_PYTHON").unwrap_or_else(|_| "python3".into());
    let read = std::process::Command::new(&python)
        .arg("tests/support/read_rrd.py")
        .arg(out)
        .arg(SDK)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {python}: {e}"));
    assert!(
        read.status.success(),
        "reading the recording with rerun-sdk {SDK} failed (pip install rerun-sdk=={SDK}; \
         SCENALOG_RERUN_PYTHON names the Python): {}",
        String::from_utf8_lossy(&read.stderr)
    );
    serde_json::from_slice(&read.stdout).expect("json")
}

#[cfg(feature = "rerun")]
#[test]
fn rerun_recording_of_a_run_holds_each_programs_matches() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    let o = mine_rerun(&out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("wrote the Rerun recording"), "{err}");
    let got = read_back(&out.join("matches.rrd"));
    let log_id = LOG.rsplit('/').next().expect("log id");
    let entities = &got["entities"];
    assert_eq!(
        entities[format!("/logs/{log_id}/map/lanes")]["static"],
        true
    );
    // Per program, the tracks it refers to over the log are the run's matches (matches.json).
    let matches: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("matches.json")).expect("matches.json"),
    )
    .expect("json");
    for program in ["vehicle_with_bicycle_to_its_right", "stopped_car"] {
        let rows = entities[format!("/logs/{log_id}/programs/{program}/referred")]["rows"]
            .as_array()
            .unwrap_or_else(|| panic!("no referred entity of {program}"))
            .clone();
        let recorded: std::collections::BTreeSet<String> = rows
            .iter()
            .flat_map(|r| r["labels"].as_array().cloned().unwrap_or_default())
            .filter_map(|l| l.as_str().map(|l| l[..8].to_string()))
            .collect();
        let mined: std::collections::BTreeSet<String> = matches
            .as_array()
            .expect("matches")
            .iter()
            .filter(|m| m["program"] == program)
            .map(|m| m["track_uuid"].as_str().expect("uuid")[..8].to_string())
            .collect();
        assert!(!mined.is_empty(), "{program}");
        assert_eq!(recorded, mined, "{program}");
    }
    // Every object at every frame (157 frames).
    assert_eq!(
        entities[format!("/logs/{log_id}/objects")]["rows"]
            .as_array()
            .expect("objects")
            .len(),
        157
    );
}

#[cfg(feature = "rerun")]
#[test]
fn rerun_recording_holds_the_map_the_boxes_and_the_proof_at_every_frame() {
    use serde_json::Value;

    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("match.rrd");
    let o = explain_rerun(&out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.is_file());
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .expect("dir")
        .filter_map(Result::ok)
        .filter(|e| e.file_name() != "match.rrd")
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");

    let got = read_back(&out);
    assert_eq!(got["recordings"], serde_json::json!(["scenalog"]));
    let entities = &got["entities"];
    let rows = |e: &str| -> Vec<Value> {
        entities[e]["rows"]
            .as_array()
            .unwrap_or_else(|| panic!("no entity {e} in {entities}"))
            .clone()
    };
    let at = |e: &str, frame: u64| -> Value {
        rows(e)
            .into_iter()
            .find(|r| r["frame"] == frame)
            .unwrap_or_else(|| panic!("no row of {e} at frame {frame}"))
    };

    // The map, once.
    for e in ["/map/lanes", "/map/crossings", "/map/drivable", "/program"] {
        assert_eq!(entities[e]["static"], true, "{e}");
    }
    assert!(rows("/map/lanes")[0]["strips"].as_u64().expect("strips") > 10);
    assert!(rows("/program")[0]["text"]
        .as_str()
        .expect("program")
        .contains("bicycle_right(V, B, T)"));

    // A proof at every frame of the log (157), each the explain text of that frame.
    let proofs = rows("/proof");
    assert_eq!(proofs.len(), 157);
    let frame_80 = at("/proof", 80)["text"].as_str().expect("text").to_string();
    assert!(
        frame_80.contains("at 8.0 s (frame 80): referred") && frame_80.contains("Proof:"),
        "{frame_80}"
    );
    let cli = crate::util::scenalog()
        .args([
            "explain", "--rules", RULES, "--log", LOG, "--track", TRACK, "--at", "8",
        ])
        .output()
        .expect("explain");
    let cli_text = String::from_utf8_lossy(&cli.stdout);
    // The same proof as `explain` prints (the recording names the rules file the same way).
    assert_eq!(frame_80.trim_end(), cli_text.trim_end());
    let frame_72 = at("/proof", 72)["text"].as_str().expect("text").to_string();
    assert!(
        frame_72.contains("(frame 72): NOT referred") && frame_72.contains("Why not:"),
        "{frame_72}"
    );
    let frame_0 = at("/proof", 0)["text"].as_str().expect("text").to_string();
    assert!(
        frame_0.contains("NOT referred") && frame_0.contains("no box at this frame"),
        "{frame_0}"
    );
    assert!(at("/explained", 0)["boxes"] == 0 || at("/explained", 0)["boxes"].is_null());

    // The boxes at frame 80: the track referred, the bicycle related, the ego, the others.
    let labels = |e: &str| -> Vec<String> {
        at(e, 80)["labels"]
            .as_array()
            .map(|l| {
                l.iter()
                    .filter_map(|s| s.as_str().map(str::to_string))
                    .collect()
            })
            .unwrap_or_default()
    };
    assert!(
        labels("/objects/referred").contains(&"2f09a161 (REGULAR_VEHICLE)".to_string()),
        "{:?}",
        labels("/objects/referred")
    );
    // The rule relates bicycles only; the one in the proof among them.
    let related = labels("/objects/related");
    assert!(
        related.contains(&"8f1f6bc5 (BICYCLE)".to_string())
            && related.iter().all(|l| l.ends_with("(BICYCLE)")),
        "{related:?}"
    );
    assert_eq!(labels("/objects/ego").len(), 1);
    assert!(labels("/objects/other").len() > 10);
    assert_eq!(at("/explained", 80)["boxes"], 1);
}
