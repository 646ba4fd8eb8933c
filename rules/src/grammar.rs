//! The language's grammar for servers that constrain decoding to one (llama.cpp's `grammar`,
//! vLLM's `structured_outputs.grammar`, SGLang's `ebnf`): written once as data ([`rules`]) and
//! printed as GBNF ([`gbnf`]), so a model's answer cannot fail to parse.
//!
//! The grammar follows the parser ([`crate::parser`]): clauses and `.decl` lines, comments
//! (`//`, `%`, `/* */`), atoms, negation (`!` or `not`), comparisons, aggregates, arithmetic with
//! `abs`/`min`/`max`, strings with the parser's escapes and numbers as the lexer reads them, with
//! a unit or none (`50 km/h`). It is a little wider than the parser where a context-free grammar
//! cannot say more (an atom named like a built-in function, a call with the wrong number of
//! arguments, `m2` as a unit): those still reach the checker and its diagnostics. An answer may be wrapped in one Markdown code fence, as the
//! prompt asks; with [`Answer::ProgramOrKeep`] it may instead be the word `KEEP` (the evidence
//! round's answer).

use scenalog_facts::units;

/// A grammar expression.
#[derive(Debug, Clone, PartialEq)]
pub enum G {
    /// The text itself.
    Lit(&'static str),
    /// One character of a class, in GBNF's bracket syntax without the brackets (`a-z`, `^\n`).
    Class(&'static str),
    /// Another rule, by name.
    Ref(&'static str),
    /// Each in turn.
    Seq(Vec<G>),
    /// Any one of them.
    Alt(Vec<G>),
    /// Zero or one.
    Opt(Box<G>),
    /// Zero or more.
    Star(Box<G>),
    /// One or more.
    Plus(Box<G>),
}

/// What an answer may be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Answer {
    /// A program (maybe in a code fence).
    Program,
    /// A program, or the word `KEEP` (the evidence round).
    ProgramOrKeep,
}

fn lit(s: &'static str) -> G {
    G::Lit(s)
}
fn class(s: &'static str) -> G {
    G::Class(s)
}
fn r(s: &'static str) -> G {
    G::Ref(s)
}
fn seq(v: Vec<G>) -> G {
    G::Seq(v)
}
fn alt(v: Vec<G>) -> G {
    G::Alt(v)
}
fn opt(g: G) -> G {
    G::Opt(Box::new(g))
}
fn star(g: G) -> G {
    G::Star(Box::new(g))
}
fn plus(g: G) -> G {
    G::Plus(Box::new(g))
}
/// `first (sep first)*` with optional whitespace around `sep`.
fn list(item: &'static str, sep: &'static str) -> G {
    seq(vec![
        r(item),
        star(seq(vec![r("ws"), lit(sep), r("ws"), r(item)])),
    ])
}

/// The grammar's rules, `root` first.
pub fn rules(answer: Answer) -> Vec<(&'static str, G)> {
    let fenced = seq(vec![
        lit("```"),
        star(class("a-z")),
        lit("\n"),
        r("program"),
        lit("```"),
        r("ws"),
    ]);
    let program = alt(vec![fenced, r("program")]);
    let root = match answer {
        Answer::Program => program,
        Answer::ProgramOrKeep => alt(vec![seq(vec![lit("KEEP"), r("ws")]), program]),
    };
    let col_type = alt([
        "track", "time", "lane", "str", "symbol", "string", "float", "number", "int",
    ]
    .into_iter()
    .map(lit)
    .collect());
    let column = seq(vec![
        alt(vec![r("var"), r("ident")]),
        r("ws"),
        lit(":"),
        r("ws"),
        r("coltype"),
        // The unit of a number column, as `scenalog catalog` prints it: `float<m/s>`.
        opt(seq(vec![
            r("ws"),
            lit("<"),
            r("ws"),
            r("unit"),
            opt(seq(vec![r("ws"), lit("/"), r("ws"), r("unit")])),
            r("ws"),
            lit(">"),
        ])),
    ]);
    vec![
        ("root", root),
        (
            "program",
            seq(vec![r("ws"), star(seq(vec![r("item"), r("ws")]))]),
        ),
        ("item", alt(vec![r("clause"), r("decl")])),
        (
            "decl",
            seq(vec![
                lit(".decl"),
                r("ws1"),
                r("ident"),
                r("ws"),
                lit("("),
                r("ws"),
                opt(list("column", ",")),
                r("ws"),
                lit(")"),
                opt(seq(vec![r("ws"), lit(".")])),
            ]),
        ),
        ("column", column),
        ("coltype", col_type),
        (
            "clause",
            seq(vec![
                r("atom"),
                opt(seq(vec![r("ws"), lit(":-"), r("ws"), r("body")])),
                r("ws"),
                lit("."),
            ]),
        ),
        ("body", list("literal", ",")),
        (
            "literal",
            alt(vec![
                seq(vec![lit("!"), r("ws"), r("atom")]),
                seq(vec![lit("not"), r("ws1"), r("atom")]),
                r("aggregate"),
                r("comparison"),
                r("atom"),
            ]),
        ),
        (
            "atom",
            seq(vec![
                r("ident"),
                opt(seq(vec![
                    r("ws"),
                    lit("("),
                    r("ws"),
                    opt(list("expr", ",")),
                    r("ws"),
                    lit(")"),
                ])),
            ]),
        ),
        (
            "comparison",
            seq(vec![r("expr"), r("ws"), r("cmpop"), r("ws"), r("expr")]),
        ),
        (
            "cmpop",
            alt(vec![
                lit("<="),
                lit(">="),
                lit("!="),
                lit("<"),
                lit(">"),
                lit("="),
            ]),
        ),
        (
            "aggregate",
            seq(vec![
                r("expr"),
                r("ws"),
                lit("="),
                r("ws"),
                alt(vec![
                    lit("count"),
                    seq(vec![
                        alt(vec![lit("min"), lit("max"), lit("sum")]),
                        r("ws1"),
                        r("expr"),
                    ]),
                ]),
                r("ws"),
                lit(":"),
                r("ws"),
                lit("{"),
                r("ws"),
                r("body"),
                r("ws"),
                lit("}"),
            ]),
        ),
        (
            "expr",
            seq(vec![
                r("term"),
                star(seq(vec![
                    r("ws"),
                    alt(vec![lit("+"), lit("-")]),
                    r("ws"),
                    r("term"),
                ])),
            ]),
        ),
        (
            "term",
            seq(vec![
                r("unary"),
                star(seq(vec![
                    r("ws"),
                    alt(vec![lit("*"), lit("/"), lit("mod")]),
                    r("ws"),
                    r("unary"),
                ])),
            ]),
        ),
        (
            "unary",
            alt(vec![seq(vec![lit("-"), r("ws"), r("unary")]), r("power")]),
        ),
        (
            "power",
            seq(vec![
                r("primary"),
                opt(seq(vec![r("ws"), lit("^"), r("ws"), r("unary")])),
            ]),
        ),
        (
            "primary",
            alt(vec![
                r("var"),
                lit("_"),
                r("string"),
                seq(vec![
                    r("number"),
                    opt(seq(vec![
                        r("ws"),
                        r("unit"),
                        opt(seq(vec![r("ws"), lit("/"), r("ws"), r("unit")])),
                    ])),
                ]),
                seq(vec![
                    alt(vec![lit("abs"), lit("min"), lit("max")]),
                    r("ws"),
                    lit("("),
                    r("ws"),
                    list("expr", ","),
                    r("ws"),
                    lit(")"),
                ]),
                seq(vec![lit("("), r("ws"), r("expr"), r("ws"), lit(")")]),
            ]),
        ),
        ("ident", seq(vec![class("a-z"), star(class("a-zA-Z0-9_"))])),
        (
            "var",
            alt(vec![
                seq(vec![class("A-Z"), star(class("a-zA-Z0-9_"))]),
                seq(vec![lit("_"), plus(class("a-zA-Z0-9_"))]),
            ]),
        ),
        (
            "string",
            seq(vec![
                lit("\""),
                star(alt(vec![
                    class("^\"\\\\\\n"),
                    seq(vec![lit("\\"), class("\"\\\\ntr")]),
                ])),
                lit("\""),
            ]),
        ),
        (
            "number",
            seq(vec![
                plus(class("0-9")),
                opt(seq(vec![lit("."), plus(class("0-9"))])),
                opt(seq(vec![class("eE"), opt(class("-+")), plus(class("0-9"))])),
            ]),
        ),
        (
            "unit",
            seq(vec![
                alt(units::LITERAL_UNITS.iter().map(|u| lit(u.name)).collect()),
                opt(lit("2")),
            ]),
        ),
        ("ws", star(alt(vec![class(" \\t\\r\\n"), r("comment")]))),
        ("ws1", seq(vec![plus(class(" \\t\\r\\n")), r("ws")])),
        (
            "comment",
            alt(vec![
                // The newline may be missing at the end of the text.
                seq(vec![lit("//"), star(class("^\\n")), opt(lit("\n"))]),
                seq(vec![lit("%"), star(class("^\\n")), opt(lit("\n"))]),
                seq(vec![
                    lit("/*"),
                    star(alt(vec![
                        class("^*"),
                        seq(vec![plus(lit("*")), class("^*/")]),
                    ])),
                    plus(lit("*")),
                    lit("/"),
                ]),
            ]),
        ),
    ]
}

/// The grammar as GBNF (llama.cpp's grammar format; vLLM and SGLang read it too).
pub fn gbnf(answer: Answer) -> String {
    let mut out = String::from(
        "# The Scenalog rule language (scenalog_rules::grammar), for constrained decoding.\n",
    );
    for (name, g) in rules(answer) {
        out.push_str(&format!("{name} ::= {}\n", gbnf_expr(&g)));
    }
    out
}

fn gbnf_expr(g: &G) -> String {
    match g {
        G::Lit(s) => crate::printer::quote(s),
        G::Class(c) => format!("[{c}]"),
        G::Ref(n) => (*n).to_string(),
        G::Seq(v) => v.iter().map(gbnf_atom).collect::<Vec<_>>().join(" "),
        G::Alt(v) => v.iter().map(gbnf_expr).collect::<Vec<_>>().join(" | "),
        G::Opt(g) => format!("{}?", gbnf_atom(g)),
        G::Star(g) => format!("{}*", gbnf_atom(g)),
        G::Plus(g) => format!("{}+", gbnf_atom(g)),
    }
}

/// An expression that can take a postfix operator or sit in a sequence.
fn gbnf_atom(g: &G) -> String {
    match g {
        G::Seq(v) if v.len() > 1 => format!("({})", gbnf_expr(g)),
        G::Alt(v) if v.len() > 1 => format!("({})", gbnf_expr(g)),
        _ => gbnf_expr(g),
    }
}
