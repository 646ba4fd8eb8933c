//! Mutation fuzzing of every reader of outside input: a log's annotations and ego poses (Arrow
//! IPC, LZ4), its vector map (JSON), and the evaluation's submissions (Arrow tables, LZ4 and
//! uncompressed, and pickles). Each test reads a few thousand deterministic mutants of a small
//! real input (byte flips, truncations, insertions, deletions, declared-size blow-ups) in a child
//! process with its address space capped, and fails on any panic (caught or not), abort, error
//! that does not name the file, or if no mutant is rejected at all.
//!
//! The counts each test prints (`--nocapture`) are the README's figures.

mod harness;
mod inputs;
mod mutate;

use std::path::Path;

use harness::{fuzz, Campaign, Outcome};
use inputs::SmallLog;
use scenalog_eval::{evaluate, read_pickle_bytes, table_from_bytes, EvalOptions, Submission};
use scenalog_facts::read::{ANNOTATIONS_WITH_EGO_FILE, EGO_POSES_FILE};
use scenalog_facts::{load_scene, LoadError};

/// Mutants per reader: enough to hit every kind of damage many times, few enough that a test
/// takes seconds in a debug build.
const CASES: u64 = 3000;

/// The small log written into `dir` (its feathers uncompressed: the fuzzed file is written
/// over for each mutant).
fn write_log(dir: &Path, files: &SmallLog) {
    std::fs::create_dir_all(dir.join("map")).expect("mkdir");
    std::fs::write(
        dir.join(ANNOTATIONS_WITH_EGO_FILE),
        &files.annotations_plain,
    )
    .expect("write");
    std::fs::write(dir.join(EGO_POSES_FILE), &files.poses_plain).expect("write");
    std::fs::write(dir.join("map").join(inputs::MAP_FILE), &files.map).expect("write");
}

fn load_outcome(result: Result<scenalog_facts::Scene, LoadError>) -> Outcome {
    match result {
        Ok(_) => Outcome::Accepted,
        Err(e) => Outcome::Rejected(e.to_string()),
    }
}

/// Fuzzes one file of the small log (`rel`, relative to the log directory) through `load_scene`.
fn fuzz_log_file(test: &str, rel: &str, seed: u64, pick: fn(&SmallLog) -> &[u8]) {
    let files = inputs::small_log();
    let tmp = tempfile::tempdir().expect("tempdir");
    let dir = tmp.path().join(inputs::LOG);
    write_log(&dir, &files);
    let target = dir.join(rel);
    let name = Path::new(rel)
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let campaign = Campaign {
        test,
        base: pick(&files),
        seed,
        cases: CASES,
        must_name: &name,
    };
    fuzz(&campaign, |bytes| {
        std::fs::write(&target, bytes).expect("write the mutant");
        load_outcome(load_scene(&dir))
    });
}

#[test]
fn annotations_feather() {
    fuzz_log_file(
        "annotations_feather",
        ANNOTATIONS_WITH_EGO_FILE,
        0xA11_0001,
        |f| &f.annotations,
    );
}

#[test]
fn ego_poses_feather() {
    fuzz_log_file("ego_poses_feather", EGO_POSES_FILE, 0xA11_0002, |f| {
        &f.poses
    });
}

#[test]
fn map_json() {
    let rel = format!("map/{}", inputs::MAP_FILE);
    fuzz_log_file("map_json", &rel, 0xA11_0003, |f| &f.map);
}

/// Reads a submission with `read`; when it is read, evaluates it against `gt` as `scenalog eval`
/// would (a damaged value must not make the metrics panic either).
fn read_and_evaluate(
    gt: &Submission,
    read: impl Fn() -> Result<Submission, scenalog_eval::EvalError>,
) -> Outcome {
    match read() {
        Err(e) => Outcome::Rejected(e.to_string()),
        Ok(pred) => {
            // Alignment errors are the evaluation's answer to a well-formed but different file.
            let _ = evaluate(&pred, gt, &EvalOptions::default());
            Outcome::Accepted
        }
    }
}

fn fuzz_table(test: &str, lz4: bool, seed: u64) {
    let base = inputs::small_prediction_table(120, lz4);
    let gt = table_from_bytes(&base, "gt").expect("the small table reads");
    let campaign = Campaign {
        test,
        base: &base,
        seed,
        cases: CASES,
        must_name: "predictions.feather",
    };
    fuzz(&campaign, |bytes| {
        read_and_evaluate(&gt, || table_from_bytes(bytes, "predictions.feather"))
    });
}

#[test]
fn eval_arrow_table_lz4() {
    fuzz_table("eval_arrow_table_lz4", true, 0xA11_0004);
}

#[test]
fn eval_arrow_table_uncompressed() {
    fuzz_table("eval_arrow_table_uncompressed", false, 0xA11_0005);
}

#[test]
fn eval_pickle() {
    let table = inputs::small_prediction_table(120, false);
    let base = inputs::pickle_of_table(&table);
    let gt = read_pickle_bytes(&base, "gt").expect("the small pickle reads");
    let campaign = Campaign {
        test: "eval_pickle",
        base: &base,
        seed: 0xA11_0006,
        cases: CASES,
        must_name: "predictions.pkl",
    };
    fuzz(&campaign, |bytes| {
        read_and_evaluate(&gt, || read_pickle_bytes(bytes, "predictions.pkl"))
    });
}

#[test]
fn the_mutant_that_aborted_the_unvalidated_decoder_is_an_error() {
    // Mutant 1 of `eval_arrow_table_lz4`'s campaign: read by arrow-ipc's FileReader directly (as
    // `scenalog eval` did before it validated declared sizes), it tried to allocate
    // 288,683,374,942,489,801 bytes and aborted the process.
    let base = inputs::small_prediction_table(120, true);
    let bytes = mutate::mutant(&base, 0xA11_0004, 1);
    let err = table_from_bytes(&bytes, "predictions.feather").expect_err("a corrupt table");
    let text = err.to_string();
    assert!(
        text.starts_with("predictions.feather: not a readable Arrow IPC file: "),
        "{text}"
    );

    // The same file through the command: exit 2 and a message naming it, not SIGABRT.
    let tmp = tempfile::tempdir().expect("tempdir");
    let pred = tmp.path().join("predictions.feather");
    std::fs::write(&pred, &bytes).expect("write");
    let gt = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/av2/eval/combined_gt_dev.pkl");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_scenalog"))
        .arg("eval")
        .arg("--pred")
        .arg(&pred)
        .arg("--gt")
        .arg(&gt)
        .output()
        .expect("run scenalog eval");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{:?}: {err}", out.status);
    assert!(
        err.contains("predictions.feather: not a readable Arrow IPC file"),
        "{err}"
    );
}
