//! The proof's geometric facts drawn on the map: the areas (a lane, a crossing, the sector of a
//! `direction`, the half-plane of a `crossing`) under the objects, the lines (a `near`
//! distance, a link between two objects) over them, and each fact's label, placed with the
//! others by [`crate::label`].

use scenalog_facts::scene::{Frame, Scene, TrackBox, TrackId};

use crate::label::Label;
use crate::mark::Mark;
use crate::request::{centre_px, Picture};
use crate::style;
use crate::svg::{path_data, Svg};
use crate::view::View;

/// Which annotations are drawn: areas under the objects, lines and labels over them.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Layer {
    /// Areas, drawn under the objects.
    Under,
    /// Lines and labels, drawn over them.
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

/// Draws the picture's annotations of one layer; returns the labels of the `Over` layer.
pub fn draw_annotations(svg: &mut Svg, view: &View, p: &Picture<'_>, layer: Layer) -> Vec<Label> {
    let mut labels = Vec::new();
    for (k, a) in p.annotations.iter().enumerate() {
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
                target: [at[0], at[1], at[0], at[1]],
                text: a.label.clone(),
                size: 12.0,
                bold: true,
                fill: colour,
                priority: 4,
                keep: true,
                id: format!("label-fact-{k}"),
            });
        }
    }
    labels
}
