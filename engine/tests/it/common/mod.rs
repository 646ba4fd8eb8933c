//! Paths shared by the engine's real-log tests: the workspace root, the bundled sample logs and
//! the library's programs.

use std::path::{Path, PathBuf};

/// The workspace root (the engine crate's parent).
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The bundled sample logs (`tests/data/av2/logs/*`), sorted by name.
pub fn logs() -> Vec<PathBuf> {
    let dir = root().join("tests/data/av2/logs");
    let mut logs: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    logs.sort();
    logs
}

/// The library's program files (`rules/library/*.dl`), sorted by name.
#[allow(dead_code)] // not every test file that includes this module lists the library
pub fn library_files() -> Vec<PathBuf> {
    let dir = root().join("rules/library");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "dl"))
        .collect();
    files.sort();
    files
}
