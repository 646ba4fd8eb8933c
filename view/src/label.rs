//! Placing text labels on the map without collisions: each label is tried at positions around
//! the thing it names (above, below, beside, at the corners), and the ones that must be kept
//! (the referred object's, the related objects', the proof's facts') further out with a leader
//! line, until one is found that overlaps no object box, no other label and stays inside the map.
//! Labels are placed by priority, so when space runs out the minor ones are dropped first.

use crate::measure::text_width;
use crate::svg::Svg;

/// An axis-aligned rectangle in pixels: left, top, right, bottom.
pub type Rect = [f64; 4];

/// Whether two rectangles overlap (touching edges do not).
pub fn overlaps(a: &Rect, b: &Rect) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

/// The area two rectangles share.
fn overlap_area(a: &Rect, b: &Rect) -> f64 {
    let w = a[2].min(b[2]) - a[0].max(b[0]);
    let h = a[3].min(b[3]) - a[1].max(b[1]);
    if w > 0.0 && h > 0.0 {
        w * h
    } else {
        0.0
    }
}

/// The bounding rectangle of points.
pub fn bounds(points: &[[f64; 2]]) -> Rect {
    points.iter().fold(
        [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ],
        |r, p| {
            [
                r[0].min(p[0]),
                r[1].min(p[1]),
                r[2].max(p[0]),
                r[3].max(p[1]),
            ]
        },
    )
}

/// A text label for something on the map.
#[derive(Debug, Clone)]
pub struct Label {
    /// What it names, pixels: an object's bounding rectangle, or a point (a zero-size rectangle).
    pub target: Rect,
    /// The text.
    pub text: String,
    /// Font size, pixels.
    pub size: f64,
    /// Bold or not.
    pub bold: bool,
    /// Fill colour.
    pub fill: &'static str,
    /// Higher first.
    pub priority: u8,
    /// Searched for further out (with a leader line) rather than dropped.
    pub keep: bool,
    /// An id for the SVG element (e.g. `label-referred`), for tools and tests.
    pub id: String,
}

/// A label where it was put: the rectangle its text fills (halo included).
#[derive(Debug, Clone, PartialEq)]
pub struct Placed {
    /// The label's text.
    pub text: String,
    /// The rectangle, pixels.
    pub rect: Rect,
    /// The SVG element's id.
    pub id: String,
    /// The label's priority.
    pub priority: u8,
}

/// The halo drawn around text (half the stroke), pixels.
const HALO: f64 = 1.5;
/// The gap between a label and what it names, pixels.
const GAP: f64 = 2.0;

/// The label's rectangle size: width and height, halo included.
fn label_size(l: &Label) -> [f64; 2] {
    [
        text_width(&l.text, l.size, l.bold) + 2.0 * HALO,
        // DejaVu Sans: ascent 0.93 em, descent 0.24 em.
        1.17 * l.size + 2.0 * HALO,
    ]
}

/// Candidate top-left corners for a `w` × `h` label naming `t`, nearest first: the eight
/// positions touching the target, then (for labels kept) rings further out.
fn candidates(t: &Rect, w: f64, h: f64, keep: bool) -> Vec<[f64; 2]> {
    let (cx, cy) = ((t[0] + t[2]) / 2.0, (t[1] + t[3]) / 2.0);
    let mut out = vec![
        [cx - w / 2.0, t[1] - GAP - h],
        [t[2] + GAP, cy - h / 2.0],
        [cx - w / 2.0, t[3] + GAP],
        [t[0] - GAP - w, cy - h / 2.0],
        [t[2] + GAP, t[1] - GAP - h],
        [t[0] - GAP - w, t[1] - GAP - h],
        [t[2] + GAP, t[3] + GAP],
        [t[0] - GAP - w, t[3] + GAP],
    ];
    if keep {
        let (hw, hh) = ((t[2] - t[0]) / 2.0, (t[3] - t[1]) / 2.0);
        for ring in [
            8.0, 18.0, 30.0, 45.0, 65.0, 90.0, 120.0, 160.0, 210.0, 280.0, 380.0,
        ] {
            for k in 0..24 {
                let a = std::f64::consts::TAU * k as f64 / 24.0 - std::f64::consts::FRAC_PI_2;
                let (s, c) = a.sin_cos();
                // From the target's edge out to the label's near edge, `ring` pixels.
                let reach_x = hw + GAP + ring + w / 2.0;
                let reach_y = hh + GAP + ring + h / 2.0;
                out.push([cx + c * reach_x - w / 2.0, cy + s * reach_y - h / 2.0]);
            }
        }
    }
    out
}

/// Places labels (by priority, higher first; in order within a priority) inside `area`,
/// avoiding `obstacles` (object boxes, pixels) and each other. A label that is not `keep` and
/// finds no free position is dropped; a kept one that finds none takes the position that
/// covers the least of the obstacles, none of the `hard` ones (the referred object, the ego)
/// and no other label (or, failing that, its first).
pub fn place(
    mut labels: Vec<Label>,
    obstacles: &[Rect],
    hard: &[Rect],
    area: &Rect,
) -> Vec<(Label, Placed)> {
    labels.sort_by_key(|l| std::cmp::Reverse(l.priority));
    let mut placed: Vec<(Label, Placed)> = Vec::new();
    for l in labels {
        let [w, h] = label_size(&l);
        let inside =
            |r: &Rect| r[0] >= area[0] && r[1] >= area[1] && r[2] <= area[2] && r[3] <= area[3];
        let rect_at = |p: [f64; 2]| [p[0], p[1], p[0] + w, p[1] + h];
        let free_of_labels = |r: &Rect| {
            placed.iter().all(|(_, q)| !overlaps(r, &q.rect))
                && hard.iter().all(|o| !overlaps(r, o))
        };
        let cands: Vec<Rect> = candidates(&l.target, w, h, l.keep)
            .into_iter()
            .map(rect_at)
            .filter(|r| inside(r))
            .collect();
        let free = cands
            .iter()
            .find(|r| free_of_labels(r) && obstacles.iter().all(|o| !overlaps(r, o)));
        let chosen = match free {
            Some(r) => Some(*r),
            None if l.keep => cands
                .iter()
                .filter(|r| free_of_labels(r))
                .map(|r| (r, obstacles.iter().map(|o| overlap_area(r, o)).sum::<f64>()))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(r, _)| *r)
                .or_else(|| cands.first().copied()),
            None => None,
        };
        if let Some(rect) = chosen {
            let p = Placed {
                text: l.text.clone(),
                rect,
                id: l.id.clone(),
                priority: l.priority,
            };
            placed.push((l, p));
        }
    }
    placed
}

/// The point of `r` nearest to `p`.
fn nearest_in(r: &Rect, p: [f64; 2]) -> [f64; 2] {
    [p[0].clamp(r[0], r[2]), p[1].clamp(r[1], r[3])]
}

/// Draws placed labels: the text, and a thin leader line to what it names when the label is not
/// touching it.
pub fn draw(svg: &mut Svg, placed: &[(Label, Placed)]) {
    for (l, p) in placed {
        let r = &p.rect;
        let gap = [
            (l.target[0] - r[2]).max(r[0] - l.target[2]).max(0.0),
            (l.target[1] - r[3]).max(r[1] - l.target[3]).max(0.0),
        ];
        if gap[0] > GAP + 1.0 || gap[1] > GAP + 1.0 {
            let centre = [
                (l.target[0] + l.target[2]) / 2.0,
                (l.target[1] + l.target[3]) / 2.0,
            ];
            let from = nearest_in(r, centre);
            let to = nearest_in(&l.target, from);
            svg.line(
                from,
                to,
                &format!(
                    r##"stroke="{}" stroke-width="1" stroke-opacity="0.8""##,
                    l.fill
                ),
            );
        }
        // The baseline: the ascent below the rectangle's top.
        let at = [r[0] + HALO, r[1] + HALO + 0.93 * l.size];
        svg.text(
            at,
            l.size,
            &l.text,
            &format!(
                r##"id="{}" font-weight="{}" fill="{}" stroke="#ffffff" stroke-width="{}" paint-order="stroke""##,
                l.id,
                if l.bold { "bold" } else { "normal" },
                l.fill,
                2.0 * HALO
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn label(target: Rect, text: &str, priority: u8, keep: bool) -> Label {
        Label {
            target,
            text: text.into(),
            size: 12.0,
            bold: true,
            fill: "#111111",
            priority,
            keep,
            id: format!("label-{text}"),
        }
    }

    #[test]
    fn crowded_labels_never_overlap_and_the_kept_one_survives() {
        // A tight group of 12 boxes, each 10 px wide, 2 px apart: no room beside most of them.
        let boxes: Vec<Rect> = (0..12)
            .map(|i| {
                let x = 100.0 + 12.0 * (i % 4) as f64;
                let y = 100.0 + 12.0 * (i / 4) as f64;
                [x, y, x + 10.0, y + 10.0]
            })
            .collect();
        let mut labels: Vec<Label> = boxes
            .iter()
            .enumerate()
            .map(|(i, b)| label(*b, &format!("obj{i}"), 0, false))
            .collect();
        // The referred object is in the middle of the group, last in the list.
        labels.push(label(boxes[5], "REFERRED", 9, true));
        let placed = place(labels, &boxes, &[], &[0.0, 0.0, 400.0, 400.0]);
        assert!(placed.iter().any(|(_, p)| p.text == "REFERRED"));
        for (i, (_, a)) in placed.iter().enumerate() {
            for b in &boxes {
                assert!(!overlaps(&a.rect, b), "{} covers a box", a.text);
            }
            for (_, b) in &placed[i + 1..] {
                assert!(!overlaps(&a.rect, &b.rect), "{} and {}", a.text, b.text);
            }
            assert!(a.rect[0] >= 0.0 && a.rect[2] <= 400.0);
        }
    }
}
