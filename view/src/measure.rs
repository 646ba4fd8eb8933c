//! The width of a line of text as the rasteriser draws it: the advance widths of the embedded
//! DejaVu Sans (regular and bold) glyphs, read once from the font, so labels are placed and
//! lines wrapped with the text's true extent rather than a guess.

use std::collections::HashMap;
use std::sync::OnceLock;

use skrifa::prelude::{FontRef, LocationRef, MetadataProvider, Size};

/// Advance widths in em of one font's characters; `fallback` for characters it lacks.
struct Advances {
    widths: HashMap<char, f64>,
    fallback: f64,
}

impl Advances {
    /// Reads the advances of every character the font maps.
    fn of(data: &'static [u8]) -> Advances {
        let mut widths = HashMap::new();
        let mut fallback = 0.7;
        if let Ok(font) = FontRef::new(data) {
            let upem = f64::from(
                font.metrics(Size::unscaled(), LocationRef::default())
                    .units_per_em,
            );
            let metrics = font.glyph_metrics(Size::unscaled(), LocationRef::default());
            if upem > 0.0 {
                for (code, glyph) in font.charmap().mappings() {
                    let (Some(c), Some(w)) = (char::from_u32(code), metrics.advance_width(glyph))
                    else {
                        continue;
                    };
                    widths.insert(c, f64::from(w) / upem);
                }
                fallback = widths.get(&'M').copied().unwrap_or(fallback);
            }
        }
        Advances { widths, fallback }
    }

    fn width(&self, text: &str) -> f64 {
        text.chars()
            .map(|c| self.widths.get(&c).copied().unwrap_or(self.fallback))
            .sum()
    }
}

fn regular() -> &'static Advances {
    static A: OnceLock<Advances> = OnceLock::new();
    A.get_or_init(|| Advances::of(dejavu::sans::regular()))
}

fn bold() -> &'static Advances {
    static A: OnceLock<Advances> = OnceLock::new();
    A.get_or_init(|| Advances::of(dejavu::sans::bold()))
}

/// The width in pixels of `text` at `size` pixels, bold or not.
pub fn text_width(text: &str, size: f64, bold_weight: bool) -> f64 {
    let a = if bold_weight { bold() } else { regular() };
    a.width(text) * size
}

/// `text` cut into lines no wider than `width` pixels at `size`, breaking after spaces and
/// commas where it can and inside a word only when one word is wider than a line. Continuation
/// lines start with `indent`.
pub fn wrap(text: &str, size: f64, bold_weight: bool, width: f64, indent: &str) -> Vec<String> {
    let fits = |s: &str| text_width(s, size, bold_weight) <= width;
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    // Pieces end after a space or a comma, so that joining them gives back the text.
    let mut pieces: Vec<&str> = Vec::new();
    let mut start = 0;
    for (i, c) in text.char_indices() {
        if c == ' ' || c == ',' {
            pieces.push(&text[start..i + c.len_utf8()]);
            start = i + c.len_utf8();
        }
    }
    if start < text.len() {
        pieces.push(&text[start..]);
    }
    for piece in pieces {
        let candidate = format!("{line}{piece}");
        if fits(candidate.trim_end()) || line.trim().is_empty() && fits(piece.trim_end()) {
            line = candidate;
            continue;
        }
        if !line.trim().is_empty() {
            lines.push(line.trim_end().to_string());
            line = indent.to_string();
        }
        // A piece wider than a line by itself is cut by characters.
        for c in piece.chars() {
            let mut next = line.clone();
            next.push(c);
            if !fits(next.trim_end()) && !line.trim().is_empty() {
                lines.push(line.trim_end().to_string());
                line = format!("{indent}{c}");
            } else {
                line = next;
            }
        }
    }
    if !line.trim().is_empty() || lines.is_empty() {
        lines.push(line.trim_end().to_string());
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn widths_come_from_the_font() {
        // DejaVu Sans: digits are 0.636 em, bold digits 0.696 em, a space 0.318 em.
        assert!((text_width("0000", 10.0, false) - 25.45).abs() < 0.1);
        assert!((text_width("0000", 10.0, true) - 27.84).abs() < 0.1);
        assert!(text_width("W", 10.0, false) > text_width("i", 10.0, false) * 2.0);
    }

    #[test]
    fn wrapping_keeps_every_character_and_the_width() {
        let text = "direction(2f09a161 (REGULAR_VEHICLE), 8f1f6bc5 (BICYCLE), 8.0 s, \"right\", \
                    1.98 m, 0.00 m)";
        let lines = wrap(text, 12.0, false, 150.0, "  ");
        assert!(lines.len() >= 3, "{lines:?}");
        for l in &lines {
            assert!(text_width(l, 12.0, false) <= 150.0, "{l}");
        }
        let joined: String = lines.iter().map(|l| l.trim()).collect::<Vec<_>>().join(" ");
        let squash = |s: &str| s.replace(' ', "");
        assert_eq!(squash(&joined), squash(text));
        // A word longer than the line is cut.
        let long = wrap(&"x".repeat(100), 12.0, false, 100.0, "");
        assert!(long.len() > 1 && long.iter().all(|l| text_width(l, 12.0, false) <= 100.0));
    }
}
