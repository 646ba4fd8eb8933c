//! What an editor asks of a program while it is typed (`scenalog lsp`): the checker's diagnostics
//! with their places and fixes, the documentation of the relation under the cursor, and what can
//! be written where the cursor is. Everything works on the program's text; places are
//! [`Position`]s as editors count them (lines from 0, columns in UTF-16 code units, the Language
//! Server Protocol's default), turned from and into byte offsets by [`LineIndex`].

use scenalog_facts::catalog::{self, ColType};
use scenalog_rules::ast::{Atom, Expr, ExprKind, Literal};
use scenalog_rules::prelude;
use scenalog_rules::{check, CheckOptions, Program, Severity};

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
pub struct LineIndex<'t> {
    text: &'t str,
    line_starts: Vec<usize>,
}

impl<'t> LineIndex<'t> {
    /// The index of `text`.
    pub fn new(text: &'t str) -> LineIndex<'t> {
        let mut line_starts = vec![0];
        line_starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        LineIndex { text, line_starts }
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

/// Whether `c` may be part of a name (a relation's or a variable's).
fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The identifier around byte `offset`: its bytes, or `None` off an identifier or inside a
/// string or a comment.
fn word_at(text: &str, offset: usize) -> Option<(usize, usize)> {
    let offset = offset.min(text.len());
    if in_string_or_comment(text, offset).is_some() {
        return None;
    }
    let start = text[..offset]
        .char_indices()
        .rev()
        .take_while(|&(_, c)| is_ident(c))
        .last()
        .map_or(offset, |(i, _)| i);
    let end = text[offset..]
        .char_indices()
        .find(|&(_, c)| !is_ident(c))
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
/// (types, units, closed values) or definition, as `scenalog catalog NAME` prints it; for a
/// variable, its type and the column it comes from.
pub fn hover(text: &str, pos: Position) -> Option<Hover> {
    let index = LineIndex::new(text);
    let (start, end) = word_at(text, index.offset(pos))?;
    let name = &text[start..end];
    let doc = if let Some(p) = prelude::relation(name) {
        Catalog::Concept(p).text()
    } else if let Some(r) = catalog::relation(name) {
        Catalog::Relation(r).text()
    } else {
        let (program, _) = scenalog_rules::parse(text);
        let all = names(&program);
        let n = name_at(&all, start).filter(|n| n.start == start)?;
        format!("{name}: {}\n", variable_type(text, &program, n)?)
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
                    .take_while(|&(_, c)| is_ident(c))
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

/// What a name in a program is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum NameKind {
    /// A relation's name in an atom (in a head when `head`).
    Relation { head: bool },
    /// A variable, within its clause.
    Variable { clause: usize },
}

/// One name written in a program: its text, its bytes and what it is.
#[derive(Clone, Debug, PartialEq)]
struct Name {
    text: String,
    start: usize,
    end: usize,
    kind: NameKind,
}

/// Every relation and variable name written in `program`, in source order.
fn names(program: &Program) -> Vec<Name> {
    fn expr(e: &Expr, clause: usize, out: &mut Vec<Name>) {
        match &e.kind {
            ExprKind::Var(v) => out.push(Name {
                text: v.clone(),
                start: e.span.start,
                end: e.span.end,
                kind: NameKind::Variable { clause },
            }),
            ExprKind::Neg(a) => expr(a, clause, out),
            ExprKind::Binary(_, a, b) => {
                expr(a, clause, out);
                expr(b, clause, out);
            }
            ExprKind::Call(_, args) => args.iter().for_each(|a| expr(a, clause, out)),
            _ => {}
        }
    }
    fn atom(a: &Atom, head: bool, clause: usize, out: &mut Vec<Name>) {
        out.push(Name {
            text: a.pred.clone(),
            start: a.pred_span.start,
            end: a.pred_span.end,
            kind: NameKind::Relation { head },
        });
        a.args.iter().for_each(|e| expr(e, clause, out));
    }
    fn literal(l: &Literal, clause: usize, out: &mut Vec<Name>) {
        match l {
            Literal::Pos(a) | Literal::Neg(a, _) => atom(a, false, clause, out),
            Literal::Cmp(c) => {
                expr(&c.lhs, clause, out);
                expr(&c.rhs, clause, out);
            }
            Literal::Agg(g) => {
                expr(&g.result, clause, out);
                if let Some(t) = &g.target {
                    expr(t, clause, out);
                }
                g.body.iter().for_each(|l| literal(l, clause, out));
            }
        }
    }
    let mut out = Vec::new();
    for (i, c) in program.clauses.iter().enumerate() {
        atom(&c.head, true, i, &mut out);
        c.body.iter().for_each(|l| literal(l, i, &mut out));
    }
    out.sort_by_key(|n| n.start);
    out
}

/// The name at byte `offset` (its last byte's end counts: a cursor just after a name is on it).
fn name_at(names: &[Name], offset: usize) -> Option<&Name> {
    names.iter().find(|n| n.start <= offset && offset <= n.end)
}

/// The names that are the same as `n`: the relation's every use, or the variable's in its clause.
fn same<'a>(names: &'a [Name], n: &Name) -> impl Iterator<Item = &'a Name> {
    let (text, kind) = (n.text.clone(), n.kind);
    names.iter().filter(move |m| {
        m.text == text
            && match (kind, m.kind) {
                (NameKind::Relation { .. }, NameKind::Relation { .. }) => true,
                (NameKind::Variable { clause: a }, NameKind::Variable { clause: b }) => a == b,
                _ => false,
            }
    })
}

/// Where a name is defined.
#[derive(Clone, Debug, PartialEq)]
pub enum Definition {
    /// In the program itself: the heads of its rules (or the variable's first use).
    Here(Vec<Range>),
    /// In the prelude: its `.decl` line in [`prelude_file`].
    Prelude(Range),
}

/// The prelude's file in the source tree this binary was built from, when it is there (an
/// installed binary's tree may be gone; the prelude's text is in the binary either way).
pub fn prelude_file() -> Option<std::path::PathBuf> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(prelude::PATH);
    path.is_file().then_some(path)
}

/// Where the relation or variable at `pos` is defined: the program's rules for a relation it
/// defines, the prelude's declaration for a prelude concept, a variable's first use in its
/// clause; `None` for a catalog relation (computed, not written anywhere) or off a name.
pub fn definition(text: &str, pos: Position) -> Option<Definition> {
    let index = LineIndex::new(text);
    let (program, _) = scenalog_rules::parse(text);
    let all = names(&program);
    let n = name_at(&all, index.offset(pos))?;
    let uses: Vec<&Name> = same(&all, n).collect();
    match n.kind {
        NameKind::Variable { .. } => {
            let first = uses.first()?;
            Some(Definition::Here(vec![index.range(first.start, first.end)]))
        }
        NameKind::Relation { .. } => {
            let heads: Vec<Range> = uses
                .iter()
                .filter(|m| m.kind == NameKind::Relation { head: true })
                .map(|m| index.range(m.start, m.end))
                .collect();
            if !heads.is_empty() {
                return Some(Definition::Here(heads));
            }
            prelude::relation(&n.text)?;
            let decl = format!(".decl {}(", n.text);
            let at = prelude::SOURCE.find(&decl)? + ".decl ".len();
            let prelude_index = LineIndex::new(prelude::SOURCE);
            Some(Definition::Prelude(
                prelude_index.range(at, at + n.text.len()),
            ))
        }
    }
}

/// Every use of the relation or variable at `pos` in the program (a variable's in its clause).
pub fn references(text: &str, pos: Position) -> Vec<Range> {
    let index = LineIndex::new(text);
    let (program, _) = scenalog_rules::parse(text);
    let all = names(&program);
    let Some(n) = name_at(&all, index.offset(pos)) else {
        return Vec::new();
    };
    same(&all, n).map(|m| index.range(m.start, m.end)).collect()
}

/// The edits renaming the relation or variable at `pos` to `new_name`: a relation the program
/// defines (not `referred` or `related`, whose names are the program's answer, nor a catalog
/// relation), or a variable within its clause. An error says why a rename cannot be done.
pub fn rename(text: &str, pos: Position, new_name: &str) -> Result<Vec<TextEdit>, String> {
    let index = LineIndex::new(text);
    let (program, _) = scenalog_rules::parse(text);
    let all = names(&program);
    let n = name_at(&all, index.offset(pos)).ok_or("no relation or variable here")?;
    let ident = |first: fn(char) -> bool| {
        new_name.chars().next().is_some_and(first) && new_name.chars().all(is_ident)
    };
    match n.kind {
        NameKind::Variable { .. } => {
            if !ident(|c| c.is_ascii_uppercase() || c == '_') || new_name == "_" {
                return Err(format!(
                    "`{new_name}` is not a variable name (a capital letter or `_`, then letters, digits, `_`)"
                ));
            }
            let clash = all.iter().any(|m| {
                m.text == new_name
                    && matches!((m.kind, n.kind), (NameKind::Variable { clause: a }, NameKind::Variable { clause: b }) if a == b)
            });
            if clash {
                return Err(format!("the clause already has a variable `{new_name}`"));
            }
        }
        NameKind::Relation { .. } => {
            if ["referred", "related"].contains(&n.text.as_str()) {
                return Err(format!("`{}` names the program's answer", n.text));
            }
            if !same(&all, n).any(|m| m.kind == NameKind::Relation { head: true }) {
                return Err(format!(
                    "`{}` is not defined in this program (the catalog's and the prelude's names are fixed)",
                    n.text
                ));
            }
            if !ident(|c| c.is_ascii_lowercase()) {
                return Err(format!(
                    "`{new_name}` is not a relation name (a small letter, then letters, digits, `_`)"
                ));
            }
            let taken = catalog::relation(new_name).is_some()
                || prelude::relation(new_name).is_some()
                || all
                    .iter()
                    .any(|m| m.text == new_name && matches!(m.kind, NameKind::Relation { .. }));
            if taken {
                return Err(format!("`{new_name}` is already a relation's name"));
            }
        }
    }
    Ok(same(&all, n)
        .map(|m| TextEdit {
            range: index.range(m.start, m.end),
            new_text: new_name.to_string(),
        })
        .collect())
}

/// One rule of the program, for an outline.
#[derive(Clone, Debug, PartialEq)]
pub struct Symbol {
    /// The relation the rule defines.
    pub name: String,
    /// The whole rule.
    pub range: Range,
    /// Its head's relation name.
    pub selection: Range,
}

/// The program's rules, in order, each named by the relation it defines.
pub fn symbols(text: &str) -> Vec<Symbol> {
    let index = LineIndex::new(text);
    let (program, _) = scenalog_rules::parse(text);
    program
        .clauses
        .iter()
        .map(|c| Symbol {
            name: c.head.pred.clone(),
            range: index.range(c.span.start, c.span.end),
            selection: index.range(c.head.pred_span.start, c.head.pred_span.end),
        })
        .collect()
}

/// The type of the variable `n` from the first column it fills whose type is known (a catalog
/// relation's, with its unit, a prelude concept's, or one the checker inferred for the program's
/// own relations when it checks).
fn variable_type(text: &str, program: &Program, n: &Name) -> Option<String> {
    let NameKind::Variable { clause } = n.kind else {
        return None;
    };
    let checked = check(text, &CheckOptions::default()).program;
    let c = program.clauses.get(clause)?;
    let atoms = std::iter::once(&c.head).chain(c.body.iter().filter_map(|l| match l {
        Literal::Pos(a) | Literal::Neg(a, _) => Some(a),
        _ => None,
    }));
    for a in atoms {
        for (i, arg) in a.args.iter().enumerate() {
            if !matches!(&arg.kind, ExprKind::Var(v) if *v == n.text) {
                continue;
            }
            if let Some(col) = catalog::relation(&a.pred).and_then(|r| r.columns.get(i)) {
                let unit = col.unit.symbol();
                let ty = if unit.is_empty() || col.ty == ColType::Time {
                    col.ty.to_string()
                } else {
                    format!("{}<{unit}>", col.ty)
                };
                return Some(format!(
                    "{ty}, from `{}`'s column {} ({})",
                    a.pred,
                    i + 1,
                    col.name
                ));
            }
            if let Some((name, ty)) = prelude::relation(&a.pred).and_then(|p| p.columns.get(i)) {
                return Some(format!(
                    "{}, from `{}`'s column {} ({name})",
                    ty.as_str(),
                    a.pred,
                    i + 1
                ));
            }
            let inferred = checked
                .as_ref()
                .and_then(|p| p.predicates.get(&a.pred))
                .and_then(|p| p.types.get(i));
            if let Some(ty) = inferred {
                return Some(format!(
                    "{}, from `{}`'s column {}",
                    ty.as_str(),
                    a.pred,
                    i + 1
                ));
            }
        }
    }
    None
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
