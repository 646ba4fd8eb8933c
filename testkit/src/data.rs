//! The repository's test data: the three bundled Argoverse 2 sample logs (`tests/data/av2/logs`)
//! and the scenario library (`rules/library`).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use scenalog_facts::{load_scene, Scene};

/// The ids of the bundled sample logs, sorted.
pub const SAMPLE_LOGS: [&str; 3] = [
    "3b3570b4-7b0b-3268-a571-b0889dbf40b6",
    "3bffdcff-c3a7-38b6-a0f2-64196d130958",
    "adcf7d18-0510-35b0-a2fa-b4cea13a6d76",
];

/// The workspace root.
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The directory holding the sample logs (`tests/data/av2/logs`), as `--logs` takes it.
pub fn sample_logs_dir() -> PathBuf {
    repo_root().join("tests/data/av2/logs")
}

/// The directory of the sample log `id` (one of [`SAMPLE_LOGS`]).
pub fn sample_log(id: &str) -> PathBuf {
    sample_logs_dir().join(id)
}

/// The directories of the sample logs, in [`SAMPLE_LOGS`] order.
pub fn sample_log_dirs() -> Vec<PathBuf> {
    SAMPLE_LOGS.iter().map(|id| sample_log(id)).collect()
}

/// The sample logs loaded, in [`SAMPLE_LOGS`] order: read once per test binary and shared. A log
/// that does not load fails the test that asked, naming it.
pub fn sample_scenes() -> &'static [Scene] {
    static SCENES: OnceLock<Vec<Scene>> = OnceLock::new();
    SCENES.get_or_init(|| {
        sample_log_dirs()
            .iter()
            .map(|dir| load_scene(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())))
            .collect()
    })
}

/// The scenario library's program files (`rules/library/*.dl`), sorted by name.
pub fn library_files() -> Vec<PathBuf> {
    let dir = repo_root().join("rules/library");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "dl"))
        .collect();
    files.sort();
    files
}

/// A copy of the sample log `id` (its files and its `map/`) made in `into/<id>`, for a test that
/// adds files a user would (a colour cache, an attributes file); the copy's directory.
pub fn copy_sample_log(id: &str, into: &Path) -> PathBuf {
    let from = sample_log(id);
    let to = into.join(id);
    for rel in ["", "map"] {
        std::fs::create_dir_all(to.join(rel)).unwrap_or_else(|e| panic!("{e}"));
        for entry in std::fs::read_dir(from.join(rel)).unwrap_or_else(|e| panic!("{e}")) {
            let path = entry.unwrap_or_else(|e| panic!("{e}")).path();
            if path.is_file() {
                let name = path.file_name().unwrap_or_default();
                std::fs::copy(&path, to.join(rel).join(name)).unwrap_or_else(|e| panic!("{e}"));
            }
        }
    }
    to
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sample_logs_and_the_library_are_where_they_are_said_to_be() {
        let dirs: Vec<PathBuf> = std::fs::read_dir(sample_logs_dir())
            .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        let mut found: Vec<PathBuf> = dirs.into_iter().filter(|p| p.is_dir()).collect();
        found.sort();
        let listed: Vec<PathBuf> = sample_log_dirs()
            .iter()
            .map(|p| p.canonicalize().unwrap_or_else(|e| panic!("{e}")))
            .collect();
        let found: Vec<PathBuf> = found
            .iter()
            .map(|p| p.canonicalize().unwrap_or_else(|e| panic!("{e}")))
            .collect();
        assert_eq!(listed, found);
        assert!(library_files().len() > 50);
    }
}
