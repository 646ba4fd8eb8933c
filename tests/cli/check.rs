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
