//! scenalog-view owns Scenalog's pictures: the bird's-eye picture of a log's scene at a frame
//! (map, every object, the match highlighted, the proof's geometric facts drawn), the picture of
//! a track's path over a span of frames and its animation, and the static HTML report of a run.
//!
//! Everything is drawn once, as SVG text ([`svg`]), by plain functions over plain data: a
//! [`Picture`] says what to draw (the scene, the frame, the point of view, the referred and
//! related tracks, the [`Annotation`]s); [`scene_svg`] draws it. PNG and GIF come from that SVG
//! rasterised by `resvg` ([`raster`]) with the DejaVu Sans font that ships inside the `dejavu`
//! crate, so a clean clone renders text without system fonts. [`report`] writes the HTML page.

pub mod animation;
pub mod annotate;
pub mod error;
pub mod label;
pub mod map;
pub mod mark;
pub mod measure;
pub mod output;
pub mod panel;
pub mod picture;
pub mod raster;
pub mod report;
pub mod request;
pub mod style;
pub mod svg;
pub mod track_path;
pub mod view;

pub use error::ViewError;
pub use mark::{Annotation, Mark, Side};
pub use output::write_animation;
pub use output::{write_picture, Format};
pub use picture::{draw_scene, layout, scene_svg, Drawn, Layout, Picture, Reference};
pub use raster::{decode_png, render_png, render_rgba};
pub use report::{write_report, Report, ReportFrame, ReportMatch};
/// The rasteriser's pixel buffer type, for callers that inspect pixels.
pub use resvg::tiny_skia;
/// The parsed SVG tree ([`raster::parse`]), for callers that inspect where things are drawn.
pub use resvg::usvg;
pub use track_path::{path_svg, PathPicture};
