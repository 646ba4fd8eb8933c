//! A minimal SVG writer: elements appended to a string, text escaped, numbers rounded to
//! 0.01 px so the output is small and identical across runs.

use std::fmt::Write;

/// An SVG document being written.
pub struct Svg {
    body: String,
    width: u32,
    height: u32,
}

/// Escapes text for SVG/XML content and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// Path data for a polygon or polyline through `points` (closed with `Z` when `close`).
pub fn path_data(points: &[[f64; 2]], close: bool) -> String {
    let mut d = String::with_capacity(points.len() * 16);
    for (i, p) in points.iter().enumerate() {
        let _ = write!(
            d,
            "{}{:.2} {:.2}",
            if i == 0 { "M" } else { "L" },
            p[0],
            p[1]
        );
    }
    if close && !points.is_empty() {
        d.push('Z');
    }
    d
}

impl Svg {
    /// A new document of this size in pixels.
    pub fn new(width: u32, height: u32) -> Svg {
        Svg {
            body: String::with_capacity(64 * 1024),
            width,
            height,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Appends raw markup (already escaped).
    pub fn raw(&mut self, markup: &str) {
        self.body.push_str(markup);
    }

    /// A path with the given data and style attributes (e.g. `fill="#fff" stroke="none"`).
    pub fn path(&mut self, d: &str, style: &str) {
        if d.is_empty() {
            return;
        }
        let _ = writeln!(self.body, r#"<path d="{d}" {style}/>"#);
    }

    /// A line segment.
    pub fn line(&mut self, a: [f64; 2], b: [f64; 2], style: &str) {
        let _ = writeln!(
            self.body,
            r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" {style}/>"#,
            a[0], a[1], b[0], b[1]
        );
    }

    /// A circle.
    pub fn circle(&mut self, c: [f64; 2], r: f64, style: &str) {
        let _ = writeln!(
            self.body,
            r#"<circle cx="{:.2}" cy="{:.2}" r="{r:.2}" {style}/>"#,
            c[0], c[1]
        );
    }

    /// An axis-aligned rectangle.
    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, style: &str) {
        let _ = writeln!(
            self.body,
            r#"<rect x="{x:.2}" y="{y:.2}" width="{w:.2}" height="{h:.2}" {style}/>"#
        );
    }

    /// Text at `at` (the baseline's start, or as `anchor` says), in the embedded font, with a
    /// light halo so it reads over any background.
    pub fn text(&mut self, at: [f64; 2], size: f64, text: &str, style: &str) {
        let _ = writeln!(
            self.body,
            r#"<text x="{:.2}" y="{:.2}" font-family="{}" font-size="{size:.1}" {style}>{}</text>"#,
            at[0],
            at[1],
            crate::style::FONT,
            escape(text)
        );
    }

    /// The finished document.
    pub fn finish(self) -> String {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
             viewBox=\"0 0 {w} {h}\">\n{}</svg>\n",
            self.body,
            w = self.width,
            h = self.height
        )
    }
}
