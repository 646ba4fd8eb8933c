//! `scenalog synth` end to end: the built binary against a scripted OpenAI-compatible server on
//! 127.0.0.1 (the same test server as the synth crate's tests).

use crate::server;

use std::fs;
use std::process::Output;

use server::{program, with_usage, Reply, Server};

const GOOD: &str = "referred(V, T) :- category(V, \"VEHICLE\"), turning(V, T, \"left\").";
const UNKNOWN: &str = "referred(V, T) :- category(V, \"VEHICLE\"), turning_left(V, T).";

/// Runs the binary with no LLM settings from the environment but `env`.
fn scenalog(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = crate::util::scenalog();
    c.arg("synth").args(args);
    for v in [
        "SCENALOG_LLM_BASE_URL",
        "SCENALOG_LLM_MODEL",
        "SCENALOG_LLM_API_KEY",
    ] {
        c.env_remove(v);
    }
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run scenalog")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn print_prompt_shows_the_catalog_examples_and_description() {
    let o = scenalog(&["--print-prompt", "vehicle making a left turn"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.starts_with("=== system ===\n"));
    assert!(text.contains("=== user ===\n"));
    for r in scenalog_facts::catalog::catalog() {
        // RefAV's own definitions are for imported programs: one meaning of a concept a prompt.
        let shown = r.group != scenalog_facts::catalog::Group::Refav;
        assert_eq!(text.contains(&r.signature()), shown, "{}", r.name);
    }
    assert!(text.contains("WHEELED_RIDER"));
    assert!(text.ends_with(
        "Write the Scenalog program for this description:\nvehicle making a left turn\n"
    ));
    // The library's left-turn example is among the examples.
    assert!(text.contains("turning(V, T, \"left\")"), "{text}");
    // All examples: at least as long as with the default 8.
    let all = scenalog(&["--print-prompt", "--examples", "all", "x"], &[]);
    assert!(all.status.success());
    let none = scenalog(&["--print-prompt", "--examples", "0", "x"], &[]);
    assert!(!stdout(&none).contains("Examples of checked programs"));
    assert!(stdout(&all).len() > stdout(&none).len());
    let bad = scenalog(&["--print-prompt", "--examples", "some", "x"], &[]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(stderr(&bad).contains("--examples"));
}

#[test]
fn one_description_clean_after_a_repair_prints_the_program() {
    let server = Server::scripted(vec![program(UNKNOWN), program(GOOD)]);
    let url = server.base_url();
    let o = scenalog(
        &[
            "vehicle making a left turn",
            "--model",
            "m1",
            "--api-key",
            "k1",
        ],
        &[("SCENALOG_LLM_BASE_URL", url.as_str())],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(
        stdout(&o),
        format!("// description: vehicle making a left turn\n{GOOD}\n")
    );
    assert!(stderr(&o).contains("checked clean in round 2"));
    let reqs = server.requests();
    assert_eq!(reqs.len(), 2);
    assert_eq!(reqs[0].json["model"], "m1");
    assert_eq!(reqs[0].header("authorization"), Some("Bearer k1"));
    assert!(reqs[1].last_message().contains("turning_left"));
    assert_eq!(reqs[0].json["temperature"], 0.0);

    // --temperature default sends none.
    let server = Server::scripted(vec![program(GOOD)]);
    let url = server.base_url();
    let o = scenalog(&["x", "--temperature", "default", "--base-url", &url], &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(server.requests()[0].json.get("temperature").is_none());
    let o = scenalog(&["x", "--temperature", "hot", "--base-url", &url], &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--temperature"));
}

#[test]
fn one_description_written_to_a_file_and_cached() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("new").join("left.dl");
    let out_s = out.to_string_lossy().into_owned();
    let cache = dir.path().join("cache");
    let cache_s = cache.to_string_lossy().into_owned();
    let server = Server::scripted(vec![program(GOOD)]);
    let url = server.base_url();
    let args = [
        "vehicle making a left turn",
        "-o",
        &out_s,
        "--cache-dir",
        &cache_s,
        "--base-url",
        &url,
    ];
    let o = scenalog(&args, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stdout(&o).is_empty());
    let written = fs::read_to_string(&out).expect("program");
    assert!(written.starts_with("// description: vehicle making a left turn\n"));
    assert!(dir.path().join("new/left.transcript.json").exists());
    // Again: answered by the cache, the server sees nothing new.
    let o = scenalog(&args, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(server.count(), 1);
    assert_eq!(fs::read_to_string(&out).expect("program"), written);
}

#[test]
fn rounds_run_out_exit_1_with_the_attempt_and_diagnostics_written() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("bad.dl");
    let out_s = out.to_string_lossy().into_owned();
    let server = Server::start(|_, _| program(UNKNOWN));
    let url = server.base_url();
    let o = scenalog(
        &[
            "vehicle making a left turn",
            "-o",
            &out_s,
            "--rounds",
            "2",
            "--base-url",
            &url,
        ],
        &[],
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(server.count(), 2);
    assert!(stderr(&o).contains("no clean program after 2 rounds"));
    assert!(fs::read_to_string(&out)
        .expect("attempt")
        .contains("turning_left"));
    let diags: serde_json::Value = serde_json::from_str(
        &fs::read_to_string(dir.path().join("bad.dl.diagnostics.json")).expect("diagnostics"),
    )
    .expect("json");
    assert!(diags[0]["message"]
        .as_str()
        .is_some_and(|m| m.contains("turning_left")));

    // Without -o the attempt goes to stdout and its diagnostics to stderr.
    let o = scenalog(
        &[
            "vehicle making a left turn",
            "--rounds",
            "1",
            "--base-url",
            &url,
        ],
        &[],
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(stdout(&o).contains("turning_left"));
    assert!(stderr(&o).contains("turning_left"), "{}", stderr(&o));
}

#[test]
fn unreachable_or_refused_exits_2_with_the_servers_message() {
    let server = Server::scripted(vec![Reply::Error {
        status: 401,
        message: "Invalid API key".into(),
        retry_after: None,
    }]);
    let url = server.base_url();
    let o = scenalog(&["stopped car", "--base-url", &url], &[]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains("401") && err.contains("Invalid API key"),
        "{err}"
    );
    assert!(stdout(&o).is_empty());

    let o = scenalog(
        &[
            "stopped car",
            "--base-url",
            "http://127.0.0.1:9/v1",
            "--retries",
            "0",
        ],
        &[],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("could not reach the LLM server at http://127.0.0.1:9/v1"),
        "{}",
        stderr(&o)
    );

    // `--eval` too: the report is printed, and the exit says the server was not reached.
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("set.txt");
    fs::write(&file, "stopped car\nparked bus\n").expect("write descriptions");
    let logs_dir = scenalog_testkit::sample_logs_dir();
    let logs = logs_dir.to_str().expect("a UTF-8 path");
    let o = scenalog(
        &[
            "--eval",
            file.to_str().expect("utf-8 path"),
            "--logs",
            logs,
            "--base-url",
            "http://127.0.0.1:9/v1",
            "--retries",
            "0",
        ],
        &[],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("could not be reached for 2 of 2 descriptions")
            && err.contains("http://127.0.0.1:9/v1"),
        "{err}"
    );
    assert!(stdout(&o).contains("descriptions"), "{}", stdout(&o));
}

#[test]
fn a_batch_writes_one_program_per_description_and_resumes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let list = dir.path().join("d.txt");
    fs::write(
        &list,
        "vehicle making a left turn\n\n# comment\nstopped car\n",
    )
    .expect("write");
    let out = dir.path().join("out");
    let server = Server::start(|_, r| {
        if r.description().contains("stopped") {
            program(UNKNOWN)
        } else {
            program(GOOD)
        }
    });
    let url = server.base_url();
    let args = [
        "--descriptions",
        &list.to_string_lossy(),
        "--out",
        &out.to_string_lossy(),
        "--base-url",
        &url,
        "--jobs",
        "2",
    ]
    .map(|s| s.to_string());
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = scenalog(&args, &[]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("2 descriptions: 1 clean (round 1: 1, round 2: 0, round 3: 0), 0 already done, 1 failed"), "{err}");
    assert!(out.join("vehicle-making-a-left-turn.dl").exists());
    assert!(out.join("stopped-car.dl.diagnostics.json").exists());
    assert!(stdout(&o).contains("stopped-car.dl\tFAILED\tstopped car"));
    assert_eq!(server.count(), 4);

    // Rerun: the clean one is skipped, the failed one comes from the cache in DIR/.llm-cache.
    let o = scenalog(&args, &[]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("1 already done"), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("0 completions from the server, 3 from the cache"),
        "{}",
        stderr(&o)
    );
    assert_eq!(server.count(), 4);
}

#[test]
fn bad_arguments_are_refused() {
    let o = scenalog(&[], &[]);
    assert_eq!(o.status.code(), Some(2));
    let o = scenalog(&["--descriptions", "x.txt"], &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--out"), "{}", stderr(&o));
    let dir = tempfile::tempdir().expect("tempdir");
    let missing = dir.path().join("missing.txt");
    let o = scenalog(
        &[
            "--descriptions",
            &missing.to_string_lossy(),
            "--out",
            &dir.path().to_string_lossy(),
        ],
        &[],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("missing.txt"), "{}", stderr(&o));
}

#[test]
fn eval_reports_a_description_set_with_held_out_prompts_on_the_sample_logs() {
    const STOPPED: &str =
        "referred(V, T) :- category(V, \"REGULAR_VEHICLE\"), speed(V, T, S), S < 0.5 m/s.";
    const TRAIN: &str = "referred(V, T) :- category(V, \"RAILED_VEHICLE\"), present(V, T).";
    let server = Server::scripted(vec![program(STOPPED), program(UNKNOWN), program(TRAIN)]);
    let url = server.base_url();
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("set.txt");
    fs::write(&file, "stopped car\ntram crossing\n").expect("write descriptions");
    let logs_dir = scenalog_testkit::sample_logs_dir();
    let logs = logs_dir.to_str().expect("a UTF-8 path");
    let o = scenalog(
        &["--eval", file.to_str().expect("utf-8 path"), "--logs", logs],
        &[("SCENALOG_LLM_BASE_URL", url.as_str())],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("descriptions                      2\n"),
        "{text}"
    );
    assert!(
        text.contains("clean on round 1                  1 (50 %)"),
        "{text}"
    );
    assert!(
        text.contains("clean within 3 rounds             2 (100 %)"),
        "{text}"
    );
    assert!(
        text.contains("mean rounds                       1.50"),
        "{text}"
    );
    // No railed vehicle in the three sample logs; stopped cars in all of them.
    assert!(
        text.contains("clean but match nothing on logs   1\n"),
        "{text}"
    );
    assert!(
        text.contains("  matches nothing: tram crossing\n"),
        "{text}"
    );
    // Held out: the library's own stopped-car program was not among the examples.
    let reqs = server.requests();
    let first = reqs[0].messages();
    assert!(
        !first[1].contains("// description: stopped car\n"),
        "{}",
        first[1]
    );
    assert!(
        first[1].contains("Examples of checked programs"),
        "{}",
        first[1]
    );
}

/// `--eval` on `set` (one description a line) with the scripted `replies` and `extra`
/// arguments, on the sample logs; it must succeed.
fn run_eval(set: &str, replies: Vec<Reply>, extra: &[&str]) -> Output {
    let server = Server::scripted(replies);
    let url = server.base_url();
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("set.txt");
    fs::write(&file, set).expect("write descriptions");
    let logs_dir = scenalog_testkit::sample_logs_dir();
    let logs = logs_dir.to_str().expect("a UTF-8 path");
    let mut args = vec!["--eval", file.to_str().expect("utf-8 path"), "--logs", logs];
    args.extend_from_slice(extra);
    let o = scenalog(&args, &[("SCENALOG_LLM_BASE_URL", url.as_str())]);
    assert!(o.status.success(), "{}", stderr(&o));
    o
}

/// The JSON report of `--eval` on `set` with the scripted `replies`.
fn eval_json(set: &str, replies: Vec<Reply>, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["--json"];
    args.extend_from_slice(extra);
    let o = run_eval(set, replies, &args);
    serde_json::from_str(&stdout(&o)).unwrap_or_else(|e| panic!("{e}: {}", stdout(&o)))
}

#[test]
fn eval_scores_the_fixture_prompts_as_mine_does() {
    // The model answers the two fixture prompts with the library's programs, and a third
    // description that is no prompt of the fixture: the fixture score is the main job's
    // (README.md: `scenalog mine` scores 0.5708605517786205 with the same two programs).
    let stopped = include_str!("../../rules/library/stopped_car.dl");
    let bike = include_str!("../../rules/library/vehicle_with_bicycle_to_its_right.dl");
    const TRAIN: &str = "referred(V, T) :- category(V, \"RAILED_VEHICLE\"), present(V, T).";
    let report = eval_json(
        "stopped car\ntram crossing\nvehicle with a bicycle to its right\n",
        vec![program(stopped), program(TRAIN), program(bike)],
        &[],
    );
    assert_eq!(report["descriptions"], 3, "{report:#}");
    assert_eq!(report["clean_first_round"], 3);
    let f = &report["fixture"];
    assert_eq!(
        f["prompts"],
        serde_json::json!(["stopped car", "vehicle with a bicycle to its right"])
    );
    assert_eq!(f["without_program"], serde_json::json!([]));
    let hota = f["hota_temporal"].as_f64().expect("a number");
    assert!((hota - 0.5708605517786205).abs() < 1e-12, "{f:#}");
    let per: Vec<(String, f64)> = f["by_prompt"]
        .as_array()
        .expect("by_prompt")
        .iter()
        .map(|p| {
            (
                p["prompt"].as_str().unwrap_or_default().to_string(),
                p["hota_temporal"].as_f64().unwrap_or(-1.0),
            )
        })
        .collect();
    assert_eq!(per.len(), 2, "{per:?}");
    assert_eq!(per[0].0, "stopped car");
    assert!((per[0].1 - 0.8527).abs() < 5e-5, "{per:?}");
    assert!((per[1].1 - 0.2890).abs() < 5e-5, "{per:?}");
    // Each clean program is in its item.
    assert!(report["items"][0]["program"]
        .as_str()
        .is_some_and(|p| p.contains("REGULAR_VEHICLE")));
}

#[test]
fn eval_scores_a_fixture_prompt_without_a_clean_program_as_predicting_nothing() {
    // One round, an unknown relation: no clean program for "stopped car", which then predicts
    // nothing and scores 0 instead of being left out of the score.
    let report = eval_json("stopped car\n", vec![program(UNKNOWN)], &["--rounds", "1"]);
    let f = &report["fixture"];
    assert_eq!(
        f["prompts"],
        serde_json::json!(["stopped car"]),
        "{report:#}"
    );
    assert_eq!(f["without_program"], serde_json::json!(["stopped car"]));
    assert_eq!(f["hota_temporal"].as_f64(), Some(0.0), "{f:#}");
    // A set without fixture prompts has no fixture score.
    const TRAIN: &str = "referred(V, T) :- category(V, \"RAILED_VEHICLE\"), present(V, T).";
    let none = eval_json("tram crossing\n", vec![program(TRAIN)], &[]);
    assert!(none["fixture"].is_null(), "{none:#}");
}

#[test]
fn eval_stops_a_runaway_program_at_the_time_limit_and_scores_it_as_predicting_nothing() {
    // The model answers "stopped car" with a program that checks clean but would run for many
    // minutes on every log (issue #18's reproducer, with a product no range narrowing can
    // bound). With `--timeout-ms` the run ends, each of
    // its (log, prompt) pairs is listed as failed, and the prompt scores 0 rather than being
    // left out of the score.
    const RUNAWAY: &str =
        "referred(A, T) :- present(A, T), present(B, T), present(C, T3), T3 * T < 0, A != B, B != C.";
    let report = eval_json(
        "stopped car\n",
        vec![program(RUNAWAY)],
        &["--timeout-ms", "300"],
    );
    assert_eq!(report["clean_first_round"], 1, "{report:#}");
    let f = &report["fixture"];
    assert_eq!(f["prompts"], serde_json::json!(["stopped car"]), "{f:#}");
    assert_eq!(f["without_program"], serde_json::json!([]));
    let failed = f["failed_pairs"].as_array().expect("failed_pairs");
    assert!(!failed.is_empty(), "{f:#}");
    for p in failed {
        let p = p.as_str().unwrap_or_default();
        assert!(
            p.contains("stopped car") && p.contains("ran longer than"),
            "{p}"
        );
    }
    assert_eq!(f["hota_temporal"].as_f64(), Some(0.0), "{f:#}");
}

#[test]
fn eval_text_report_shows_the_fixture_score() {
    // README.md's held-out synthesis report, exactly: three descriptions, two of them the
    // fixture's prompts answered with the library's programs, one repaired once.
    let stopped = include_str!("../../rules/library/stopped_car.dl");
    let bike = include_str!("../../rules/library/vehicle_with_bicycle_to_its_right.dl");
    const TRAIN: &str = "referred(V, T) :- category(V, \"RAILED_VEHICLE\"), present(V, T).";
    let o = run_eval(
        "stopped car\ntram crossing\nvehicle with a bicycle to its right\n",
        vec![
            with_usage(program(stopped), 4812, Some(0), 131),
            with_usage(program(UNKNOWN), 4790, Some(4736), 38),
            with_usage(program(TRAIN), 5102, Some(4736), 41),
            with_usage(program(bike), 4840, Some(4736), 172),
        ],
        &["--price", "2,0.5,8"],
    );
    let text = stdout(&o);
    let readme = include_str!("../../README.md");
    let start = readme
        .find("~~~\ndescriptions                      3\n")
        .expect("README.md shows the report");
    let block = &readme[start + 4..];
    let block = &block[..block.find("~~~").expect("the block ends")];
    assert_eq!(text, block);
    // A --gt that is not a file is refused before anything is asked (no server listens).
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("set.txt");
    fs::write(&file, "stopped car\n").expect("write descriptions");
    let o = scenalog(
        &[
            "--eval",
            file.to_str().expect("utf-8 path"),
            "--gt",
            "/nonexistent/gt.pkl",
        ],
        &[("SCENALOG_LLM_BASE_URL", "http://127.0.0.1:9/v1")],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("/nonexistent/gt.pkl"), "{}", stderr(&o));
}

/// An LLM completion holding a 6,000-term `+` chain, or a condition inside 6,000 parentheses, is
/// a diagnostic (E0002, too deep) sent back to the model, never an abort of `synth`; and since
/// the cached completion is checked again when it is read back, a rerun answered by the cache
/// ends the same way (the cache is not poisoned).
#[test]
fn deep_expressions_in_a_completion_are_a_diagnostic_and_the_cache_stays_usable() {
    let n = 6_000;
    let chain = format!(
        "referred(V, T) :- category(V, \"VEHICLE\"), speed(V, T, S), S > {}.",
        vec!["1"; n].join(" + ")
    );
    let parens = format!(
        "referred(V, T) :- category(V, \"VEHICLE\"), speed(V, T, S), {}S{} > 1.",
        "(".repeat(n),
        ")".repeat(n)
    );
    for (what, deep) in [("plus chain", chain), ("parentheses", parens)] {
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("deep.dl");
        let out_s = out.to_string_lossy().into_owned();
        let cache = dir.path().join("cache");
        let cache_s = cache.to_string_lossy().into_owned();
        let args = |url: &str| {
            vec![
                "vehicle making a left turn".to_string(),
                "-o".into(),
                out_s.clone(),
                "--cache-dir".into(),
                cache_s.clone(),
                "--base-url".into(),
                url.to_string(),
            ]
        };
        let run = |url: &str| {
            let a = args(url);
            let a: Vec<&str> = a.iter().map(String::as_str).collect();
            scenalog(&a, &[])
        };
        // Round 1 is the deep completion; round 2 repairs it.
        let server = Server::scripted(vec![program(&deep), program(GOOD)]);
        let o = run(&server.base_url());
        assert_eq!(o.status.code(), Some(0), "{what}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("checked clean in round 2"),
            "{what}: {}",
            stderr(&o)
        );
        let reqs = server.requests();
        assert_eq!(reqs.len(), 2, "{what}");
        let feedback = reqs[1].last_message();
        assert!(feedback.contains("E0002"), "{what}: {feedback}");
        let written = fs::read_to_string(&out).expect("program");
        assert!(
            written.contains("turning(V, T, \"left\")"),
            "{what}: {written}"
        );

        // Rerun: both completions come from the cache, the deep one is diagnosed again.
        let server = Server::start(|_, _| program(UNKNOWN));
        let o = run(&server.base_url());
        assert_eq!(o.status.code(), Some(0), "{what} rerun: {}", stderr(&o));
        assert_eq!(server.count(), 0, "{what}: the rerun asked the server");
        assert_eq!(fs::read_to_string(&out).expect("program"), written);

        // A model that only ever answers the deep program: the rounds run out, a clear exit 1
        // with the diagnostic, no abort.
        let dir2 = tempfile::tempdir().expect("tempdir");
        let out2 = dir2.path().join("deep.dl");
        let server = Server::start(move |_, _| program(&deep));
        let o = scenalog(
            &[
                "vehicle making a left turn",
                "-o",
                &out2.to_string_lossy(),
                "--rounds",
                "2",
                "--base-url",
                &server.base_url(),
            ],
            &[],
        );
        assert_eq!(o.status.code(), Some(1), "{what}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("no clean program after 2 rounds"),
            "{what}"
        );
        let diags =
            fs::read_to_string(dir2.path().join("deep.dl.diagnostics.json")).expect("diagnostics");
        assert!(diags.contains("E0002"), "{what}: {diags}");
    }
}

/// The programs of a held-out prompt's examples, in the order the prompt shows them (the
/// closest to the description last).
fn shown_examples(description: &str) -> Vec<String> {
    let o = scenalog(&["--print-prompt", "--held-out", description], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    stdout(&o)
        .split("```scenalog\n")
        .skip(1)
        .filter_map(|b| b.split("```").next())
        .map(str::to_string)
        .collect()
}

/// What a model that imitates the examples instead of the conventions writes: it takes the
/// closest example whose program mentions `word`, copies that example's helper rules (every rule
/// but `referred` and `related`) and then writes `answer`, where `{BIKE}` becomes the example's
/// own bicycle helper when it has one (`bike(B)`) and `category(B, "BICYCLE")` otherwise.
fn imitating(description: &str, word: &str, answer: &str) -> String {
    let examples = shown_examples(description);
    let Some(example) = examples.iter().rev().find(|e| {
        e.lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .any(|l| l.contains(word))
    }) else {
        panic!("no example for {description:?} mentions {word}")
    };
    let (program, _) = scenalog_rules::parse(example);
    let helpers: Vec<&scenalog_rules::ast::Clause> = program
        .clauses
        .iter()
        .filter(|c| c.head.pred != "referred" && c.head.pred != "related")
        .collect();
    let bike = helpers
        .iter()
        .find(|c| {
            scenalog_rules::printer::print_clause(c).contains("\"BICYCLE\"")
                && c.head.args.len() == 1
        })
        .map_or("category(B, \"BICYCLE\")".to_string(), |c| {
            format!("{}(B)", c.head.pred)
        });
    let mut out = format!("// description: {description}\n");
    for c in helpers {
        out.push_str(&scenalog_rules::printer::print_clause(c));
        out.push('\n');
    }
    out.push_str(&answer.replace("{BIKE}", &bike));
    out
}

#[test]
fn held_out_synthesis_scores_the_same_whichever_part_of_the_prompt_a_model_follows() {
    // Answering the fixture's two prompts from the conventions (the prelude's `stopped`; a
    // bicycle is a BICYCLE) and by imitating the closest example that speaks of the concept give
    // one fixture score, because the examples use the prelude's relations rather than their own
    // meanings of them.
    let stopped = "referred(V, T) :- category(V, \"REGULAR_VEHICLE\"), stopped(V, T).";
    let bike = "answer_right(V, B, T) :- category(V, \"VEHICLE\"), {BIKE}, direction(V, B, T, \"right\", Dist, Lat), Dist <= 3.0 m, Lat <= 5.0 m.\nreferred(V, T) :- answer_right(V, _, T).\nrelated(V, B, T) :- answer_right(V, B, T).";
    let set = "stopped car\nvehicle with a bicycle to its right\n";
    let by_conventions = eval_json(
        set,
        vec![
            program(&format!("// description: stopped car\n{stopped}")),
            program(&format!(
                "// description: vehicle with a bicycle to its right\n{}",
                bike.replace("{BIKE}", "category(B, \"BICYCLE\")")
            )),
        ],
        &["--held-out"],
    );
    let copied_stopped = imitating("stopped car", "stopped", stopped);
    let copied_bike = imitating("vehicle with a bicycle to its right", "BICYCLE", bike);
    let by_examples = eval_json(
        set,
        vec![program(&copied_stopped), program(&copied_bike)],
        &["--held-out"],
    );
    let score = |r: &serde_json::Value| r["fixture"]["hota_temporal"].as_f64();
    assert!(score(&by_conventions).is_some(), "{by_conventions:#}");
    assert_eq!(
        score(&by_conventions),
        score(&by_examples),
        "imitating the examples:\n{copied_stopped}\n{copied_bike}\n{by_examples:#}"
    );
}

#[test]
fn eval_prints_tokens_and_cost() {
    const TRAIN: &str = "referred(V, T) :- category(V, \"RAILED_VEHICLE\"), present(V, T).";
    let replies = || {
        vec![
            with_usage(program(UNKNOWN), 5000, Some(0), 100),
            with_usage(program(TRAIN), 5300, Some(4992), 60),
        ]
    };
    let o = run_eval("tram crossing\n", replies(), &["--price", "2,0.5,8"]);
    let text = stdout(&o);
    // 10,300 prompt tokens of which 4,992 cached: 5,308 uncached at 2, 4,992 cached at 0.5,
    // 160 output at 8, per million: 0.014392.
    assert!(
        text.contains("tokens: uncached input            5308"),
        "{text}"
    );
    assert!(
        text.contains("tokens: cached input              4992"),
        "{text}"
    );
    assert!(
        text.contains("tokens: output                    160"),
        "{text}"
    );
    assert!(
        text.contains("cost at 2, 0.5, 8 per million     0.0144"),
        "{text}"
    );
    let j = eval_json("tram crossing\n", replies(), &["--price", "2,0.5,8"]);
    let cost = j["usage"]["cost"].as_f64().expect("cost");
    assert!(
        (cost - (5308.0 * 2.0 + 4992.0 * 0.5 + 160.0 * 8.0) / 1e6).abs() < 1e-15,
        "{j:#}"
    );
    assert_eq!(j["items"][0]["usage"]["prompt_tokens"], 10300);
    assert_eq!(j["price"]["cached"], 0.5);
    // No price: tokens, no cost; a server without usage says so.
    let j = eval_json("tram crossing\n", vec![program(TRAIN)], &[]);
    assert!(j["usage"].get("cost").is_none(), "{j:#}");
    assert_eq!(j["usage"]["without_usage"], 1);
    // A malformed price is refused before anything is asked.
    let o = scenalog(&["--eval", "x.txt", "--price", "2,0.5"], &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("IN,CACHED,OUT"), "{}", stderr(&o));
}

/// Tokens of `text` for the scripted server below: 4 characters a token, rounded up.
fn tokens(chars: usize) -> u64 {
    chars.div_ceil(4) as u64
}

/// The token table of README.md: the library's descriptions synthesized one after another
/// against a scripted server that answers each with the library's own program and reports
/// `usage` as a provider with automatic prompt caching would (OpenAI's rule: prompts of 1,024
/// tokens or more, the longest prefix shared with an earlier request cached in 128-token steps),
/// counting 4 characters a token. Run with `--nocapture` to see the table.
#[test]
fn usage_table_of_the_library_descriptions() {
    use std::sync::Mutex;
    let lib = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("rules/library");
    let mut programs: Vec<(String, String)> = fs::read_dir(&lib)
        .expect("library")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "dl"))
        .map(|p| {
            let text = fs::read_to_string(&p).expect("read program");
            let d = text
                .lines()
                .find_map(|l| l.strip_prefix("// description:"))
                .expect("a description line")
                .trim()
                .to_string();
            (d, text)
        })
        .collect();
    programs.sort();
    programs.dedup_by(|a, b| a.0 == b.0);
    let by_description: std::collections::BTreeMap<String, String> =
        programs.iter().cloned().collect();
    let seen: Mutex<Vec<String>> = Mutex::new(Vec::new());
    let server = Server::start(move |_, r| {
        let prompt: String = r.messages().concat();
        let mut seen = seen.lock().expect("lock");
        let shared = seen
            .iter()
            .map(|p| {
                p.chars()
                    .zip(prompt.chars())
                    .take_while(|(a, b)| a == b)
                    .count()
            })
            .max()
            .unwrap_or(0);
        seen.push(prompt.clone());
        let (total, shared) = (tokens(prompt.len()), shared as u64 / 4);
        let cached = if total >= 1024 && shared >= 1024 {
            shared / 128 * 128
        } else {
            0
        };
        let answer = by_description
            .get(&r.description())
            .cloned()
            .unwrap_or_default();
        let out = tokens(answer.len());
        with_usage(program(&answer), total, Some(cached), out)
    });
    let dir = tempfile::tempdir().expect("tempdir");
    let list = dir.path().join("library.txt");
    let set: Vec<&str> = programs.iter().map(|(d, _)| d.as_str()).collect();
    fs::write(&list, set.join("\n")).expect("write");
    let out = dir.path().join("out");
    let url = server.base_url();
    let o = scenalog(
        &[
            "--descriptions",
            list.to_str().expect("utf-8"),
            "--out",
            out.to_str().expect("utf-8"),
            "--base-url",
            &url,
            "--jobs",
            "1",
            "--price",
            "2,0.5,8",
        ],
        &[],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("summary.json")).expect("summary"))
            .expect("json");
    let items = summary["items"].as_array().expect("items");
    assert_eq!(items.len(), programs.len());
    let field = |v: &serde_json::Value, k: &str| v[k].as_u64().expect("a count");
    let mut sum = [0u64; 3];
    for (i, item) in items.iter().enumerate() {
        let u = &item["usage"];
        let (p, c, o) = (
            field(u, "prompt_tokens"),
            field(u, "cached_tokens"),
            field(u, "completion_tokens"),
        );
        assert!(c <= p && o > 0, "{item:#}");
        // Every description after the first shares the system message with the one before.
        assert_eq!(c > 0, i > 0, "{item:#}");
        sum = [sum[0] + p, sum[1] + c, sum[2] + o];
    }
    let total = &summary["summary"]["usage"];
    assert_eq!(
        [
            field(total, "prompt_tokens"),
            field(total, "cached_tokens"),
            field(total, "completion_tokens")
        ],
        sum
    );
    let cost = ((sum[0] - sum[1]) as f64 * 2.0 + sum[1] as f64 * 0.5 + sum[2] as f64 * 8.0) / 1e6;
    let err = stderr(&o);
    assert!(err.contains(&format!("cost {cost:.4}")), "{err}");
    let first = &items[0]["usage"];
    eprintln!(
        "| descriptions | uncached input | cached input | output | cost at 2 / 0.5 / 8 per million |"
    );
    eprintln!("|---|---|---|---|---|");
    eprintln!(
        "| {} (the first alone: {} / {} / {}) | {} | {} | {} | {cost:.4} |",
        items.len(),
        field(first, "prompt_tokens") - field(first, "cached_tokens"),
        field(first, "cached_tokens"),
        field(first, "completion_tokens"),
        sum[0] - sum[1],
        sum[1],
        sum[2]
    );
    let uncached_all = (sum[0] as f64 * 2.0 + sum[2] as f64 * 8.0) / 1e6;
    eprintln!("without the prompt cache: {uncached_all:.4}");
}

fn read_json(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&fs::read_to_string(path).expect("read")).expect("json")
}

/// `synth DESCRIPTION EXTRA…` on the sample logs against `server`, the transcript written to
/// `transcript`.
fn on_sample_logs(
    description: &str,
    extra: &[&str],
    server: &Server,
    transcript: &std::path::Path,
) -> Output {
    let logs_dir = scenalog_testkit::sample_logs_dir();
    let logs = logs_dir.to_str().expect("a UTF-8 path");
    let url = server.base_url();
    let mut args = vec![description, "--logs", logs, "--base-url", &url];
    args.extend_from_slice(&["--transcript", transcript.to_str().expect("utf8")]);
    args.extend_from_slice(extra);
    scenalog(&args, &[])
}

/// `--candidates 4` against a server whose candidates mean two things: three mean "vehicle
/// turning left" (written three ways, one only after a repair), one "regular vehicle turning
/// right". Each clean candidate is run on the sample logs; the majority's meaning is kept, and
/// of its programs the one of fewest rounds, then shortest. The first candidate is asked at the
/// configured temperature, the others sampled; every candidate's tokens are counted.
#[test]
fn candidates_run_on_the_logs_and_the_majoritys_meaning_is_kept() {
    let minority = "referred(V, T) :- category(V, \"REGULAR_VEHICLE\"), turning(V, T, \"right\").";
    let helper = "left(V, T) :- turning(V, T, \"left\").\nreferred(V, T) :- category(V, \"VEHICLE\"), left(V, T).";
    let swapped = "referred(X, T) :- turning(X, T, \"left\"), category(X, \"VEHICLE\").";
    let server = Server::scripted(vec![
        with_usage(program(minority), 100, None, 10),
        with_usage(program(GOOD), 100, None, 10),
        with_usage(program(UNKNOWN), 100, None, 10),
        with_usage(program(swapped), 100, None, 10),
        with_usage(program(helper), 100, None, 10),
        with_usage(Reply::Completion("KEEP".into()), 100, None, 1),
    ]);
    let dir = tempfile::tempdir().expect("tempdir");
    let transcript = dir.path().join("t.json");
    let o = on_sample_logs(
        "vehicle making a left turn",
        &["--candidates", "4"],
        &server,
        &transcript,
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(
        stdout(&o),
        format!("// description: vehicle making a left turn\n{GOOD}\n"),
        "{}",
        stderr(&o)
    );
    assert!(stderr(&o).contains("4 candidates"), "{}", stderr(&o));
    let reqs = server.requests();
    assert_eq!(reqs.len(), 6);
    assert_eq!(reqs[0].json["temperature"], 0.0);
    assert!(reqs[1..5].iter().all(|r| r.json["temperature"] == 0.7));
    // One evidence round by default with candidates: the kept program's matches, shown to the
    // model at the configured temperature, which keeps it.
    let shown = reqs[5].last_message();
    assert!(
        shown.starts_with(
            "Your program was run on real driving logs. On the 3 logs your program matches "
        ),
        "{shown}"
    );
    assert!(shown.contains("The longest match: track "), "{shown}");
    assert_eq!(reqs[5].json["temperature"], 0.0);
    assert!(
        stderr(&o).contains("evidence round 1: the model kept the program"),
        "{}",
        stderr(&o)
    );
    let t = read_json(&transcript);
    assert_eq!(t["evidence"][0]["verdict"], "keep", "{t:#}");
    let search = &t["search"];
    assert_eq!(search["chosen"], 1, "{search:#}");
    let candidates = search["candidates"].as_array().expect("candidates");
    assert_eq!(candidates.len(), 4);
    assert_eq!(candidates[1]["group"], serde_json::json!([1, 2, 3]));
    assert_eq!(candidates[0]["group"], serde_json::json!([0]));
    assert_ne!(candidates[0]["matched"], candidates[1]["matched"]);
    assert!(candidates[1]["matched"].as_u64().expect("matched") > 0);
    assert!(candidates[0]["agreement"].as_f64() < candidates[1]["agreement"].as_f64());
    // Each candidate's line: what it matched, its agreement, its tokens.
    let err = stderr(&o);
    assert!(
        err.contains("  candidate 2: matched 633 boxes, agreement 0.667; tokens: 200 uncached input, 0 cached input, 20 output"),
        "two rounds: {err}"
    );
    assert!(
        err.contains("  candidate 0: matched 654 boxes, agreement 0.000;"),
        "{err}"
    );
    // Every candidate's tokens and the evidence round's: 6 completions of 100 in.
    assert!(
        stderr(&o).contains("600 uncached input") && stderr(&o).contains("51 output"),
        "{}",
        stderr(&o)
    );

    // One candidate: today's transcript, with no search in it.
    let server = Server::scripted(vec![program(GOOD)]);
    let o = scenalog(
        &[
            "vehicle making a left turn",
            "--base-url",
            &server.base_url(),
            "--transcript",
            transcript.to_str().expect("utf8"),
        ],
        &[],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let t = read_json(&transcript);
    assert!(t.get("search").is_none(), "{t:#}");
}

/// `--max-tokens` stops asking once the server's reported tokens reach it: a search of three
/// candidates whose answers cost 110 tokens each stops after two under a budget of 150, keeps
/// one of the two, and records why the third was not asked.
#[test]
fn max_tokens_stops_asking_once_spent() {
    let server = Server::scripted(vec![
        with_usage(program(GOOD), 100, None, 10),
        with_usage(program(GOOD), 100, None, 10),
        with_usage(program(GOOD), 100, None, 10),
    ]);
    let dir = tempfile::tempdir().expect("tempdir");
    let transcript = dir.path().join("t.json");
    let o = on_sample_logs(
        "vehicle making a left turn",
        &["--candidates", "3", "--max-tokens", "150"],
        &server,
        &transcript,
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(server.count(), 2);
    let t = read_json(&transcript);
    let third = &t["search"]["candidates"][2]["transcript"]["outcome"];
    assert_eq!(third["status"], "over_budget", "{t:#}");
    // The evidence round is not asked either, and says why.
    assert_eq!(t["evidence"][0]["verdict"], "over_budget", "{t:#}");
    assert!(
        third["error"]
            .as_str()
            .unwrap_or_default()
            .contains("token budget of 150"),
        "{third}"
    );
    assert!(stderr(&o).contains("200 uncached input"), "{}", stderr(&o));
}

/// `--eval --candidates 3`: the first candidate of "stopped car" leaves parked cars out (a
/// minority meaning), the two others mean the library's program (written two ways). The report
/// scores the first candidates and the kept programs on the fixture side by side, with the
/// kept one's agreement; the kept program is the majority's and scores what `mine` scores
/// with the library's program.
#[test]
fn eval_with_candidates_reports_the_first_and_the_kept_programs_scores() {
    let moving_out =
        "referred(V, T) :- category(V, \"REGULAR_VEHICLE\"), stopped(V, T), !stationary(V).";
    let library = "referred(V, T) :- category(V, \"REGULAR_VEHICLE\"), stopped(V, T).";
    let swapped = "referred(C, T) :- stopped(C, T), category(C, \"REGULAR_VEHICLE\").";
    let keep = Reply::Completion("KEEP".into());
    let replies = vec![
        program(moving_out),
        program(library),
        program(swapped),
        keep,
    ];
    let report = eval_json("stopped car\n", replies.clone(), &["--candidates", "3"]);
    assert_eq!(report["searched"], 1, "{report:#}");
    assert_eq!(report["selection_changed"], 1);
    let item = &report["items"][0];
    assert_eq!(item["candidates"], 3);
    assert_eq!(item["clean_candidates"], 3);
    let described = |p: &str| format!("// description: stopped car\n{p}\n");
    assert_eq!(
        item["first_program"].as_str(),
        Some(described(moving_out).as_str())
    );
    assert_eq!(
        item["program"].as_str(),
        Some(described(library).as_str()),
        "{item:#}"
    );
    let agreement = item["agreement"].as_f64().expect("agreement");
    assert!(agreement > 0.5 && agreement < 1.0, "{agreement}");
    assert_eq!(report["mean_agreement"].as_f64(), Some(agreement));
    let kept = report["fixture"]["hota_temporal"].as_f64().expect("kept");
    let first = report["first_fixture"]["hota_temporal"]
        .as_f64()
        .expect("first");
    // The library's stopped car scores 0.8527 on the fixture (README).
    assert!((kept - 0.8527).abs() < 5e-5, "{kept}");
    assert!(first < kept, "first {first}, kept {kept}");

    // The text report shows both, per prompt.
    let o = run_eval("stopped car\n", replies, &["--candidates", "3"]);
    let text = stdout(&o);
    assert!(
        text.contains(
            "searches over candidates          1 (1 kept another program than the first)"
        ),
        "{text}"
    );
    assert!(
        text.contains(&format!("fixture HOTA-Temporal: first      {first:.4}")),
        "{text}"
    );
    assert!(
        text.contains(&format!("fixture HOTA-Temporal: kept       {kept:.4}")),
        "{text}"
    );
    assert!(
        text.contains(&format!(
            "  stopped car: first {first:.4}, kept {kept:.4}, agreement {agreement:.3}"
        )),
        "{text}"
    );

    // One candidate: no search lines, no first score.
    let report = eval_json("stopped car\n", vec![program(library)], &[]);
    assert_eq!(report["searched"], 0);
    assert!(report["first_fixture"].is_null(), "{report:#}");
    assert_eq!(report["items"][0]["candidates"], 1);
}

/// The evidence round: a program that matches nothing on the sample logs is shown its nearest
/// misses (the failing comparison with the values that failed it); the model revises it; the
/// revision checks, runs, is kept, and the next round shows it its own matches (per category,
/// the longest match's proof), which the model keeps.
#[test]
fn the_evidence_round_shows_the_model_its_matches_and_keeps_a_revision() {
    let nothing = "referred(V, T) :- category(V, \"BUS\"), speed(V, T, S), S > 60.0 m/s.";
    let revised = "referred(V, T) :- category(V, \"BUS\"), speed(V, T, S), S > 2.0 m/s.";
    let server = Server::scripted(vec![
        program(nothing),
        program(revised),
        Reply::Completion("KEEP".into()),
    ]);
    let dir = tempfile::tempdir().expect("tempdir");
    let transcript = dir.path().join("t.json");
    let o = on_sample_logs(
        "bus moving faster than 2 m/s",
        &["--evidence-rounds", "2"],
        &server,
        &transcript,
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(
        stdout(&o),
        format!("// description: bus moving faster than 2 m/s\n{revised}\n")
    );
    let reqs = server.requests();
    assert_eq!(reqs.len(), 3);
    let first = reqs[1].last_message();
    assert!(
        first.contains("your program matches nothing. The nearest misses"),
        "{first}"
    );
    assert!(first.contains("(BUS) on log"), "{first}");
    assert!(first.contains("✗ S > 60 m/s"), "{first}");
    // The conversation shows the program it is about.
    assert!(reqs[1].messages().iter().any(|m| m.contains("S > 60.0")));
    let second = reqs[2].last_message();
    assert!(second.contains("\n- BUS: "), "{second}");
    assert!(second.contains("✓ S > 2 m/s"), "{second}");
    let err = stderr(&o);
    assert!(
        err.contains("evidence round 1: the model revised the program; the revision (candidate 1)"),
        "{err}"
    );
    assert!(
        err.contains("evidence round 2: the model kept the program"),
        "{err}"
    );
    let t = read_json(&transcript);
    let rounds = t["evidence"].as_array().expect("evidence rounds");
    assert_eq!(rounds.len(), 2, "{t:#}");
    assert_eq!(rounds[0]["verdict"], "revised");
    assert_eq!(rounds[0]["candidate"], 1);
    assert_eq!(rounds[1]["verdict"], "keep");
    assert_eq!(t["search"]["chosen"], 1);
    assert_eq!(t["search"]["candidates"][0]["matched"], 0);
    assert!(t["search"]["candidates"][1]["matched"].as_u64() > Some(0));

    // A revision that never checks clean leaves the program shown in place.
    let server = Server::scripted(vec![
        program(nothing),
        program(UNKNOWN),
        program(UNKNOWN),
        program(UNKNOWN),
    ]);
    let o = on_sample_logs(
        "bus moving faster than 2 m/s",
        &["--evidence-rounds", "1"],
        &server,
        &transcript,
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stdout(&o).contains("S > 60.0"), "{}", stdout(&o));
    assert!(
        stderr(&o).contains(
            "evidence round 1: the model's revision never checked clean; the program stays"
        ),
        "{}",
        stderr(&o)
    );
}

/// `--grammar SERVER` sends the language's grammar in that server's field (the evidence round's
/// grammar also allows `KEEP`), and `--print-grammar` prints the one sent for a program;
/// without it no grammar is sent.
#[test]
fn grammar_is_sent_in_the_servers_field() {
    let printed = scenalog(&["--print-grammar"], &[]);
    assert_eq!(printed.status.code(), Some(0), "{}", stderr(&printed));
    let grammar = stdout(&printed);
    assert!(grammar.contains("\nroot ::= "), "{grammar}");
    for (server, path) in [
        ("llama-cpp", "/grammar"),
        ("vllm", "/structured_outputs/grammar"),
        ("sglang", "/ebnf"),
    ] {
        let s = Server::scripted(vec![program(GOOD), Reply::Completion("KEEP".into())]);
        let dir = tempfile::tempdir().expect("tempdir");
        let transcript = dir.path().join("t.json");
        let o = on_sample_logs(
            "vehicle making a left turn",
            &["--grammar", server, "--evidence-rounds", "1"],
            &s,
            &transcript,
        );
        assert_eq!(o.status.code(), Some(0), "{server}: {}", stderr(&o));
        let reqs = s.requests();
        assert_eq!(reqs.len(), 2, "{server}");
        let sent = reqs[0].json.pointer(path).and_then(|g| g.as_str());
        assert_eq!(
            sent,
            Some(grammar.trim_end())
                .map(|g| format!("{g}\n"))
                .as_deref(),
            "{server}"
        );
        let keep = reqs[1]
            .json
            .pointer(path)
            .and_then(|g| g.as_str())
            .unwrap_or_default();
        assert!(keep.contains("root ::= \"KEEP\" ws | "), "{server}: {keep}");
    }
    let s = Server::scripted(vec![program(GOOD)]);
    let dir = tempfile::tempdir().expect("tempdir");
    let o = on_sample_logs(
        "vehicle making a left turn",
        &[],
        &s,
        &dir.path().join("t.json"),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let body = &s.requests()[0].json;
    assert!(
        body.get("grammar").is_none()
            && body.get("structured_outputs").is_none()
            && body.get("ebnf").is_none()
    );
}
