//! The bird's-eye picture of a scene at one frame: the map (drivable area, lanes with bike and
//! bus lanes in their own colours, pedestrian crossings), every object as its oriented box
//! coloured by category with its short id, stop signs, the ego, the referred object
//! highlighted and linked to its related objects, the proof's geometric facts; beside the map,
//! never over it, the panel with the description, time, proof, legend, scale bar and north
//! arrow.

use scenalog_facts::scene::{Frame, Scene, TrackBox, TrackId};

use crate::annotate::{draw_annotations, Layer};
use crate::error::ViewError;
use crate::label::{self, bounds, Label, Placed, Rect};
use crate::map::{draw_map, MapKinds};
use crate::panel::{draw_panel, panel_width};
use crate::style;
use crate::svg::{path_data, Svg};
use crate::view::View;

pub use crate::request::{centre_px, Picture, Reference};

/// The largest half extent a picture grows to, metres.
const MAX_HALF_EXTENT: f64 = 70.0;

/// A box's ground rectangle in the city frame: corners counter-clockwise from front-left.
pub fn box_corners(b: &TrackBox) -> [[f64; 2]; 4] {
    let c = b.city_center();
    let yaw = b.city_yaw();
    let (s, co) = yaw.sin_cos();
    let (hl, hw) = (b.size[0] / 2.0, b.size[1] / 2.0);
    let at = |x: f64, y: f64| [c.x + x * co - y * s, c.y + x * s + y * co];
    [at(hl, hw), at(-hl, hw), at(-hl, -hw), at(hl, -hw)]
}

/// The box of `track` at `frame`, or a clear error.
pub fn box_at(scene: &Scene, track: TrackId, frame: Frame) -> Result<&TrackBox, ViewError> {
    let t = scene
        .tracks
        .get(track.index())
        .ok_or(ViewError::NoSuchTrack(track.0))?;
    t.box_at(frame).ok_or_else(|| ViewError::TrackNotAtFrame {
        log: scene.log_id.clone(),
        uuid: t.uuid.clone(),
        frame,
        span: match t.frame_span() {
            Some((a, b)) => format!("it is annotated from frame {a} to frame {b}, with gaps"),
            None => "it has no boxes".to_string(),
        },
    })
}

/// Checks that `frame` is one of the scene's frames.
pub fn check_frame(scene: &Scene, frame: Frame) -> Result<(), ViewError> {
    if (frame as usize) < scene.num_frames() && (frame as usize) < scene.ego_poses.len() {
        Ok(())
    } else {
        Err(ViewError::FrameOutsideLog {
            log: scene.log_id.clone(),
            frame,
            frames: scene.num_frames(),
        })
    }
}

/// The ego's centre and heading at a frame (the frame is checked).
fn ego_pose(scene: &Scene, frame: Frame) -> Result<([f64; 2], f64), ViewError> {
    check_frame(scene, frame)?;
    let pose = &scene.ego_poses[frame as usize];
    let t = pose.translation.vector;
    Ok(([t.x, t.y], scenalog_facts::scene::yaw_of(&pose.rotation)))
}

/// The view of a picture: centred on the reference object, its heading up, grown to show the
/// referred and related objects.
pub fn picture_view(p: &Picture<'_>) -> Result<View, ViewError> {
    let (center, heading) = match (p.reference, p.referred) {
        (Reference::Referred, Some(r)) => {
            check_frame(p.scene, p.frame)?;
            let b = box_at(p.scene, r, p.frame)?;
            let c = b.city_center();
            ([c.x, c.y], b.city_yaw())
        }
        _ => ego_pose(p.scene, p.frame)?,
    };
    let mut half = p.half_extent;
    for t in p.referred.iter().chain(&p.related) {
        if let Some(b) = p
            .scene
            .tracks
            .get(t.index())
            .and_then(|t| t.box_at(p.frame))
        {
            let c = b.city_center();
            let d = (c.x - center[0]).hypot(c.y - center[1]);
            half = half.max(d + 8.0);
        }
    }
    Ok(View::new(
        center,
        heading,
        half.min(MAX_HALF_EXTENT),
        p.width as f64,
        p.height as f64,
        0.0,
    ))
}

/// Where a picture's parts go, pixels: the map on the left, the panel on its right.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layout {
    /// The whole picture's width.
    pub width: u32,
    /// The whole picture's height.
    pub height: u32,
    /// The map's rectangle.
    pub map: Rect,
    /// The panel's rectangle (text, legend, scale bar, north arrow).
    pub panel: Rect,
}

/// The layout of a picture whose map is `p.width` × `p.height`.
pub fn layout(p: &Picture<'_>) -> Layout {
    let (w, h) = (p.width, p.height);
    let panel = panel_width(w);
    Layout {
        width: w + panel,
        height: h,
        map: [0.0, 0.0, w as f64, h as f64],
        panel: [w as f64, 0.0, (w + panel) as f64, h as f64],
    }
}

/// A picture as drawn: the SVG text and where things went (for tools and tests).
#[derive(Debug, Clone)]
pub struct Drawn {
    /// The SVG document.
    pub svg: String,
    /// The map and panel rectangles.
    pub layout: Layout,
    /// The labels drawn on the map, where they went.
    pub labels: Vec<Placed>,
    /// The referred object's bounding rectangle, pixels, when it is drawn.
    pub referred: Option<Rect>,
}

/// The picture as SVG text. Errors: the frame is outside the log, or the referred track has no
/// box at the frame.
pub fn scene_svg(p: &Picture<'_>) -> Result<String, ViewError> {
    Ok(draw_scene(p)?.svg)
}

/// The picture drawn: the SVG and where its parts went. Errors as [`scene_svg`]'s.
pub fn draw_scene(p: &Picture<'_>) -> Result<Drawn, ViewError> {
    if let Some(r) = p.referred {
        box_at(p.scene, r, p.frame)?;
    }
    let view = picture_view(p)?;
    Ok(draw_with(p, &view, |_, _| {}, Vec::new()))
}

/// Draws a picture with `view`: the map, then `under` (e.g. a track's path) under the objects,
/// the objects, the annotations, the labels (`extra` with the objects' own), then the panel.
pub fn draw_with(
    p: &Picture<'_>,
    view: &View,
    under: impl FnOnce(&mut Svg, &View),
    extra: Vec<Label>,
) -> Drawn {
    let layout = layout(p);
    let mut svg = Svg::new(layout.width, layout.height);
    // Everything of the map is clipped to its rectangle: nothing reaches the panel.
    let [mx0, my0, mx1, my1] = layout.map;
    svg.raw(&format!(
        "<defs><clipPath id=\"map-area\"><rect x=\"{mx0}\" y=\"{my0}\" width=\"{}\" height=\"{}\"/></clipPath></defs>\n<g id=\"map\" clip-path=\"url(#map-area)\">\n",
        mx1 - mx0,
        my1 - my0
    ));
    let kinds: MapKinds = draw_map(&mut svg, view, p.scene, &layout.map);
    draw_annotations(&mut svg, view, p, Layer::Under);
    under(&mut svg, view);
    let objects = draw_objects(
        &mut svg,
        view,
        p.scene,
        p.frame,
        (p.referred, p.referred_here),
        &p.related,
    );
    let mut labels = objects.labels;
    labels.extend(draw_annotations(&mut svg, view, p, Layer::Over));
    labels.extend(extra);
    // Labels stay 2 px inside the map.
    let area = [
        layout.map[0] + 2.0,
        layout.map[1] + 2.0,
        layout.map[2] - 2.0,
        layout.map[3] - 2.0,
    ];
    let placed = label::place(labels, &objects.boxes, &objects.hard, &area);
    label::draw(&mut svg, &placed);
    svg.raw("</g>\n");
    draw_panel(&mut svg, view, p, layout.panel, kinds);
    Drawn {
        svg: svg.finish(),
        layout,
        labels: placed.into_iter().map(|(_, p)| p).collect(),
        referred: objects.referred,
    }
}

/// The pixel corners of a box.
fn box_px(view: &View, b: &TrackBox) -> Vec<[f64; 2]> {
    box_corners(b).iter().map(|c| view.px(*c)).collect()
}

/// The first `n` characters of a uuid.
fn short(uuid: &str, n: usize) -> String {
    uuid.chars().take(n).collect()
}

/// What [`draw_objects`] drew, for the labels: each object's label, every box's rectangle
/// (labels avoid them), the ones no label may cover, and the referred object's.
#[derive(Debug, Clone, Default)]
pub struct Objects {
    /// A label per object (its short id; `EGO`; `STOP`).
    pub labels: Vec<Label>,
    /// Every drawn object's bounding rectangle, pixels.
    pub boxes: Vec<Rect>,
    /// The rectangles no label may cover: the referred object's and the ego's.
    pub hard: Vec<Rect>,
    /// The referred object's rectangle.
    pub referred: Option<Rect>,
}

/// Label priorities: the referred object's first, then the related objects', the proof's
/// facts', the ego's, then the rest (dropped first when space runs out).
pub mod priority {
    /// The referred object's label.
    pub const REFERRED: u8 = 6;
    /// A related object's label.
    pub const RELATED: u8 = 5;
    /// A proof fact's label.
    pub const FACT: u8 = 4;
    /// The path's start and end times.
    pub const PATH: u8 = 3;
    /// The ego's label.
    pub const EGO: u8 = 2;
    /// A stop sign's label.
    pub const STOP: u8 = 1;
    /// Any other object's label.
    pub const OTHER: u8 = 0;
}

/// Draws every object present at `frame`: oriented boxes coloured by category with a heading
/// tick, stop signs as octagons, the ego, the referred object highlighted, related objects
/// outlined and linked to it; returns each object's short id as a label to place last.
/// `referred` is the highlighted track and whether it is referred at `frame` (see
/// [`Picture::referred_here`]).
pub fn draw_objects(
    svg: &mut Svg,
    view: &View,
    scene: &Scene,
    frame: Frame,
    (referred, referred_here): (Option<TrackId>, bool),
    related: &[TrackId],
) -> Objects {
    let mut out = Objects::default();
    let label = |target: Rect, text: String, strong: bool, priority: u8, id: String| Label {
        target,
        text,
        size: if strong { 13.0 } else { 9.0 },
        bold: strong,
        fill: style::TEXT,
        priority,
        keep: priority >= self::priority::RELATED,
        id,
    };
    let referred_box = referred.and_then(|r| scene.tracks.get(r.index())?.box_at(frame));
    // Links first, so boxes cover their ends.
    if let Some(rb) = referred_box {
        for t in related {
            if let Some(b) = scene.tracks.get(t.index()).and_then(|t| t.box_at(frame)) {
                svg.line(
                    centre_px(view, rb),
                    centre_px(view, b),
                    &format!(
                        r#"stroke="{}" stroke-width="2.5" stroke-dasharray="7 4""#,
                        style::RELATED
                    ),
                );
            }
        }
    }
    for t in &scene.tracks {
        let Some(b) = t.box_at(frame) else { continue };
        let c = b.city_center();
        if (c.x - view.center[0]).hypot(c.y - view.center[1]) > view.radius + 5.0 {
            continue;
        }
        let is_ego = t.id == scene.ego;
        let is_referred = Some(t.id) == referred;
        let is_related = related.contains(&t.id);
        let px = box_px(view, b);
        let centre = centre_px(view, b);
        if t.category == "STOP_SIGN" {
            let r = (b.size[0].max(b.size[1]) * view.scale / 2.0).max(6.0);
            let oct: Vec<[f64; 2]> = (0..8)
                .map(|k| {
                    let a = std::f64::consts::PI / 8.0 + k as f64 * std::f64::consts::PI / 4.0;
                    [centre[0] + r * a.cos(), centre[1] + r * a.sin()]
                })
                .collect();
            svg.path(
                &path_data(&oct, true),
                r##"fill="#c62828" stroke="#ffffff" stroke-width="1.5""##,
            );
            let rect = bounds(&oct);
            out.boxes.push(rect);
            out.labels.push(label(
                rect,
                "STOP".into(),
                false,
                priority::STOP,
                format!("label-{}", short(&t.uuid, 8)),
            ));
            continue;
        }
        let fill = if is_referred && referred_here {
            style::REFERRED
        } else {
            style::category_colour(&t.category)
        };
        let stroke = if is_related {
            format!(r#"stroke="{}" stroke-width="3.5""#, style::RELATED)
        } else if is_referred && !referred_here {
            format!(
                r#"stroke="{}" stroke-width="2.5" stroke-dasharray="5 3""#,
                style::REFERRED
            )
        } else if is_referred {
            r##"stroke="#000000" stroke-width="2""##.to_string()
        } else {
            r##"stroke="#ffffff" stroke-width="0.8""##.to_string()
        };
        let id = if is_referred {
            r#"id="referred-box" "#
        } else {
            ""
        };
        if is_referred && referred_here {
            // A halo that shows the referred object even when it is small.
            svg.path(
                &path_data(&px, true),
                &format!(
                    r#"fill="none" stroke="{}" stroke-opacity="0.35" stroke-width="10" stroke-linejoin="round""#,
                    style::REFERRED
                ),
            );
        }
        svg.path(
            &path_data(&px, true),
            &format!(r#"{id}fill="{fill}" {stroke}"#),
        );
        // Heading: a tick from the centre to the middle of the front edge.
        let front = [(px[0][0] + px[3][0]) / 2.0, (px[0][1] + px[3][1]) / 2.0];
        svg.line(
            centre,
            front,
            r##"stroke="#ffffff" stroke-width="1.5" stroke-opacity="0.9""##,
        );
        // The box with its outline's half width (the referred object's halo too).
        let grow = if is_referred {
            5.0
        } else if is_related {
            1.75
        } else {
            1.0
        };
        let r = bounds(&px);
        let rect = [r[0] - grow, r[1] - grow, r[2] + grow, r[3] + grow];
        out.boxes.push(rect);
        let short_id = short(&t.uuid, 8);
        if is_ego {
            out.hard.push(rect);
            out.labels.push(label(
                rect,
                "EGO".into(),
                true,
                priority::EGO,
                "label-ego".into(),
            ));
        } else if is_referred {
            out.hard.push(rect);
            out.referred = Some(rect);
            out.labels.push(label(
                rect,
                short_id,
                true,
                priority::REFERRED,
                "label-referred".into(),
            ));
        } else if is_related {
            out.labels.push(label(
                rect,
                short_id.clone(),
                true,
                priority::RELATED,
                format!("label-related-{short_id}"),
            ));
        } else {
            out.labels.push(label(
                rect,
                short(&t.uuid, 4),
                false,
                priority::OTHER,
                format!("label-{short_id}"),
            ));
        }
    }
    out
}
