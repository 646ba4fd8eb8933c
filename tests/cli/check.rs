//! `scenalog check` end to end: exit codes, human and JSON output, stdin, `--no-referred`.

use std::process::Output;

fn scenalog(args: &[&str], stdin: Option<&str>) -> Output {
    crate::util::with_stdin(args, stdin.unwrap_or(""))
}

fn library(name: &str) -> String {
    format!("{}/rules/library/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn clean_library_files_exit_zero() {
    let a = library("stopped_car.dl");
    let b = library("vehicle_with_bicycle_to_its_right.dl");
    let out = scenalog(&["check", &a, &b], None);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("stopped_car.dl: 0 error(s), 0 warning(s)"),
        "{text}"
    );
}

#[test]
fn errors_exit_one_with_caret_under_the_span() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("bad.dl");
    std::fs::write(&path, "referred(X, T) :- nearr(X, _, T, _).\n").expect("write");
    let out = scenalog(&["check", path.to_str().unwrap_or("")], None);
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("error[E0101]"), "{text}");
    assert!(text.contains("^^^^^"), "{text}");
    assert!(text.contains("did you mean"), "{text}");
}

#[test]
fn stdin_json_and_no_referred() {
    let src = "slow(X, T) :- speed(X, T, S), S < 1.0.\n";
    let out = scenalog(&["check", "--json", "-"], Some(src));
    assert_eq!(out.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(v[0]["file"], "<stdin>");
    let d = &v[0]["diagnostics"][0];
    assert_eq!(d["code"], "E0401");
    assert_eq!(d["severity"], "error");
    assert_eq!(d["line"], 1);
    assert_eq!(d["column"], 1);
    assert_eq!(d["span"]["start"], 0);
    assert!(d["hint"].is_string());
    assert!(d["related"].is_array());
    let out = scenalog(&["check", "--no-referred", "-"], Some(src));
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
}

#[test]
fn warnings_only_exit_zero() {
    let src = "referred(X, T) :- present(X, T), speed(X, T, Speed).\n";
    let out = scenalog(&["check", "--json", "-"], Some(src));
    assert_eq!(out.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(v[0]["diagnostics"][0]["code"], "W0501");
    assert_eq!(v[0]["diagnostics"][0]["severity"], "warning");
    assert_eq!(v[0]["diagnostics"][0]["column"], 46);
}

#[test]
fn unreadable_input_exits_two() {
    let out = scenalog(&["check", "/nonexistent/nope.dl"], None);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("/nonexistent/nope.dl"));
}

#[test]
fn fix_writes_the_units_a_program_was_read_in_and_keeps_its_answer() {
    // A program of bare numbers as the library was written before units: `--fix` writes each
    // reading's unit (and a duration of frames in seconds) and the program checks clean.
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("bare.dl");
    let bare = "referred(V, T2) :- category(V, \"VEHICLE\"), speed(V, T2, S), S > 5.0,\n    \
                stopped(V, T1), T2 > T1, T2 - T1 <= 30, T0 = T2 - 10, present(V, T0).\n";
    std::fs::write(&path, bare).expect("write");
    let p = path.to_str().unwrap_or("");
    let out = scenalog(&["check", p], None);
    assert_eq!(out.status.code(), Some(1), "E0106 on `T2 - 10`");
    let out = scenalog(&["check", "--fix", p], None);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    assert!(text.contains("bare.dl: 3 fix(es) applied"), "{text}");
    assert!(text.contains("bare.dl: 0 error(s), 0 warning(s)"), "{text}");
    let fixed = std::fs::read_to_string(&path).expect("read");
    assert_eq!(
        fixed,
        "referred(V, T2) :- category(V, \"VEHICLE\"), speed(V, T2, S), S > 5.0 m/s,\n    \
         stopped(V, T1), T2 > T1, T2 - T1 <= 3 s, T0 = T2 - 1 s, present(V, T0).\n"
    );
    // From standard input the fixed program goes to standard output, diagnostics to stderr.
    let out = scenalog(&["check", "--fix", "-"], Some(bare));
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(String::from_utf8_lossy(&out.stdout), fixed);
    // A link is not rewritten (nor replaced by a file).
    #[cfg(unix)]
    {
        let link = dir.path().join("link.dl");
        let target = dir.path().join("target.dl");
        std::fs::write(&target, bare).expect("write");
        std::os::unix::fs::symlink(&target, &link).expect("symlink");
        let out = scenalog(&["check", "--fix", link.to_str().unwrap_or("")], None);
        assert_eq!(out.status.code(), Some(2));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("symbolic link"), "{err}");
        assert_eq!(std::fs::read_to_string(&target).expect("read"), bare);
        assert!(std::fs::symlink_metadata(&link)
            .expect("link")
            .file_type()
            .is_symlink());
    }
}
