//! Why reading a log failed: every error names the file (and the column, row or field) and says
//! what was expected.

use std::path::PathBuf;

/// An error reading an Argoverse 2 log directory with [`crate::read::load_scene`].
///
/// The `Display` text always starts with the path of the offending file (or directory), so it can
/// be printed as is.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// A file or directory the log needs is not there.
    #[error("{}: not found; expected {expected}", path.display())]
    MissingFile {
        /// The path that was looked for.
        path: PathBuf,
        /// What should have been there.
        expected: &'static str,
    },
    /// Something is at the path but it is not a regular file (a directory where a file was
    /// expected, a FIFO, a socket, a device; or a file where the log directory was expected).
    #[error("{}: {what}", path.display())]
    NotRegularFile {
        /// The path.
        path: PathBuf,
        /// What it is and what was expected, e.g. "is a FIFO (named pipe), not a regular file",
        /// or why it was not read ("is too large …").
        what: String,
    },
    /// A file or directory exists but could not be read: permission denied, a symlink loop, an
    /// I/O error (the message says which).
    #[error("{}: cannot read: {}", path.display(), scenalog_input::file::describe_io(source))]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A `.feather` file is not a readable Arrow IPC file.
    #[error("{}: not a readable Arrow IPC (feather v2) file: {reason}", path.display())]
    NotArrow {
        /// The file.
        path: PathBuf,
        /// What the Arrow reader reported.
        reason: String,
    },
    /// A column the reader needs is absent.
    #[error("{}: no column `{column}`; expected a {expected} column `{column}`", path.display())]
    MissingColumn {
        /// The file.
        path: PathBuf,
        /// The column's name.
        column: &'static str,
        /// The expected type, e.g. "int64".
        expected: &'static str,
    },
    /// A column has the wrong Arrow type.
    #[error("{}: column `{column}` has type {found}; expected {expected}", path.display())]
    ColumnType {
        /// The file.
        path: PathBuf,
        /// The column's name.
        column: &'static str,
        /// The expected type, e.g. "int64".
        expected: &'static str,
        /// The Arrow type found.
        found: String,
    },
    /// A column holds a null.
    #[error("{}: column `{column}` row {row} is null; expected a value", path.display())]
    Null {
        /// The file.
        path: PathBuf,
        /// The column's name.
        column: &'static str,
        /// The 0-based row over the whole file.
        row: usize,
    },
    /// A pose or box number is NaN or infinite.
    #[error("{}: column `{column}` row {row} is {value}; expected a finite number", path.display())]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// The column's name.
        column: &'static str,
        /// The 0-based row over the whole file.
        row: usize,
        /// The value found.
        value: f64,
    },
    /// A quaternion (qw, qx, qy, qz) has (near) zero length and names no rotation.
    #[error(
        "{}: row {row}: quaternion (qw, qx, qy, qz) has length {norm}; expected a rotation (length 1)",
        path.display()
    )]
    BadQuaternion {
        /// The file.
        path: PathBuf,
        /// The 0-based row over the whole file.
        row: usize,
        /// The quaternion's length.
        norm: f64,
    },
    /// Two annotation rows for the same track and timestamp.
    #[error(
        "{}: track `{track}` has two rows at timestamp_ns {timestamp_ns} (rows {first_row} and {second_row}); expected at most one row per (track_uuid, timestamp_ns)",
        path.display()
    )]
    DuplicateRow {
        /// The annotations file.
        path: PathBuf,
        /// The track uuid.
        track: String,
        /// The timestamp both rows have.
        timestamp_ns: i64,
        /// The first row (0-based).
        first_row: usize,
        /// The second row (0-based).
        second_row: usize,
    },
    /// One track uuid with two different categories.
    #[error(
        "{}: column `category`: track `{track}` is `{first}` in row {first_row} but `{second}` in row {second_row}; expected one category per track",
        path.display()
    )]
    MixedCategory {
        /// The annotations file.
        path: PathBuf,
        /// The track uuid.
        track: String,
        /// The category first seen.
        first: String,
        /// The row it was seen in.
        first_row: usize,
        /// The other category.
        second: String,
        /// The row it was seen in.
        second_row: usize,
    },
    /// More than one track has the category EGO_VEHICLE.
    #[error(
        "{}: column `category`: tracks `{first}` and `{second}` are both EGO_VEHICLE; expected at most one ego track",
        path.display()
    )]
    SeveralEgoTracks {
        /// The annotations file.
        path: PathBuf,
        /// One ego uuid.
        first: String,
        /// Another ego uuid.
        second: String,
    },
    /// A plain annotations file uses the uuid reserved for the ego track the reader adds.
    #[error(
        "{}: column `track_uuid`: a `{category}` track uses the uuid `{uuid}`, which is reserved for the ego track added to logs without ego rows",
        path.display()
    )]
    ReservedUuid {
        /// The annotations file.
        path: PathBuf,
        /// The reserved uuid.
        uuid: &'static str,
        /// The category of the track that uses it.
        category: String,
    },
    /// An annotation timestamp has no ego pose with exactly that timestamp.
    #[error(
        "{}: column `timestamp_ns`: no ego pose at {timestamp_ns}, which is an annotation timestamp of {}; expected a pose at every annotation timestamp",
        path.display(),
        annotations.display()
    )]
    NoEgoPose {
        /// The ego pose file.
        path: PathBuf,
        /// The annotations file the timestamp comes from.
        annotations: PathBuf,
        /// The timestamp without a pose.
        timestamp_ns: i64,
    },
    /// The ego pose file has two rows with the same timestamp.
    #[error(
        "{}: column `timestamp_ns`: {timestamp_ns} appears in rows {first_row} and {second_row}; expected distinct timestamps",
        path.display()
    )]
    DuplicatePoseTimestamp {
        /// The ego pose file.
        path: PathBuf,
        /// The repeated timestamp.
        timestamp_ns: i64,
        /// One row (0-based).
        first_row: usize,
        /// Another row (0-based).
        second_row: usize,
    },
    /// The map JSON is malformed: not JSON, a missing field, a wrong type or value.
    #[error("{}: field `{field}`: {message}", path.display())]
    MapJson {
        /// The map file.
        path: PathBuf,
        /// Where in the document, e.g. `lane_segments.37979824.lane_type` (`.` for the whole file).
        field: String,
        /// What was wrong and what was expected.
        message: String,
    },
    /// The log has no vector map file.
    #[error("{}: no vector map; expected a file map/log_map_archive_*.json", path.display())]
    NoMapFile {
        /// The log directory.
        path: PathBuf,
    },
    /// The log has more than one vector map file.
    #[error(
        "{}: several vector maps ({first}, {second}); expected one map/log_map_archive_*.json",
        path.display()
    )]
    SeveralMapFiles {
        /// The map directory.
        path: PathBuf,
        /// One map file name.
        first: String,
        /// Another map file name.
        second: String,
    },
}

impl LoadError {
    /// The file (or directory) the error is about.
    pub fn path(&self) -> &std::path::Path {
        match self {
            LoadError::MissingFile { path, .. }
            | LoadError::Io { path, .. }
            | LoadError::NotRegularFile { path, .. }
            | LoadError::NotArrow { path, .. }
            | LoadError::MissingColumn { path, .. }
            | LoadError::ColumnType { path, .. }
            | LoadError::Null { path, .. }
            | LoadError::NonFinite { path, .. }
            | LoadError::BadQuaternion { path, .. }
            | LoadError::DuplicateRow { path, .. }
            | LoadError::MixedCategory { path, .. }
            | LoadError::SeveralEgoTracks { path, .. }
            | LoadError::ReservedUuid { path, .. }
            | LoadError::NoEgoPose { path, .. }
            | LoadError::DuplicatePoseTimestamp { path, .. }
            | LoadError::MapJson { path, .. }
            | LoadError::NoMapFile { path }
            | LoadError::SeveralMapFiles { path, .. } => path,
        }
    }
}
