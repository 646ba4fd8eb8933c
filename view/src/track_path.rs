//! A track over time: the object's path over a span of frames drawn over the scene, the
//! frames where it is referred marked, as one picture or as an animated GIF (one picture per
//! frame, the view held still).

use std::path::Path;

use scenalog_facts::scene::{Frame, TrackId};

use crate::error::ViewError;
use crate::output::write_file;
use crate::picture::{
    box_at, check_frame, draw_map, draw_objects, draw_overlays, Picture, Reference,
};
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
        crate::picture::header_height(&p.picture),
    );
    Ok((points, view))
}

/// Draws the path: a line through every centre, a dot per frame (filled where referred,
/// hollow elsewhere), up to `upto` (inclusive), and the start and end times.
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
    let scene = p.picture.scene;
    for (f, px) in [points.first(), points.last()]
        .into_iter()
        .flatten()
        .map(|(f, q)| (*f, view.px(*q)))
    {
        let s = scene.timeline.seconds(f).unwrap_or(0.0);
        svg.text(
            [px[0] + 7.0, px[1] + 4.0],
            11.0,
            &format!("{s:.1} s"),
            r##"fill="#111111" stroke="#ffffff" stroke-width="2.5" paint-order="stroke""##,
        );
    }
}

/// One picture of the path over the scene at `p.picture.frame`.
pub fn path_svg(p: &PathPicture<'_>) -> Result<String, ViewError> {
    let (points, view) = path_view(p)?;
    check_frame(p.picture.scene, p.picture.frame)?;
    Ok(frame_svg(p, &points, &view, p.picture.frame, p.last))
}

fn frame_svg(
    p: &PathPicture<'_>,
    points: &[(Frame, [f64; 2])],
    view: &View,
    frame: Frame,
    upto: Frame,
) -> String {
    let pic = &p.picture;
    let mut svg = Svg::new(pic.width, pic.height);
    draw_map(&mut svg, view, pic.scene);
    draw_path(&mut svg, view, p, points, upto);
    let labels = draw_objects(&mut svg, view, pic.scene, frame, pic.referred, &pic.related);
    crate::picture::draw_labels(&mut svg, labels);
    let mut shown = pic.clone();
    shown.frame = frame;
    let referred = p.referred_frames.binary_search(&frame).is_ok();
    shown.status = format!(
        "path from frame {} to {}: {} referred frames (filled dots){}",
        p.first,
        p.last,
        p.referred_frames
            .iter()
            .filter(|f| **f >= p.first && **f <= p.last)
            .count(),
        if referred { " · referred now" } else { "" }
    );
    draw_overlays(&mut svg, view, &shown);
    svg.finish()
}

/// One SVG per frame of the span, the view held still and the path drawn up to that frame.
pub fn animation_frames(p: &PathPicture<'_>) -> Result<Vec<String>, ViewError> {
    let (points, view) = path_view(p)?;
    Ok((p.first..=p.last)
        .map(|f| frame_svg(p, &points, &view, f, f))
        .collect())
}

/// Writes SVG pictures (all of one size) as an animated GIF, `delay_cs` hundredths of a second
/// per picture, looping.
pub fn write_animation(path: &Path, frames: &[String], delay_cs: u16) -> Result<(), ViewError> {
    let render = |e: gif::EncodingError| ViewError::Render(e.to_string());
    let mut rasters = Vec::with_capacity(frames.len());
    for svg in frames {
        rasters.push(crate::raster::render_rgba(svg)?);
    }
    let Some((w, h, _)) = rasters.first() else {
        return Err(ViewError::Render(
            "an animation needs at least one frame".into(),
        ));
    };
    let too_large = || ViewError::Render(format!("GIF size {w} x {h} is too large"));
    let w16 = u16::try_from(*w).map_err(|_| too_large())?;
    let h16 = u16::try_from(*h).map_err(|_| too_large())?;
    let mut bytes = Vec::new();
    {
        let mut encoder = gif::Encoder::new(&mut bytes, w16, h16, &[]).map_err(render)?;
        encoder.set_repeat(gif::Repeat::Infinite).map_err(render)?;
        for (_, _, mut rgba) in rasters {
            let mut frame = gif::Frame::from_rgba_speed(w16, h16, &mut rgba, 20);
            frame.delay = delay_cs;
            encoder.write_frame(&frame).map_err(render)?;
        }
    }
    write_file(path, &bytes)
}
