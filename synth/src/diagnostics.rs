//! The checker's diagnostics as the repair loop sends them back: the JSON of `scenalog check
//! --json`, and the offending source lines with a caret under each span.

use scenalog_rules::{Diagnostic, Severity};

use scenalog_rules::render::line_column as line_col;

fn severity(s: Severity) -> &'static str {
    match s {
        Severity::Error => "error",
        Severity::Warning => "warning",
    }
}

/// The diagnostics as JSON, exactly as `scenalog check --json` prints them (see
/// [`scenalog_rules::diagnostics_json`]: `code`, `severity`, `message`, 1-based `line` and
/// `column`, byte `span`, `hint`, `related`).
pub fn to_json(diagnostics: &[Diagnostic], source: &str) -> serde_json::Value {
    scenalog_rules::diagnostics_json(diagnostics, source)
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
    use scenalog_rules::Span;

    fn diag(start: usize, end: usize) -> Diagnostic {
        Diagnostic {
            code: "E0101",
            severity: Severity::Error,
            message: "unknown predicate `turn`".into(),
            span: Span::new(start, end),
            related: vec![(Span::new(0, 2), "here".into())],
            hint: Some("did you mean `turning`?".into()),
            fix: Vec::new(),
        }
    }

    #[test]
    fn json_and_text_name_the_place() {
        let s = "// d\nreferred(X, T) :- turn(X, T).\n";
        let start = s.find("turn(").expect("turn");
        let d = diag(start, start + 4);
        let j = to_json(std::slice::from_ref(&d), s);
        assert_eq!(j[0]["line"], 2);
        assert_eq!(j[0]["column"], 19);
        assert_eq!(j[0]["code"], "E0101");
        assert_eq!(j[0]["hint"], "did you mean `turning`?");
        assert_eq!(j[0]["related"][0]["message"], "here");
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
