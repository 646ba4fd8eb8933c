//! The lexer: program text to tokens with byte spans. Comments (`//`, `%`, `/* */`) are skipped;
//! a leading `// description: …` comment is returned separately.

use crate::ast::Span;

/// The kinds of tokens.
#[derive(Debug, Clone, PartialEq)]
pub enum Tok<'a> {
    /// A lowercase identifier: predicate names and keywords (`not`, `count`, `decl`, …).
    Ident(&'a str),
    /// A variable: starts with an uppercase letter, or `_` followed by more characters.
    Var(&'a str),
    /// `_` alone.
    Wildcard,
    /// A string constant, unescaped.
    Str(String),
    /// An integer literal as written (digits only).
    Int(&'a str),
    /// A float literal as written.
    Float(&'a str),
    /// `(`
    LParen,
    /// `)`
    RParen,
    /// `{`
    LBrace,
    /// `}`
    RBrace,
    /// `,`
    Comma,
    /// `.`
    Dot,
    /// `:`
    Colon,
    /// `:-`
    If,
    /// `!`
    Bang,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
    /// `=`
    Eq,
    /// `!=`
    Ne,
    /// `+`
    Plus,
    /// `-`
    Minus,
    /// `*`
    Star,
    /// `/`
    Slash,
    /// `^` (power)
    Caret,
    /// Text the lexer could not read, with the reason.
    Error(String),
    /// The end of the text.
    Eof,
}

impl Tok<'_> {
    /// How the token is described in "expected …, found …" messages.
    pub fn describe(&self) -> String {
        match self {
            Tok::Ident(s) => format!("identifier `{s}`"),
            Tok::Var(s) => format!("variable `{s}`"),
            Tok::Wildcard => "`_`".into(),
            Tok::Str(s) => format!("string {s:?}"),
            Tok::Int(s) | Tok::Float(s) => format!("number `{s}`"),
            Tok::LParen => "`(`".into(),
            Tok::RParen => "`)`".into(),
            Tok::LBrace => "`{`".into(),
            Tok::RBrace => "`}`".into(),
            Tok::Comma => "`,`".into(),
            Tok::Dot => "`.`".into(),
            Tok::Colon => "`:`".into(),
            Tok::If => "`:-`".into(),
            Tok::Bang => "`!`".into(),
            Tok::Lt => "`<`".into(),
            Tok::Le => "`<=`".into(),
            Tok::Gt => "`>`".into(),
            Tok::Ge => "`>=`".into(),
            Tok::Eq => "`=`".into(),
            Tok::Ne => "`!=`".into(),
            Tok::Plus => "`+`".into(),
            Tok::Minus => "`-`".into(),
            Tok::Star => "`*`".into(),
            Tok::Slash => "`/`".into(),
            Tok::Caret => "`^`".into(),
            Tok::Error(m) => m.clone(),
            Tok::Eof => "the end of the program".into(),
        }
    }
}

/// A token and where it is.
#[derive(Debug, Clone, PartialEq)]
pub struct Token<'a> {
    /// What it is.
    pub tok: Tok<'a>,
    /// Where it is.
    pub span: Span,
}

/// The tokens of `source` (ending with [`Tok::Eof`]) and the leading description, if the first
/// comment before any token is `// description: …`.
pub fn lex(source: &str) -> (Vec<Token<'_>>, Option<String>) {
    let bytes = source.as_bytes();
    let mut toks = Vec::new();
    let mut description = None;
    let mut i = 0;
    let n = bytes.len();
    while i < n {
        let c = bytes[i];
        let start = i;
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        if c == b'/' && i + 1 < n && bytes[i + 1] == b'/' || c == b'%' {
            let end = source[i..].find('\n').map_or(n, |k| i + k);
            if toks.is_empty() && description.is_none() {
                let text = source[i..end]
                    .trim_start_matches('/')
                    .trim_start_matches('%')
                    .trim();
                if let Some(rest) = text.strip_prefix("description:") {
                    description = Some(rest.trim().to_string());
                }
            }
            i = end;
            continue;
        }
        if c == b'/' && i + 1 < n && bytes[i + 1] == b'*' {
            match source[i + 2..].find("*/") {
                Some(k) => i = i + 2 + k + 2,
                None => {
                    toks.push(Token {
                        tok: Tok::Error("an unterminated `/*` comment".into()),
                        span: Span::new(i, i + 2),
                    });
                    i = n;
                }
            }
            continue;
        }
        let next = bytes.get(i + 1).copied();
        let (tok, len) = match c {
            b'(' => one(Tok::LParen),
            b')' => one(Tok::RParen),
            b'{' => one(Tok::LBrace),
            b'}' => one(Tok::RBrace),
            b',' => one(Tok::Comma),
            b'.' => one(Tok::Dot),
            b':' if next == Some(b'-') => (Tok::If, 2),
            b':' => one(Tok::Colon),
            b'!' if next == Some(b'=') => (Tok::Ne, 2),
            b'!' => one(Tok::Bang),
            b'<' if next == Some(b'=') => (Tok::Le, 2),
            b'<' => one(Tok::Lt),
            b'>' if next == Some(b'=') => (Tok::Ge, 2),
            b'>' => one(Tok::Gt),
            b'=' => one(Tok::Eq),
            b'+' => one(Tok::Plus),
            b'-' => one(Tok::Minus),
            b'*' => one(Tok::Star),
            b'/' => one(Tok::Slash),
            b'^' => one(Tok::Caret),
            b'"' => {
                let (tok, len) = lex_string(source, i);
                if matches!(&tok, Tok::Error(m) if m.contains("unterminated")) {
                    // Show the whole bad string, but lex on after the quote so the clause's
                    // `.` is still seen and error recovery stops there.
                    toks.push(Token {
                        tok,
                        span: Span::new(i, i + len),
                    });
                    i += 1;
                    continue;
                }
                (tok, len)
            }
            b'0'..=b'9' => lex_number(source, i),
            b'a'..=b'z' | b'A'..=b'Z' | b'_' => {
                let mut j = i + 1;
                while j < n && (bytes[j].is_ascii_alphanumeric() || bytes[j] == b'_') {
                    j += 1;
                }
                let word = &source[i..j];
                let tok = if word == "_" {
                    Tok::Wildcard
                } else if c.is_ascii_uppercase() || c == b'_' {
                    Tok::Var(word)
                } else {
                    Tok::Ident(word)
                };
                (tok, j - i)
            }
            _ => {
                let ch = source[i..].chars().next().unwrap_or('?');
                (
                    Tok::Error(format!("an unexpected character {ch:?}")),
                    ch.len_utf8(),
                )
            }
        };
        i += len;
        toks.push(Token {
            tok,
            span: Span::new(start, i),
        });
    }
    toks.push(Token {
        tok: Tok::Eof,
        span: Span::new(n, n),
    });
    (toks, description)
}

fn lex_string(source: &str, start: usize) -> (Tok<'_>, usize) {
    let mut out = String::new();
    let mut chars = source[start + 1..].char_indices();
    while let Some((k, ch)) = chars.next() {
        match ch {
            '"' => return (Tok::Str(out), k + 2),
            '\\' => match chars.next() {
                Some((_, 'n')) => out.push('\n'),
                Some((_, 't')) => out.push('\t'),
                Some((_, 'r')) => out.push('\r'),
                Some((_, '"')) => out.push('"'),
                Some((_, '\\')) => out.push('\\'),
                Some((k2, other)) => {
                    return (
                        Tok::Error(format!(
                        "an unknown escape `\\{other}` in a string (use \\\" \\\\ \\n \\t or \\r)"
                    )),
                        k2 + 1 + other.len_utf8(),
                    )
                }
                None => break,
            },
            '\n' => {
                return (
                    Tok::Error("an unterminated string (strings end on the same line)".into()),
                    k + 1,
                )
            }
            c => out.push(c),
        }
    }
    (
        Tok::Error("an unterminated string".into()),
        source.len() - start,
    )
}

fn lex_number(source: &str, start: usize) -> (Tok<'_>, usize) {
    let bytes = source.as_bytes();
    let n = bytes.len();
    let digits = |mut j: usize| {
        while j < n && bytes[j].is_ascii_digit() {
            j += 1;
        }
        j
    };
    let mut j = digits(start);
    let mut float = false;
    if j + 1 < n && bytes[j] == b'.' && bytes[j + 1].is_ascii_digit() {
        j = digits(j + 1);
        float = true;
    }
    if j < n && (bytes[j] == b'e' || bytes[j] == b'E') {
        let mut k = j + 1;
        if k < n && (bytes[k] == b'+' || bytes[k] == b'-') {
            k += 1;
        }
        if k < n && bytes[k].is_ascii_digit() {
            j = digits(k);
            float = true;
        }
    }
    let text = &source[start..j];
    (
        if float {
            Tok::Float(text)
        } else {
            Tok::Int(text)
        },
        j - start,
    )
}

fn one(t: Tok<'_>) -> (Tok<'_>, usize) {
    (t, 1)
}
