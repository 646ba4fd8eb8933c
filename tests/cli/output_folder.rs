//! One writer per output folder and writes that fail loudly, end to end on a real log: a second
//! `mine` into a folder another run is writing is refused naming the holder, a lock left by a
//! process no longer running is taken over, and a run past `ulimit -f` reports the file it could
//! not write (no silent SIGXFSZ kill) and publishes nothing half-written.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn log() -> PathBuf {
    scenalog_testkit::sample_log(scenalog_testkit::SAMPLE_LOGS[0])
}

fn stopped_car() -> PathBuf {
    root().join("rules/library/stopped_car.dl")
}

fn s(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

fn mine_command(rules: &Path, out: &Path, extra: &[&str]) -> Command {
    let mut c = crate::util::scenalog();
    c.args([
        "mine",
        "--rules",
        &s(rules),
        "--logs",
        &s(&log()),
        "--out",
        &s(out),
    ])
    .args(extra);
    c
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// A program that runs until its pair's time limit: no range narrowing applies to `T3 * T < 0`.
const RUNAWAY: &str =
    "referred(A, T) :- present(A, T), present(B, T), present(C, T3), T3 * T < 0.\n";

#[test]
fn a_second_run_into_a_held_folder_is_refused_naming_the_holder() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    let runaway = dir.path().join("runaway.dl");
    std::fs::write(&runaway, RUNAWAY).expect("write");
    let first = mine_command(&runaway, &out, &["--timeout-ms", "6000"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start the first run");
    let holder = format!("pid {}", first.id());
    // Wait until the first run holds the folder (its lock names it).
    let lock = out.join(".lock");
    let start = Instant::now();
    while !std::fs::read_to_string(&lock).is_ok_and(|t| t.starts_with(&holder)) {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the first run never took the lock"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let second = mine_command(&stopped_car(), &out, &[])
        .output()
        .expect("run the second");
    let refused = text(&second);
    assert_eq!(second.status.code(), Some(2), "{refused}");
    assert!(
        refused.contains("is in use by another run")
            && refused.contains(&holder)
            && refused.contains("started ")
            && refused.contains("runaway.dl"),
        "the holder is named (pid, start, command): {refused}"
    );
    let first = first.wait_with_output().expect("first run");
    // The first run finishes on its own terms: its pair stopped at the time limit, its outputs
    // published, and the second run left no trace of its own.
    assert_eq!(first.status.code(), Some(1), "{}", text(&first));
    assert!(text(&first).contains("longer than"), "{}", text(&first));
    assert!(out.join("summary.json").is_file());
    let summary = std::fs::read_to_string(out.join("summary.json")).expect("summary");
    assert!(summary.contains("runaway"), "{summary}");
    assert!(!summary.contains("stopped_car"), "{summary}");
    // Released: the next run goes ahead.
    let third = mine_command(&stopped_car(), &out, &[])
        .output()
        .expect("third");
    assert_eq!(third.status.code(), Some(0), "{}", text(&third));
}

#[test]
fn a_stale_lock_of_a_dead_process_is_taken_over() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    std::fs::create_dir_all(&out).expect("mkdir");
    // A holder that died without a word: its text stays, its lock went with it.
    std::fs::write(
        out.join(".lock"),
        "pid 4000000, started 2026-01-01 00:00:00 UTC, command `scenalog mine`\n",
    )
    .expect("write");
    let o = mine_command(&stopped_car(), &out, &[])
        .output()
        .expect("run");
    let all = text(&o);
    assert_eq!(o.status.code(), Some(0), "{all}");
    assert!(
        all.contains("took over the lock") && all.contains("pid 4000000"),
        "{all}"
    );
    assert!(out.join("predictions.feather").is_file());
    assert_eq!(
        std::fs::read_to_string(out.join(".lock")).expect("lock"),
        "",
        "released when the run ends"
    );
}

#[cfg(unix)]
#[test]
fn a_file_past_ulimit_f_is_an_error_naming_it_and_nothing_is_published() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    // `ulimit -f 2`: files of at most 1-2 KB (the shell's blocks); the pair's record and the
    // run's outputs are larger.
    let o = Command::new("sh")
        .arg("-c")
        .arg("ulimit -f 2 && exec \"$@\"")
        .arg("sh")
        .arg(env!("CARGO_BIN_EXE_scenalog"))
        .args(["mine", "--rules", &s(&stopped_car()), "--logs", &s(&log())])
        .args(["--out", &s(&out)])
        .output()
        .expect("run under ulimit");
    let all = text(&o);
    assert!(
        o.status.code().is_some(),
        "killed by a signal instead of reporting the error: {:?}\n{all}",
        o.status
    );
    assert_ne!(o.status.code(), Some(0), "{all}");
    assert!(
        all.contains("File too large") && all.contains(&s(&out)),
        "the error names the file: {all}"
    );
    // Nothing was published, and no temporary or partial file was left behind.
    assert!(
        std::fs::symlink_metadata(out.join(".current")).is_err(),
        "{all}"
    );
    assert!(!out.join("predictions.feather").exists());
    let left: Vec<PathBuf> = crate::util::files_under(&out)
        .into_iter()
        .filter(|p| {
            let name = p.file_name().map(|n| n.to_string_lossy().into_owned());
            name.is_some_and(|n| n.ends_with(".tmp") || n.contains(".tmp"))
        })
        .collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
    let staging: Vec<PathBuf> = std::fs::read_dir(&out)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.to_string_lossy().contains(".staging-"))
        .collect();
    assert!(staging.is_empty(), "a generation left: {staging:?}");
}
