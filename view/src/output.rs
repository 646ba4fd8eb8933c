//! Writing a picture to a file in the format its extension names, atomically (a temporary
//! file beside it, then a rename), with errors that name the file.

use std::path::{Path, PathBuf};

use crate::error::ViewError;

/// A picture file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// PNG, rasterised.
    Png,
    /// SVG, as drawn.
    Svg,
    /// Animated GIF.
    Gif,
}

impl Format {
    /// The format an output path's extension names (case-insensitive).
    pub fn of(path: &Path) -> Result<Format, ViewError> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("png") => Ok(Format::Png),
            Some("svg") => Ok(Format::Svg),
            Some("gif") => Ok(Format::Gif),
            _ => Err(ViewError::UnknownFormat {
                path: path.to_path_buf(),
            }),
        }
    }
}

/// Writes bytes to `path` through a temporary file in the same directory and a rename, so a
/// reader never sees half a file.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<(), ViewError> {
    let err = |source| ViewError::Write {
        path: path.to_path_buf(),
        source,
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(err)?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        err(e)
    })
}

/// Writes an SVG picture as `.svg` (as is), `.png` (rasterised) or `.gif` (one frame).
pub fn write_picture(path: &Path, svg: &str) -> Result<(), ViewError> {
    match Format::of(path)? {
        Format::Svg => write_file(path, svg.as_bytes()),
        Format::Png => write_file(path, &crate::raster::render_png(svg)?),
        Format::Gif => crate::track_path::write_animation(path, &[svg.to_string()], 100),
    }
}
