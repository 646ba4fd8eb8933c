//! The library API (`scenalog::api`) called directly, as the Python package calls it, against
//! the built command on the real sample logs: the same requests give the same files and
//! matches, and errors name flags for the command and keyword arguments for Python.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use scenalog::api::check::{check, CheckRequest, ProgramSource};
use scenalog::api::mine::{Limits, MineRequest};
use scenalog::api::split::SplitRequest;
use scenalog::api::ErrorKind;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn logs() -> PathBuf {
    root().join("tests/data/av2/logs")
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
    let outcome = scenalog::api::mine::run(&request, &plan).expect("run");
    assert_eq!(outcome.published, Ok(()));
    assert!(outcome.pair_failures.is_empty() && outcome.score_errors.is_empty());

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
    let report = scenalog::api::split::run(&request, &plan).expect("run");
    assert!(!report.pairs.is_empty());
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
