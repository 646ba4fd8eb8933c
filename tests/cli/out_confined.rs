//! Nothing written outside `--out` (issue #42): a `--logs` path ending in `..`, relative or
//! absolute, names the log by the directory it resolves to and writes only under OUT; a log
//! directory whose name is not a plain log id is refused, naming it.

use std::path::{Path, PathBuf};

const LOG: &str = "3b3570b4-7b0b-3268-a571-b0889dbf40b6";

fn sample_log() -> PathBuf {
    scenalog_testkit::sample_logs_dir().join(LOG)
}

fn stopped_car() -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("rules/library/stopped_car.dl")
        .to_string_lossy()
        .into_owned()
}

/// A copy of the sample log (its files and its map) at `dir`.
fn copy_log(dir: &Path) {
    let from = sample_log();
    std::fs::create_dir_all(dir.join("map")).expect("mkdir");
    for sub in ["", "map"] {
        for e in std::fs::read_dir(from.join(sub))
            .expect("read log")
            .flatten()
        {
            if e.file_type().is_ok_and(|t| t.is_file()) {
                std::fs::copy(e.path(), dir.join(sub).join(e.file_name())).expect("copy");
            }
        }
    }
}

/// The files under `root` that are not under `out`.
fn outside(root: &Path, out: &Path) -> Vec<PathBuf> {
    crate::util::files_under(root)
        .into_iter()
        .filter(|p| !p.starts_with(out))
        .collect()
}

fn text(o: &std::process::Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

#[test]
fn logs_paths_ending_in_dot_dot_write_only_under_out() {
    let t = tempfile::tempdir().expect("tempdir");
    let root = t.path().canonicalize().expect("canonical tempdir");
    let log = root.join("log");
    copy_log(&log);
    let cwd = root.join("c").join("d");
    std::fs::create_dir_all(&cwd).expect("mkdir");
    let before = outside(&root, &root.join("none"));
    // Absolute and relative paths that end in `..`; `out` relative to the working directory.
    for (i, logs) in [
        log.join("map").join("..").to_string_lossy().into_owned(),
        "../../log/map/..".to_string(),
        "../../log/map/../.".to_string(),
    ]
    .into_iter()
    .enumerate()
    {
        let out = cwd.join(format!("out{i}"));
        let o = crate::util::scenalog()
            .current_dir(&cwd)
            .args(["mine", "--rules", &stopped_car(), "--logs", &logs])
            .args(["--out", &format!("out{i}")])
            .output()
            .expect("run");
        assert!(o.status.success(), "--logs {logs}: {}", text(&o));
        // Every run's OUT is under the working directory, which holds nothing else.
        let after = outside(&root, &cwd);
        let new: Vec<_> = after.iter().filter(|p| !before.contains(p)).collect();
        assert!(new.is_empty(), "--logs {logs} wrote outside OUT: {new:?}");
        // The log is named by the directory the path resolves to.
        assert!(
            out.join("pairs")
                .join("log")
                .join("stopped_car.json")
                .is_file(),
            "--logs {logs}: {:?}",
            crate::util::files_under(&out)
        );
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(
            stdout.lines().next().unwrap_or_default().contains("log"),
            "{stdout}"
        );
    }
}

#[test]
fn a_log_directory_whose_name_is_not_a_log_id_is_refused_naming_it() {
    let t = tempfile::tempdir().expect("tempdir");
    let log = t.path().join("my log; rm");
    copy_log(&log);
    let out = t.path().join("out");
    let o = crate::util::scenalog()
        .args(["mine", "--rules", &stopped_car(), "--logs"])
        .arg(&log)
        .arg("--out")
        .arg(&out)
        .output()
        .expect("run");
    let all = text(&o);
    assert_eq!(o.status.code(), Some(2), "{all}");
    assert!(
        all.contains("my log; rm") && all.contains("log id"),
        "the message names the directory and says why: {all}"
    );
    assert!(!out.join("pairs").exists(), "nothing mined: {all}");
}

/// `mine --rules stopped_car --logs SAMPLE --out OUT`.
fn mine_into(out: &Path) -> std::process::Output {
    crate::util::scenalog()
        .args(["mine", "--rules", &stopped_car(), "--logs"])
        .arg(sample_log())
        .arg("--out")
        .arg(out)
        .output()
        .expect("run")
}

#[cfg(unix)]
#[test]
fn links_planted_in_an_output_folder_are_refused_and_never_written_through() {
    use std::os::unix::fs::symlink;
    let t = tempfile::tempdir().expect("tempdir");
    let victim = t.path().join("victim.txt");
    let elsewhere = t.path().join("elsewhere");
    std::fs::create_dir(&elsewhere).expect("mkdir");
    // Each planted link: where it is, relative to OUT, and what it points at.
    let cases: [(&str, &Path); 4] = [
        (".lock", &victim),
        ("pairs", &elsewhere),
        (&format!("pairs/{LOG}"), &elsewhere),
        ("programs", &elsewhere),
    ];
    for (i, (at, target)) in cases.iter().enumerate() {
        std::fs::write(&victim, "keep").expect("write");
        let out = t.path().join(format!("out{i}"));
        let link = out.join(at);
        std::fs::create_dir_all(link.parent().expect("parent")).expect("mkdir");
        symlink(target, &link).expect("link");
        let o = mine_into(&out);
        let all = text(&o);
        assert!(!o.status.success(), "{at}: {all}");
        assert!(
            all.contains(&link.display().to_string()) && all.contains("link"),
            "{at}: the message names the link: {all}"
        );
        assert_eq!(std::fs::read_to_string(&victim).expect("read"), "keep");
        assert_eq!(
            std::fs::read_dir(&elsewhere).expect("read").count(),
            0,
            "{at}: nothing written through the link"
        );
        // With the link removed, the same command runs; run again, its own links pass.
        std::fs::remove_file(&link).expect("rm");
        for _ in 0..2 {
            let o = mine_into(&out);
            assert!(o.status.success(), "{at}: {}", text(&o));
        }
    }
}

#[cfg(unix)]
#[test]
fn eval_out_replaces_a_planted_link_without_writing_its_target() {
    let t = tempfile::tempdir().expect("tempdir");
    let victim = t.path().join("victim.txt");
    std::fs::write(&victim, "keep").expect("write");
    let out = t.path().join("metrics");
    std::fs::create_dir(&out).expect("mkdir");
    std::os::unix::fs::symlink(&victim, out.join("temporal_metrics.json")).expect("link");
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/av2/eval");
    let o = crate::util::scenalog()
        .args(["eval", "--pred"])
        .arg(data.join("combined_predictions_dev.pkl"))
        .arg("--gt")
        .arg(data.join("combined_gt_dev.pkl"))
        .arg("--out")
        .arg(&out)
        .output()
        .expect("run");
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(std::fs::read_to_string(&victim).expect("read"), "keep");
    let written = out.join("temporal_metrics.json");
    assert!(
        !std::fs::symlink_metadata(&written)
            .expect("written")
            .file_type()
            .is_symlink(),
        "the link is replaced by the file"
    );
    assert!(std::fs::read_to_string(&written)
        .expect("read")
        .contains("balanced_accuracy"));
}
