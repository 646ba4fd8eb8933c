//! The bird's-eye picture of a scene at one frame: the map (drivable area, lanes with bike and
//! bus lanes in their own colours, pedestrian crossings), every object as its oriented box
//! coloured by category with its short id, stop signs, the ego, the referred object
//! highlighted and linked to its related objects, the proof's geometric facts, and the scale
//! bar, north arrow, time and description.

use scenalog_facts::map::LaneType;
use scenalog_facts::scene::{Frame, Scene, TrackBox, TrackId};

use crate::error::ViewError;
use crate::mark::{Annotation, Mark};
use crate::style;
use crate::svg::{path_data, Svg};
use crate::view::View;

/// Whose frame the picture is drawn in: that object's heading points up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reference {
    /// The ego vehicle at the centre, heading up.
    Ego,
    /// The referred object at the centre, heading up.
    Referred,
}

/// What to draw: plain data, filled in by the caller.
#[derive(Debug, Clone)]
pub struct Picture<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The frame drawn.
    pub frame: Frame,
    /// The point of view.
    pub reference: Reference,
    /// The referred object, highlighted.
    pub referred: Option<TrackId>,
    /// Objects related to the referred one, outlined and linked to it.
    pub related: Vec<TrackId>,
    /// The proof's geometric facts.
    pub annotations: Vec<Annotation>,
    /// First line: the scenario's description.
    pub title: String,
    /// A line under the time, e.g. `referred` or `NOT referred: S < 0.5 fails`.
    pub status: String,
    /// Lines of text listed under the header (the proof's facts), each with whether it holds.
    pub notes: Vec<(String, bool)>,
    /// Picture width, pixels.
    pub width: u32,
    /// Picture height, pixels.
    pub height: u32,
    /// Metres shown either side of the centre at least (grown to fit the related objects).
    pub half_extent: f64,
}

impl<'a> Picture<'a> {
    /// A picture of `scene` at `frame` from the ego, 800 × 800 px, 30 m either side, with
    /// nothing highlighted: set the fields to add the match.
    pub fn new(scene: &'a Scene, frame: Frame) -> Picture<'a> {
        Picture {
            scene,
            frame,
            reference: Reference::Ego,
            referred: None,
            related: Vec::new(),
            annotations: Vec::new(),
            title: String::new(),
            status: String::new(),
            notes: Vec::new(),
            width: 800,
            height: 800,
            half_extent: 30.0,
        }
    }
}

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
        header_height(p),
    ))
}

/// The picture as SVG text. Errors: the frame is outside the log, or the referred track has no
/// box at the frame.
pub fn scene_svg(p: &Picture<'_>) -> Result<String, ViewError> {
    if let Some(r) = p.referred {
        box_at(p.scene, r, p.frame)?;
    }
    let view = picture_view(p)?;
    let mut svg = Svg::new(p.width, p.height);
    draw_map(&mut svg, &view, p.scene);
    draw_annotations(&mut svg, &view, p, Layer::Under);
    let mut labels = draw_objects(&mut svg, &view, p.scene, p.frame, p.referred, &p.related);
    labels.extend(draw_annotations(&mut svg, &view, p, Layer::Over));
    draw_labels(&mut svg, labels);
    draw_overlays(&mut svg, &view, p);
    Ok(svg.finish())
}

/// Draws the drivable areas, lanes and pedestrian crossings near the view.
pub fn draw_map(svg: &mut Svg, view: &View, scene: &Scene) {
    svg.rect(
        0.0,
        0.0,
        svg.width() as f64,
        svg.height() as f64,
        &format!(r#"fill="{}""#, style::BACKGROUND),
    );
    svg.raw(
        r##"<defs><pattern id="zebra" width="6" height="6" patternUnits="userSpaceOnUse" patternTransform="rotate(45)"><rect width="3" height="6" fill="#9a9a9a"/></pattern></defs>
"##,
    );
    let mut d = String::new();
    for a in &scene.map.drivable_areas {
        let pts: Vec<[f64; 2]> = a.boundary.iter().map(|p| [p.x, p.y]).collect();
        if view.touches(&pts, 0.0) {
            let px: Vec<[f64; 2]> = pts.iter().map(|q| view.px(*q)).collect();
            d.push_str(&path_data(&px, true));
        }
    }
    svg.path(&d, &format!(r#"fill="{}""#, style::DRIVABLE));
    // Vehicle lanes first, bike and bus lanes over them; intersection lanes translucent.
    for (kind, colour) in [
        (LaneType::Vehicle, style::VEHICLE_LANE),
        (LaneType::Bus, style::BUS_LANE),
        (LaneType::Bike, style::BIKE_LANE),
    ] {
        for intersection in [false, true] {
            let mut d = String::new();
            for l in &scene.map.lanes {
                if l.lane_type != kind || l.is_intersection != intersection {
                    continue;
                }
                let pts = l.polygon_xy();
                if view.touches(&pts, 0.0) {
                    let px: Vec<[f64; 2]> = pts.iter().map(|q| view.px(*q)).collect();
                    d.push_str(&path_data(&px, true));
                }
            }
            let opacity = if intersection { 0.45 } else { 1.0 };
            svg.path(
                &d,
                &format!(
                    r#"fill="{colour}" fill-opacity="{opacity}" stroke="{}" stroke-width="0.8""#,
                    style::LANE_EDGE
                ),
            );
        }
    }
    let mut d = String::new();
    for c in &scene.map.crossings {
        let pts = c.polygon_xy();
        if view.touches(&pts, 0.0) {
            let px: Vec<[f64; 2]> = pts.iter().map(|q| view.px(*q)).collect();
            d.push_str(&path_data(&px, true));
        }
    }
    svg.path(&d, &format!(r#"fill="{}" stroke="none""#, style::CROSSING));
    svg.path(
        &d,
        &format!(
            r#"fill="url(#zebra)" stroke="{}" stroke-width="1""#,
            style::CROSSING_EDGE
        ),
    );
}

/// The pixel corners of a box.
fn box_px(view: &View, b: &TrackBox) -> Vec<[f64; 2]> {
    box_corners(b).iter().map(|c| view.px(*c)).collect()
}

fn centre_px(view: &View, b: &TrackBox) -> [f64; 2] {
    let c = b.city_center();
    view.px([c.x, c.y])
}

/// The first `n` characters of a uuid.
fn short(uuid: &str, n: usize) -> String {
    uuid.chars().take(n).collect()
}

/// Draws every object present at `frame`: oriented boxes coloured by category with a heading
/// tick, stop signs as octagons, the ego, the referred object highlighted, related objects
/// outlined and linked to it; returns each object's short id as a label to draw last.
pub fn draw_objects(
    svg: &mut Svg,
    view: &View,
    scene: &Scene,
    frame: Frame,
    referred: Option<TrackId>,
    related: &[TrackId],
) -> Vec<Label> {
    let mut labels: Vec<Label> = Vec::new();
    let label = |at: [f64; 2], text: String, strong: bool, priority: u8| Label {
        at,
        text,
        size: if strong { 13.0 } else { 9.0 },
        bold: strong,
        fill: style::TEXT,
        start: false,
        priority,
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
            labels.push(label(
                [centre[0] + r + 2.0, centre[1] + 4.0],
                "STOP".into(),
                false,
                1,
            ));
            continue;
        }
        let fill = if is_referred {
            style::REFERRED
        } else {
            style::category_colour(&t.category)
        };
        let stroke = if is_related {
            format!(r#"stroke="{}" stroke-width="3.5""#, style::RELATED)
        } else if is_referred {
            r##"stroke="#000000" stroke-width="2""##.to_string()
        } else {
            r##"stroke="#ffffff" stroke-width="0.8""##.to_string()
        };
        if is_referred {
            // A halo that shows the referred object even when it is small.
            svg.path(
                &path_data(&px, true),
                &format!(
                    r#"fill="none" stroke="{}" stroke-opacity="0.35" stroke-width="10" stroke-linejoin="round""#,
                    style::REFERRED
                ),
            );
        }
        svg.path(&path_data(&px, true), &format!(r#"fill="{fill}" {stroke}"#));
        // Heading: a tick from the centre to the middle of the front edge.
        let front = [(px[0][0] + px[3][0]) / 2.0, (px[0][1] + px[3][1]) / 2.0];
        svg.line(
            centre,
            front,
            r##"stroke="#ffffff" stroke-width="1.5" stroke-opacity="0.9""##,
        );
        let top = px.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        if is_ego {
            labels.push(label([centre[0], top - 4.0], "EGO".into(), true, 3));
        } else if is_referred {
            labels.push(label([centre[0], top - 5.0], short(&t.uuid, 8), true, 4));
        } else if is_related {
            // Beside the box rather than above: related objects are often side by side.
            let right = px.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max);
            let half = 0.31 * 13.0 * 8.0;
            labels.push(label(
                [right + 3.0 + half, centre[1] + 5.0],
                short(&t.uuid, 8),
                true,
                2,
            ));
        } else {
            labels.push(label([centre[0], top - 3.0], short(&t.uuid, 4), false, 0));
        }
    }
    labels
}

/// A text label placed on the map; labels are drawn last, by priority, leaving out any that
/// would overlap one already placed.
#[derive(Debug, Clone)]
pub struct Label {
    /// Anchor point, pixels (the baseline's middle, or its start when `start`).
    pub at: [f64; 2],
    /// The text.
    pub text: String,
    /// Font size, pixels.
    pub size: f64,
    /// Bold or not.
    pub bold: bool,
    /// Fill colour.
    pub fill: &'static str,
    /// Anchored at the start (true) or the middle (false).
    pub start: bool,
    /// Higher first.
    pub priority: u8,
}

/// Draws labels by priority, leaving out those that would overlap one already drawn.
pub fn draw_labels(svg: &mut Svg, mut labels: Vec<Label>) {
    labels.sort_by_key(|l| std::cmp::Reverse(l.priority));
    let mut placed: Vec<[f64; 4]> = Vec::new();
    for mut l in labels {
        let width = 0.62 * l.size * l.text.chars().count() as f64;
        let mut x0 = if l.start {
            l.at[0]
        } else {
            l.at[0] - width / 2.0
        };
        // Kept inside the picture: moved left when it would run off the right edge.
        let overflow = x0 + width - (svg.width() as f64 - 4.0);
        if overflow > 0.0 {
            x0 -= overflow;
            l.at[0] -= overflow;
        }
        let rect = [x0, l.at[1] - l.size, x0 + width, l.at[1] + 2.0];
        if placed
            .iter()
            .any(|r| rect[0] < r[2] && r[0] < rect[2] && rect[1] < r[3] && r[1] < rect[3])
        {
            continue;
        }
        placed.push(rect);
        svg.text(
            l.at,
            l.size,
            &l.text,
            &format!(
                r##"text-anchor="{}" font-weight="{}" fill="{}" stroke="#ffffff" stroke-width="3" paint-order="stroke""##,
                if l.start { "start" } else { "middle" },
                if l.bold { "bold" } else { "normal" },
                l.fill
            ),
        );
    }
}

/// Which annotations are drawn: areas under the objects, lines and labels over them.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Layer {
    Under,
    Over,
}

/// The box of a track at the picture's frame, if present.
fn find(scene: &Scene, t: TrackId, frame: Frame) -> Option<&TrackBox> {
    scene.tracks.get(t.index())?.box_at(frame)
}

/// A point `along` metres from a box centre in the box frame (x forward, y left).
fn box_point(b: &TrackBox, x: f64, y: f64) -> [f64; 2] {
    let c = b.city_center();
    let (s, co) = b.city_yaw().sin_cos();
    [c.x + x * co - y * s, c.y + x * s + y * co]
}

fn draw_annotations(svg: &mut Svg, view: &View, p: &Picture<'_>, layer: Layer) -> Vec<Label> {
    let mut labels = Vec::new();
    for a in &p.annotations {
        let colour = if a.holds { style::FACT } else { style::FAILED };
        let dash = if a.holds {
            ""
        } else {
            r#" stroke-dasharray="6 4""#
        };
        let label_at: Option<[f64; 2]> = match (&a.mark, layer) {
            (Mark::Lane { lane, .. }, Layer::Under) => {
                if let Some(l) = p.scene.map.lane(*lane) {
                    let px: Vec<[f64; 2]> = l.polygon_xy().iter().map(|q| view.px(*q)).collect();
                    svg.path(
                        &path_data(&px, true),
                        &format!(
                            r#"fill="{colour}" fill-opacity="0.22" stroke="{colour}" stroke-width="3"{dash}"#
                        ),
                    );
                }
                None
            }
            (Mark::Lane { track, lane }, Layer::Over) => p
                .scene
                .map
                .lane(*lane)
                .and_then(|l| l.right_boundary.get(l.right_boundary.len() / 2))
                .map(|q| view.px([q.x, q.y]))
                .or_else(|| find(p.scene, *track, p.frame).map(|b| centre_px(view, b))),
            (Mark::Crosswalk { track }, Layer::Under) => {
                if let Some(b) = find(p.scene, *track, p.frame) {
                    let c = b.city_center();
                    let nearest = p.scene.map.crossings.iter().min_by(|x, y| {
                        let dist = |pc: &scenalog_facts::map::PedestrianCrossing| {
                            let pts = pc.polygon_xy();
                            pts.iter()
                                .map(|q| (q[0] - c.x).hypot(q[1] - c.y))
                                .fold(f64::INFINITY, f64::min)
                        };
                        dist(x).total_cmp(&dist(y))
                    });
                    if let Some(n) = nearest {
                        let px: Vec<[f64; 2]> =
                            n.polygon_xy().iter().map(|q| view.px(*q)).collect();
                        svg.path(
                            &path_data(&px, true),
                            &format!(
                                r#"fill="{colour}" fill-opacity="0.25" stroke="{colour}" stroke-width="3"{dash}"#
                            ),
                        );
                    }
                }
                None
            }
            (Mark::Crosswalk { track }, Layer::Over) => {
                find(p.scene, *track, p.frame).map(|b| centre_px(view, b))
            }
            (Mark::Sector { from, to, side }, Layer::Under) => {
                if let Some(b) = find(p.scene, *from, p.frame) {
                    let reach = find(p.scene, *to, p.frame)
                        .map(|t| {
                            let (c, d) = (b.city_center(), t.city_center());
                            (c.x - d.x).hypot(c.y - d.y) + 3.0
                        })
                        .unwrap_or(10.0)
                        .max(6.0);
                    let u = side.unit();
                    let base = u[1].atan2(u[0]);
                    let mut pts = vec![view.px(box_point(b, 0.0, 0.0))];
                    for k in 0..=12 {
                        let ang = base - std::f64::consts::FRAC_PI_4
                            + k as f64 * std::f64::consts::FRAC_PI_2 / 12.0;
                        pts.push(view.px(box_point(b, reach * ang.cos(), reach * ang.sin())));
                    }
                    svg.path(
                        &path_data(&pts, true),
                        &format!(
                            r#"fill="{colour}" fill-opacity="0.16" stroke="{colour}" stroke-width="1.5"{dash}"#
                        ),
                    );
                }
                None
            }
            (Mark::Sector { from, side, .. }, Layer::Over) => {
                find(p.scene, *from, p.frame).map(|b| {
                    let u = side.unit();
                    view.px(box_point(b, u[0] * 5.0, u[1] * 5.0))
                })
            }
            (Mark::Crossing { from, side, .. }, Layer::Under) => {
                if let Some(b) = find(p.scene, *from, p.frame) {
                    let (hl, hw) = (b.size[0] / 2.0, b.size[1] / 2.0);
                    let (depth, u) = (10.0, side.unit());
                    // The rectangle from the side's edge out to 10 m, as wide as the side.
                    let (near, half) = if u[0] != 0.0 { (hl, hw) } else { (hw, hl) };
                    let corners = [
                        [near, -half],
                        [near + depth, -half],
                        [near + depth, half],
                        [near, half],
                    ];
                    let pts: Vec<[f64; 2]> = corners
                        .iter()
                        .map(|[a, s]| {
                            // (along the side's normal, along the side)
                            let x = a * u[0] - s * u[1];
                            let y = a * u[1] + s * u[0];
                            view.px(box_point(b, x, y))
                        })
                        .collect();
                    svg.path(
                        &path_data(&pts, true),
                        &format!(
                            r#"fill="{colour}" fill-opacity="0.18" stroke="{colour}" stroke-width="2"{dash}"#
                        ),
                    );
                }
                None
            }
            (Mark::Crossing { by, .. }, Layer::Over) => {
                find(p.scene, *by, p.frame).map(|b| centre_px(view, b))
            }
            (Mark::Distance { a: x, b: y, .. } | Mark::Link { a: x, b: y }, Layer::Over) => {
                match (find(p.scene, *x, p.frame), find(p.scene, *y, p.frame)) {
                    (Some(bx), Some(by)) => {
                        let (u, v) = (centre_px(view, bx), centre_px(view, by));
                        svg.line(
                            u,
                            v,
                            &format!(r#"stroke="{colour}" stroke-width="2.5"{dash}"#),
                        );
                        svg.circle(u, 3.0, &format!(r#"fill="{colour}""#));
                        svg.circle(v, 3.0, &format!(r#"fill="{colour}""#));
                        Some([(u[0] + v[0]) / 2.0, (u[1] + v[1]) / 2.0])
                    }
                    _ => None,
                }
            }
            (Mark::Distance { .. } | Mark::Link { .. }, Layer::Under) => None,
        };
        if let Some(at) = label_at {
            labels.push(Label {
                at: [at[0] + 6.0, at[1] - 6.0],
                text: a.label.clone(),
                size: 12.0,
                bold: true,
                fill: colour,
                start: true,
                priority: 5,
            });
        }
    }
    labels
}

/// A round length for a scale bar about a fifth of the picture wide.
fn scale_length(view: &View, width: f64) -> f64 {
    let want = width / 5.0 / view.scale;
    [1.0, 2.0, 5.0, 10.0, 20.0, 25.0, 50.0, 100.0]
        .into_iter()
        .filter(|l| *l <= want)
        .fold(1.0, f64::max)
}

/// The header's lines: text, size, weight, colour.
fn header_lines(p: &Picture<'_>) -> Vec<(String, f64, &'static str, &'static str)> {
    let seconds = p.scene.timeline.seconds(p.frame).unwrap_or(0.0);
    let who = match (p.reference, p.referred) {
        (Reference::Referred, Some(_)) => "referred object's heading up",
        _ => "ego heading up",
    };
    let short_log: String = p.scene.log_id.chars().take(8).collect();
    let mut lines: Vec<(String, f64, &'static str, &'static str)> = Vec::new();
    if !p.title.is_empty() {
        lines.push((p.title.clone(), 17.0, "bold", style::TEXT));
    }
    lines.push((
        format!(
            "t = {seconds:.1} s (frame {}) · log {short_log} · {who}",
            p.frame
        ),
        12.0,
        "normal",
        style::TEXT,
    ));
    if !p.status.is_empty() {
        lines.push((p.status.clone(), 12.0, "bold", style::TEXT));
    }
    for (note, holds) in &p.notes {
        let mark = if *holds { "✓" } else { "✗" };
        let colour = if *holds { style::FACT } else { style::FAILED };
        lines.push((format!("{mark} {note}"), 11.5, "normal", colour));
    }
    lines
}

/// The header's height in pixels.
pub fn header_height(p: &Picture<'_>) -> f64 {
    12.0 + header_lines(p).iter().map(|l| l.1 + 5.0).sum::<f64>()
}

/// The header (description, time, status, facts), scale bar, north arrow and legend.
pub fn draw_overlays(svg: &mut Svg, view: &View, p: &Picture<'_>) {
    let (w, h) = (p.width as f64, p.height as f64);
    let lines = header_lines(p);
    let band = header_height(p);
    svg.rect(0.0, 0.0, w, band, r##"fill="#ffffff" fill-opacity="0.86""##);
    let mut y = 6.0;
    for (text, size, weight, colour) in &lines {
        y += size + 5.0;
        svg.text(
            [10.0, y - 3.0],
            *size,
            text,
            &format!(r#"font-weight="{weight}" fill="{colour}""#),
        );
    }
    // Scale bar, bottom left.
    let len = scale_length(view, w);
    let bar = len * view.scale;
    let (x0, y0) = (14.0, h - 18.0);
    svg.rect(
        x0 - 6.0,
        y0 - 20.0,
        bar + 12.0,
        30.0,
        r##"fill="#ffffff" fill-opacity="0.8""##,
    );
    svg.line(
        [x0, y0],
        [x0 + bar, y0],
        r##"stroke="#111111" stroke-width="3""##,
    );
    for x in [x0, x0 + bar] {
        svg.line(
            [x, y0 - 5.0],
            [x, y0 + 5.0],
            r##"stroke="#111111" stroke-width="2""##,
        );
    }
    svg.text(
        [x0 + bar / 2.0, y0 - 7.0],
        11.0,
        &format!("{len} m"),
        r##"text-anchor="middle" fill="#111111""##,
    );
    // North arrow, top right under the header.
    let c = [w - 42.0, band + 34.0];
    let n = view.direction(std::f64::consts::FRAC_PI_2);
    svg.circle(
        c,
        20.0,
        r##"fill="#ffffff" fill-opacity="0.85" stroke="#555555""##,
    );
    let tip = [c[0] + n[0] * 15.0, c[1] + n[1] * 15.0];
    let tail = [c[0] - n[0] * 9.0, c[1] - n[1] * 9.0];
    let side = [-n[1] * 6.0, n[0] * 6.0];
    svg.path(
        &path_data(
            &[
                tip,
                [tail[0] + side[0], tail[1] + side[1]],
                [c[0] - n[0] * 4.0, c[1] - n[1] * 4.0],
                [tail[0] - side[0], tail[1] - side[1]],
            ],
            true,
        ),
        r##"fill="#333333""##,
    );
    svg.text(
        [c[0] + n[0] * 25.0, c[1] + n[1] * 25.0 + 4.0],
        11.0,
        "N",
        r##"text-anchor="middle" font-weight="bold" fill="#333333" stroke="#ffffff" stroke-width="2.5" paint-order="stroke""##,
    );
    // Legend, bottom right; the lane colours too.
    let mut entries: Vec<(&str, &str)> = style::LEGEND.to_vec();
    entries.push((style::BIKE_LANE, "bike lane"));
    entries.push((style::BUS_LANE, "bus lane"));
    if !p.related.is_empty() {
        entries.insert(1, (style::RELATED, "related"));
    }
    let lw = 92.0;
    let lh = entries.len() as f64 * 15.0 + 8.0;
    let (lx, ly) = (w - lw - 8.0, h - lh - 8.0);
    svg.rect(lx, ly, lw, lh, r##"fill="#ffffff" fill-opacity="0.85""##);
    for (i, (colour, name)) in entries.iter().enumerate() {
        let y = ly + 6.0 + i as f64 * 15.0;
        svg.rect(lx + 6.0, y, 11.0, 11.0, &format!(r#"fill="{colour}""#));
        svg.text(
            [lx + 22.0, y + 10.0],
            10.5,
            name,
            &format!(r#"fill="{}""#, style::TEXT),
        );
    }
}
