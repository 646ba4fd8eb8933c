//! The command on hostile input and output (issue 18): float flags that are not finite numbers in
//! range, input paths that are FIFOs, symlink loops or unreadable, corrupt Arrow tables, and a
//! standard output whose reader has gone (`| head`). Each must end with a clear message or
//! quietly, never with a panic, an abort or a hang. (A corrupt Arrow table through `scenalog
//! eval`: `tests/fuzz_readers`.)

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const MIA: &str = "3b3570b4-7b0b-3268-a571-b0889dbf40b6";
const ANNOTATIONS: &str = "annotations_with_ego.feather";
/// How long a command may take before it counts as hung (it would otherwise hang the suite).
const DEADLINE: Duration = Duration::from_secs(120);

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

fn log_dir(id: &str) -> PathBuf {
    scenalog_testkit::sample_logs_dir().join(id)
}

/// Runs the command with `stdout` as its standard output, killing it after [`DEADLINE`].
fn run_with(args: &[&str], stdout: Stdio) -> Output {
    let mut child = crate::util::scenalog()
        .args(args)
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(Stdio::piped())
        .spawn()
        .expect("run scenalog");
    let start = Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if start.elapsed() > DEADLINE {
            let _ = child.kill();
            let out = child.wait_with_output().expect("output");
            panic!(
                "scenalog {args:?} hung; stderr: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

fn scenalog(args: &[&str]) -> Output {
    run_with(args, Stdio::piped())
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn assert_fails_saying(out: &Output, code: i32, words: &[&str]) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(code), "stderr: {err}");
    for w in words {
        assert!(err.contains(w), "stderr lacks {w:?}: {err}");
    }
    assert!(!err.contains("panicked"), "a panic: {err}");
}

/// A copy of the MIA log in a temp dir.
fn copy_log() -> (tempfile::TempDir, PathBuf) {
    let tmp = tempfile::tempdir().expect("tempdir");
    let dst = tmp.path().join(MIA);
    let src = log_dir(MIA);
    std::fs::create_dir_all(dst.join("map")).expect("mkdir");
    for rel in [ANNOTATIONS, "city_SE3_egovehicle.feather"] {
        std::fs::copy(src.join(rel), dst.join(rel)).expect("copy");
    }
    for entry in std::fs::read_dir(src.join("map")).expect("map dir") {
        let entry = entry.expect("entry");
        std::fs::copy(entry.path(), dst.join("map").join(entry.file_name())).expect("copy");
    }
    (tmp, dst)
}

fn mkfifo(path: &Path) {
    let made = Command::new("mkfifo").arg(path).status().expect("mkfifo");
    assert!(made.success(), "mkfifo {}", path.display());
}

#[test]
fn float_flags_must_be_finite_and_in_range() {
    let gt = repo("tests/data/av2/eval/combined_gt_dev.pkl");
    let gt = gt.to_str().expect("utf8");
    let pred = repo("tests/data/av2/eval/combined_predictions_dev.pkl");
    let pred = pred.to_str().expect("utf8");
    for bad in ["NaN", "inf", "-inf", "-1", "0"] {
        let flag = format!("--max-range-m={bad}");
        let out = scenalog(&["eval", "--pred", pred, "--gt", gt, &flag]);
        assert_fails_saying(&out, 2, &["--max-range-m"]);
    }
    // A sane value still scores.
    let out = scenalog(&["eval", "--pred", pred, "--gt", gt, "--max-range-m", "30"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(String::from_utf8_lossy(&out.stdout).contains("HOTA-Temporal: 0."));

    let log = log_dir(MIA);
    let rules = repo("tests/support/stopped_not_parked.dl");
    for bad in ["NaN", "inf", "-0.5"] {
        let at = format!("--at={bad}");
        let out = scenalog(&[
            "explain",
            "--rules",
            rules.to_str().expect("utf8"),
            "--log",
            log.to_str().expect("utf8"),
            "--track",
            "0f0d16d4",
            &at,
        ]);
        assert_fails_saying(&out, 2, &["--at"]);
    }
}

#[test]
fn fifo_symlink_loop_and_directory_are_reported_as_what_they_are() {
    let (_tmp, dir) = copy_log();
    let ann = dir.join(ANNOTATIONS);
    let dir_s = dir.to_str().expect("utf8").to_owned();

    std::fs::remove_file(&ann).expect("rm");
    mkfifo(&ann);
    let out = scenalog(&["facts", &dir_s]);
    assert_fails_saying(&out, 2, &[ANNOTATIONS, "FIFO", "not a regular file"]);
    assert!(!stderr(&out).contains("not found"), "{}", stderr(&out));

    std::fs::remove_file(&ann).expect("rm");
    std::os::unix::fs::symlink(dir.join("loop_b"), &ann).expect("symlink");
    std::os::unix::fs::symlink(&ann, dir.join("loop_b")).expect("symlink");
    let out = scenalog(&["facts", &dir_s]);
    assert_fails_saying(&out, 2, &[ANNOTATIONS, "symlink loop"]);

    std::fs::remove_file(&ann).expect("rm");
    std::fs::create_dir(&ann).expect("mkdir");
    let out = scenalog(&["facts", &dir_s]);
    assert_fails_saying(&out, 2, &[ANNOTATIONS, "is a directory"]);

    // The map file and the ego poses as FIFOs: an error, not a read waiting for a writer.
    let (_tmp2, dir2) = copy_log();
    let poses = dir2.join("city_SE3_egovehicle.feather");
    std::fs::remove_file(&poses).expect("rm");
    mkfifo(&poses);
    let out = scenalog(&["facts", dir2.to_str().expect("utf8")]);
    assert_fails_saying(&out, 2, &["city_SE3_egovehicle.feather", "FIFO"]);

    // `eval` on a FIFO and on a symlink loop.
    let tmp = tempfile::tempdir().expect("tempdir");
    let fifo = tmp.path().join("predictions.pkl");
    mkfifo(&fifo);
    let looped = tmp.path().join("loop.feather");
    std::os::unix::fs::symlink(&looped, &looped).expect("symlink");
    let gt = repo("tests/data/av2/eval/combined_gt_dev.pkl");
    for (pred, words) in [
        (&fifo, ["predictions.pkl", "FIFO"]),
        (&looped, ["loop.feather", "symlink loop"]),
    ] {
        let pred = pred.to_str().expect("utf8");
        let out = scenalog(&["eval", "--pred", pred, "--gt", gt.to_str().expect("utf8")]);
        assert_fails_saying(&out, 2, &words);
    }
}

#[test]
fn unsearchable_log_directory_is_permission_denied() {
    use std::os::unix::fs::PermissionsExt;
    let (_tmp, dir) = copy_log();
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o000)).expect("chmod");
    // A privileged user (root in a container) reads through any mode: nothing to test there.
    let privileged = std::fs::metadata(dir.join(ANNOTATIONS)).is_ok();
    let out = scenalog(&["facts", dir.to_str().expect("utf8")]);
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    if privileged {
        eprintln!("running as a privileged user: mode 000 does not deny; only the load is checked");
        assert!(out.status.success(), "{}", stderr(&out));
        return;
    }
    assert_fails_saying(&out, 2, &[ANNOTATIONS, "permission denied"]);
}

/// Runs the command with its standard output a pipe whose reading end is already closed.
fn with_closed_stdout(args: &[&str]) -> Output {
    let (reader, writer) = std::io::pipe().expect("pipe");
    drop(reader);
    run_with(args, Stdio::from(writer))
}

#[test]
fn a_closed_stdout_pipe_ends_every_command_quietly() {
    let log = log_dir(MIA);
    let log = log.to_str().expect("utf8");
    let rules = repo("tests/support/stopped_not_parked.dl");
    let rules = rules.to_str().expect("utf8");
    let gt = repo("tests/data/av2/eval/combined_gt_dev.pkl");
    let gt = gt.to_str().expect("utf8");
    let pred = repo("tests/data/av2/eval/combined_predictions_dev.pkl");
    let pred = pred.to_str().expect("utf8");
    let out_dir = tempfile::tempdir().expect("tempdir");
    let out_s = out_dir.path().to_str().expect("utf8");
    let commands: Vec<Vec<&str>> = vec![
        vec!["check", rules],
        vec!["check", "--json", rules],
        vec!["facts", log],
        vec!["facts", log, "--relation", "category", "--json"],
        vec!["catalog"],
        vec!["eval", "--pred", pred, "--gt", gt],
        vec!["mine", "--rules", rules, "--logs", log, "--out", out_s],
        vec![
            "explain", "--rules", rules, "--log", log, "--track", "0f0d16d4",
        ],
    ];
    for args in commands {
        let out = with_closed_stdout(&args);
        let err = stderr(&out);
        assert!(
            !err.contains("panicked"),
            "scenalog {args:?} panicked: {err}"
        );
        assert_eq!(out.status.code(), Some(0), "scenalog {args:?}: {err}");
    }
    // `mine` still wrote its outputs.
    assert!(out_dir.path().join("predictions.feather").is_file());
}

/// How long one command on a special file may take: reading a FIFO would wait forever and
/// `/dev/zero` would fill the memory, so ending at all, quickly, is the point.
const SPECIAL_DEADLINE: Duration = Duration::from_secs(30);

/// Every input flag of every command given a FIFO and `/dev/zero` (directly, and through a `.dl`
/// link in a `--rules`/`--programs` directory and a log's files): each ends within seconds with
/// an error naming the path and what it is.
#[test]
fn every_input_flag_refuses_a_fifo_and_dev_zero_naming_the_path() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let fifo = tmp.path().join("special.fifo");
    mkfifo(&fifo);
    let zero = Path::new("/dev/zero");
    if !zero.exists() {
        eprintln!("skipped: no /dev/zero");
        return;
    }
    let s = |p: &Path| p.to_str().expect("utf8").to_owned();
    let rules = s(&repo("tests/support/stopped_not_parked.dl"));
    let logs = s(&scenalog_testkit::sample_logs_dir());
    let log = s(&log_dir(MIA));
    let gt = s(&repo("tests/data/av2/eval/combined_gt_dev.pkl"));
    let pairs = s(&repo(
        "tests/data/av2/tracker/log_prompt_pairs_fixture.json",
    ));
    let out = s(&tmp.path().join("out"));
    // `{}` stands for the special file.
    let commands: Vec<Vec<&str>> = vec![
        vec!["check", "{}"],
        vec!["run", "{}"],
        vec!["mine", "--rules", "{}", "--logs", &log, "--out", &out],
        vec![
            "mine", "--rules", &rules, "--logs", &log, "--gt", "{}", "--out", &out,
        ],
        vec![
            "mine",
            "--rules",
            &rules,
            "--logs",
            &log,
            "--eval-timestamps",
            "{}",
            "--out",
            &out,
        ],
        vec![
            "mine",
            "--log-prompts",
            "{}",
            "--dataset-dir",
            &logs,
            "--out",
            &out,
        ],
        vec![
            "mine",
            "--log-prompts",
            &pairs,
            "--dataset-dir",
            &logs,
            "--tracks",
            "{}",
            "--out",
            &out,
        ],
        vec![
            "mine",
            "--descriptions",
            "{}",
            "--logs",
            &log,
            "--out",
            &out,
        ],
        vec!["explain", "--rules", "{}", "--log", &log, "--track", "ego"],
        vec!["eval", "--pred", "{}", "--gt", &gt],
        vec!["eval", "--pred", &gt, "--gt", "{}"],
        vec!["eval", "--pred", &gt, "--gt", &gt, "--timestamps", "{}"],
        vec!["synth", "--eval", "{}", "--logs", &logs],
        vec!["synth", "--descriptions", "{}", "--out", &out],
        vec!["import", "refav", "{}", "-o", &out],
    ];
    for special in [&fifo, &zero.to_path_buf()] {
        let path = s(special);
        let what = if special == &fifo {
            "FIFO"
        } else {
            "character device"
        };
        for template in &commands {
            let args: Vec<&str> = template
                .iter()
                .map(|a| if *a == "{}" { path.as_str() } else { a })
                .collect();
            let start = Instant::now();
            let o = scenalog(&args);
            assert!(start.elapsed() < SPECIAL_DEADLINE, "{args:?} took too long");
            assert!(!o.status.success(), "{args:?} succeeded");
            let err = stderr(&o);
            assert!(
                err.contains(&path) && err.contains(what),
                "{args:?}: the error must name {path} and say it is a {what}: {err}"
            );
            assert!(!err.contains("panicked"), "{args:?}: {err}");
        }

        // Inside directories: a `.dl` link in `--rules` and `--programs`, a log's map file.
        let dir = tempfile::tempdir().expect("tempdir");
        let link = dir.path().join("special.dl");
        std::os::unix::fs::symlink(special, &link).expect("symlink");
        let d = s(dir.path());
        for args in [
            vec!["mine", "--rules", &d, "--logs", &log, "--out", &out],
            vec![
                "mine",
                "--log-prompts",
                &pairs,
                "--dataset-dir",
                &logs,
                "--programs",
                &d,
                "--out",
                &out,
            ],
        ] {
            let o = scenalog(&args);
            let err = stderr(&o);
            assert!(
                err.contains("special.dl") && err.contains(what),
                "{args:?}: {err}"
            );
        }
        let (_log_tmp, copy) = copy_log();
        let map = std::fs::read_dir(copy.join("map"))
            .expect("map dir")
            .flatten()
            .map(|e| e.path())
            .find(|p| {
                p.file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with("log_map_archive"))
            })
            .expect("a map file");
        std::fs::remove_file(&map).expect("rm");
        std::os::unix::fs::symlink(special, &map).expect("symlink");
        let o = scenalog(&["facts", &s(&copy)]);
        assert_fails_saying(&o, 2, &["log_map_archive", what]);
    }
}

/// Inputs padded with `truncate -s 20G` (sparse: no disk used) are errors at once naming the
/// file, not an allocation of their size (which aborted the process): a log's annotations and
/// map (`facts`, `mine`), and the evaluation's and the tracker's pickles. Issue #42, item 3.
#[test]
fn inputs_padded_to_20_gib_are_errors_at_once_not_aborts() {
    const PADDED: u64 = 20 << 30;
    let pad = |path: &Path| {
        std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .and_then(|f| f.set_len(PADDED))
            .expect("pad");
    };
    let s = |p: &Path| p.to_str().expect("utf8").to_owned();
    // The annotations, then the map, of a log.
    for padded in ["annotations", "map"] {
        let (_tmp, log) = copy_log();
        let file = if padded == "map" {
            std::fs::read_dir(log.join("map"))
                .expect("map")
                .flatten()
                .map(|e| e.path())
                .find(|p| p.to_string_lossy().contains("log_map_archive"))
                .expect("the map file")
        } else {
            log.join(ANNOTATIONS)
        };
        pad(&file);
        let name = file
            .file_name()
            .expect("name")
            .to_string_lossy()
            .into_owned();
        let out = scenalog(&["facts", &s(&log)]);
        assert_fails_saying(&out, 2, &[&name]);
        let out_dir = tempfile::tempdir().expect("tempdir");
        let rules = s(&repo("rules/library/stopped_car.dl"));
        let out = scenalog(&[
            "mine",
            "--rules",
            &rules,
            "--logs",
            &s(&log),
            "--out",
            &s(out_dir.path()),
        ]);
        let err = stderr(&out);
        assert!(out.status.code().is_some(), "mine died of a signal: {err}");
        assert!(err.contains(&name) && !err.contains("panicked"), "{err}");
    }
    // The evaluation's predictions and ground truth, and a tracker's pickle.
    let tmp = tempfile::tempdir().expect("tempdir");
    let gt = repo("tests/data/av2/eval/combined_gt_dev.pkl");
    let pred = tmp.path().join("predictions.pkl");
    std::fs::copy(
        repo("tests/data/av2/eval/combined_predictions_dev.pkl"),
        &pred,
    )
    .expect("copy");
    pad(&pred);
    let out = scenalog(&["eval", "--pred", &s(&pred), "--gt", &s(&gt)]);
    assert_fails_saying(&out, 2, &["predictions.pkl", "STOP"]);
    let out = scenalog(&["eval", "--pred", &s(&gt), "--gt", &s(&pred)]);
    assert_fails_saying(&out, 2, &["predictions.pkl", "STOP"]);
    let pairs = s(&repo(
        "tests/data/av2/tracker/log_prompt_pairs_fixture.json",
    ));
    let out = scenalog(&[
        "mine",
        "--log-prompts",
        &pairs,
        "--dataset-dir",
        &s(&scenalog_testkit::sample_logs_dir()),
        "--tracks",
        &s(&pred),
        "--out",
        &s(&tmp.path().join("out")),
    ]);
    assert_fails_saying(&out, 2, &["predictions.pkl", "STOP"]);
}
