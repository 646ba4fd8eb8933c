//! A track over time: the object's path over a span of frames drawn over the scene, the
//! frames where it is referred marked, as one picture or as an animated GIF (one picture per
//! frame, the view held still, each frame with its own proof, one palette for all).

use scenalog_facts::scene::{Frame, TrackId};

use rayon::prelude::*;

use crate::error::ViewError;
use crate::label::Label;
use crate::picture::{box_at, check_frame, draw_with, priority, Picture, Reference};
use crate::style;
use crate::svg::{path_data, Svg};
use crate::view::View;

/// What to draw for a track over time.
#[derive(Debug, Clone)]
pub struct PathPicture<'a> {
    /// The picture drawn under the path (its frame is the one shown in a still picture; its
    /// `referred` should be the track).
    pub picture: Picture<'a>,
    /// The track whose path is drawn.
    pub track: TrackId,
    /// First frame of the span.
    pub first: Frame,
    /// Last frame of the span (inclusive).
    pub last: Frame,
    /// Frames where the track is referred (sorted), marked on the path.
    pub referred_frames: Vec<Frame>,
    /// For an animation, each frame's own picture (its frame, related objects, proof), by
    /// frame; a frame of the span without one is drawn with no proof, saying so.
    pub frames: Vec<Picture<'a>>,
}

/// A track's centre (city frame) at each frame where it has a box.
type PathPoints = Vec<(Frame, [f64; 2])>;

/// The track's centre at each frame of the span where it has a box.
fn path_points(p: &PathPicture<'_>) -> PathPoints {
    let Some(t) = p.picture.scene.tracks.get(p.track.index()) else {
        return Vec::new();
    };
    t.boxes
        .iter()
        .filter(|b| b.frame >= p.first && b.frame <= p.last)
        .map(|b| {
            let c = b.city_center();
            (b.frame, [c.x, c.y])
        })
        .collect()
}

/// Checks the span and returns the path and a view that holds all of it, oriented as the
/// picture's reference is at the picture's frame.
fn path_view(p: &PathPicture<'_>) -> Result<(PathPoints, View), ViewError> {
    if p.first > p.last {
        return Err(ViewError::EmptyRange {
            first: p.first,
            last: p.last,
        });
    }
    let scene = p.picture.scene;
    check_frame(scene, p.first)?;
    check_frame(scene, p.last)?;
    let points = path_points(p);
    if points.is_empty() {
        // The track is absent over the whole span: say where it is.
        box_at(scene, p.track, p.first)?;
    }
    let heading = match p.picture.reference {
        Reference::Referred => box_at(scene, p.track, p.picture.frame)
            .map(|b| b.city_yaw())
            .unwrap_or(0.0),
        Reference::Ego => {
            check_frame(scene, p.picture.frame)?;
            scenalog_facts::scene::yaw_of(&scene.ego_poses[p.picture.frame as usize].rotation)
        }
    };
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for (_, q) in &points {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    let center = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
    let half = ((hi[0] - lo[0]).hypot(hi[1] - lo[1]) / 2.0 + 12.0)
        .max(p.picture.half_extent)
        .min(150.0);
    let view = View::new(
        center,
        heading,
        half,
        p.picture.width as f64,
        p.picture.height as f64,
        0.0,
    );
    Ok((points, view))
}

/// Draws the path: a line through every centre, a dot per frame (filled where referred,
/// hollow elsewhere), up to `upto` (inclusive).
fn draw_path(
    svg: &mut Svg,
    view: &View,
    p: &PathPicture<'_>,
    points: &[(Frame, [f64; 2])],
    upto: Frame,
) {
    let all: Vec<[f64; 2]> = points.iter().map(|(_, q)| view.px(*q)).collect();
    svg.path(
        &path_data(&all, false),
        &format!(
            r#"fill="none" stroke="{}" stroke-opacity="0.35" stroke-width="3""#,
            style::REFERRED
        ),
    );
    for ((f, _), px) in points.iter().zip(&all) {
        if *f > upto {
            break;
        }
        if p.referred_frames.binary_search(f).is_ok() {
            svg.circle(*px, 3.2, &format!(r#"fill="{}""#, style::REFERRED));
        } else {
            svg.circle(
                *px,
                2.6,
                r##"fill="#ffffff" stroke="#555555" stroke-width="1""##,
            );
        }
    }
}

/// The path's start and end times, as labels by its ends.
fn path_labels(view: &View, p: &PathPicture<'_>, points: &[(Frame, [f64; 2])]) -> Vec<Label> {
    let scene = p.picture.scene;
    [points.first(), points.last()]
        .into_iter()
        .flatten()
        .enumerate()
        .map(|(k, (f, q))| {
            let px = view.px(*q);
            let s = scene.timeline.seconds(*f).unwrap_or(0.0);
            Label {
                target: [px[0] - 3.0, px[1] - 3.0, px[0] + 3.0, px[1] + 3.0],
                text: format!("{s:.1} s"),
                size: 11.0,
                bold: false,
                fill: style::TEXT,
                priority: priority::PATH,
                keep: false,
                id: format!("label-path-{}", if k == 0 { "start" } else { "end" }),
            }
        })
        .collect()
}

/// One picture of the path over the scene at `p.picture.frame`.
pub fn path_svg(p: &PathPicture<'_>) -> Result<String, ViewError> {
    let (points, view) = path_view(p)?;
    check_frame(p.picture.scene, p.picture.frame)?;
    Ok(frame_svg(p, &p.picture, &points, &view, p.last))
}

/// The picture of the path with `pic`'s frame, objects and proof, the dots up to `upto`.
fn frame_svg(
    p: &PathPicture<'_>,
    pic: &Picture<'_>,
    points: &[(Frame, [f64; 2])],
    view: &View,
    upto: Frame,
) -> String {
    let mut shown = pic.clone();
    let referred = p.referred_frames.binary_search(&pic.frame).is_ok();
    let path_line = format!(
        "path from frame {} to {}: {} referred frames (filled dots){}",
        p.first,
        p.last,
        p.referred_frames
            .iter()
            .filter(|f| **f >= p.first && **f <= p.last)
            .count(),
        if referred { " · referred now" } else { "" }
    );
    shown.status = if pic.status.is_empty() {
        path_line
    } else {
        format!("{}\n{path_line}", pic.status)
    };
    let labels = path_labels(view, p, points);
    draw_with(
        &shown,
        view,
        |svg, view| draw_path(svg, view, p, points, upto),
        labels,
    )
    .svg
}

/// The picture of frame `f` of an animation: the caller's picture of that frame, or the still
/// picture moved to `f` with its proof left out (it is another frame's).
fn picture_at<'a>(p: &PathPicture<'a>, f: Frame) -> Picture<'a> {
    if let Some(pic) = p.frames.iter().find(|q| q.frame == f) {
        return pic.clone();
    }
    let mut pic = p.picture.clone();
    pic.frame = f;
    pic.annotations.clear();
    pic.notes.clear();
    pic.related.clear();
    pic.status = "no proof drawn for this frame".to_string();
    pic
}

/// One SVG per frame of the span, the view held still, the path drawn up to that frame, and
/// each frame's own objects and proof.
pub fn animation_frames(p: &PathPicture<'_>) -> Result<Vec<String>, ViewError> {
    let (points, view) = path_view(p)?;
    Ok((p.first..=p.last)
        .into_par_iter()
        .map(|f| frame_svg(p, &picture_at(p, f), &points, &view, f))
        .collect())
}
