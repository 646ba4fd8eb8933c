//! The AV2 3D-tracking submission pickle: `{log_id: [frame, …]}`, parsed once and decoded one log
//! at a time (a log's frames are decoded when asked for, so memory holds the raw file and one
//! log's detections).

use std::collections::BTreeMap;
use std::path::Path;

use scenalog_eval::Pickle;

use crate::error::TrackerError;
use crate::frames::{decode_frame, Detections, REQUIRED_FIELDS};

/// A parsed tracking pickle.
pub struct TrackerPickle {
    pickle: Pickle,
    /// Log id → the arena position of its frame list (as the pickle's root dict item index).
    logs: BTreeMap<String, usize>,
    file: String,
}

impl TrackerPickle {
    /// Reads and parses a tracking pickle file; the error says why it is not one (unreadable,
    /// not a pickle, not `{log_id: [frame dict, …]}`, frames without the tracking fields).
    pub fn open(path: &Path) -> Result<TrackerPickle, TrackerError> {
        let file = path.display().to_string();
        let data = scenalog_input::read_file_checking_ends(
            path,
            scenalog_input::DATA_LIMIT,
            &scenalog_eval::dict_pickle_ends,
        )
        .map_err(|problem| TrackerError::file(&file, problem.to_string()))?;
        Self::from_bytes(&data, &file)
    }

    /// Parses tracking-pickle bytes; `file` names them in errors.
    pub fn from_bytes(data: &[u8], file: &str) -> Result<TrackerPickle, TrackerError> {
        let pickle = scenalog_eval::parse_pickle_dict(data, file)
            .map_err(|e| TrackerError::file(file, format!("not a readable pickle: {e}")))?;
        let not_format = |m: String| {
            TrackerError::file(
                file,
                format!("not the AV2 3D-tracking format ({{log_id: [frame dict, …]}}): {m}"),
            )
        };
        let root = pickle.root();
        let items = root
            .dict()
            .ok_or_else(|| not_format(format!("the top level is a {}", root.kind())))?;
        let mut logs = BTreeMap::new();
        for (i, (k, v)) in items.iter().enumerate() {
            let Some(log) = k.str() else {
                return Err(not_format(format!("a key is a {}, not a log id", k.kind())));
            };
            scenalog_input::check_log_id(log).map_err(not_format)?;
            let frames = v
                .items()
                .ok_or_else(|| not_format(format!("log {log} holds a {}, not a list", v.kind())))?;
            if let Some(first) = frames.first() {
                let keys: Vec<&str> = first
                    .dict()
                    .map(|d| d.iter().filter_map(|(k, _)| k.str()).collect())
                    .unwrap_or_default();
                if let Some(missing) = REQUIRED_FIELDS.iter().find(|f| !keys.contains(f)) {
                    return Err(not_format(format!(
                        "log {log} frame 0 has no field {missing:?}"
                    )));
                }
            }
            if logs.insert(log.to_string(), i).is_some() {
                return Err(not_format(format!("log {log} appears twice")));
            }
        }
        drop(items);
        Ok(TrackerPickle {
            pickle,
            logs,
            file: file.to_string(),
        })
    }

    /// The file it was read from.
    pub fn file(&self) -> &str {
        &self.file
    }

    /// The log ids, sorted.
    pub fn log_ids(&self) -> impl Iterator<Item = &str> {
        self.logs.keys().map(|s| s.as_str())
    }

    /// Whether the pickle has this log.
    pub fn contains(&self, log_id: &str) -> bool {
        self.logs.contains_key(log_id)
    }

    /// The decoded, validated frames of one log, in the file's order; the error names the log,
    /// frame and field.
    pub fn frames(&self, log_id: &str) -> Result<Vec<Detections>, TrackerError> {
        let Some(&i) = self.logs.get(log_id) else {
            return Err(TrackerError::log(
                &self.file,
                log_id,
                "not in the tracker file",
            ));
        };
        let items = self
            .pickle
            .root()
            .dict()
            .ok_or_else(|| TrackerError::file(&self.file, "the top level is not a dict"))?;
        let frames = items
            .get(i)
            .and_then(|(_, v)| v.items())
            .ok_or_else(|| TrackerError::log(&self.file, log_id, "not a list of frames"))?;
        frames
            .iter()
            .enumerate()
            .map(|(f, node)| decode_frame(*node, &self.file, log_id, f))
            .collect()
    }
}
