//! What every command-line test shares: the built `scenalog` binary as a [`Command`].

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// The `scenalog` binary this test run built, as a command to add arguments to. Variables of
/// the environment that change the command's behaviour (the LLM server, the cache, the thread
/// count) are left as the test sets them.
pub fn scenalog() -> Command {
    Command::new(env!("CARGO_BIN_EXE_scenalog"))
}

/// Runs the binary with `args`, writing `stdin` to its standard input, and collects its output.
pub fn with_stdin(args: &[&str], stdin: &str) -> Output {
    let mut child = scenalog()
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run scenalog");
    if let Some(mut pipe) = child.stdin.take() {
        // A command that exits without reading its input closes the pipe: not an error here.
        let _ = pipe.write_all(stdin.as_bytes());
    }
    child.wait_with_output().expect("wait for scenalog")
}

/// Every file under `dir`, recursively (symbolic links not followed).
pub fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = e.path();
            if e.file_type().is_ok_and(|t| t.is_dir()) {
                todo.push(p);
            } else {
                out.push(p);
            }
        }
    }
    out
}

/// The first Chromium-like browser found on PATH (Debian's `chromium`), for the tests that
/// load a page; `None` when none is installed.
pub fn browser() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |d| d.join(name)))
        .find(|p| p.is_file())
}
