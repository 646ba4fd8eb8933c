//! Per-track attributes from outside the log: what a camera and a model can say about a track
//! and the boxes and map cannot ("ambulance", "construction worker", "red"), read per log and
//! joined as the relation `attribute(X, Name, Score)`.
//!
//! The file is `<log dir>/attributes.csv`: a CSV file with a header row naming at least the
//! columns `track_uuid` (a track of the log), `name` (the attribute, any text: a word or a
//! phrase) and `score` (the model's confidence in `[0, 1]`), in any order; other columns (an
//! index pandas writes, a model name) are ignored. pandas writes one with
//! `df[["track_uuid", "name", "score"]].to_csv("attributes.csv", index=False)`. A track may have
//! several rows, one a name; a row of a track the log does not have is left out, but a file
//! none of whose rows names a track of the log is an error (it belongs to another log).
//!
//! RefAV's colour cache ([`crate::color`]) is a second source: each colour it holds is an
//! attribute of that name with score 1 (it keeps no scores); a track it holds `null` for has
//! none. A log with neither has no attributes, and `mine` says so once.

use std::path::{Path, PathBuf};

use crate::ids::TrackId;

/// Where a log keeps its attributes file, relative to the log directory.
pub const ATTRIBUTES_FILE: &str = "attributes.csv";

/// The most bytes of an attributes file read.
pub const ATTRIBUTES_LIMIT: u64 = 256 << 20;

/// The columns an attributes file must have.
pub const ATTRIBUTE_COLUMNS: [&str; 3] = ["track_uuid", "name", "score"];

/// One attribute of one track.
#[derive(Debug, Clone, PartialEq)]
pub struct Attribute {
    /// The track.
    pub track: TrackId,
    /// What is said of it.
    pub name: String,
    /// How sure the model is, in `[0, 1]`.
    pub score: f64,
}

/// A log's attributes file, as read.
#[derive(Debug, Clone, Default, PartialEq)]
pub enum Attributes {
    /// The log has no attributes file.
    #[default]
    Absent,
    /// The rows of the log's tracks, in file order.
    Read {
        /// The file read.
        path: PathBuf,
        /// Its rows naming tracks of the log.
        rows: Vec<Attribute>,
    },
    /// The file exists but cannot be read; the message names it and says why.
    Unreadable(String),
}

/// Reads `log_dir/attributes.csv` for the tracks of `track_of` (uuid to track id).
pub fn read_attributes(log_dir: &Path, track_of: impl Fn(&str) -> Option<TrackId>) -> Attributes {
    let path = log_dir.join(ATTRIBUTES_FILE);
    let bytes = match scenalog_input::read_regular_file(&path, ATTRIBUTES_LIMIT) {
        Ok(b) => b,
        Err(scenalog_input::FileProblem::NotFound) => return Attributes::Absent,
        Err(e) => return Attributes::Unreadable(format!("`{}` {e}", path.display())),
    };
    match parse_attributes(&bytes, track_of) {
        Ok(rows) => Attributes::Read { path, rows },
        Err(e) => Attributes::Unreadable(format!("`{}`: {e}", path.display())),
    }
}

/// The rows of known tracks from the file's bytes.
fn parse_attributes(
    bytes: &[u8],
    track_of: impl Fn(&str) -> Option<TrackId>,
) -> Result<Vec<Attribute>, String> {
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_reader(bytes);
    let header = reader
        .headers()
        .map_err(|e| format!("no CSV header row ({e})"))?
        .clone();
    let column = |name: &str| -> Result<usize, String> {
        let mut at = header.iter().enumerate().filter(|(_, h)| *h == name);
        match (at.next(), at.next()) {
            (Some((i, _)), None) => Ok(i),
            (Some(_), Some(_)) => Err(format!("the header names `{name}` twice")),
            (None, _) => Err(format!(
                "the header ({}) has no `{name}` column; an attributes file has the columns {}",
                header.iter().collect::<Vec<_>>().join(", "),
                ATTRIBUTE_COLUMNS.join(", ")
            )),
        }
    };
    let (uuid_at, name_at, score_at) = (column("track_uuid")?, column("name")?, column("score")?);
    let (mut rows, mut seen) = (Vec::new(), 0usize);
    for (k, record) in reader.records().enumerate() {
        // Line numbers as an editor shows them: the header is line 1.
        let line = k + 2;
        let record = record.map_err(|e| format!("line {line}: {e}"))?;
        let field = |i: usize| record.get(i).unwrap_or("");
        let (uuid, name, score) = (field(uuid_at), field(name_at), field(score_at));
        if uuid.is_empty() {
            return Err(format!("line {line}: the track_uuid is empty"));
        }
        if name.is_empty() {
            return Err(format!("line {line}: the name is empty"));
        }
        let score: f64 = score
            .parse()
            .map_err(|_| format!("line {line}: the score `{score}` is not a number"))?;
        if !(0.0..=1.0).contains(&score) {
            return Err(format!(
                "line {line}: the score {score} is not in [0, 1] (a confidence, not a logit)"
            ));
        }
        seen += 1;
        if let Some(track) = track_of(uuid) {
            rows.push(Attribute {
                track,
                name: name.to_string(),
                score,
            });
        }
    }
    if seen > 0 && rows.is_empty() {
        return Err(format!(
            "none of its {seen} rows names a track of this log (is it another log's file?)"
        ));
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Vec<(u32, String, f64)>, String> {
        let rows = parse_attributes(text.as_bytes(), |u| match u {
            "a" => Some(TrackId(0)),
            "b" => Some(TrackId(1)),
            _ => None,
        })?;
        Ok(rows
            .into_iter()
            .map(|r| (r.track.0, r.name, r.score))
            .collect())
    }

    #[test]
    fn rows_of_known_tracks_in_any_column_order() {
        let got = parse("score,track_uuid,name\n0.9,a,ambulance\n0.25,b,red\n1,other,red\n");
        assert_eq!(
            got,
            Ok(vec![(0, "ambulance".into(), 0.9), (1, "red".into(), 0.25)])
        );
    }

    #[test]
    fn files_as_pandas_and_spreadsheets_write_them() {
        // pandas with its index, a quoted name with a comma, Windows line ends, a BOM.
        let pandas = ",track_uuid,name,score,model\n0,a,\"worker, construction\",0.8,vlm\n";
        assert_eq!(
            parse(pandas),
            Ok(vec![(0, "worker, construction".into(), 0.8)])
        );
        let excel = "\u{feff}track_uuid,name,score\r\na,police car,0.5\r\n";
        assert_eq!(parse(excel), Ok(vec![(0, "police car".into(), 0.5)]));
        assert_eq!(parse("track_uuid,name,score\n"), Ok(vec![]));
    }

    #[test]
    fn what_is_not_an_attributes_file_is_an_error_naming_why() {
        for (text, why) in [
            ("", "no `track_uuid` column"),
            ("uuid,name,score\na,x,1\n", "no `track_uuid` column"),
            (
                "track_uuid,name,score,name\na,x,1,y\n",
                "names `name` twice",
            ),
            (
                "track_uuid,name,score\na,x,high\n",
                "line 2: the score `high`",
            ),
            ("track_uuid,name,score\na,x,3.5\n", "not in [0, 1]"),
            ("track_uuid,name,score\na,x,NaN\n", "not in [0, 1]"),
            (
                "track_uuid,name,score\na,,0.5\n",
                "line 2: the name is empty",
            ),
            ("track_uuid,name,score\na,x\n", "line 2"),
            ("track_uuid,name,score\nz,x,0.5\n", "none of its 1 rows"),
        ] {
            let e = parse(text).expect_err(text);
            assert!(e.contains(why), "{text:?}: {e}");
        }
    }

    #[test]
    fn arbitrary_bytes_never_panic() {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let alphabet = b"ab,\"\n\r01.5 track_uuidnamescore\xff";
        for len in 0..400 {
            let bytes: Vec<u8> = (0..len)
                .map(|_| {
                    seed ^= seed << 13;
                    seed ^= seed >> 7;
                    seed ^= seed << 17;
                    alphabet[(seed % alphabet.len() as u64) as usize]
                })
                .collect();
            let _ = parse_attributes(&bytes, |_| Some(TrackId(0)));
            let mut with_header = b"track_uuid,name,score\n".to_vec();
            with_header.extend(&bytes);
            let _ = parse_attributes(&with_header, |_| Some(TrackId(0)));
        }
    }
}
