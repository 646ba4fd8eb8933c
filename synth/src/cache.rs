//! The on-disk completion cache: one JSON file per request, named by the SHA-256 of the model and
//! the messages, written atomically (temporary file, then rename) before the completion is used,
//! so a rerun asks the server nothing it has answered and a crash loses no answer.

use std::fs;
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use crate::client::Message;
use crate::SynthError;

/// A directory of cached completions.
#[derive(Debug, Clone)]
pub struct Cache {
    dir: PathBuf,
}

impl Cache {
    /// Opens the cache in `dir`, creating the directory if needed.
    pub fn open(dir: &Path) -> Result<Cache, SynthError> {
        fs::create_dir_all(dir).map_err(|e| SynthError::io(dir, e))?;
        Ok(Cache {
            dir: dir.to_path_buf(),
        })
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The key of a request: hex SHA-256 of the JSON `{"model": …, "messages": […]}`.
    pub fn key(model: &str, messages: &[Message]) -> String {
        Cache::sample_key(model, messages, 0)
    }

    /// The key of candidate `sample` of a search (sample 0 is [`Cache::key`]'s, so one candidate
    /// reads the completions cached before searches existed; each other sample has its own).
    pub fn sample_key(model: &str, messages: &[Message], sample: usize) -> String {
        let mut canonical = serde_json::json!({ "model": model, "messages": messages });
        if sample > 0 {
            canonical["sample"] = serde_json::json!(sample);
        }
        let canonical = canonical.to_string();
        let digest = Sha256::digest(canonical.as_bytes());
        digest.iter().map(|b| format!("{b:02x}")).collect()
    }

    fn path(&self, key: &str) -> PathBuf {
        self.dir.join(format!("{key}.json"))
    }

    /// The cached completion for `key`, if there is a readable entry. A corrupt entry is
    /// treated as missing (and replaced by the next [`Cache::put`]).
    pub fn get(&self, key: &str) -> Option<String> {
        let text =
            scenalog_input::read_text_file(&self.path(key), scenalog_input::TEXT_LIMIT).ok()?;
        let v: serde_json::Value = serde_json::from_str(&text).ok()?;
        v.get("completion")?.as_str().map(str::to_string)
    }

    /// Stores a completion with its request, atomically.
    pub fn put(
        &self,
        key: &str,
        model: &str,
        messages: &[Message],
        completion: &str,
    ) -> Result<(), SynthError> {
        let entry = serde_json::json!({
            "model": model,
            "messages": messages,
            "completion": completion,
        });
        let text = serde_json::to_string_pretty(&entry).unwrap_or_else(|_| entry.to_string());
        write_atomic(&self.path(key), text.as_bytes())
    }
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename, so
/// `path` holds either its old content or all of the new.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), SynthError> {
    scenalog_input::out_dir::write_atomic(path, bytes, true).map_err(|e| SynthError::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_depend_on_model_and_every_message() {
        let m = vec![Message::system("s"), Message::user("u")];
        let k = Cache::key("a", &m);
        assert_eq!(k.len(), 64);
        assert_eq!(k, Cache::key("a", &m));
        assert_ne!(k, Cache::key("b", &m));
        assert_ne!(
            k,
            Cache::key("a", &[Message::system("s"), Message::user("v")])
        );
        assert_ne!(k, Cache::key("a", &m[..1]));
    }

    #[test]
    fn put_then_get_and_corrupt_entries_are_misses() {
        let dir = tempfile::tempdir().expect("tempdir");
        let cache = Cache::open(&dir.path().join("c")).expect("open");
        let m = vec![Message::user("u")];
        let k = Cache::key("m", &m);
        assert_eq!(cache.get(&k), None);
        cache.put(&k, "m", &m, "answer").expect("put");
        assert_eq!(cache.get(&k).as_deref(), Some("answer"));
        fs::write(cache.path(&k), "{ truncated").expect("write");
        assert_eq!(cache.get(&k), None);
        cache.put(&k, "m", &m, "again").expect("put");
        assert_eq!(cache.get(&k).as_deref(), Some("again"));
        // No temporary file is left behind.
        let names: Vec<_> = fs::read_dir(cache.dir())
            .expect("read_dir")
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, vec![format!("{k}.json")]);
    }
}
