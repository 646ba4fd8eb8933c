//! The side panel beside the map: the description, the time, the status and the proof's facts
//! (wrapped to the panel, cut with a count when they do not fit), then the legend of what the
//! map shows, the scale bar and the north arrow. Nothing of it is drawn over the map.

use crate::label::Rect;
use crate::map::MapKinds;
use crate::measure::{text_width, wrap};
use crate::request::{Picture, Reference};
use crate::style;
use crate::svg::{path_data, Svg};
use crate::view::View;

/// The panel's width for a map `map_width` pixels wide.
pub fn panel_width(map_width: u32) -> u32 {
    (map_width / 2).max(240)
}

/// Left and right margin inside the panel, pixels.
const MARGIN: f64 = 12.0;
/// Height of one legend row, pixels.
const ROW: f64 = 15.0;
/// Height of the scale bar and north arrow row, pixels.
const SCALE_ROW: f64 = 52.0;

/// One line of the panel's text: text, size, bold, colour.
struct Line {
    text: String,
    /// Pixels from the margin (continuation lines are indented).
    indent: f64,
    size: f64,
    bold: bool,
    colour: &'static str,
}

impl Line {
    fn height(&self) -> f64 {
        self.size * 1.3
    }
}

/// The panel's text, wrapped to `width` pixels: description, time, status lines, facts.
fn text_lines(p: &Picture<'_>, width: f64) -> (Vec<Line>, Vec<Line>) {
    let seconds = p.scene.timeline.seconds(p.frame).unwrap_or(0.0);
    let who = match (p.reference, p.referred) {
        (Reference::Referred, Some(_)) => "referred object's heading up",
        _ => "ego heading up",
    };
    let short_log: String = p.scene.log_id.chars().take(8).collect();
    let mut head: Vec<Line> = Vec::new();
    let push = |out: &mut Vec<Line>, text: &str, size, bold, colour, indent: &str| {
        for t in wrap(text, size, bold, width, indent) {
            // SVG collapses leading spaces: the indent is a shift instead.
            let body = t.trim_start();
            let lead = &t[..t.len() - body.len()];
            out.push(Line {
                indent: text_width(lead, size, bold),
                text: body.to_string(),
                size,
                bold,
                colour,
            });
        }
    };
    if !p.title.is_empty() {
        push(&mut head, &p.title, 16.0, true, style::TEXT, "");
    }
    push(
        &mut head,
        &format!("t = {seconds:.1} s (frame {}) · log {short_log}", p.frame),
        12.0,
        false,
        style::TEXT,
        "",
    );
    push(&mut head, who, 11.0, false, style::MUTED, "");
    for s in p.status.lines().filter(|s| !s.is_empty()) {
        push(&mut head, s, 12.0, true, style::TEXT, "  ");
    }
    let mut notes: Vec<Line> = Vec::new();
    for (note, holds) in &p.notes {
        let mark = if *holds { "✓" } else { "✗" };
        let colour = if *holds { style::FACT } else { style::FAILED };
        push(
            &mut notes,
            &format!("{mark} {note}"),
            11.5,
            false,
            colour,
            "    ",
        );
    }
    (head, notes)
}

/// How a legend entry's swatch is drawn.
enum Swatch {
    /// A filled square.
    Fill(&'static str),
    /// An outlined square.
    Outline(&'static str),
    /// A short line.
    Stroke(&'static str),
    /// The pedestrian crossing's stripes.
    Zebra,
}

/// The legend's entries for what this picture shows.
fn legend(p: &Picture<'_>, kinds: MapKinds) -> Vec<(Swatch, &'static str)> {
    let mut e = vec![(Swatch::Fill(style::REFERRED), "referred")];
    if !p.related.is_empty() {
        e.push((Swatch::Outline(style::RELATED), "related"));
    }
    for (colour, name) in style::LEGEND.iter().skip(1) {
        e.push((Swatch::Fill(colour), name));
    }
    if kinds.vehicle_lane {
        e.push((Swatch::Fill(style::VEHICLE_LANE), "lane"));
    }
    if kinds.bike_lane {
        e.push((Swatch::Fill(style::BIKE_LANE), "bike lane"));
    }
    if kinds.bus_lane {
        e.push((Swatch::Fill(style::BUS_LANE), "bus lane"));
    }
    if kinds.crossing {
        e.push((Swatch::Zebra, "crossing"));
    }
    if p.annotations.iter().any(|a| a.holds) {
        e.push((Swatch::Stroke(style::FACT), "proof's fact"));
    }
    if p.annotations.iter().any(|a| !a.holds) {
        e.push((Swatch::Stroke(style::FAILED), "failing"));
    }
    e
}

/// A round length for a scale bar at most `room` pixels long.
fn scale_length(view: &View, room: f64) -> f64 {
    let want = room / view.scale;
    [1.0, 2.0, 5.0, 10.0, 20.0, 25.0, 50.0, 100.0, 200.0]
        .into_iter()
        .filter(|l| *l <= want)
        .fold(1.0, f64::max)
}

/// Draws the panel in `area` (right of the map): text at the top, legend, scale bar and north
/// arrow at the bottom.
pub fn draw_panel(svg: &mut Svg, view: &View, p: &Picture<'_>, area: Rect, kinds: MapKinds) {
    let [x0, y0, x1, y1] = area;
    let width = x1 - x0 - 2.0 * MARGIN;
    svg.raw("<g id=\"panel\">\n");
    svg.rect(
        x0,
        y0,
        x1 - x0,
        y1 - y0,
        &format!(r#"fill="{}""#, style::PANEL),
    );
    svg.line(
        [x0 + 0.5, y0],
        [x0 + 0.5, y1],
        &format!(r#"stroke="{}" stroke-width="1""#, style::PANEL_EDGE),
    );
    let entries = legend(p, kinds);
    let legend_height = entries.len().div_ceil(2) as f64 * ROW + 8.0;
    let bottom = y1 - SCALE_ROW - legend_height;
    // The text: the head always, the facts as many as fit, then how many did not.
    let (head, notes) = text_lines(p, width);
    let mut y = y0 + 8.0;
    let draw_line = |svg: &mut Svg, l: &Line, y: &mut f64| {
        *y += l.height();
        svg.text(
            [x0 + MARGIN + l.indent, *y - 0.3 * l.size],
            l.size,
            &l.text,
            &format!(
                r#"font-weight="{}" fill="{}""#,
                if l.bold { "bold" } else { "normal" },
                l.colour
            ),
        );
    };
    for l in &head {
        draw_line(svg, l, &mut y);
    }
    y += 4.0;
    let room = bottom - 8.0;
    let total: f64 = notes.iter().map(Line::height).sum();
    let mut shown = notes.len();
    if y + total > room {
        let more = Line {
            text: String::new(),
            indent: 0.0,
            size: 11.0,
            bold: false,
            colour: style::MUTED,
        };
        let mut used = more.height();
        shown = notes
            .iter()
            .take_while(|l| {
                used += l.height();
                y + used <= room
            })
            .count();
    }
    for l in &notes[..shown] {
        draw_line(svg, l, &mut y);
    }
    if shown < notes.len() {
        let more = Line {
            indent: 0.0,
            text: format!("… {} more lines of the proof", notes.len() - shown),
            size: 11.0,
            bold: false,
            colour: style::MUTED,
        };
        draw_line(svg, &more, &mut y);
    }
    // The legend, in two columns.
    let col = width / 2.0;
    for (i, (swatch, name)) in entries.iter().enumerate() {
        let x = x0 + MARGIN + (i % 2) as f64 * col;
        let y = bottom + 4.0 + (i / 2) as f64 * ROW;
        match swatch {
            Swatch::Fill(c) => svg.rect(
                x,
                y,
                11.0,
                11.0,
                &format!(r##"fill="{c}" stroke="#777777" stroke-width="0.5""##),
            ),
            Swatch::Outline(c) => svg.rect(
                x + 1.0,
                y + 1.0,
                9.0,
                9.0,
                &format!(r#"fill="none" stroke="{c}" stroke-width="2.5""#),
            ),
            Swatch::Stroke(c) => svg.line(
                [x, y + 5.5],
                [x + 11.0, y + 5.5],
                &format!(r#"stroke="{c}" stroke-width="2.5""#),
            ),
            Swatch::Zebra => svg.rect(
                x,
                y,
                11.0,
                11.0,
                &format!(r#"fill="url(#zebra)" stroke="{}""#, style::CROSSING_EDGE),
            ),
        }
        svg.text(
            [x + 16.0, y + 10.0],
            10.5,
            name,
            &format!(r#"fill="{}""#, style::TEXT),
        );
    }
    // Scale bar (left) and north arrow (right), at the bottom.
    let len = scale_length(view, width - 70.0);
    let bar = len * view.scale;
    let (bx, by) = (x0 + MARGIN, y1 - 16.0);
    svg.line(
        [bx, by],
        [bx + bar, by],
        r##"stroke="#111111" stroke-width="3""##,
    );
    for x in [bx, bx + bar] {
        svg.line(
            [x, by - 5.0],
            [x, by + 5.0],
            r##"stroke="#111111" stroke-width="2""##,
        );
    }
    let label = format!("{len} m");
    svg.text(
        [
            bx + bar / 2.0 - text_width(&label, 11.0, false) / 2.0,
            by - 8.0,
        ],
        11.0,
        &label,
        r##"fill="#111111""##,
    );
    let c = [x1 - MARGIN - 20.0, y1 - SCALE_ROW / 2.0];
    let n = view.direction(std::f64::consts::FRAC_PI_2);
    svg.circle(c, 18.0, r##"fill="#ffffff" stroke="#555555""##);
    let tip = [c[0] + n[0] * 14.0, c[1] + n[1] * 14.0];
    let tail = [c[0] - n[0] * 8.0, c[1] - n[1] * 8.0];
    let side = [-n[1] * 6.0, n[0] * 6.0];
    svg.path(
        &path_data(
            &[
                tip,
                [tail[0] + side[0], tail[1] + side[1]],
                [c[0] - n[0] * 3.0, c[1] - n[1] * 3.0],
                [tail[0] - side[0], tail[1] - side[1]],
            ],
            true,
        ),
        r##"fill="#333333""##,
    );
    svg.text(
        [c[0] - 30.0 - text_width("N", 11.0, true), c[1] + 4.0],
        11.0,
        "N",
        r##"font-weight="bold" fill="#333333""##,
    );
    svg.raw("</g>\n");
}
