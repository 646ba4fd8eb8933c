//! The errors of drawing and writing pictures; each names the log, frame, track or file.

use std::path::PathBuf;

/// Why a picture could not be made or written.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// The frame asked for is not one of the log's frames.
    #[error("frame {frame} is outside log {log} (it has frames 0..{frames})")]
    FrameOutsideLog {
        /// The log id.
        log: String,
        /// The frame asked for.
        frame: u32,
        /// How many frames the log has.
        frames: usize,
    },
    /// The track has no box at the frame.
    #[error("track {uuid} is not present at frame {frame} of log {log} ({span})")]
    TrackNotAtFrame {
        /// The log id.
        log: String,
        /// The track's uuid.
        uuid: String,
        /// The frame.
        frame: u32,
        /// Where the track is present, for the message.
        span: String,
    },
    /// A track id that is not in the scene.
    #[error("track #{0} is not in the scene")]
    NoSuchTrack(u32),
    /// An empty frame range.
    #[error("the frame range {first}..{last} is empty")]
    EmptyRange {
        /// First frame.
        first: u32,
        /// Last frame.
        last: u32,
    },
    /// The output file's extension names no format this crate writes.
    #[error("`{path}`: unknown picture format (use .png, .svg or .gif)")]
    UnknownFormat {
        /// The output path.
        path: PathBuf,
    },
    /// Writing a file failed.
    #[error("cannot write `{path}`: {source}")]
    Write {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The rasteriser or an encoder failed (a bug: our SVG should always parse).
    #[error("rendering failed: {0}")]
    Render(String),
}
