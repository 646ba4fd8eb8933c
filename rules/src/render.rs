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

/// Renders diagnostics as text with the source line and a caret under each span, like rustc.
pub fn render_human(diags: &[Diagnostic], source: &str, file_name: &str, color: bool) -> String {
    let file = SimpleFile::new(file_name, source);
    let config = Config::default();
    let mut out = String::new();
    for d in diags {
        let mut labels = vec![Label::primary((), clamp(source, d.span))];
        for (s, m) in &d.related {
            labels.push(Label::secondary((), clamp(source, *s)).with_message(m.clone()));
        }
        let severity = match d.severity {
            Severity::Error => CsSeverity::Error,
            Severity::Warning => CsSeverity::Warning,
        };
        let mut cs = CsDiagnostic::new(severity)
            .with_code(d.code)
            .with_message(d.message.clone())
            .with_labels(labels);
        if let Some(h) = &d.hint {
            cs = cs.with_notes(vec![format!("hint: {h}")]);
        }
        let text = if color {
            let mut w = Ansi::new(Vec::new());
            match term::emit_to_write_style(&mut w, &config, &file, &cs) {
                Ok(()) => String::from_utf8_lossy(&w.into_inner()).into_owned(),
                Err(_) => plain(d, source, file_name),
            }
        } else {
            term::emit_into_string(&config, &file, &cs)
                .unwrap_or_else(|_| plain(d, source, file_name))
        };
        out.push_str(&text);
    }
    out
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
