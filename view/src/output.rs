//! Writing a picture to a file in the format its extension names, atomically (a temporary
//! file beside it, then a rename), with errors that name the file.

use std::path::Path;

use rayon::prelude::*;

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
    scenalog_input::out_dir::write_atomic(path, bytes, false).map_err(err)
}

/// Writes an SVG picture as `.svg` (as is), `.png` (rasterised) or `.gif` (one frame).
pub fn write_picture(path: &Path, svg: &str) -> Result<(), ViewError> {
    match Format::of(path)? {
        Format::Svg => write_file(path, svg.as_bytes()),
        Format::Png => write_file(path, &crate::raster::render_png(svg)?),
        Format::Gif => write_animation(path, &[svg.to_string()], 100),
    }
}

/// Writes SVG pictures (all of one size) as an animated GIF, `delay_cs` hundredths of a second
/// per picture, looping, one palette for all of them (see [`crate::animation`]).
pub fn write_animation(path: &Path, frames: &[String], delay_cs: u16) -> Result<(), ViewError> {
    // Shapes without anti-aliasing: an object whose box moves by less than a pixel (the
    // annotations of parked cars jitter by centimetres) then leaves its pixels as they were,
    // so frames differ only where something really moved, and compress.
    let rasters = frames
        .par_iter()
        .map(|svg| {
            let crisp = svg.replacen("<svg ", "<svg shape-rendering=\"crispEdges\" ", 1);
            crate::raster::render_rgba(&crisp)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let bytes = crate::animation::encode(&rasters, delay_cs)?;
    write_file(path, &bytes)
}
