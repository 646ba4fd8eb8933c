//! RefAV's per-log colour cache: what its `is_color` reads.
//!
//! RefAV (CainanD/RefAV 5c5be64, `refAV/utils.py`, `construct_caches`) classifies each track's
//! best camera crop offline with SigLIP2 (`google/siglip2-so400m-patch16-naflex`, zero-shot
//! over "a {colour} object" for white, silver, black, red, yellow and blue) and writes the log's
//! answers to `<log dir>/cache/color_cache.json`: one JSON object from track uuid to the colour
//! word, or `null` for a track with no usable crop. Its `is_color(objects, log_dir, color)`
//! then drops an object only when the cache is present and not empty, holds the object's uuid,
//! and holds `null` or another colour for it; every other object is kept at all its
//! timestamps (so without a cache, or for a track the cache lacks, `is_color` keeps
//! everything). A file RefAV cannot read it ignores silently; here it is an error for the
//! programs that ask for colours ([`ColorCache::Unreadable`]), never a quiet answer.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::ids::TrackId;

/// The colours RefAV's classifier chooses from (`possible_colors`), in its order.
pub const REFAV_COLORS: &[&str] = &["white", "silver", "black", "red", "yellow", "blue"];

/// `refav_color`'s value for a track the cache holds `null` for (no usable crop).
pub const NO_COLOR: &str = "none";

/// Where a log keeps RefAV's colour cache, relative to the log directory.
pub const COLOR_CACHE_FILE: &str = "cache/color_cache.json";

/// The most bytes of a colour cache read (a log's cache is a few tens of kilobytes).
pub const COLOR_CACHE_LIMIT: u64 = 64 << 20;

/// RefAV's colour cache of one log, as read.
#[derive(Debug, Clone, Default, PartialEq)]
pub enum ColorCache {
    /// The log has no cache file, or an empty one (`{}`), which RefAV takes as none.
    #[default]
    Absent,
    /// The cache's entry for each of the log's tracks it holds: the colour word, or `None`
    /// where it holds `null`. Uuids of other logs' tracks are left out.
    Read {
        /// The file read.
        path: PathBuf,
        /// Per track: its colour, `None` for `null`.
        colors: BTreeMap<TrackId, Option<String>>,
    },
    /// The file exists but cannot be read as RefAV writes it; the message names it and says why.
    Unreadable(String),
}

/// Reads `log_dir/cache/color_cache.json` for the tracks of `track_of` (uuid to track id).
pub fn read_color_cache(log_dir: &Path, track_of: impl Fn(&str) -> Option<TrackId>) -> ColorCache {
    let path = log_dir.join(COLOR_CACHE_FILE);
    let bytes = match scenalog_input::read_regular_file(&path, COLOR_CACHE_LIMIT) {
        Ok(b) => b,
        Err(scenalog_input::FileProblem::NotFound) => return ColorCache::Absent,
        Err(e) => return ColorCache::Unreadable(format!("`{}` {e}", path.display())),
    };
    match parse_color_cache(&bytes, track_of) {
        Ok(None) => ColorCache::Absent,
        Ok(Some(colors)) => ColorCache::Read { path, colors },
        Err(e) => ColorCache::Unreadable(format!("`{}`: {e}", path.display())),
    }
}

/// The cache's entries for known tracks from the file's bytes; `None` for an empty object.
fn parse_color_cache(
    bytes: &[u8],
    track_of: impl Fn(&str) -> Option<TrackId>,
) -> Result<Option<BTreeMap<TrackId, Option<String>>>, String> {
    let value: serde_json::Value = serde_json::from_slice(bytes)
        .map_err(|e| format!("not JSON ({e}); RefAV writes an object of track uuid to colour"))?;
    let serde_json::Value::Object(entries) = value else {
        return Err("not a JSON object of track uuid to colour".into());
    };
    if entries.is_empty() {
        return Ok(None);
    }
    let mut colors = BTreeMap::new();
    for (uuid, v) in entries {
        let color = match v {
            serde_json::Value::String(s) if REFAV_COLORS.contains(&s.as_str()) => Some(s),
            serde_json::Value::String(s) => {
                return Err(format!(
                    "the entry of `{uuid}` is \"{s}\", not one of RefAV's colours ({})",
                    REFAV_COLORS.join(", ")
                ))
            }
            serde_json::Value::Null => None,
            other => {
                return Err(format!(
                    "the entry of `{uuid}` is {other}, not a colour word or null"
                ))
            }
        };
        if let Some(t) = track_of(&uuid) {
            colors.insert(t, color);
        }
    }
    Ok(Some(colors))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Option<BTreeMap<TrackId, Option<String>>>, String> {
        parse_color_cache(text.as_bytes(), |u| match u {
            "a" => Some(TrackId(0)),
            "b" => Some(TrackId(1)),
            _ => None,
        })
    }

    #[test]
    fn entries_of_known_tracks_are_kept_with_null_as_none() {
        let got = parse(r#"{"a": "red", "b": null, "other-log": "blue"}"#);
        let want: BTreeMap<TrackId, Option<String>> =
            [(TrackId(0), Some("red".into())), (TrackId(1), None)].into();
        assert_eq!(got, Ok(Some(want)));
        assert_eq!(parse("{}"), Ok(None));
    }

    #[test]
    fn what_refav_does_not_write_is_an_error_naming_why() {
        for (text, why) in [
            ("[1, 2]", "not a JSON object"),
            ("{\"a\": 3}", "not a colour word or null"),
            ("{\"a\": \"green\"}", "not one of RefAV's colours"),
            ("{\"a\": ", "not JSON"),
        ] {
            let e = parse(text).expect_err(text);
            assert!(e.contains(why), "{text}: {e}");
        }
    }

    #[test]
    fn arbitrary_bytes_never_panic() {
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        for len in 0..300 {
            let bytes: Vec<u8> = (0..len)
                .map(|_| {
                    seed ^= seed << 13;
                    seed ^= seed >> 7;
                    seed ^= seed << 17;
                    b"{}[]\":,nul redab0\\"[(seed % 18) as usize]
                })
                .collect();
            let _ = parse_color_cache(&bytes, |_| Some(TrackId(0)));
        }
    }
}
