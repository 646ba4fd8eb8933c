//! The Scenalog rule language: text in, checked program out.
//!
//! # The language
//!
//! Soufflé-flavoured Datalog over the relations of the catalog (`scenalog_facts::catalog`):
//!
//! ```text
//! // description: vehicle with a bicycle to its right
//! bicycle_right(V, B, T) :-
//!     category(V, "VEHICLE"), category(B, "BICYCLE"),
//!     direction(V, B, T, "right", Dist, _), Dist <= 3.0.
//! referred(V, T) :- bicycle_right(V, _, T).
//! related(V, B, T) :- bicycle_right(V, B, T).
//! ```
//!
//! - Clauses `head :- body.` and ground facts `head.`; comments `//`, `%` and `/* */`; a leading
//!   `// description: …` comment is kept as [`Program::description`].
//! - Terms: variables (`Capitalised` or `_name`), `_`, strings, integers, floats, `+ - * /` with the
//!   usual precedence, unary `-`, `abs(E)`, `min(E, E)`, `max(E, E)`.
//! - Body literals: atoms, negated atoms (`!p(..)` or `not p(..)`), comparisons
//!   (`< <= > >= = !=`), bindings `X = expr` (binds `X` when it is otherwise unbound and `expr`'s
//!   variables are bound), aggregates `N = count : { … }`, `M = min E : { … }`, `max`, `sum`
//!   (grouped by the variables the braces share with the rest of the clause; as in Soufflé they
//!   fold over the matching tuples of the braces, each `_` there a fresh variable). A variable of
//!   a `min`'s or `max`'s braces that the rest of the rule uses but does not bind is a witness
//!   (Soufflé's): it takes the values of the tuples that reach the minimum or maximum
//!   (`nearest(V, P) :- D = min X : { near(V, P, T, X) }, …` names the nearest `P`) — see
//!   [`witness`].
//! - Optional `.decl name(Col: type, …)` lines declare a helper's column types (track, time, lane,
//!   str, float, int); without them the types are inferred by unification, and a `.decl` wins.
//!   Arithmetic on a time gives a time; int, float and time compare freely (a time against a
//!   float is warning W0504: frames, not seconds).
//! - `referred(Track, T)` is the output (required unless [`CheckOptions::require_referred`] is
//!   off); `related(Track, Other, T)` is optional. Recursion is allowed, but not through negation
//!   or aggregation.
//!
//! [`check()`] parses and checks a program and returns a [`CheckedProgram`] (typed and stratified:
//! the engine's input) when there is no error, with every [`Diagnostic`] in source order. The codes
//! are in [`diagnostics`] and documented with examples in `rules/DIAGNOSTICS.md`. [`parse`] and
//! [`print_program`] convert between text and [`ast`]; [`render_human`] and [`diagnostics_json`]
//! present diagnostics; [`strata`] exposes the dependency graph.
//!
//! Owns: the lexer and parser (with byte spans and error recovery), the AST ([`ast`]), the
//! pretty-printer, the checks against the catalog (arity, types, safety, stratification,
//! `referred`/`related` shape) and the diagnostics they produce, rendered for people and as JSON.
//! Also holds `rules/library/*.dl`, the scenario library.
//!
//! Does not own: evaluation (the `engine` crate), the catalog itself (the `facts` crate), or the
//! `scenalog check` command line (the root package's `src/cli/check.rs`, a thin wrapper).
//!
//! The contract with the engine is [`CheckedProgram`]: a parsed program whose every predicate has
//! known column types and whose clauses are grouped into strata in evaluation order.

#![warn(missing_docs)]

pub mod ast;
pub mod check;
pub mod diagnostics;
pub mod grammar;
mod habits;
pub mod lexer;
pub mod parser;
pub mod prelude;
pub mod printer;
pub mod render;
pub mod strata;
pub mod walk;
pub mod witness;

pub use parser::parse;
pub use printer::print_program;
pub use render::{diagnostics_json, render_human};
pub use strata::{dependency_graph, DepGraph};

use std::collections::BTreeMap;

use scenalog_facts::catalog::ColType;

pub use ast::Span;

/// How bad a diagnostic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    /// The program cannot run.
    Error,
    /// The program runs but is probably not what was meant.
    Warning,
}

/// One finding of the parser or checker.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    /// Stable code, e.g. "E0101".
    pub code: &'static str,
    /// Error or warning.
    pub severity: Severity,
    /// What is wrong, in one sentence.
    pub message: String,
    /// Where.
    pub span: Span,
    /// Other places that explain it, each with a short label.
    pub related: Vec<(Span, String)>,
    /// How to fix it, when a hint helps.
    pub hint: Option<String>,
    /// The edits that carry the hint out, when it can be applied mechanically (see
    /// [`apply_fix`]); empty when the hint is advice only.
    pub fix: Vec<Edit>,
}

/// One machine-applicable edit of the program text: replace the bytes of `span` with `text`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Edit {
    /// The byte range to replace (empty to insert).
    pub span: ast::Span,
    /// The replacement text.
    pub text: String,
}

/// The source with a diagnostic's fix applied (edits in any order, none overlapping); `None`
/// when the diagnostic has no fix or its edits do not fit the source.
pub fn apply_fix(source: &str, d: &Diagnostic) -> Option<String> {
    if d.fix.is_empty() {
        return None;
    }
    let mut edits: Vec<&Edit> = d.fix.iter().collect();
    edits.sort_by_key(|e| std::cmp::Reverse(e.span.start));
    let mut out = source.to_string();
    let mut limit = out.len();
    for e in edits {
        let (a, b) = (e.span.start, e.span.end);
        if a > b || b > limit || !out.is_char_boundary(a) || !out.is_char_boundary(b) {
            return None;
        }
        out.replace_range(a..b, &e.text);
        limit = a;
    }
    Some(out)
}

/// `source` with the fixes of every diagnostic applied whose edits overlap no earlier one's
/// (in source order), and how many diagnostics were fixed.
pub fn apply_fixes(source: &str, diags: &[Diagnostic]) -> (String, usize) {
    let mut taken: Vec<&Edit> = Vec::new();
    let mut fixed = 0;
    for d in diags {
        if d.fix.is_empty() {
            continue;
        }
        let valid = d.fix.iter().all(|e| {
            e.span.start <= e.span.end
                && e.span.end <= source.len()
                && source.is_char_boundary(e.span.start)
                && source.is_char_boundary(e.span.end)
        });
        let clear = d.fix.iter().all(|e| {
            taken.iter().all(|t| {
                let touch = e.span.start == e.span.end || t.span.start == t.span.end;
                e.span.end <= t.span.start && !(touch && e.span.end == t.span.start)
                    || t.span.end <= e.span.start && !(touch && t.span.end == e.span.start)
            })
        });
        if valid && clear {
            taken.extend(d.fix.iter());
            fixed += 1;
        }
    }
    taken.sort_by_key(|e| std::cmp::Reverse((e.span.start, e.span.end)));
    let mut out = source.to_string();
    for e in taken {
        out.replace_range(e.span.start..e.span.end, &e.text);
    }
    (out, fixed)
}

/// Where a predicate's tuples come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PredKind {
    /// A relation of the catalog, provided by the extractors (EDB).
    Catalog,
    /// Defined by the program's own clauses and facts (IDB).
    Derived,
}

/// What the checker knows about one predicate the program uses or defines.
#[derive(Debug, Clone, PartialEq)]
pub struct PredicateInfo {
    /// The name.
    pub name: String,
    /// Column types (declared, from the catalog, or inferred).
    pub types: Vec<ColType>,
    /// Catalog or derived.
    pub kind: PredKind,
}

/// A set of mutually recursive derived predicates and the clauses that define them.
#[derive(Debug, Clone, PartialEq)]
pub struct Stratum {
    /// The predicates this stratum defines.
    pub predicates: Vec<String>,
    /// Indices into `program.clauses` of the clauses whose heads are in this stratum.
    pub clauses: Vec<usize>,
    /// Whether some predicate here depends on itself (needs fixpoint iteration).
    pub recursive: bool,
}

/// A program that passed every check: safe, typed and stratified. The engine's input.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckedProgram {
    /// The parsed program.
    pub program: Program,
    /// Every predicate used or defined, by name.
    pub predicates: BTreeMap<String, PredicateInfo>,
    /// Strata in evaluation order: each depends only on earlier ones and the catalog
    /// (negation and aggregates only on earlier strata).
    pub strata: Vec<Stratum>,
    /// Warnings the checker found (the program has no error).
    pub warnings: Vec<Diagnostic>,
    /// The prelude relations ([`prelude`]) the checker added to the program because it uses
    /// them: their clauses are at the end of `program.clauses`, spans past the program's text.
    pub prelude: Vec<String>,
}

pub use ast::Program;

/// Options of [`check()`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CheckOptions {
    /// Report a missing `referred/2` rule as an error (true for mining; false for `scenalog run`).
    pub require_referred: bool,
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            require_referred: true,
        }
    }
}

/// What [`check()`] found: the checked program when there is no error, and every diagnostic.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckOutcome {
    /// `Some` exactly when no diagnostic is an error.
    pub program: Option<CheckedProgram>,
    /// Errors and warnings, in source order.
    pub diagnostics: Vec<Diagnostic>,
}

/// The longest program checked, in bytes (4 MiB): parsing and checking hold several times a
/// program's size, so a longer one is refused (E0003) before it is parsed. The library's
/// programs are a few kilobytes; 10,000 one-line rules are about 400 KB.
pub const MAX_PROGRAM_BYTES: usize = 4 << 20;

/// Parses and checks a program against the catalog: every syntax error, unknown predicate, arity
/// and type error, unsafe variable, recursion through negation or aggregation, output-shape
/// problem and warning, in source order. Never panics, whatever the input; a program longer
/// than [`MAX_PROGRAM_BYTES`] is one E0003 and is not parsed.
pub fn check(source: &str, options: &CheckOptions) -> CheckOutcome {
    if source.len() > MAX_PROGRAM_BYTES {
        let end = (0..=64)
            .rev()
            .find(|&i| source.is_char_boundary(i))
            .unwrap_or(0);
        let d = diagnostics::error(
            diagnostics::TOO_LARGE,
            ast::Span::new(0, end),
            format!(
                "this program is {} bytes long; the longest checked is {MAX_PROGRAM_BYTES} bytes",
                source.len()
            ),
        )
        .with_hint(
            "split it into several programs, or derive repeated rules from one rule over a \
             helper relation of the varying constants",
        );
        return CheckOutcome {
            program: None,
            diagnostics: vec![d],
        };
    }
    check::check_source(source, options)
}
