//! Soufflé and Prolog habits that people and language models bring to Scenalog: `;` disjunction,
//! `\+`, `count(C) : {…}`, `.output`/`.input`, `.decl` with `symbol`/`number`, single-quoted
//! strings and unknown string escapes. Each recognised habit is an E0001 whose hint shows the
//! corrected text and whose fix (see [`crate::apply_fix`]) makes it; the checker applies the
//! fixes to check the rest of the program as it would read once they are made.

use crate::ast::Span;
use crate::diagnostics::{self, error};
use crate::lexer::{lex, Tok, Token};
use crate::Diagnostic;

/// At most this many rules from one disjunctive clause (the product of its alternatives).
const MAX_ALTERNATIVES: usize = 16;
/// At most this depth of nested parenthesised disjunctions.
const MAX_NESTING: usize = 4;

/// Every habit recognised in `source`, in source order.
pub(crate) fn scan(source: &str) -> Vec<Diagnostic> {
    let (toks, _) = lex(source);
    let closing = closing_parens(&toks);
    let mut out = Vec::new();
    let mut i = 0;
    while i < toks.len() && toks[i].tok != Tok::Eof {
        let end = if is_directive(source, &toks, i) {
            directive(source, &toks, i, &mut out)
        } else {
            clause(source, &toks, &closing, i, &mut out)
        };
        i = end.max(i + 1);
    }
    out
}

/// For each token, the index of the `)` closing it when it is a `(` closed before the next `.`,
/// found in one pass with a stack (so nested calls cost no rescan per level).
fn closing_parens(toks: &[Token<'_>]) -> Vec<Option<usize>> {
    let mut closing = vec![None; toks.len()];
    let mut open: Vec<usize> = Vec::new();
    for (n, t) in toks.iter().enumerate() {
        match t.tok {
            Tok::LParen => open.push(n),
            Tok::RParen => {
                if let Some(o) = open.pop() {
                    closing[o] = Some(n);
                }
            }
            Tok::Dot | Tok::Eof => open.clear(),
            _ => {}
        }
    }
    closing
}

/// Whether token `i` is a `.` that starts a directive (`.decl`, `.output`, …): at the start of
/// its line and glued to a name.
fn is_directive(source: &str, toks: &[Token<'_>], i: usize) -> bool {
    let (Some(dot), Some(next)) = (toks.get(i), toks.get(i + 1)) else {
        return false;
    };
    dot.tok == Tok::Dot
        && matches!(next.tok, Tok::Ident(_))
        && next.span.start == dot.span.end
        && source[..dot.span.start]
            .chars()
            .rev()
            .find(|&c| c == '\n' || !c.is_whitespace())
            .is_none_or(|c| c == '\n')
}

/// The end of the line holding byte `at`, including its newline.
fn line_end(source: &str, at: usize) -> usize {
    source[at..].find('\n').map_or(source.len(), |k| at + k + 1)
}

/// Handles the directive at token `i`; returns the index of the first token after it.
fn directive(source: &str, toks: &[Token<'_>], i: usize, out: &mut Vec<Diagnostic>) -> usize {
    let dot = &toks[i];
    let Tok::Ident(name) = toks[i + 1].tok else {
        return i + 1;
    };
    if name == "decl" {
        return decl(source, toks, i, out);
    }
    let end = line_end(source, dot.span.start);
    let next = toks
        .iter()
        .position(|t| t.span.start >= end || t.tok == Tok::Eof)
        .unwrap_or(toks.len());
    let line = source[dot.span.start..end].trim_end();
    let hint = match name {
        "output" | "printsize" => format!(
            "Scenalog has no `.{name}`: `referred` (and `related`) are what is reported; delete \
             the line `{line}`"
        ),
        "input" => format!(
            "Scenalog has no `.input`: catalog relations come from the logs and helpers from the \
             program's rules and facts; delete the line `{line}`"
        ),
        "type" => format!(
            "Scenalog has no `.type`: column types are track, time, lane, str, float and int; \
             delete the line `{line}`"
        ),
        _ => return next,
    };
    out.push(
        error(
            diagnostics::SYNTAX,
            dot.span.to(toks[i + 1].span),
            format!("syntax error: `.{name}` is Soufflé, not Scenalog"),
        )
        .with_hint(hint)
        .with_edit(Span::new(dot.span.start, end), ""),
    );
    next
}

/// The Scenalog type for a Soufflé one.
fn souffle_type(t: &str) -> Option<&'static str> {
    match t {
        "symbol" | "Symbol" | "string" => Some("str"),
        "number" | "unsigned" | "integer" => Some("int"),
        _ => None,
    }
}

/// `.decl name(C: type, …)` with Soufflé types: each becomes the Scenalog type (for `referred`
/// and `related`, the required ones).
fn decl(source: &str, toks: &[Token<'_>], i: usize, out: &mut Vec<Diagnostic>) -> usize {
    let name = match toks.get(i + 2).map(|t| &t.tok) {
        Some(Tok::Ident(n)) => *n,
        _ => return i + 2,
    };
    let required: Option<&[&str]> = match name {
        "referred" => Some(&["track", "time"]),
        "related" => Some(&["track", "track", "time"]),
        _ => None,
    };
    let mut j = i + 3;
    let mut col = 0;
    let mut edits = Vec::new();
    while let Some(t) = toks.get(j) {
        match t.tok {
            Tok::RParen | Tok::Eof | Tok::Dot => break,
            Tok::Colon => {
                if let Some(Token {
                    tok: Tok::Ident(ty),
                    span,
                }) = toks.get(j + 1)
                {
                    let want = match required {
                        Some(r) => r.get(col).copied().filter(|w| {
                            w != ty
                                && (souffle_type(ty).is_some()
                                    || scenalog_facts::catalog::ColType::parse(ty).is_none())
                        }),
                        None => souffle_type(ty),
                    };
                    if let Some(w) = want {
                        edits.push((*span, w));
                    }
                    col += 1;
                    j += 1;
                }
            }
            _ => {}
        }
        j += 1;
    }
    let end = toks.get(j).map_or(source.len(), |t| t.span.end);
    if !edits.is_empty() {
        let start = toks[i].span.start;
        let mut fixed = source[start..end].to_string();
        for (span, w) in edits.iter().rev() {
            fixed.replace_range(span.start - start..span.end - start, w);
        }
        let d = error(
            diagnostics::SYNTAX,
            edits[0].0,
            format!(
                "syntax error: `{}` is not a Scenalog column type",
                &source[edits[0].0.start..edits[0].0.end]
            ),
        );
        // Soufflé's integer types are a Scenalog int, time or float by what the column holds;
        // the checker infers it, so the fix drops the declaration rather than guess (an `int`
        // for a frame would turn every use into a type error).
        let integer = edits.iter().any(|(span, _)| {
            matches!(
                &source[span.start..span.end],
                "number" | "unsigned" | "integer"
            )
        });
        let d = if integer && required.is_none() {
            d.with_hint(format!(
                "Scenalog's types are track, time (a frame), lane, str, float and int; column types are inferred, so drop the line `{}` or write the type its column holds",
                source[start..end].trim_end()
            ))
            .with_edit(Span::new(start, line_end(source, end.saturating_sub(1)).max(end)), "")
        } else {
            let mut d = d.with_hint(format!(
                "column types are track, time, lane, str, float and int: `{fixed}`"
            ));
            for (span, w) in &edits {
                d = d.with_edit(*span, *w);
            }
            d
        };
        out.push(d);
    }
    j + 1
}

/// Handles the clause starting at token `i`; returns the index after its final `.`.
fn clause(
    source: &str,
    toks: &[Token<'_>],
    closing: &[Option<usize>],
    i: usize,
    out: &mut Vec<Diagnostic>,
) -> usize {
    let mut j = i;
    let mut depth = 0i32;
    let mut if_at = None;
    while let Some(t) = toks.get(j) {
        match t.tok {
            Tok::Eof => break,
            Tok::LParen | Tok::LBrace => depth += 1,
            Tok::RParen | Tok::RBrace => depth -= 1,
            Tok::If if if_at.is_none() => if_at = Some(j),
            Tok::Dot if depth <= 0 => break,
            _ => {}
        }
        if j > i && is_directive(source, toks, j) {
            break;
        }
        j += 1;
    }
    let end = j.min(toks.len().saturating_sub(1));
    let ended = toks.get(end).is_some_and(|t| t.tok == Tok::Dot);
    for k in i..end {
        token_habits(source, toks, closing, k, out);
    }
    if let (Some(f), true) = (if_at, ended) {
        disjunction(source, toks, i, f, end, out);
    }
    end + 1
}

/// The text of a token's source (for error tokens: the character the lexer stopped at).
fn starts_with(source: &str, t: &Token<'_>, c: u8) -> bool {
    source.as_bytes().get(t.span.start) == Some(&c)
}

/// `ego` written as an argument of a body atom (`near(ego, X, T, D)`): the ego vehicle is an
/// object bound by `ego(E)`, not a constant. The fix binds it before the atom and uses the
/// variable, so the program means the ego (writing `Ego` alone would be a variable matching any
/// object, and `_` after that any object too).
fn ego_constant(source: &str, toks: &[Token<'_>], k: usize, out: &mut Vec<Diagnostic>) {
    let t = &toks[k];
    let before = k.checked_sub(1).map(|p| &toks[p].tok);
    let after = toks.get(k + 1).map(|n| &n.tok);
    if !matches!(before, Some(Tok::LParen | Tok::Comma))
        || !matches!(after, Some(Tok::Comma | Tok::RParen))
    {
        return;
    }
    // The atom's opening parenthesis, its predicate, and a `!` before it.
    let mut depth = 0i32;
    let mut open = None;
    for p in (0..k).rev() {
        match toks[p].tok {
            Tok::RParen | Tok::RBrace => depth += 1,
            Tok::LParen if depth == 0 => {
                open = Some(p);
                break;
            }
            Tok::LParen | Tok::LBrace => depth -= 1,
            Tok::Dot | Tok::If => return,
            _ => {}
        }
    }
    let Some(pred) = open.and_then(|o| o.checked_sub(1)) else {
        return;
    };
    let Tok::Ident(name) = toks[pred].tok else {
        return;
    };
    if name == "ego" {
        return;
    }
    // Only in a body: a `:-` between the clause's start and the atom.
    let in_body = toks[..pred]
        .iter()
        .rev()
        .take_while(|x| x.tok != Tok::Dot)
        .any(|x| x.tok == Tok::If);
    if !in_body {
        return;
    }
    let start = match pred.checked_sub(1).map(|b| &toks[b]) {
        Some(b) if b.tok == Tok::Bang || b.tok == Tok::Ident("not") => b.span.start,
        _ => toks[pred].span.start,
    };
    out.push(
        error(
            diagnostics::SYNTAX,
            t.span,
            "syntax error: `ego` is not a value: the ego vehicle is an object, bound by `ego(E)`",
        )
        .with_hint(format!(
            "bind the ego vehicle and use its variable: `ego(Ego), {}Ego{}`",
            &source[start..t.span.start],
            &source[t.span.end..atom_end(toks, k).max(t.span.end)]
        ))
        .with_edit(Span::new(start, start), "ego(Ego), ")
        .with_edit(t.span, "Ego"),
    );
}

/// The byte after the `)` that closes the atom whose argument token `k` is.
fn atom_end(toks: &[Token<'_>], k: usize) -> usize {
    let mut depth = 0i32;
    for t in &toks[k..] {
        match t.tok {
            Tok::LParen | Tok::LBrace => depth += 1,
            Tok::RParen if depth == 0 => return t.span.end,
            Tok::RParen | Tok::RBrace => depth -= 1,
            Tok::Dot | Tok::Eof => return t.span.start,
            _ => {}
        }
    }
    toks[k].span.end
}

/// Habits that one token shows: `\+`, single quotes, bad escapes, `count(C) :`, `ego` as a value.
fn token_habits(
    source: &str,
    toks: &[Token<'_>],
    closing: &[Option<usize>],
    k: usize,
    out: &mut Vec<Diagnostic>,
) {
    let t = &toks[k];
    if t.tok == Tok::Ident("ego") {
        ego_constant(source, toks, k, out);
        return;
    }
    match &t.tok {
        Tok::Error(_) if starts_with(source, t, b'\\') => {
            if let Some(plus) = toks
                .get(k + 1)
                .filter(|p| p.tok == Tok::Plus && p.span.start == t.span.end)
            {
                let mut end = plus.span.end;
                while source.as_bytes().get(end) == Some(&b' ') {
                    end += 1;
                }
                let line = corrected_line(source, Span::new(t.span.start, end), "!");
                out.push(
                    error(
                        diagnostics::SYNTAX,
                        t.span.to(plus.span),
                        "syntax error: `\\+` is Prolog negation; Scenalog writes `!`",
                    )
                    .with_hint(format!("write `{line}`"))
                    .with_edit(Span::new(t.span.start, end), "!"),
                );
            }
        }
        Tok::Error(_) if starts_with(source, t, b'\'') => {
            let rest = &source[t.span.end..];
            let Some(close) = rest.find(['\'', '\n']) else {
                return;
            };
            if rest.as_bytes()[close] != b'\'' {
                return;
            }
            let inner = &rest[..close];
            let quoted = format!("{inner:?}");
            let span = Span::new(t.span.start, t.span.end + close + 1);
            let line = corrected_line(source, span, &quoted);
            out.push(
                error(
                    diagnostics::SYNTAX,
                    span,
                    "syntax error: a single-quoted string",
                )
                .with_hint(format!("strings are written in double quotes: `{line}`"))
                .with_edit(span, quoted),
            );
        }
        Tok::Error(m) if m.starts_with("an unknown escape") => {
            // The token ends just after the escaped character; the backslash is before it.
            let text = &source[t.span.start..t.span.end];
            let Some(slash) = text.rfind('\\') else {
                return;
            };
            let at = t.span.start + slash;
            let line = corrected_line(source, Span::new(at, at + 1), "\\\\");
            out.push(
                error(diagnostics::SYNTAX, t.span, format!("syntax error: {m}"))
                    .with_hint(format!("to write a backslash, double it: `{line}`"))
                    .with_edit(Span::new(at, at + 1), "\\\\"),
            );
        }
        Tok::Ident(f @ ("count" | "sum" | "min" | "max")) => {
            let Some(open) = toks.get(k + 1).filter(|o| o.tok == Tok::LParen) else {
                return;
            };
            let Some(c) = closing.get(k + 1).copied().flatten() else {
                return;
            };
            if toks.get(c + 1).map(|x| &x.tok) != Some(&Tok::Colon) {
                return; // `min(A, B)` the function, not an aggregate.
            }
            let inner = source[open.span.end..toks[c].span.start].trim();
            let replacement = if *f == "count" {
                String::new()
            } else {
                format!(" {inner}")
            };
            let span = Span::new(open.span.start, toks[c].span.end);
            let line = corrected_line(source, span, &replacement);
            let what = if *f == "count" {
                "`count` takes no argument: it counts the matching tuples of the braces".to_string()
            } else {
                format!("`{f}` takes its expression without parentheses")
            };
            out.push(
                error(
                    diagnostics::SYNTAX,
                    t.span.to(toks[c].span),
                    format!("syntax error: {what}"),
                )
                .with_hint(format!("write `{line}`"))
                .with_edit(span, replacement),
            );
        }
        _ => {}
    }
}

/// The line holding `span` with `span` replaced by `with`, trimmed.
/// Most bytes of the line a hint quotes on each side of a correction: a long line is cut there
/// (marked `…`), so many habits on one huge line do not each copy it whole.
const LINE_CONTEXT: usize = 120;

/// The line holding `span` with `span` replaced by `with` (at most [`LINE_CONTEXT`] bytes of it
/// on each side).
fn corrected_line(source: &str, span: Span, with: &str) -> String {
    let mut from = span.start.saturating_sub(LINE_CONTEXT);
    while !source.is_char_boundary(from) {
        from -= 1;
    }
    let mut to = (span.end + LINE_CONTEXT).min(source.len());
    while !source.is_char_boundary(to) {
        to += 1;
    }
    let (start, cut_start) = match source[from..span.start].rfind('\n') {
        Some(k) => (from + k + 1, false),
        None => (from, from > 0 && source.as_bytes()[from - 1] != b'\n'),
    };
    let (end, cut_end) = match source[span.end..to].find('\n') {
        Some(k) => (span.end + k, false),
        None => (to, to < source.len() && source.as_bytes()[to] != b'\n'),
    };
    format!(
        "{}{}{with}{}{}",
        if cut_start { "… " } else { "" },
        &source[start..span.start],
        &source[span.end..end],
        if cut_end { " …" } else { "" },
    )
    .trim()
    .to_string()
}

/// Whether a token is the `;` the lexer could not read.
fn is_semicolon(source: &str, t: &Token<'_>) -> bool {
    matches!(t.tok, Tok::Error(_)) && starts_with(source, t, b';')
}

/// `head :- A ; B.` (or a parenthesised `(A ; B)` among other literals): one rule per
/// alternative.
fn disjunction(
    source: &str,
    toks: &[Token<'_>],
    first: usize,
    if_at: usize,
    dot: usize,
    out: &mut Vec<Diagnostic>,
) {
    let body = &toks[if_at + 1..dot];
    let Some(semi) = body.iter().find(|t| is_semicolon(source, t)) else {
        return;
    };
    let message = "syntax error: Scenalog has no `;` (disjunction)";
    let Some(alts) = alternatives(source, body, 0).filter(|a| a.len() <= MAX_ALTERNATIVES) else {
        out.push(
            error(diagnostics::SYNTAX, semi.span, message)
                .with_hint("write one rule per alternative, each with the same head"),
        );
        return;
    };
    let head = source[toks[first].span.start..toks[if_at].span.start].trim_end();
    let rules: Vec<String> = alts.iter().map(|b| format!("{head} :- {b}.")).collect();
    out.push(
        error(diagnostics::SYNTAX, semi.span, message)
            .with_hint(format!(
                "write one rule per alternative, each with the same head:\n{}",
                rules.join("\n")
            ))
            .with_edit(
                Span::new(toks[first].span.start, toks[dot].span.end),
                rules.join("\n"),
            ),
    );
}

/// The conjunctions a body with `;` stands for, as text; `None` when it has a shape this does
/// not rewrite (a `;` inside braces, unbalanced parentheses, too deep).
fn alternatives(source: &str, toks: &[Token<'_>], nesting: usize) -> Option<Vec<String>> {
    if nesting > MAX_NESTING || toks.is_empty() {
        return None;
    }
    let mut out = Vec::new();
    for alt in split_top(toks, |t| is_semicolon(source, t))? {
        // The product of each literal's alternatives.
        let mut conj: Vec<String> = vec![String::new()];
        for item in split_top(alt, |t| t.tok == Tok::Comma)? {
            let (first, last) = (item.first()?, item.last()?);
            let wrapped = first.tok == Tok::LParen
                && last.tok == Tok::RParen
                && split_top(&item[1..item.len() - 1], |_| false).is_some()
                && matching(item) == Some(item.len() - 1);
            let options = if wrapped {
                alternatives(source, &item[1..item.len() - 1], nesting + 1)?
            } else {
                if item.iter().any(|t| is_semicolon(source, t)) {
                    return None; // inside braces or an expression
                }
                vec![source[first.span.start..last.span.end].to_string()]
            };
            let mut next = Vec::new();
            for c in &conj {
                for o in &options {
                    next.push(if c.is_empty() {
                        o.clone()
                    } else {
                        format!("{c}, {o}")
                    });
                    if next.len() > MAX_ALTERNATIVES {
                        return None;
                    }
                }
            }
            conj = next;
        }
        out.extend(conj);
        if out.len() > MAX_ALTERNATIVES {
            return None;
        }
    }
    Some(out)
}

/// The index of the token closing the parenthesis that opens `toks`.
fn matching(toks: &[Token<'_>]) -> Option<usize> {
    let mut depth = 0;
    for (n, t) in toks.iter().enumerate() {
        match t.tok {
            Tok::LParen | Tok::LBrace => depth += 1,
            Tok::RParen | Tok::RBrace => {
                depth -= 1;
                if depth == 0 {
                    return Some(n);
                }
            }
            _ => {}
        }
    }
    None
}

/// `toks` split at the separators outside parentheses and braces; `None` if they do not balance
/// or a part is empty.
fn split_top<'t, 'a>(
    toks: &'t [Token<'a>],
    is_sep: impl Fn(&Token<'a>) -> bool,
) -> Option<Vec<&'t [Token<'a>]>> {
    let mut parts = Vec::new();
    let mut depth = 0i32;
    let mut start = 0;
    for (n, t) in toks.iter().enumerate() {
        match t.tok {
            Tok::LParen | Tok::LBrace => depth += 1,
            Tok::RParen | Tok::RBrace => {
                depth -= 1;
                if depth < 0 {
                    return None;
                }
            }
            _ if depth == 0 && is_sep(t) => {
                if n == start {
                    return None;
                }
                parts.push(&toks[start..n]);
                start = n + 1;
            }
            _ => {}
        }
    }
    if depth != 0 || start >= toks.len() {
        return None;
    }
    parts.push(&toks[start..]);
    Some(parts)
}

/// W0514 for each `%` that follows an operand on its line and is followed by what reads as more
/// of the expression (a number, a variable or `(`, then an operator, `)`, `,` or `.`): in
/// Scenalog `%` starts a comment (Prolog's habit), so `X % 2 = 0` hides `2 = 0` and what follows
/// on the line; Soufflé's remainder is written `mod`. A comment after code (`D < 5 % metres`)
/// is left alone.
pub(crate) fn percent_comments(source: &str) -> Vec<Diagnostic> {
    let (toks, _) = lex(source);
    let mut out = Vec::new();
    for pair in toks.windows(2) {
        let [t, next] = pair else { continue };
        let operand = matches!(
            t.tok,
            Tok::Var(_) | Tok::Int(_) | Tok::Float(_) | Tok::RParen | Tok::Ident(_)
        );
        let Some(gap) = source.get(t.span.end..next.span.start) else {
            continue;
        };
        let Some(at) = gap.find('%') else { continue };
        if !operand || !gap[..at].chars().all(|c| c == ' ' || c == '\t') {
            continue;
        }
        let start = t.span.end + at;
        let line_end = source[start..]
            .find('\n')
            .map_or(source.len(), |n| start + n);
        let rest = source[start + 1..line_end].trim_start();
        if !reads_as_operand_then_operator(rest) {
            continue;
        }
        out.push(
            crate::diagnostics::warning(
                diagnostics::PERCENT_COMMENT,
                Span::new(start, start + 1),
                "`%` starts a comment here, so the rest of the line is not read",
            )
            .with_hint("the remainder of a division is written `mod` (`X mod 2`)")
            .with_edit(Span::new(start, start + 1), spaced_mod(source, start)),
        );
    }
    out
}

/// Whether `text` starts with a number, a variable or `(`, then (after spaces) an operator,
/// `)`, `,` or `.`.
fn reads_as_operand_then_operator(text: &str) -> bool {
    let b = text.as_bytes();
    let Some(&first) = b.first() else {
        return false;
    };
    let mut i = if first == b'(' {
        return true;
    } else if first.is_ascii_digit() || first.is_ascii_uppercase() || first == b'_' {
        b.iter()
            .position(|c| !(c.is_ascii_alphanumeric() || *c == b'_' || *c == b'.'))
            .unwrap_or(b.len())
    } else {
        return false;
    };
    // A number ending the clause (`X % 2.`) is read with its `.`.
    if i == b.len() && text.ends_with('.') {
        return true;
    }
    while i < b.len() && b[i] == b' ' {
        i += 1;
    }
    b.get(i).is_some_and(|c| b"=<>!+-*/^),.".contains(c))
}

/// `mod` for the `%` at `at`, with a space on each side that has none.
fn spaced_mod(source: &str, at: usize) -> String {
    let before = source[..at].ends_with([' ', '\t']);
    let after = source[at + 1..].starts_with([' ', '\t']);
    format!(
        "{}mod{}",
        if before { "" } else { " " },
        if after { "" } else { " " }
    )
}
