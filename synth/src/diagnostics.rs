//! The checker's diagnostics as the repair loop sends them back: JSON with line and column
//! positions, and the offending source lines with a caret under each span.

use scenalog_rules::{Diagnostic, Severity, Span};

/// 1-based line and column (in characters) of a byte offset, clamped into the text.
pub fn line_col(source: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(source.len());
    while !source.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &source[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, source[line_start..offset].chars().count() + 1)
}

fn severity(s: Severity) -> &'static str {
    match s {
        Severity::Error => "error",
        Severity::Warning => "warning",
    }
}

fn span_json(source: &str, span: Span) -> serde_json::Value {
    let (line, column) = line_col(source, span.start);
    let (end_line, end_column) = line_col(source, span.end);
    serde_json::json!({
        "start": span.start, "end": span.end,
        "line": line, "column": column, "end_line": end_line, "end_column": end_column,
    })
}

/// The diagnostics as a JSON array: `code`, `severity`, `message`, `span` (byte offsets and
/// 1-based line/column), `related` (`span`, `label`), `hint`.
pub fn to_json(diagnostics: &[Diagnostic], source: &str) -> serde_json::Value {
    serde_json::Value::Array(
        diagnostics
            .iter()
            .map(|d| {
                serde_json::json!({
                    "code": d.code,
                    "severity": severity(d.severity),
                    "message": d.message,
                    "span": span_json(source, d.span),
                    "related": d.related.iter().map(|(s, label)| serde_json::json!({
                        "span": span_json(source, *s), "label": label,
                    })).collect::<Vec<_>>(),
                    "hint": d.hint,
                })
            })
            .collect(),
    )
}

/// Each diagnostic as text: `line:col: severity[code]: message`, the source line with its number,
/// a caret line under the span, and the hint.
pub fn render(diagnostics: &[Diagnostic], source: &str) -> String {
    let lines: Vec<&str> = source.lines().collect();
    let mut out = String::new();
    for d in diagnostics {
        let (line, col) = line_col(source, d.span.start);
        let (end_line, end_col) = line_col(source, d.span.end);
        out.push_str(&format!(
            "{line}:{col}: {}[{}]: {}\n",
            severity(d.severity),
            d.code,
            d.message
        ));
        if let Some(text) = lines.get(line - 1) {
            let width = if end_line == line && end_col > col {
                end_col - col
            } else {
                text.chars().count().saturating_sub(col - 1).max(1)
            };
            out.push_str(&format!("{line:>4} | {text}\n"));
            out.push_str(&format!(
                "     | {}{}\n",
                " ".repeat(col - 1),
                "^".repeat(width)
            ));
        }
        for (span, label) in &d.related {
            let (l, c) = line_col(source, span.start);
            out.push_str(&format!("     = {l}:{c}: {label}\n"));
        }
        if let Some(hint) = &d.hint {
            out.push_str(&format!("     = hint: {hint}\n"));
        }
    }
    out
}

/// How many of the diagnostics are errors.
pub fn error_count(diagnostics: &[Diagnostic]) -> usize {
    diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn diag(start: usize, end: usize) -> Diagnostic {
        Diagnostic {
            code: "E0101",
            severity: Severity::Error,
            message: "unknown predicate `turn`".into(),
            span: Span::new(start, end),
            related: vec![(Span::new(0, 2), "here".into())],
            hint: Some("did you mean `turning`?".into()),
        }
    }

    #[test]
    fn positions_are_one_based_and_clamped() {
        let s = "ab\ncdé\n";
        assert_eq!(line_col(s, 0), (1, 1));
        assert_eq!(line_col(s, 3), (2, 1));
        assert_eq!(line_col(s, 6), (2, 3)); // inside 'é': moved back to its start
        assert_eq!(line_col(s, 999), (3, 1));
    }

    #[test]
    fn json_and_text_name_the_place() {
        let s = "// d\nreferred(X, T) :- turn(X, T).\n";
        let start = s.find("turn(").expect("turn");
        let d = diag(start, start + 4);
        let j = to_json(std::slice::from_ref(&d), s);
        assert_eq!(j[0]["span"]["line"], 2);
        assert_eq!(j[0]["span"]["column"], 19);
        assert_eq!(j[0]["code"], "E0101");
        assert_eq!(j[0]["hint"], "did you mean `turning`?");
        assert_eq!(j[0]["related"][0]["label"], "here");
        let text = render(&[d], s);
        assert!(
            text.starts_with("2:19: error[E0101]: unknown predicate `turn`\n"),
            "{text}"
        );
        assert!(
            text.contains("   2 | referred(X, T) :- turn(X, T).\n     |                   ^^^^\n"),
            "{text}"
        );
        assert!(text.contains("hint: did you mean `turning`?"));
        assert_eq!(error_count(&[diag(0, 0)]), 1);
    }
}
