//! What an editor asks of a program while it is typed (`scenalog lsp`): the checker's diagnostics
//! with their places and fixes, the documentation of the relation under the cursor, and what can
//! be written where the cursor is. Everything works on the program's text; places are
//! [`Position`]s as editors count them (lines from 0, columns in UTF-16 code units, the Language
//! Server Protocol's default), turned from and into byte offsets by [`LineIndex`].

use scenalog_facts::catalog::{self, ColType};
use scenalog_rules::prelude;
use scenalog_rules::{check, CheckOptions, Severity};

use crate::api::catalog::Catalog;

/// A place in a text: a line (from 0) and a column in UTF-16 code units (from 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Position {
    /// The line, from 0.
    pub line: u32,
    /// The column in UTF-16 code units, from 0.
    pub character: u32,
}

/// A stretch of text from `start` up to (not including) `end`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Range {
    /// Where it starts.
    pub start: Position,
    /// Where it ends.
    pub end: Position,
}

/// Byte offsets of a text to editor positions and back.
#[derive(Clone, Debug)]
pub struct LineIndex {
    text: String,
    line_starts: Vec<usize>,
}

impl LineIndex {
    /// The index of `text`.
    pub fn new(text: &str) -> LineIndex {
        let mut line_starts = vec![0];
        line_starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        LineIndex {
            text: text.to_string(),
            line_starts,
        }
    }

    /// The position of byte `offset` (clamped to the text; inside a character, its start).
    pub fn position(&self, offset: usize) -> Position {
        let mut offset = offset.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.line_starts.partition_point(|&s| s <= offset) - 1;
        let start = self.line_starts[line];
        let character: usize = self.text[start..offset].chars().map(char::len_utf16).sum();
        Position {
            line: line as u32,
            character: character as u32,
        }
    }

    /// The byte offset of `pos` (a line past the end is the text's end; a column past its line's
    /// end is the line's end).
    pub fn offset(&self, pos: Position) -> usize {
        let Some(&start) = self.line_starts.get(pos.line as usize) else {
            return self.text.len();
        };
        let end = self
            .line_starts
            .get(pos.line as usize + 1)
            .map_or(self.text.len(), |&e| e - 1);
        let mut units = 0u32;
        for (i, c) in self.text[start..end].char_indices() {
            if units >= pos.character {
                return start + i;
            }
            units += c.len_utf16() as u32;
        }
        end
    }

    /// The range of the bytes `start..end`.
    pub fn range(&self, start: usize, end: usize) -> Range {
        Range {
            start: self.position(start),
            end: self.position(end),
        }
    }
}

/// How bad a diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    /// The program cannot run.
    Error,
    /// The program runs but is probably not what was meant.
    Warning,
}

/// One replacement of the text.
#[derive(Clone, Debug, PartialEq)]
pub struct TextEdit {
    /// What is replaced (empty to insert).
    pub range: Range,
    /// The new text.
    pub new_text: String,
}

/// A diagnostic of the checker, placed for an editor.
#[derive(Clone, Debug, PartialEq)]
pub struct EditorDiagnostic {
    /// Where.
    pub range: Range,
    /// Error or warning.
    pub level: Level,
    /// Its stable code (`E0101`), documented in `rules/DIAGNOSTICS.md`.
    pub code: String,
    /// What is wrong, then the hint on a line of its own when there is one.
    pub message: String,
    /// Other places that explain it, each with its label.
    pub related: Vec<(Range, String)>,
    /// The edits that carry the hint out, when it can be applied mechanically; empty otherwise.
    pub fix: Vec<TextEdit>,
    /// The hint, the fix's title.
    pub hint: Option<String>,
}

/// The checker's diagnostics of `text`, as `scenalog check` gives them for a file.
pub fn diagnostics(text: &str) -> Vec<EditorDiagnostic> {
    let index = LineIndex::new(text);
    let outcome = check(text, &CheckOptions::default());
    outcome
        .diagnostics
        .iter()
        .map(|d| {
            let mut message = d.message.clone();
            if let Some(h) = &d.hint {
                message.push_str("\nhint: ");
                message.push_str(h);
            }
            EditorDiagnostic {
                range: index.range(d.span.start, d.span.end),
                level: match d.severity {
                    Severity::Error => Level::Error,
                    Severity::Warning => Level::Warning,
                },
                code: d.code.to_string(),
                message,
                related: d
                    .related
                    .iter()
                    .map(|(s, label)| (index.range(s.start, s.end), label.clone()))
                    .collect(),
                fix: d
                    .fix
                    .iter()
                    .map(|e| TextEdit {
                        range: index.range(e.span.start, e.span.end),
                        new_text: e.text.clone(),
                    })
                    .collect(),
                hint: d.hint.clone(),
            }
        })
        .collect()
}

/// The documentation shown over a name.
#[derive(Clone, Debug, PartialEq)]
pub struct Hover {
    /// The name's place.
    pub range: Range,
    /// Markdown.
    pub markdown: String,
}

/// The identifier around byte `offset`: its bytes, or `None` off an identifier or inside a
/// string or a comment.
fn word_at(text: &str, offset: usize) -> Option<(usize, usize)> {
    let offset = offset.min(text.len());
    if in_string_or_comment(text, offset).is_some() {
        return None;
    }
    let is_word = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let start = text[..offset]
        .char_indices()
        .rev()
        .take_while(|&(_, c)| is_word(c))
        .last()
        .map_or(offset, |(i, _)| i);
    let end = text[offset..]
        .char_indices()
        .find(|&(_, c)| !is_word(c))
        .map_or(text.len(), |(i, _)| offset + i);
    (start < end).then_some((start, end))
}

/// Whether byte `offset` of its line lies in a string (`Some(true)`, with the string's opening
/// quote) or a `//` comment (`Some(false)`), reading the line from its start.
fn in_string_or_comment(text: &str, offset: usize) -> Option<bool> {
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let mut in_string = false;
    let mut chars = text[line_start..offset].chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' => in_string = !in_string,
            '\\' if in_string => {
                chars.next();
            }
            '/' if !in_string && chars.peek() == Some(&'/') => return Some(false),
            _ => {}
        }
    }
    in_string.then_some(true)
}

/// The documentation of the relation or concept named at `pos`: its signature, doc, columns
/// (types, units, closed values) or definition, as `scenalog catalog NAME` prints it.
pub fn hover(text: &str, pos: Position) -> Option<Hover> {
    let index = LineIndex::new(text);
    let (start, end) = word_at(text, index.offset(pos))?;
    let name = &text[start..end];
    let doc = if let Some(p) = prelude::relation(name) {
        Catalog::Concept(p).text()
    } else if let Some(r) = catalog::relation(name) {
        Catalog::Relation(r).text()
    } else {
        return None;
    };
    Some(Hover {
        range: index.range(start, end),
        markdown: format!("```\n{}```", doc),
    })
}

/// What a completion proposes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompletionKind {
    /// A relation of the catalog.
    Relation,
    /// A concept of the prelude.
    Concept,
    /// A relation the program defines.
    Helper,
    /// A value of a closed string column.
    Value,
}

/// One thing that can be written at the cursor.
#[derive(Clone, Debug, PartialEq)]
pub struct Completion {
    /// What is shown and matched against what is typed.
    pub label: String,
    /// What it is: a signature, or the column a value belongs to.
    pub detail: String,
    /// Its documentation.
    pub documentation: String,
    /// The text written, a snippet with `${1:X}` placeholders for a relation's arguments.
    pub insert_text: String,
    /// What it is.
    pub kind: CompletionKind,
}

/// `name(${1:A}, ${2:B})`: a relation written with its columns as placeholders.
fn template(name: &str, columns: &[&str]) -> String {
    let args: Vec<String> = columns
        .iter()
        .enumerate()
        .map(|(i, c)| format!("${{{}:{c}}}", i + 1))
        .collect();
    format!("{name}({})", args.join(", "))
}

/// The atom whose argument list holds byte `offset` (outside any string): its name and the
/// argument's position, read back from `offset` to the unmatched `(` (on any line of the clause).
fn enclosing_argument(text: &str, offset: usize) -> Option<(&str, usize)> {
    let mut depth = 0usize;
    let mut commas = 0usize;
    let mut in_string = false;
    let before = &text[..offset];
    for (i, c) in before.char_indices().rev() {
        match c {
            '"' => in_string = !in_string,
            _ if in_string => {}
            ')' | '}' => depth += 1,
            '(' | '{' if depth > 0 => depth -= 1,
            '{' => return None,
            '(' => {
                let name_end = before[..i].trim_end().len();
                let name_start = before[..name_end]
                    .char_indices()
                    .rev()
                    .take_while(|&(_, c)| c.is_ascii_alphanumeric() || c == '_')
                    .last()
                    .map(|(k, _)| k)?;
                return Some((&before[name_start..name_end], commas));
            }
            ',' if depth == 0 => commas += 1,
            '.' if depth == 0 => return None,
            _ => {}
        }
    }
    None
}

/// What can be written at `pos`: inside a string argument of a closed column (a category, a
/// direction, a lane type), its values; elsewhere the relations of the catalog and the prelude
/// and the program's own, each with its arguments as placeholders.
pub fn completions(text: &str, pos: Position) -> Vec<Completion> {
    let index = LineIndex::new(text);
    let offset = index.offset(pos);
    match in_string_or_comment(text, offset) {
        Some(false) => return Vec::new(),
        Some(true) => return value_completions(text, offset),
        None => {}
    }
    let mut out: Vec<Completion> = catalog::catalog()
        .iter()
        .map(|r| Completion {
            label: r.name.to_string(),
            detail: r.signature(),
            documentation: r.doc.to_string(),
            insert_text: template(
                r.name,
                &r.columns.iter().map(|c| c.name).collect::<Vec<_>>(),
            ),
            kind: CompletionKind::Relation,
        })
        .collect();
    out.extend(
        prelude::relations()
            .iter()
            .filter(|p| !prelude::is_helper(p))
            .map(|p| Completion {
                label: p.name.clone(),
                detail: p.signature(),
                documentation: p.doc.clone(),
                insert_text: template(
                    &p.name,
                    &p.columns
                        .iter()
                        .map(|(n, _)| n.as_str())
                        .collect::<Vec<_>>(),
                ),
                kind: CompletionKind::Concept,
            }),
    );
    let (program, _) = scenalog_rules::parse(text);
    let mut own: Vec<(String, usize)> = program
        .clauses
        .iter()
        .map(|c| (c.head.pred.clone(), c.head.args.len()))
        .collect();
    own.sort();
    own.dedup();
    for (name, arity) in own {
        if out.iter().any(|c| c.label == name) {
            continue;
        }
        let columns: Vec<String> = (1..=arity).map(|i| format!("A{i}")).collect();
        out.push(Completion {
            detail: format!("{name}/{arity} (this program)"),
            documentation: String::new(),
            insert_text: template(
                &name,
                &columns.iter().map(String::as_str).collect::<Vec<_>>(),
            ),
            label: name,
            kind: CompletionKind::Helper,
        });
    }
    out
}

/// The values of the closed column whose string argument holds `offset` (inside the string).
fn value_completions(text: &str, offset: usize) -> Vec<Completion> {
    let Some(open) = text[..offset].rfind('"') else {
        return Vec::new();
    };
    let Some((name, arg)) = enclosing_argument(text, open) else {
        return Vec::new();
    };
    let Some(column) = catalog::relation(name).and_then(|r| r.columns.get(arg)) else {
        return Vec::new();
    };
    if column.ty != ColType::Str {
        return Vec::new();
    }
    column
        .values
        .iter()
        .map(|v| Completion {
            label: v.to_string(),
            detail: format!("{name}'s column {} ({})", arg + 1, column.name),
            documentation: String::new(),
            insert_text: v.to_string(),
            kind: CompletionKind::Value,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_count_utf16_units_and_round_trip() {
        let text = "a\n// é 😀 x\nb";
        let index = LineIndex::new(text);
        let x = text.find('x').expect("x");
        // "// " 3, "é" 1, " " 1, "😀" 2, " " 1.
        assert_eq!(
            index.position(x),
            Position {
                line: 1,
                character: 8
            }
        );
        assert_eq!(index.offset(index.position(x)), x);
        for offset in 0..=text.len() {
            if text.is_char_boundary(offset) {
                assert_eq!(index.offset(index.position(offset)), offset, "{offset}");
            }
        }
        // Past a line's end or the last line: clamped.
        let far = Position {
            line: 0,
            character: 99,
        };
        assert_eq!(index.offset(far), 1);
        let below = Position {
            line: 9,
            character: 0,
        };
        assert_eq!(index.offset(below), text.len());
    }

    #[test]
    fn the_argument_under_the_cursor_is_found_across_nesting() {
        let text = "referred(X, T) :- near(X, Y, T, D), category(Y, \"PED";
        let at = text.len() - 4;
        assert_eq!(enclosing_argument(text, at), Some(("category", 1)));
        let inner = "r(X) :- a(X, f(1, \"(\"), ";
        assert_eq!(enclosing_argument(inner, inner.len()), Some(("a", 2)));
        assert_eq!(enclosing_argument("r(X) :- a(X).", 13), None);
    }
}
