//! The library API (`scenalog::api`) called directly, as the Python package calls it, against
//! the built command on the real sample logs: the same requests give the same files and
//! matches, and errors name flags for the command and keyword arguments for Python.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use scenalog::api::check::{check, CheckRequest, ProgramSource};
use scenalog::api::mine::MineRequest;
use scenalog::api::split::SplitRequest;
use scenalog::api::{ErrorKind, Limits};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn logs() -> PathBuf {
    scenalog_testkit::sample_logs_dir()
}

/// Library programs that match on the sample logs.
fn programs() -> Vec<PathBuf> {
    ["a_group_of_people", "accelerating_truck", "stopped_car"]
        .iter()
        .map(|n| root().join("rules/library").join(format!("{n}.dl")))
        .collect()
}

fn scenalog(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_scenalog"))
        .args(args)
        .output()
        .expect("run scenalog")
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn a_mine_request_gives_the_commands_files_matches_and_score() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let gt = root().join("tests/data/av2/eval/combined_gt_dev.pkl");
    let request = MineRequest {
        rules: programs(),
        logs: vec![logs()],
        out: Some(tmp.path().join("api")),
        gt: Some(gt.clone()),
        threads: Some(2),
        pickle: true,
        ..MineRequest::default()
    };
    let plan = scenalog::api::mine::plan(&request).expect("plan");
    assert_eq!(plan.scenarios.len(), 3);
    assert_eq!(plan.logs.len(), 3);
    let outcome = scenalog::api::mine::run(&request, plan).expect("run");
    assert_eq!(outcome.published, Ok(()));
    assert!(outcome.failures.is_empty() && outcome.score_errors.is_empty());
    // The outcome names the files it published; they are there.
    let outputs = &outcome.outputs;
    assert_eq!(outputs.dir, tmp.path().join("api"));
    let pickle = outputs.pickle.as_ref().expect("the pickle was asked for");
    let scored = outputs.scored.as_ref().expect("scored against gt");
    for file in [
        &outputs.table,
        pickle,
        &outputs.matches,
        &outputs.summary,
        scored,
    ] {
        assert_eq!(file.path, outputs.dir.join(file.name));
        assert!(file.path.is_file(), "{}", file.path.display());
    }

    let cli_out = tmp.path().join("cli");
    let mut args: Vec<&std::ffi::OsStr> = vec!["mine".as_ref(), "--rules".as_ref()];
    let rules = programs();
    args.extend(rules.iter().map(|p| p.as_os_str()));
    let (logs, threads) = (logs(), "2");
    args.extend([
        "--logs".as_ref(),
        logs.as_os_str(),
        "--gt".as_ref(),
        gt.as_os_str(),
        "--out".as_ref(),
        cli_out.as_os_str(),
        "--threads".as_ref(),
        threads.as_ref(),
        "--format".as_ref(),
        "json".as_ref(),
        "--pickle".as_ref(),
    ]);
    let o = scenalog(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let cli: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");

    let matches = serde_json::to_value(outcome.report.matches()).expect("matches as JSON");
    assert!(matches.as_array().is_some_and(|m| m.len() > 3));
    assert_eq!(matches, cli["matches"]);
    let score = outcome.scored.as_ref().map(|s| s.report.to_json());
    assert!(score.is_some());
    assert_eq!(score.as_ref(), Some(&cli["score"]));
    for file in [
        "predictions.pkl",
        "predictions.feather",
        "matches.json",
        "scored.pkl",
    ] {
        assert_eq!(
            read(&tmp.path().join("api").join(file)),
            read(&cli_out.join(file)),
            "{file}"
        );
    }
}

#[test]
fn a_split_request_gives_the_commands_submission() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let data = root().join("tests/data/av2/tracker");
    let pairs = data.join("log_prompt_pairs_sample.json");
    let tracks = data.join("noisy.pkl");
    let request = SplitRequest {
        out: Some(tmp.path().join("api")),
        tracks: Some(tracks.clone()),
        ..SplitRequest::new(pairs.clone(), logs())
    };
    let plan = scenalog::api::split::prepare(&request).expect("prepare");
    assert!(!plan.logs.is_empty());
    let outcome = scenalog::api::split::run(&request, plan).expect("run");
    assert!(!outcome.report.pairs.is_empty());
    assert_eq!(outcome.outputs.table.name, "submission.feather");
    let cli_out = tmp.path().join("cli");
    let logs = logs();
    let o = scenalog(&[
        "mine".as_ref(),
        "--log-prompts".as_ref(),
        pairs.as_os_str(),
        "--dataset-dir".as_ref(),
        logs.as_os_str(),
        "--tracks".as_ref(),
        tracks.as_os_str(),
        "--out".as_ref(),
        cli_out.as_os_str(),
    ]);
    assert!(o.status.code().is_some_and(|c| c <= 1), "{o:?}");
    for file in ["submission.pkl", "submission.feather"] {
        assert_eq!(
            read(&tmp.path().join("api").join(file)),
            read(&cli_out.join(file)),
            "{file}"
        );
    }
}

#[test]
fn errors_name_the_commands_flags_or_pythons_keywords() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let missing = tmp.path().join("no-logs");
    let request = MineRequest {
        rules: programs(),
        logs: vec![missing.clone()],
        out: Some(tmp.path().join("o")),
        ..MineRequest::default()
    };
    let Err(e) = scenalog::api::mine::plan(&request) else {
        panic!("a missing log directory planned");
    };
    assert_eq!(e.kind, ErrorKind::NotFound);
    let said = format!("`{}` is not a directory", missing.display());
    assert_eq!(e.flags(), format!("--logs: {said}"));
    assert_eq!(e.keywords(), format!("logs: {said}"));
    // The command's own message for the same input.
    let o = scenalog(&[
        "mine".as_ref(),
        "--rules".as_ref(),
        programs()[0].as_os_str(),
        "--logs".as_ref(),
        missing.as_os_str(),
        "--out".as_ref(),
        tmp.path().join("o").as_os_str(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr).trim_end(),
        format!("scenalog mine: {}", e.flags())
    );

    for (limits, threads, keyword) in [
        (
            Limits {
                max_tuples: Some(0),
                timeout_ms: None,
            },
            None,
            "max_tuples: ",
        ),
        (
            Limits {
                max_tuples: None,
                timeout_ms: Some(0),
            },
            None,
            "timeout_ms: ",
        ),
        (Limits::default(), Some(0), "threads: "),
        (Limits::default(), Some(5000), "threads: "),
    ] {
        let request = MineRequest {
            rules: programs(),
            logs: vec![logs()],
            out: Some(tmp.path().join("o")),
            limits,
            threads,
            ..MineRequest::default()
        };
        let Err(e) = scenalog::api::mine::plan(&request) else {
            panic!("{keyword} out of range planned");
        };
        assert_eq!(e.kind, ErrorKind::Invalid);
        assert!(e.keywords().starts_with(keyword), "{}", e.keywords());
        assert!(e.flags().starts_with("--"), "{}", e.flags());
    }
}

#[test]
fn check_reads_a_file_or_takes_text_and_a_missing_file_is_not_found() {
    let clean = check(&CheckRequest {
        source: ProgramSource::File(programs()[2].clone()),
        require_referred: true,
    })
    .expect("the library's program");
    assert!(clean.outcome.program.is_some());
    assert_eq!(clean.diagnostics_json(), serde_json::json!([]));
    let typo = check(&CheckRequest {
        source: ProgramSource::Text(
            "referred(X, T) :- categry(X, \"BUS\"), present(X, T).\n".to_string(),
        ),
        require_referred: true,
    })
    .expect("text");
    assert!(typo.outcome.program.is_none());
    assert_eq!(typo.diagnostics_json()[0]["code"], "E0101");
    let missing = root().join("rules/library/stopped_cra.dl");
    let Err(e) = check(&CheckRequest {
        source: ProgramSource::File(missing.clone()),
        require_referred: true,
    }) else {
        panic!("a missing file checked");
    };
    assert_eq!(e.kind, ErrorKind::NotFound);
    assert!(e.flags().contains(&missing.display().to_string()));
}

/// `api::facts` extracts within one pair's limits, as both front ends do: a relation past the
/// tuple budget is an error naming the field to raise, which the command spells as its flag
/// (and prints as it is) and Python as its keyword.
#[test]
fn a_relation_past_the_budget_says_what_to_raise_in_each_front_ends_words() {
    use scenalog::api::facts::{facts, Facts, FactsRequest};
    use scenalog::api::Field;
    let log = logs().join("3b3570b4-7b0b-3268-a571-b0889dbf40b6");
    let request = |max_tuples| FactsRequest {
        log: log.clone(),
        relation: Some("near".to_string()),
        limits: Limits {
            max_tuples,
            timeout_ms: None,
        },
    };
    let Ok(Facts::Relation(near)) = facts(&request(None)) else {
        panic!("near within the default budget");
    };
    assert!(near.len() > 100, "{}", near.len());
    let Err(e) = facts(&request(Some(10))) else {
        panic!("near in 10 tuples");
    };
    assert_eq!(e.message.fields(), vec![Field::MaxTuples]);
    assert!(
        e.flags().ends_with(" or raise --max-tuples"),
        "{}",
        e.flags()
    );
    assert!(
        e.keywords().ends_with(" or raise max_tuples="),
        "{}",
        e.keywords()
    );
    assert!(!e.keywords().contains("--"), "{}", e.keywords());
    let o = scenalog(&[
        "facts".as_ref(),
        log.as_os_str(),
        "--relation".as_ref(),
        "near".as_ref(),
        "--max-tuples".as_ref(),
        "10".as_ref(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr).trim_end(),
        format!("scenalog facts: {}", e.flags())
    );
}

/// A pair past its tuple budget fails alone, and the run's failures name the field to raise:
/// the command's `--format json` failures are the outcome's, rendered with its flags.
#[test]
fn a_pair_past_the_budget_is_a_failure_naming_the_field() {
    use scenalog::api::Field;
    let tmp = tempfile::tempdir().expect("tempdir");
    let request = MineRequest {
        rules: programs()[..1].to_vec(),
        logs: vec![logs()],
        out: Some(tmp.path().join("api")),
        limits: Limits {
            max_tuples: Some(1),
            timeout_ms: None,
        },
        ..MineRequest::default()
    };
    let outcome = scenalog::api::mine::mine(&request).expect("run");
    assert!(outcome.any_failed());
    assert!(outcome
        .failures
        .iter()
        .any(|f| f.fields() == vec![Field::MaxTuples]));
    let o = scenalog(&[
        "mine".as_ref(),
        "--rules".as_ref(),
        programs()[0].as_os_str(),
        "--logs".as_ref(),
        logs().as_os_str(),
        "--max-tuples".as_ref(),
        "1".as_ref(),
        "--out".as_ref(),
        tmp.path().join("cli").as_os_str(),
        "--format".as_ref(),
        "json".as_ref(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let cli: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let flags: Vec<String> = outcome.failures.iter().map(|f| f.flags()).collect();
    assert_eq!(cli["failures"], serde_json::json!(flags));
    // The pairs' records name the flags in the command's file, the keywords for Python.
    let pairs = outcome.pairs_json(scenalog::api::Names::Keywords);
    let errors: Vec<&str> = pairs.iter().filter_map(|p| p["error"].as_str()).collect();
    assert!(!errors.is_empty() && errors.iter().all(|e| !e.contains("--max-tuples")));
}
