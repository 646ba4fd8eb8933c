//! Diagnostic codes and small helpers to build diagnostics and suggestions.
//!
//! Every code is documented, with an example, in `rules/DIAGNOSTICS.md`. Codes never change meaning.

use crate::ast::Span;
use crate::{Diagnostic, Severity};

/// Syntax error: what was expected and what was found.
pub const SYNTAX: &str = "E0001";
/// An expression or a nesting too deep to evaluate safely (operator chains, parentheses, signs,
/// calls, aggregates).
pub const TOO_DEEP: &str = "E0002";
/// A program longer than [`crate::MAX_PROGRAM_BYTES`]: not parsed at all.
pub const TOO_LARGE: &str = "E0003";
/// A predicate that is neither in the catalog nor defined or declared by the program.
pub const UNKNOWN_PREDICATE: &str = "E0101";
/// An atom with the wrong number of arguments.
pub const WRONG_ARITY: &str = "E0102";
/// A value of one type where another is required.
pub const TYPE_MISMATCH: &str = "E0103";
/// A string constant outside a column's closed set of values.
pub const BAD_VALUE: &str = "E0104";
/// A variable that no positive atom or binding binds.
pub const UNSAFE_VARIABLE: &str = "E0201";
/// Negation inside a recursive cycle.
pub const NEGATION_CYCLE: &str = "E0301";
/// Aggregation inside a recursive cycle.
pub const AGGREGATE_CYCLE: &str = "E0302";
/// No `referred/2` rule.
pub const NO_REFERRED: &str = "E0401";
/// `referred` or `related` with the wrong number of columns or wrong column types.
pub const OUTPUT_SHAPE: &str = "E0402";
/// A clause (or `.decl`) that defines a catalog relation.
pub const REDEFINED_CATALOG: &str = "E0403";
/// A predicate declared twice with `.decl`.
pub const DUPLICATE_DECL: &str = "E0404";
/// A variable used only once in its clause.
pub const SINGLETON: &str = "W0501";
/// A declared helper predicate with no clauses (always empty).
pub const EMPTY_PREDICATE: &str = "W0502";
/// A helper predicate defined but used by no other rule.
pub const UNUSED_PREDICATE: &str = "W0503";
/// A program defines a name that a prelude relation it uses depends on.
pub const SHADOWED_PRELUDE: &str = "E0405";
/// A rule (or an aggregate's braces) with more variables than the engine's tuples hold.
pub const TOO_MANY_VARIABLES: &str = "E0406";
/// An atom that names no object the rest of its body uses: a cross product (an existence test),
/// usually a `_` meant to join.
pub const CROSS_PRODUCT: &str = "W0506";
/// A `_` in the time column of an aggregate's atom while the clause is about a frame: it folds
/// over every frame, not the clause's.
pub const AGGREGATE_OVER_TIME: &str = "W0507";
/// A `related` rule that is not tied to `referred`: pairs whose first object is not referred at
/// that frame.
pub const RELATED_NOT_REFERRED: &str = "W0508";
/// An aggregate whose braces share no variable with the rest of its clause: the same value
/// for every object and frame.
pub const UNTIED_AGGREGATE: &str = "W0510";
/// A program defines a relation of a prelude concept's name, with the prelude's arity: its
/// definition replaces the prelude's everywhere in the program.
pub const REDEFINED_PRELUDE: &str = "W0509";
/// A program defines a relation of a prelude concept's name with another number of columns.
pub const PRELUDE_ARITY: &str = "E0407";
/// A `.decl` that names two of its columns alike.
pub const DUPLICATE_COLUMN: &str = "E0408";
/// Two units that cannot meet: a speed compared with a distance, two instants added.
pub const UNIT_MISMATCH: &str = "E0105";
/// A bare number added to a time (an instant): `T + 1` is a frame, not a duration.
pub const INSTANT_PLUS_NUMBER: &str = "E0106";
/// A bare number compared with or added to a quantity with a unit: read in that unit.
pub const BARE_NUMBER: &str = "W0511";
/// A duration measured by counting samples (`N = count : { p(X, U), … }, N >= 31`): the
/// tracker's rate decides what it means.
pub const COUNTED_SAMPLES: &str = "W0512";
/// A distance bounded as if the relation went on past its range (`near(E, P, T, D), D > 30.0`
/// for "farther than 30 m": `near` holds only within 50 m).
pub const BEYOND_RANGE: &str = "W0513";
/// A `%` right after an operand and before more of an expression (`X % 2 = 0`): it starts a
/// comment, so the rest of the line is not read; the remainder is written `mod`.
pub const PERCENT_COMMENT: &str = "W0514";
/// A variable bound only inside a `min`'s or `max`'s braces and used outside them: a witness
/// (the tuples reaching the extremum over everything the braces match), not a group.
pub const WITNESS: &str = "W0515";
/// A time (frames) compared with a float: probably seconds meant as frames.
pub const TIME_VS_FLOAT: &str = "W0504";
/// A `count` whose braces have no variable of their own: it is 0 or 1.
pub const COUNT_OF_ONE: &str = "W0505";
/// Warnings that usually mean the program does not say what was meant; the synthesis repair
/// loop sends them back to the model.
pub const MEANING_WARNINGS: &[&str] = &[
    SINGLETON,
    TIME_VS_FLOAT,
    COUNT_OF_ONE,
    CROSS_PRODUCT,
    AGGREGATE_OVER_TIME,
    RELATED_NOT_REFERRED,
    REDEFINED_PRELUDE,
    UNTIED_AGGREGATE,
    BARE_NUMBER,
    COUNTED_SAMPLES,
    BEYOND_RANGE,
    PERCENT_COMMENT,
    WITNESS,
];

/// Every code, in order, with its severity and a one-line summary.
pub const CODES: &[(&str, Severity, &str)] = &[
    (SYNTAX, Severity::Error, "syntax error"),
    (TOO_DEEP, Severity::Error, "expression or nesting too deep"),
    (TOO_LARGE, Severity::Error, "program too large"),
    (UNKNOWN_PREDICATE, Severity::Error, "unknown predicate"),
    (WRONG_ARITY, Severity::Error, "wrong number of arguments"),
    (TYPE_MISMATCH, Severity::Error, "type mismatch"),
    (
        BAD_VALUE,
        Severity::Error,
        "string outside the column's values",
    ),
    (UNIT_MISMATCH, Severity::Error, "units that cannot meet"),
    (
        INSTANT_PLUS_NUMBER,
        Severity::Error,
        "bare number added to a time",
    ),
    (UNSAFE_VARIABLE, Severity::Error, "unsafe variable"),
    (
        NEGATION_CYCLE,
        Severity::Error,
        "negation through recursion",
    ),
    (
        AGGREGATE_CYCLE,
        Severity::Error,
        "aggregation through recursion",
    ),
    (NO_REFERRED, Severity::Error, "no referred/2 rule"),
    (
        OUTPUT_SHAPE,
        Severity::Error,
        "referred/related with the wrong shape",
    ),
    (
        REDEFINED_CATALOG,
        Severity::Error,
        "catalog relation redefined",
    ),
    (DUPLICATE_DECL, Severity::Error, "predicate declared twice"),
    (
        SHADOWED_PRELUDE,
        Severity::Error,
        "prelude relation's dependency redefined",
    ),
    (
        TOO_MANY_VARIABLES,
        Severity::Error,
        "too many variables in one rule",
    ),
    (
        PRELUDE_ARITY,
        Severity::Error,
        "prelude concept redefined with another arity",
    ),
    (
        DUPLICATE_COLUMN,
        Severity::Error,
        "two columns of a declaration named alike",
    ),
    (SINGLETON, Severity::Warning, "variable used once"),
    (
        EMPTY_PREDICATE,
        Severity::Warning,
        "declared predicate never defined",
    ),
    (
        UNUSED_PREDICATE,
        Severity::Warning,
        "helper predicate never used",
    ),
    (
        TIME_VS_FLOAT,
        Severity::Warning,
        "time compared with a float",
    ),
    (
        COUNT_OF_ONE,
        Severity::Warning,
        "count with no variable of its own",
    ),
    (
        CROSS_PRODUCT,
        Severity::Warning,
        "atom sharing no variable with its body",
    ),
    (
        AGGREGATE_OVER_TIME,
        Severity::Warning,
        "aggregate over every frame",
    ),
    (
        RELATED_NOT_REFERRED,
        Severity::Warning,
        "related not tied to referred",
    ),
    (
        REDEFINED_PRELUDE,
        Severity::Warning,
        "prelude concept redefined",
    ),
    (
        UNTIED_AGGREGATE,
        Severity::Warning,
        "aggregate tied to nothing",
    ),
    (
        BARE_NUMBER,
        Severity::Warning,
        "number with no unit read in a unit",
    ),
    (
        COUNTED_SAMPLES,
        Severity::Warning,
        "duration measured by counting samples",
    ),
    (
        BEYOND_RANGE,
        Severity::Warning,
        "distance bounded past the relation's range",
    ),
    (
        PERCENT_COMMENT,
        Severity::Warning,
        "`%` after an operand starts a comment",
    ),
    (WITNESS, Severity::Warning, "a min/max witness, not a group"),
];

/// An error with no related spans and no hint.
pub fn error(code: &'static str, span: Span, message: impl Into<String>) -> Diagnostic {
    Diagnostic {
        code,
        severity: Severity::Error,
        message: message.into(),
        span,
        related: Vec::new(),
        hint: None,
        fix: Vec::new(),
    }
}

/// A warning with no related spans and no hint.
pub fn warning(code: &'static str, span: Span, message: impl Into<String>) -> Diagnostic {
    Diagnostic {
        severity: Severity::Warning,
        ..error(code, span, message)
    }
}

impl Diagnostic {
    /// The diagnostic with this hint.
    pub fn with_hint(mut self, hint: impl Into<String>) -> Diagnostic {
        self.hint = Some(hint.into());
        self
    }

    /// The diagnostic with one more edit of its machine-applicable fix.
    pub fn with_edit(mut self, span: Span, text: impl Into<String>) -> Diagnostic {
        self.fix.push(crate::Edit {
            span,
            text: text.into(),
        });
        self
    }

    /// The diagnostic with one more related span.
    pub fn with_related(mut self, span: Span, label: impl Into<String>) -> Diagnostic {
        self.related.push((span, label.into()));
        self
    }

    /// Whether this is an error.
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

/// Levenshtein distance between two strings (by characters).
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for (i, ca) in a.chars().enumerate() {
        cur[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != *cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// Up to `k` candidates closest to `name`, nearest first (ties by name), among those close
/// enough to be a plausible typo or a word in common (`stopped` for `stopped_car`).
pub fn closest<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str>,
    k: usize,
) -> Vec<&'a str> {
    let len = name.chars().count();
    let limit = (len / 2).max(1);
    let mut scored: Vec<(usize, &str)> = candidates
        .into_iter()
        .filter(|c| *c != name)
        .filter_map(|c| {
            let d = edit_distance(name, c);
            let shares_word = name
                .split('_')
                .any(|w| w.len() >= 4 && c.split('_').any(|cw| cw == w));
            if d <= limit && d < len {
                Some((d, c))
            } else if shares_word {
                Some((limit + 1, c))
            } else {
                None
            }
        })
        .collect();
    scored.sort();
    scored.dedup();
    scored.into_iter().take(k).map(|(_, c)| c).collect()
}
