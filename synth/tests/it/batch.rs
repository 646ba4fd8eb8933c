//! Batch synthesis into a directory against a scripted server: outputs, summary, resuming, the
//! cache, and an unreachable server.

use crate::support;

use std::fs;
use std::time::Duration;

use scenalog_synth::batch::{self, diagnostics_path, transcript_path};
use scenalog_synth::{BatchOptions, ItemStatus, LlmConfig, SynthConfig, Synthesizer};
use support::server::{program, Reply, Request, Server};

const GOOD_TURN: &str = "referred(V, T) :- category(V, \"VEHICLE\"), turning(V, T, \"left\").";
const GOOD_STOP: &str = "referred(V, T) :- category(V, \"VEHICLE\"), speed(V, T, S), S < 0.5 m/s.";
const BAD: &str = "referred(V, T) :- category(V, \"VEHICLE\"), stopped_somehow(V, T).";

/// Answers by description: turning is right at once, stopped is repaired in round 2 (the
/// request has 4 messages then), pedestrian never is, anything else is prose.
fn answer(_: usize, r: &Request) -> Reply {
    let d = r.description().to_lowercase();
    let round = r.messages().len() / 2;
    if d.contains("turn") {
        program(GOOD_TURN)
    } else if d.contains("stopped") {
        program(if round >= 2 { GOOD_STOP } else { BAD })
    } else if d.contains("pedestrian") {
        program(BAD)
    } else {
        Reply::Completion("I am not sure.".into())
    }
}

fn config(server: &Server, cache: &std::path::Path) -> SynthConfig {
    SynthConfig {
        llm: LlmConfig {
            base_url: server.base_url(),
            model: "m".into(),
            timeout: Duration::from_secs(5),
            max_retries: 1,
            backoff: Duration::from_millis(5),
            ..LlmConfig::default()
        },
        cache_dir: Some(cache.to_path_buf()),
        rounds: 3,
        library: Vec::new(),
        examples: None,
        held_out: false,
        candidates: 1,
        sample_temperature: scenalog_synth::search::SAMPLE_TEMPERATURE,
        matcher: None,
        max_tokens: None,
        evidence_rounds: 0,
        evidence: None,
    }
}

fn descriptions() -> Vec<String> {
    vec![
        "vehicle turning left".into(),
        "stopped vehicle".into(),
        "pedestrian walking".into(),
        "Stopped  vehicle!".into(), // same slug as the second: gets "-2"
    ]
}

#[test]
fn a_batch_writes_every_program_resumes_and_reuses_the_cache() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    let cache = dir.path().join("cache");
    let server = Server::start(answer);
    let options = BatchOptions {
        out_dir: out.clone(),
        jobs: 3,
        progress: false,
    };
    let synth = Synthesizer::new(config(&server, &cache)).expect("synth");
    let report = batch::run(&synth, &descriptions(), &options).expect("batch");
    let s = &report.summary;
    assert_eq!(s.total, 4);
    assert_eq!(s.clean_by_round, vec![1, 2, 0]);
    assert_eq!(s.failed, 1);
    assert_eq!((s.resumed, s.unreachable, s.skipped), (0, 0, 0));
    // 1 + 2 + 2 + 3 completions, each asked once (the two "stopped" prompts differ in wording).
    assert_eq!(s.requests, 8);
    assert_eq!(server.count(), 8);
    assert_eq!(s.cache_hits, 0);
    let summary = s.to_string();
    assert!(
        summary.contains("3 clean (round 1: 1, round 2: 2, round 3: 0)"),
        "{summary}"
    );

    let names: Vec<_> = report
        .items
        .iter()
        .map(|i| i.path.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect::<Option<Vec<_>>>()
        .expect("names");
    assert_eq!(
        names,
        [
            "vehicle-turning-left.dl",
            "stopped-vehicle.dl",
            "pedestrian-walking.dl",
            "stopped-vehicle-2.dl"
        ]
    );
    assert_eq!(report.items[0].status, ItemStatus::Clean { round: 1 });
    assert_eq!(report.items[2].status, ItemStatus::Failed);
    let turn = fs::read_to_string(out.join("vehicle-turning-left.dl")).expect("read");
    assert_eq!(
        turn,
        format!("// description: vehicle turning left\n{GOOD_TURN}\n")
    );
    assert_eq!(report.items[0].program.as_deref(), Some(turn.as_str()));
    let stop2 = fs::read_to_string(out.join("stopped-vehicle-2.dl")).expect("read");
    assert!(stop2.starts_with("// description: Stopped vehicle!\n"));
    // The failed one: its last attempt, its diagnostics and its transcript are kept.
    let ped = out.join("pedestrian-walking.dl");
    assert!(fs::read_to_string(&ped)
        .expect("read")
        .contains("stopped_somehow"));
    let diags: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(diagnostics_path(&ped)).expect("read"))
            .expect("json");
    assert!(diags.as_array().is_some_and(|a| !a.is_empty()));
    let tr: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(transcript_path(&ped)).expect("read"))
            .expect("json");
    assert_eq!(tr["rounds"].as_array().map(Vec::len), Some(3));
    assert!(!diagnostics_path(&out.join("vehicle-turning-left.dl")).exists());
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("summary.json")).expect("summary"))
            .expect("json");
    assert_eq!(summary["summary"]["failed"], 1);
    assert_eq!(summary["items"][2]["status"]["status"], "failed");
    assert_eq!(summary["items"][0]["status"]["round"], 1);

    // A rerun: the clean ones are skipped, the failed one is answered from the cache.
    let synth = Synthesizer::new(config(&server, &cache)).expect("synth");
    let again = batch::run(&synth, &descriptions(), &options).expect("batch");
    assert_eq!(server.count(), 8, "the rerun asked the server");
    assert_eq!(again.summary.resumed, 3);
    assert_eq!(again.summary.failed, 1);
    assert_eq!(again.summary.cache_hits, 3);
    assert_eq!(again.items[1].status, ItemStatus::Resumed);
    assert_eq!(again.items[1].program, report.items[1].program);
}

#[test]
fn an_unreachable_server_stops_the_batch_and_loses_nothing() {
    let dir = tempfile::tempdir().expect("tempdir");
    let server = Server::start(|_, _| Reply::Error {
        status: 403,
        message: "forbidden".into(),
        retry_after: None,
    });
    let synth = Synthesizer::new(config(&server, &dir.path().join("cache"))).expect("synth");
    let options = BatchOptions {
        out_dir: dir.path().join("out"),
        jobs: 1,
        progress: false,
    };
    let report = batch::run(&synth, &descriptions(), &options).expect("batch");
    assert_eq!(report.summary.unreachable, 1);
    assert_eq!(report.summary.skipped, 3);
    assert_eq!(server.count(), 1);
    match &report.items[0].status {
        ItemStatus::Unreachable { error } => {
            assert!(error.contains("403") && error.contains("forbidden"))
        }
        other => panic!("expected unreachable, got {other:?}"),
    }
    // Its transcript says why; no program file was invented.
    let dl = options.out_dir.join("vehicle-turning-left.dl");
    assert!(!dl.exists());
    assert!(fs::read_to_string(transcript_path(&dl))
        .expect("read")
        .contains("forbidden"));
}

#[test]
fn descriptions_files_skip_blanks_comments_and_repeats() {
    let dir = tempfile::tempdir().expect("tempdir");
    let f = dir.path().join("d.txt");
    fs::write(
        &f,
        "# scenarios\n\nvehicle  turning left\r\nstopped car\nvehicle turning left\n",
    )
    .expect("write");
    assert_eq!(
        batch::read_descriptions(&f).expect("read"),
        ["vehicle turning left", "stopped car"]
    );
    fs::write(&f, "\n# nothing\n").expect("write");
    let e = batch::read_descriptions(&f).unwrap_err().to_string();
    assert!(e.contains("d.txt") && e.contains("no descriptions"), "{e}");
    let e = batch::read_descriptions(&dir.path().join("missing.txt"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.txt"), "{e}");
}
