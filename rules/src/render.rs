//! Diagnostics for people (caret under the span, via `codespan-reporting`) and for machines (JSON).

use codespan_reporting::diagnostic::{Diagnostic as CsDiagnostic, Label, Severity as CsSeverity};
use codespan_reporting::files::SimpleFile;
use codespan_reporting::term::{self, termcolor::Ansi, Config};
use serde_json::{json, Value};

use crate::ast::Span;
use crate::{Diagnostic, Severity};

/// 1-based line and column (in characters) of byte offset `at` (clamped to the text).
pub fn line_column(source: &str, at: usize) -> (usize, usize) {
    let mut at = at.min(source.len());
    while !source.is_char_boundary(at) {
        at -= 1;
    }
    let before = &source[..at];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = source[line_start..at].chars().count() + 1;
    (line, column)
}

/// A span clamped to the text and to character boundaries.
fn clamp(source: &str, s: Span) -> std::ops::Range<usize> {
    let fix = |mut i: usize| {
        i = i.min(source.len());
        while !source.is_char_boundary(i) {
            i -= 1;
        }
        i
    };
    let start = fix(s.start);
    start..fix(s.end).max(start)
}

/// Lines longer than this (in bytes) are shown as a window around the span, so that many
/// diagnostics on one long line (a generated rule of thousands of atoms) cost their window
/// each, not the line.
const LONG_LINE: usize = 200;

/// Bytes of context shown on either side of a span on a long line.
const CONTEXT: usize = 60;

/// Renders diagnostics as text with the source line and a caret under each span, like rustc.
/// On a line longer than [`LONG_LINE`] bytes, the line is cut to a window around the span
/// (`…` where it is cut), with the real line and column numbers.
pub fn render_human(diags: &[Diagnostic], source: &str, file_name: &str, color: bool) -> String {
    let file = SimpleFile::new(file_name, source);
    let starts: Vec<usize> = codespan_reporting::files::line_starts(source).collect();
    let config = Config::default();
    let mut out = String::new();
    for d in diags {
        let severity = match d.severity {
            Severity::Error => CsSeverity::Error,
            Severity::Warning => CsSeverity::Warning,
        };
        let mut notes = Vec::new();
        if let Some(h) = &d.hint {
            notes.push(format!("hint: {h}"));
        }
        let cs = |labels: Vec<Label<()>>, notes: Vec<String>| {
            CsDiagnostic::new(severity)
                .with_code(d.code)
                .with_message(d.message.clone())
                .with_labels(labels)
                .with_notes(notes)
        };
        let emitted = match Window::around(source, &starts, file_name, clamp(source, d.span)) {
            Some(w) => {
                let mut labels = vec![Label::primary((), w.map(clamp(source, d.span)))];
                for (s, m) in &d.related {
                    let r = clamp(source, *s);
                    if w.holds(&r) {
                        labels.push(Label::secondary((), w.map(r)).with_message(m.clone()));
                    } else {
                        let (l, c) = line_column(source, r.start);
                        notes.push(format!("{l}:{c}: {m}"));
                    }
                }
                emit(&config, &w, &cs(labels, notes), color)
            }
            None => {
                let mut labels = vec![Label::primary((), clamp(source, d.span))];
                for (s, m) in &d.related {
                    labels.push(Label::secondary((), clamp(source, *s)).with_message(m.clone()));
                }
                emit(&config, &file, &cs(labels, notes), color)
            }
        };
        out.push_str(&emitted.unwrap_or_else(|| plain(d, source, file_name)));
    }
    out
}

/// One diagnostic rendered by `codespan-reporting`, with colour or without; `None` if it fails.
fn emit<'f, F: codespan_reporting::files::Files<'f, FileId = ()>>(
    config: &Config,
    files: &'f F,
    cs: &CsDiagnostic<()>,
    color: bool,
) -> Option<String> {
    if color {
        let mut w = Ansi::new(Vec::new());
        term::emit_to_write_style(&mut w, config, files, cs).ok()?;
        Some(String::from_utf8_lossy(&w.into_inner()).into_owned())
    } else {
        term::emit_into_string(config, files, cs).ok()
    }
}

/// A window of one long line, as a one-line file that reports the real line and columns.
struct Window<'a> {
    name: &'a str,
    /// `…`, the window's text, `…` (each mark only where the line is cut).
    text: String,
    /// Where the window starts in the source.
    from: usize,
    /// Where it ends in the source.
    to: usize,
    /// The bytes of the leading mark (0 or 3).
    mark: usize,
    /// The real 1-based line.
    line: usize,
    /// The real 1-based column of the window's first character.
    column: usize,
}

impl<'a> Window<'a> {
    /// The window around `span` when its line (found in `starts`, the lines' first bytes) is
    /// longer than [`LONG_LINE`]; `None` for a line short enough to show whole.
    fn around(
        source: &str,
        starts: &[usize],
        name: &'a str,
        span: std::ops::Range<usize>,
    ) -> Option<Window<'a>> {
        let index = starts
            .partition_point(|&s| s <= span.start)
            .saturating_sub(1);
        let line_start = *starts.get(index)?;
        let line_end = starts
            .get(index + 1)
            .map_or(source.len(), |&s| s.saturating_sub(1))
            .max(line_start);
        if line_end - line_start <= LONG_LINE {
            return None;
        }
        let boundary = |mut i: usize| {
            while !source.is_char_boundary(i) {
                i -= 1;
            }
            i
        };
        let from = boundary(span.start.saturating_sub(CONTEXT).max(line_start));
        // A span longer than the window is shown from its start.
        let to = boundary((span.end.min(span.start + 2 * CONTEXT) + CONTEXT).min(line_end));
        let mark = if from > line_start { "…".len() } else { 0 };
        let mut text = String::with_capacity(to - from + 6);
        if mark > 0 {
            text.push('…');
        }
        text.push_str(source.get(from..to)?.trim_end_matches('\r'));
        if to < line_end {
            text.push('…');
        }
        Some(Window {
            name,
            text,
            from,
            to,
            mark,
            line: index + 1,
            column: source.get(line_start..from)?.chars().count() + 1,
        })
    }

    /// Whether a source range lies in the window.
    fn holds(&self, r: &std::ops::Range<usize>) -> bool {
        r.start >= self.from && r.start <= self.to
    }

    /// A source range as a range of the window's text (cut at the window's end).
    fn map(&self, r: std::ops::Range<usize>) -> std::ops::Range<usize> {
        let at = |i: usize| i.clamp(self.from, self.to) - self.from + self.mark;
        at(r.start)..at(r.end)
    }
}

impl<'a> codespan_reporting::files::Files<'a> for Window<'a> {
    type FileId = ();
    type Name = &'a str;
    type Source = &'a str;

    fn name(&'a self, (): ()) -> Result<&'a str, codespan_reporting::files::Error> {
        Ok(self.name)
    }

    fn source(&'a self, (): ()) -> Result<&'a str, codespan_reporting::files::Error> {
        Ok(&self.text)
    }

    fn line_index(&'a self, (): (), _: usize) -> Result<usize, codespan_reporting::files::Error> {
        Ok(0)
    }

    fn line_number(&'a self, (): (), _: usize) -> Result<usize, codespan_reporting::files::Error> {
        Ok(self.line)
    }

    fn column_number(
        &'a self,
        (): (),
        _: usize,
        byte: usize,
    ) -> Result<usize, codespan_reporting::files::Error> {
        let byte = byte.clamp(self.mark, self.text.len());
        let before = self.text.get(self.mark..byte).unwrap_or_default();
        Ok(self.column + before.chars().count())
    }

    fn line_range(
        &'a self,
        (): (),
        _: usize,
    ) -> Result<std::ops::Range<usize>, codespan_reporting::files::Error> {
        Ok(0..self.text.len())
    }
}

/// A one-line fallback should the renderer fail.
fn plain(d: &Diagnostic, source: &str, file_name: &str) -> String {
    let (l, c) = line_column(source, d.span.start);
    format!(
        "{file_name}:{l}:{c}: {}[{}]: {}\n",
        severity_str(d.severity),
        d.code,
        d.message
    )
}

fn severity_str(s: Severity) -> &'static str {
    match s {
        Severity::Error => "error",
        Severity::Warning => "warning",
    }
}

/// Diagnostics as a JSON array; each object has `code`, `severity` ("error" or "warning"),
/// `message`, `line` and `column` (1-based, of the span's start; columns count characters),
/// `span` {`start`, `end`} (byte offsets), `hint` (string or null), `fix` [{`span`, `text`}]
/// (the edits that carry the hint out; empty when it is advice only) and `related`
/// [{`span`, `line`, `column`, `message`}]. These names are stable.
pub fn diagnostics_json(diags: &[Diagnostic], source: &str) -> Value {
    Value::Array(
        diags
            .iter()
            .map(|d| {
                let (line, column) = line_column(source, d.span.start);
                let related: Vec<Value> = d
                    .related
                    .iter()
                    .map(|(s, m)| {
                        let (line, column) = line_column(source, s.start);
                        json!({
                            "span": {"start": s.start, "end": s.end},
                            "line": line,
                            "column": column,
                            "message": m,
                        })
                    })
                    .collect();
                json!({
                    "code": d.code,
                    "severity": severity_str(d.severity),
                    "message": d.message,
                    "line": line,
                    "column": column,
                    "span": {"start": d.span.start, "end": d.span.end},
                    "hint": d.hint,
                    "fix": d.fix.iter().map(|e| json!({
                        "span": {"start": e.span.start, "end": e.span.end},
                        "text": e.text,
                    })).collect::<Vec<Value>>(),
                    "related": related,
                })
            })
            .collect(),
    )
}
