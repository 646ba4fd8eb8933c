//! What a mining run writes under its output directory, and how: every file atomically (a
//! temporary file in the same directory, then a rename), so a crash leaves either the old file or
//! the new one, never half of one.
//!
//! Layout of `OUT/`:
//! - `predictions.feather`: the run's predictions as the long Arrow table, every buffer
//!   zstd-compressed and the `log_id`, `prompt` and `name` columns dictionary-encoded (one
//!   record batch a log, the same dictionaries in each: every log id and description of the run);
//! - `predictions.pkl` (only when asked for, `mine --pickle`): the official pickle for the whole
//!   run, keyed `(log_id, description)`;
//! - `scored.pkl` (with ground truth): the predictions of the sequences it holds;
//! - `matches.json`: one entry per referred track of every (log, program) pair;
//! - `summary.json`: every pair's status, match count and times, and the stage totals;
//! - `pairs/<log_id>/<program>.json`: one pair's record (its derived tuples), which marks the
//!   pair done for `--resume` and from which its predictions are rebuilt; it carries the pair's
//!   fingerprint (tool version, the log's input files, program, timestamps), and a pair whose
//!   fingerprint changed is mined again.
//!
//! With `--log-prompts` the pickle and table are `submission.pkl` and `submission.feather`.
//!
//! **One generation.** A run writes its outputs (the pickle and table joined from per-pair parts,
//! `matches.json`, `summary.json`, and `mine`'s `scored.pkl` and `report/`) into its own
//! generation directory `OUT/.staging-<pid>-<n>/`, then publishes them all at once by switching one
//! symbolic link, `OUT/.current`, to it (a rename, atomic). Each output's path in `OUT/` is a
//! link through it (`OUT/predictions.pkl -> .current/predictions.pkl`), made once, so
//! `OUT/predictions.pkl` and the others keep their paths, and a reader sees either the whole
//! previous set or the whole new one, never a set mixed from two runs, whenever a run is killed.
//! An output the new generation does not hold (`scored.pkl` of an earlier run with ground truth)
//! is removed from `OUT/` with the switch. The generation replaced stays until the next run (for a
//! reader that had just resolved `.current`); whatever a killed run left behind (its generation
//! directory, `.*.tmp` files of a process no longer running) is removed by the next run into the
//! same `OUT/`. Pair records (`pairs/`) are written one by one, atomically, outside generations:
//! `--resume` reads them, not the published set.
//! (Where symbolic links are missing, non-Unix systems, the outputs are renamed into place one
//! after the other, as before.)

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use serde::{Deserialize, Serialize};

/// The run's official pickle (written when [`OutputNames::write_pickle`]).
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
/// The report's directory (`scenalog mine --report`).
pub const REPORT_DIR: &str = "report";
/// `mine --rerun`: the run's matches as a Rerun recording.
pub const MATCHES_RRD: &str = "matches.rrd";
pub use super::lock::CURRENT;

/// Every output a generation may hold: its path in `OUT/` is a link through [`CURRENT`].
pub const GENERATION_NAMES: &[&str] = &[
    PREDICTIONS_PICKLE,
    PREDICTIONS_TABLE,
    SUBMISSION_PICKLE,
    SUBMISSION_TABLE,
    SCORED_PICKLE,
    MATCHES_JSON,
    SUMMARY_JSON,
    REPORT_DIR,
    MATCHES_RRD,
];

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
    /// The pair's resume key: SHA-256 of the tool version, the log's input files, the program
    /// text, the description and the output timestamps (empty in records of older versions,
    /// which are therefore redone).
    #[serde(default)]
    pub fingerprint: String,
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
    scenalog_input::out_dir::write_atomic(path, bytes, sync)
        .map_err(|e| format!("cannot write `{}`: {e}", path.display()))
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

/// The file names of a run's pickle and Arrow table, and whether the pickle is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputNames {
    /// The official pickle.
    pub pickle: &'static str,
    /// The long Arrow table.
    pub table: &'static str,
    /// Whether the run writes the official pickle: where a submission is asked for (`mine
    /// --pickle`, a split's pairs); by default only the table (the pickle of a run is about six
    /// times its compressed table).
    pub write_pickle: bool,
}

impl Default for OutputNames {
    fn default() -> Self {
        OutputNames {
            pickle: PREDICTIONS_PICKLE,
            table: PREDICTIONS_TABLE,
            write_pickle: false,
        }
    }
}

/// The most rows of one record batch of a run's table (a log with more is written in several):
/// the rows of a batch are held decoded while it is written, about 100 bytes a row.
const ROWS_PER_BATCH: usize = 1 << 20;

/// The codec of the per-pair parts of the table (temporary: fast to write and read back).
const PART_CODEC: Option<arrow_ipc::CompressionType> = Some(arrow_ipc::CompressionType::LZ4_FRAME);

/// The submission pickle of `--log-prompts`.
pub const SUBMISSION_PICKLE: &str = "submission.pkl";
/// The submission's Arrow table.
pub const SUBMISSION_TABLE: &str = "submission.feather";

/// Prefix of a run's staging directory under `OUT/`.
const STAGING_PREFIX: &str = ".staging-";

/// Whether process `pid` is running (Linux `/proc`; elsewhere, assumed running, so nothing of a
/// live run is ever removed).
fn alive(pid: u32) -> bool {
    let proc = Path::new("/proc");
    !proc.is_dir() || proc.join(pid.to_string()).exists()
}

/// The process id a staging directory (`.staging-<pid>-<n>`) or temporary file
/// (`.<name>.<pid>-<n>.tmp`, `.<name>.tmp<pid>`) name carries.
fn owner_pid(name: &str) -> Option<u32> {
    if let Some(rest) = name.strip_prefix(STAGING_PREFIX) {
        return rest.split('-').next()?.parse().ok();
    }
    let stem = name.strip_prefix('.')?;
    if let Some(body) = stem.strip_suffix(".tmp") {
        let last = body.rsplit('.').next()?;
        return last.split('-').next()?.parse().ok();
    }
    let (_, pid) = stem.rsplit_once(".tmp")?;
    pid.parse().ok()
}

/// The directory name of the generation `OUT/.current` points to, if any.
pub fn current_generation(out: &Path) -> Option<String> {
    let target = std::fs::read_link(out.join(CURRENT)).ok()?;
    Some(target.file_name()?.to_string_lossy().into_owned())
}

/// Removes what killed runs left in `out` (generation directories other than the published one,
/// and temporary files, of processes no longer running), in `out` itself and in `out/pairs/*/`.
/// Best effort: what cannot be removed stays.
pub fn clean_orphans(out: &Path) {
    let mut dirs = vec![out.to_path_buf()];
    if let Ok(entries) = std::fs::read_dir(out.join(PAIRS_DIR)) {
        dirs.extend(
            entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_dir()),
        );
    }
    let current = current_generation(out);
    for dir in dirs {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for e in entries.filter_map(|e| e.ok()) {
            let name = e.file_name().to_string_lossy().into_owned();
            let Some(pid) = owner_pid(&name) else {
                continue;
            };
            if pid == std::process::id() || alive(pid) {
                continue;
            }
            if dir == out && current.as_deref() == Some(name.as_str()) {
                continue;
            }
            let path = e.path();
            let _ = if path.is_dir() {
                std::fs::remove_dir_all(&path)
            } else {
                std::fs::remove_file(&path)
            };
        }
    }
}

static STAGING_COUNTER: AtomicUsize = AtomicUsize::new(0);

/// A run's generation directory: per-pair parts and the outputs before they are published.
/// Removed when dropped unless published.
///
/// Its parts are one a pair (a [`PartId`]), written as each pair finishes, so a run holds one
/// pair's prediction frames per worker rather than a whole log's.
pub struct Staging {
    out: PathBuf,
    dir: PathBuf,
    published: std::sync::atomic::AtomicBool,
    /// `OUT/` held for this run from the generation's start until it is published or dropped.
    lock: super::lock::OutputLock,
    /// The dictionaries of the table's string columns, the same for every part.
    dictionaries: scenalog_eval::arrow_table::TableDictionaries,
    /// Whether the per-pair pickle parts are written (and joined).
    pickle: bool,
    /// The keys of each pickle part written so far (the joiner checks them).
    pickle_keys: std::sync::Mutex<std::collections::BTreeMap<PartId, scenalog_eval::PartKeys>>,
    /// The parts written so far.
    written: std::sync::Mutex<Vec<PartId>>,
}

/// The writer of a run's Arrow table.
type TableWriter = arrow_ipc::writer::FileWriter<std::io::BufWriter<std::fs::File>>;

/// One part of a run's predictions: (the log's index, the program's index) in the run.
pub type PartId = (usize, usize);

impl Staging {
    /// Holds `out` ([`super::lock::OutputLock`]: a folder another run is writing is an error
    /// naming it) and creates `out/.staging-<pid>-<n>/`.
    pub fn new(out: &Path) -> Result<Staging, String> {
        let lock = super::lock::OutputLock::acquire(out)?;
        let n = STAGING_COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir = out.join(format!("{STAGING_PREFIX}{}-{n}", std::process::id()));
        // Created new: something already there (a link planted at the name) is an error.
        std::fs::create_dir(&dir)
            .map_err(|e| format!("cannot create directory `{}`: {e}", dir.display()))?;
        Ok(Staging {
            out: out.to_path_buf(),
            dir,
            published: std::sync::atomic::AtomicBool::new(false),
            lock,
            dictionaries: Default::default(),
            pickle: true,
            pickle_keys: Default::default(),
            written: Default::default(),
        })
    }

    /// Sets what the parts hold: the table's dictionaries (every log id, description and object
    /// name of the run, so every log's record batch shares them) and whether the pickle is
    /// written too.
    pub fn set_contents(
        &mut self,
        dictionaries: scenalog_eval::arrow_table::TableDictionaries,
        pickle: bool,
    ) {
        self.dictionaries = dictionaries;
        self.dictionaries.normalise();
        self.pickle = pickle;
    }

    /// The holder named by a stale lock of `OUT/` (a run no longer running) this run took over.
    pub fn took_over(&self) -> Option<&str> {
        self.lock.took_over.as_deref()
    }

    /// A file in the staging directory.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    fn part(&self, (log, program): PartId, ext: &str) -> PathBuf {
        self.dir.join(format!("part-{log}-{program}.{ext}"))
    }

    /// Writes part `id`'s predictions (one pair's): its Arrow table (LZ4, the run's
    /// dictionaries) and, when the pickle is written, its sequences encoded for `eval`'s joiner
    /// ([`scenalog_eval::encode_part`]; their keys kept for the join).
    pub fn write_part(&self, id: PartId, part: &scenalog_eval::Submission) -> Result<(), String> {
        if self.pickle {
            let (keys, bytes) = scenalog_eval::encode_part(part);
            write_atomic(&self.part(id, "pkl"), &bytes, false)?;
            self.pickle_keys
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .insert(id, keys);
        }
        let path = self.part(id, "feather");
        let bytes = scenalog_eval::arrow_table::table_bytes(part, &self.dictionaries, PART_CODEC)
            .map_err(|e| format!("`{}`: {e}", path.display()))?;
        write_atomic(&path, &bytes, false)?;
        self.written
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(id);
        Ok(())
    }

    /// The parts written so far, in no particular order.
    pub fn written_parts(&self) -> Vec<PartId> {
        self.written
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// Joins the parts, in `order`, into the run's Arrow table (zstd-compressed; a log's pairs
    /// in one record batch, or in several of at most 2^20 (`ROWS_PER_BATCH`) rows) and, when asked for, its pickle (with `eval`'s joiner,
    /// [`scenalog_eval::PickleJoin`], which checks every part's keys: byte for byte the pickle of
    /// the whole submission, `order` sorting the pairs by log id and description; the parts'
    /// bytes copied, not decoded).
    pub fn join_parts(&self, order: &[PartId], names: &OutputNames) -> Result<(), String> {
        let pickle = self.path(names.pickle);
        let io = |p: &Path, e: std::io::Error| format!("cannot write `{}`: {e}", p.display());
        if self.pickle {
            let file = scenalog_input::out_dir::create_new(&pickle).map_err(|e| io(&pickle, e))?;
            let what = format!("`{}`", pickle.display());
            let mut join = scenalog_eval::PickleJoin::new(std::io::BufWriter::new(file), &what)
                .map_err(|e| e.to_string())?;
            let keys = self.pickle_keys.lock().unwrap_or_else(|e| e.into_inner());
            for &i in order {
                let part = self.part(i, "pkl");
                let Some(keys) = keys.get(&i) else {
                    return Err(format!(
                        "`{}`: part {i:?} was never written",
                        pickle.display()
                    ));
                };
                let mut r = std::fs::File::open(&part).map_err(|e| io(&part, e))?;
                join.add_encoded(keys, &mut r).map_err(|e| e.to_string())?;
            }
            let f = join.finish().map_err(|e| e.to_string())?;
            let f = f.into_inner().map_err(|e| io(&pickle, e.into_error()))?;
            f.sync_all().map_err(|e| io(&pickle, e))?;
        }
        let table = self.path(names.table);
        let arrow = |e: arrow_schema::ArrowError| format!("`{}`: {e}", table.display());
        let mut writer: Option<TableWriter> = None;
        // A log's pairs' rows are gathered into one record batch (zstd compresses a log's
        // repeated boxes well only within a batch), up to ROWS_PER_BATCH rows at a time.
        let mut pending: Vec<arrow_array::RecordBatch> = Vec::new();
        let mut pending_log = None;
        let flush = |pending: &mut Vec<arrow_array::RecordBatch>,
                     writer: &mut Option<TableWriter>|
         -> Result<(), String> {
            if pending.is_empty() {
                return Ok(());
            }
            let batch = scenalog_eval::arrow_table::concat_sharing_dictionaries(pending)
                .map_err(|e| format!("`{}`: {e}", table.display()))?;
            pending.clear();
            if let Some(w) = writer.as_mut() {
                w.write(&batch).map_err(arrow)?;
            }
            Ok(())
        };
        for &i in order {
            let part = self.part(i, "feather");
            let file = std::fs::File::open(&part).map_err(|e| io(&part, e))?;
            let reader = arrow_ipc::reader::FileReader::try_new(file, None).map_err(arrow)?;
            let rows: usize = pending.iter().map(|b| b.num_rows()).sum();
            if pending_log != Some(i.0) || rows >= ROWS_PER_BATCH {
                flush(&mut pending, &mut writer)?;
                pending_log = Some(i.0);
            }
            if writer.is_none() {
                let f = scenalog_input::out_dir::create_new(&table).map_err(|e| io(&table, e))?;
                let options = scenalog_eval::arrow_table::table_write_options(Some(
                    scenalog_eval::arrow_table::TABLE_COMPRESSION,
                ))
                .map_err(|e| e.to_string())?;
                writer = Some(
                    arrow_ipc::writer::FileWriter::try_new_with_options(
                        std::io::BufWriter::new(f),
                        &reader.schema(),
                        options,
                    )
                    .map_err(arrow)?,
                );
            }
            for batch in reader {
                pending.push(batch.map_err(arrow)?);
            }
        }
        flush(&mut pending, &mut writer)?;
        match writer {
            Some(mut w) => {
                w.finish().map_err(arrow)?;
                let f = w.into_inner().map_err(arrow)?;
                let f = f.into_inner().map_err(|e| io(&table, e.into_error()))?;
                f.sync_all().map_err(|e| io(&table, e))?;
            }
            None => scenalog_eval::arrow_table::write_table_with(
                &scenalog_eval::Submission::default(),
                &table,
                &self.dictionaries,
                Some(scenalog_eval::arrow_table::TABLE_COMPRESSION),
            )
            .map_err(|e| e.to_string())?,
        }
        Ok(())
    }

    /// The generation directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Publishes the generation (after every one of its outputs is complete): the per-pair parts
    /// are removed, every output's path in `OUT/` becomes a link through [`CURRENT`] (once), and
    /// `OUT/.current` is switched to this generation in one rename. Then the outputs this
    /// generation does not hold, and the generations replaced, are removed.
    pub fn publish(&self) -> Result<(), String> {
        if let Ok(entries) = std::fs::read_dir(&self.dir) {
            for e in entries.filter_map(|e| e.ok()) {
                if e.file_name().to_string_lossy().starts_with("part-") {
                    let _ = std::fs::remove_file(e.path());
                }
            }
        }
        let held: Vec<&str> = GENERATION_NAMES
            .iter()
            .copied()
            .filter(|n| std::fs::symlink_metadata(self.dir.join(n)).is_ok())
            .collect();
        self.switch(&held)?;
        self.published.store(true, Ordering::Relaxed);
        Ok(())
    }

    #[cfg(unix)]
    fn switch(&self, held: &[&str]) -> Result<(), String> {
        let out = &self.out;
        let pid = std::process::id();
        let cannot = |what: &Path, e: std::io::Error| {
            format!("cannot publish the outputs in `{}`: {e}", what.display())
        };
        for name in held {
            link_through_current(out, name).map_err(|e| cannot(&out.join(name), e))?;
        }
        let previous = current_generation(out);
        let generation = self
            .dir
            .file_name()
            .map(PathBuf::from)
            .ok_or_else(|| format!("`{}`: no directory name", self.dir.display()))?;
        let tmp = out.join(format!("{CURRENT}.tmp{pid}"));
        let _ = std::fs::remove_file(&tmp);
        std::os::unix::fs::symlink(&generation, &tmp).map_err(|e| cannot(&tmp, e))?;
        let current = out.join(CURRENT);
        if let Err(e) = std::fs::rename(&tmp, &current) {
            let _ = std::fs::remove_file(&tmp);
            return Err(cannot(&current, e));
        }
        if let Ok(d) = std::fs::File::open(out) {
            let _ = d.sync_all();
        }
        // What the new set does not hold is not part of it.
        for name in GENERATION_NAMES.iter().filter(|n| !held.contains(n)) {
            let path = out.join(name);
            match std::fs::symlink_metadata(&path) {
                Ok(m) if m.is_dir() => {
                    let _ = std::fs::remove_dir_all(&path);
                }
                Ok(_) => {
                    let _ = std::fs::remove_file(&path);
                }
                Err(_) => {}
            }
        }
        // The generations replaced (files already open in them stay readable).
        let this = generation.to_string_lossy().into_owned();
        if let Ok(entries) = std::fs::read_dir(out) {
            for e in entries.filter_map(|e| e.ok()) {
                let name = e.file_name().to_string_lossy().into_owned();
                let old = name.starts_with(STAGING_PREFIX)
                    && name != this
                    && (previous.as_deref() == Some(name.as_str())
                        || owner_pid(&name).is_some_and(|p| p == pid || !alive(p)));
                if old {
                    let _ = std::fs::remove_dir_all(e.path());
                }
            }
        }
        Ok(())
    }

    #[cfg(not(unix))]
    fn switch(&self, held: &[&str]) -> Result<(), String> {
        for name in held {
            let (from, to) = (self.dir.join(name), self.out.join(name));
            if to.is_dir() {
                let _ = std::fs::remove_dir_all(&to);
            }
            std::fs::rename(&from, &to)
                .map_err(|e| format!("cannot move `{}` into place: {e}", to.display()))?;
        }
        Ok(())
    }
}

/// Makes `out/name` the link `.current/name` unless it already is (an output of an older
/// version, a file or directory, is replaced).
#[cfg(unix)]
fn link_through_current(out: &Path, name: &str) -> std::io::Result<()> {
    let path = out.join(name);
    let target = Path::new(CURRENT).join(name);
    if std::fs::read_link(&path).is_ok_and(|t| t == target) {
        return Ok(());
    }
    let pid = std::process::id();
    let tmp = out.join(format!(".{name}.tmp{pid}"));
    let _ = std::fs::remove_file(&tmp);
    std::os::unix::fs::symlink(&target, &tmp)?;
    if std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_dir()) {
        let old = out.join(format!(".{name}.old.tmp{pid}"));
        std::fs::rename(&path, &old)?;
        let _ = std::fs::remove_dir_all(&old);
    }
    std::fs::rename(&tmp, &path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.published.load(Ordering::Relaxed) {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn owner_pids_of_temporary_names() {
        assert_eq!(owner_pid(".staging-4242-0"), Some(4242));
        assert_eq!(owner_pid(".x.json.4242-17.tmp"), Some(4242));
        assert_eq!(owner_pid(".predictions.pkl.tmp4242"), Some(4242));
        assert_eq!(owner_pid("predictions.pkl"), None);
        assert_eq!(owner_pid(".hidden"), None);
    }

    #[test]
    fn orphans_of_dead_processes_are_removed_and_live_ones_kept() {
        let dir = tempfile_dir("orphans");
        // pid 0 is never a user process with a /proc entry of its own; ours is alive.
        let dead = dir.join(".staging-0-3");
        std::fs::create_dir_all(&dead).unwrap();
        std::fs::write(dead.join("part-0.pkl"), b"x").unwrap();
        std::fs::write(dir.join(".predictions.pkl.tmp0"), b"x").unwrap();
        std::fs::create_dir_all(dir.join("pairs/log")).unwrap();
        std::fs::write(dir.join("pairs/log/.p.json.0-1.tmp"), b"x").unwrap();
        let live = dir.join(format!(".m.json.{}-1.tmp", std::process::id()));
        std::fs::write(&live, b"x").unwrap();
        std::fs::write(dir.join("predictions.pkl"), b"keep").unwrap();
        clean_orphans(&dir);
        assert!(!dead.exists());
        assert!(!dir.join(".predictions.pkl.tmp0").exists());
        assert!(!dir.join("pairs/log/.p.json.0-1.tmp").exists());
        assert!(live.exists());
        assert!(dir.join("predictions.pkl").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The text of every output of the set as a reader sees it through `OUT/`.
    fn visible(out: &Path) -> Vec<(&'static str, Option<String>)> {
        [
            PREDICTIONS_PICKLE,
            PREDICTIONS_TABLE,
            MATCHES_JSON,
            SUMMARY_JSON,
            SCORED_PICKLE,
        ]
        .into_iter()
        .map(|n| (n, std::fs::read_to_string(out.join(n)).ok()))
        .collect()
    }

    /// A generation holding the four outputs of a run, each reading `tag`.
    fn generation(out: &Path, tag: &str, scored: bool) -> Staging {
        let g = Staging::new(out).unwrap();
        std::fs::write(g.path("part-0.pkl"), b"part").unwrap();
        for n in [
            PREDICTIONS_PICKLE,
            PREDICTIONS_TABLE,
            MATCHES_JSON,
            SUMMARY_JSON,
        ] {
            std::fs::write(g.path(n), tag).unwrap();
        }
        if scored {
            std::fs::write(g.path(SCORED_PICKLE), tag).unwrap();
        }
        g
    }

    /// Whatever step a run stops at, a reader sees one whole set: the previous one until the
    /// switch, the new one after; an output the new run does not make is not left from the old.
    #[cfg(unix)]
    #[test]
    fn a_run_stopped_at_any_step_never_leaves_a_mixed_set() {
        let out = tempfile_dir("generations");
        let set = |tag: &str, scored: bool| {
            let mut v: Vec<(&str, Option<String>)> = [
                PREDICTIONS_PICKLE,
                PREDICTIONS_TABLE,
                MATCHES_JSON,
                SUMMARY_JSON,
            ]
            .into_iter()
            .map(|n| (n, Some(tag.to_string())))
            .collect();
            v.push((SCORED_PICKLE, scored.then(|| tag.to_string())));
            v.sort();
            v
        };
        let seen = |out: &Path| {
            let mut v = visible(out);
            v.sort();
            v
        };
        // An output of an older version (a plain file) is taken over by the first generation.
        std::fs::write(out.join(PREDICTIONS_PICKLE), "old").unwrap();
        std::fs::create_dir_all(out.join(REPORT_DIR)).unwrap();
        std::fs::write(out.join(REPORT_DIR).join("index.html"), "old").unwrap();
        generation(&out, "A", true).publish().unwrap();
        assert_eq!(seen(&out), set("A", true));
        assert!(!out.join(REPORT_DIR).exists(), "run A made no report");

        // Run B stops after writing its outputs (killed before publishing): A stays whole.
        let b = generation(&out, "B", false);
        assert_eq!(seen(&out), set("A", true));
        drop(b);
        assert_eq!(seen(&out), set("A", true));

        // Run C stops half-way through making the links (before the switch): still A.
        let c = generation(&out, "C", false);
        link_through_current(&out, MATCHES_JSON).unwrap();
        assert_eq!(seen(&out), set("A", true));
        // ... and publishes: all of C, A's scored pickle gone with A.
        c.publish().unwrap();
        assert_eq!(seen(&out), set("C", false));
        let dirs: Vec<String> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with(STAGING_PREFIX))
            .collect();
        assert_eq!(
            dirs,
            vec![current_generation(&out).unwrap()],
            "one generation kept"
        );
        let parts = std::fs::read_dir(out.join(CURRENT)).unwrap().count();
        assert_eq!(
            parts, 4,
            "the parts are not kept in the published generation"
        );

        // A killed run's generation and temporary link: removed by the next run, the
        // published generation kept.
        let dead = out.join(format!("{STAGING_PREFIX}0-9"));
        std::fs::create_dir_all(&dead).unwrap();
        std::fs::write(dead.join(PREDICTIONS_PICKLE), "D").unwrap();
        std::os::unix::fs::symlink(".current/x", out.join(".current.tmp0")).unwrap();
        clean_orphans(&out);
        assert!(!dead.exists());
        assert!(std::fs::symlink_metadata(out.join(".current.tmp0")).is_err());
        assert_eq!(seen(&out), set("C", false));
        std::fs::remove_dir_all(&out).unwrap();
    }

    fn tempfile_dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("scenalog-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

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
