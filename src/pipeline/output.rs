//! What a mining run writes under its output directory, and how: every file atomically (a
//! temporary file in the same directory, then a rename), so a crash leaves either the old file or
//! the new one, never half of one.
//!
//! Layout of `OUT/`:
//! - `predictions.pkl`: the official pickle for the whole run, keyed `(log_id, description)`;
//! - `predictions.feather`: the same predictions as the long Arrow table;
//! - `scored.pkl` (with ground truth): the predictions of the sequences it holds;
//! - `matches.json`: one entry per referred track of every (log, program) pair;
//! - `summary.json`: every pair's status, match count and times, and the stage totals;
//! - `pairs/<log_id>/<program>.json`: one pair's record (its derived tuples), which marks the
//!   pair done for `--resume` and from which its predictions are rebuilt.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use serde::{Deserialize, Serialize};

/// The run's official pickle.
pub const PREDICTIONS_PICKLE: &str = "predictions.pkl";
/// The run's long Arrow table.
pub const PREDICTIONS_TABLE: &str = "predictions.feather";
/// With ground truth: the predictions of the scored sequences only, which `scenalog eval --gt G`
/// scores as the run did.
pub const SCORED_PICKLE: &str = "scored.pkl";
/// The per-match summary.
pub const MATCHES_JSON: &str = "matches.json";
/// Every pair's status and the stage times.
pub const SUMMARY_JSON: &str = "summary.json";
/// The directory of per-pair results.
pub const PAIRS_DIR: &str = "pairs";

/// One referred track of one (log, program) pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Match {
    /// The log id.
    pub log_id: String,
    /// The description the predictions are keyed by.
    pub description: String,
    /// The program's name (its file stem).
    pub program: String,
    /// The AV2 track uuid.
    pub track_uuid: String,
    /// The track's AV2 category.
    pub category: String,
    /// Seconds from the log's start of the first frame the program referred the track at.
    pub first_s: f64,
    /// Seconds from the log's start of the last such frame.
    pub last_s: f64,
    /// How many frames (10 Hz) the program referred the track at, before dilation.
    pub frames: usize,
    /// The uuids of the objects related to it, sorted.
    pub related: Vec<String>,
}

/// The record of one finished pair: `pairs/<log_id>/<program>.json`. It holds the derived
/// tuples, from which the pair's frames and matches are rebuilt exactly on `--resume`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairRecord {
    /// The log id.
    pub log_id: String,
    /// The description the predictions are keyed by.
    pub description: String,
    /// The program's name.
    pub program: String,
    /// The program's source text: a pair is resumed only when the program is unchanged.
    pub source: String,
    /// The output timestamps the run was given for this log (`None`: every 5th frame).
    pub timestamps: Option<Vec<i64>>,
    /// The number of tracks of the log (a check that the log is the same).
    pub tracks: usize,
    /// `referred(track index, frame)` tuples.
    pub referred: Vec<(u32, u32)>,
    /// `related(track index, other track index, frame)` tuples.
    pub related: Vec<(u32, u32, u32)>,
}

/// `OUT/pairs/<log_id>/<program>.json`.
pub fn pair_path(out: &Path, log_id: &str, program: &str) -> PathBuf {
    out.join(PAIRS_DIR)
        .join(log_id)
        .join(format!("{program}.json"))
}

static TMP_COUNTER: AtomicUsize = AtomicUsize::new(0);

/// Writes `bytes` to `path` atomically: a temporary file beside it, then renamed over it, synced
/// to disk first when `sync`. The parent directory is created when missing. The error names the
/// file. Per-pair files skip the sync: the rename is still atomic for a crashed process, and a
/// pair whose files did not survive a system crash fails to read back and is redone by
/// `--resume` (syncing each of hundreds of small files cost more than the mining itself).
pub fn write_atomic(path: &Path, bytes: &[u8], sync: bool) -> Result<(), String> {
    let parent = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent)
        .map_err(|e| format!("cannot create directory `{}`: {e}", parent.display()))?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let n = TMP_COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp = parent.join(format!(".{name}.{}-{n}.tmp", std::process::id()));
    let written = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        if sync {
            f.sync_all()?;
        }
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    written.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        format!("cannot write `{}`: {e}", path.display())
    })
}

/// Writes a value as pretty JSON (with a final newline), atomically (synced when `sync`).
pub fn write_json<T: Serialize>(path: &Path, value: &T, sync: bool) -> Result<(), String> {
    let mut text = serde_json::to_string_pretty(value)
        .map_err(|e| format!("cannot encode `{}`: {e}", path.display()))?;
    text.push('\n');
    write_atomic(path, text.as_bytes(), sync)
}

/// Reads a pair record; `None` when it is missing or unreadable (the pair is then redone).
pub fn read_record(path: &Path) -> Option<PairRecord> {
    let text = std::fs::read_to_string(path).ok()?;
    serde_json::from_str(&text).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_replaces_and_leaves_no_temporary_file() {
        let dir = std::env::temp_dir().join(format!("scenalog-output-{}", std::process::id()));
        let path = dir.join("a").join("x.json");
        write_atomic(&path, b"one", true).unwrap();
        write_atomic(&path, b"two", false).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"two");
        let names: Vec<_> = std::fs::read_dir(dir.join("a"))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 1, "{names:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
