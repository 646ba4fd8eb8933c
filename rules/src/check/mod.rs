//! The checks against the catalog: predicates and arity ([`preds`]), types ([`types`]), safety
//! and singleton variables ([`safety`]); stratification lives in [`crate::strata`].

pub mod binders;
pub mod counts;
pub mod meaning;
pub mod preds;
pub mod range;
pub mod safety;
pub mod samples;
pub mod types;
pub mod units;
pub mod untied;

use std::collections::BTreeMap;

use scenalog_facts::catalog::{self, ColType};

use crate::ast::Span;
use crate::parser::parse_detailed;
use crate::{
    strata, CheckOptions, CheckOutcome, CheckedProgram, Diagnostic, Edit, PredKind, PredicateInfo,
};

/// Rounds of habit fixes applied before the rest of a program is checked.
const HABIT_ROUNDS: usize = 3;

/// Parses and checks `source`; see [`crate::check()`]. Soufflé and Prolog habits
/// ([`crate::habits`]) are reported with their fixes, and the rest of the program is checked as
/// it reads once the fixes are made (its diagnostics placed back on the original text).
pub fn check_source(source: &str, options: &CheckOptions) -> CheckOutcome {
    check_round(source, options, 0)
}

fn check_round(source: &str, options: &CheckOptions, round: usize) -> CheckOutcome {
    let habits = if round < HABIT_ROUNDS {
        crate::habits::scan(source)
    } else {
        Vec::new()
    };
    if habits.is_empty() {
        return check_plain(source, options);
    }
    let mut edits: Vec<Edit> = Vec::new();
    for h in &habits {
        if h.fix
            .iter()
            .all(|e| edits.iter().all(|x| disjoint(x.span, e.span)))
        {
            edits.extend(h.fix.iter().cloned());
        }
    }
    edits.sort_by_key(|e| (e.span.start, e.span.end));
    let mut diags = habits;
    if edits.is_empty() {
        let mut out = check_plain(source, options);
        // The habit explains the syntax error the parser gives at its place.
        out.diagnostics.retain(|d| {
            !(d.code == crate::diagnostics::SYNTAX
                && diags.iter().any(|h| !disjoint(h.span, d.span)))
        });
        diags.append(&mut out.diagnostics);
    } else {
        let mut fixed = source.to_string();
        for e in edits.iter().rev() {
            fixed.replace_range(e.span.start..e.span.end, &e.text);
        }
        let inner = check_round(&fixed, options, round + 1);
        let len = source.len();
        diags.extend(inner.diagnostics.into_iter().map(|d| {
            let mut d = place_back(d, &edits);
            d.span = Span::new(d.span.start.min(len), d.span.end.min(len));
            d
        }));
    }
    diags.sort_by_key(|d| (d.span.start, d.span.end));
    diags.dedup();
    CheckOutcome {
        program: None,
        diagnostics: diags,
    }
}

/// The column types of `pred`: the catalog's, or those inferred for a program's own relation.
pub(crate) fn column_types(
    pred: &str,
    inferred: &BTreeMap<String, Vec<ColType>>,
) -> Option<Vec<ColType>> {
    catalog::relation(pred)
        .map(|r| r.types())
        .or_else(|| inferred.get(pred).cloned())
}

/// Whether two spans share no byte (empty spans touch nothing).
fn disjoint(a: Span, b: Span) -> bool {
    a.end <= b.start || b.end <= a.start
}

/// A byte offset of the text with `edits` applied (sorted, disjoint) as an offset of the text
/// before: inside a replacement, the replaced span's start.
fn offset_back(pos: usize, edits: &[Edit]) -> usize {
    let mut delta: isize = 0;
    for e in edits {
        let new_start = (e.span.start as isize + delta).max(0) as usize;
        if pos < new_start {
            break;
        }
        if pos < new_start + e.text.len() {
            return e.span.start;
        }
        delta += e.text.len() as isize - (e.span.end - e.span.start) as isize;
    }
    (pos as isize - delta).max(0) as usize
}

fn span_back(s: Span, edits: &[Edit]) -> Span {
    let start = offset_back(s.start, edits);
    Span::new(start, offset_back(s.end, edits).max(start))
}

/// A diagnostic of the fixed text, placed on the original; a fix whose span a habit's edit
/// changed is dropped.
fn place_back(mut d: Diagnostic, edits: &[Edit]) -> Diagnostic {
    d.span = span_back(d.span, edits);
    for (s, _) in &mut d.related {
        *s = span_back(*s, edits);
    }
    let fix: Vec<Edit> = d
        .fix
        .iter()
        .map(|e| Edit {
            span: span_back(e.span, edits),
            text: e.text.clone(),
        })
        .collect();
    let kept = fix
        .iter()
        .zip(&d.fix)
        .all(|(a, b)| a.span.end - a.span.start == b.span.end - b.span.start);
    d.fix = if kept { fix } else { Vec::new() };
    d
}

/// Parses and checks `source` with no habit rewriting.
fn check_plain(source: &str, options: &CheckOptions) -> CheckOutcome {
    let parsed = parse_detailed(source);
    let mut diags = parsed.diagnostics;
    diags.extend(crate::habits::percent_comments(source));
    let mut program = parsed.program;
    // The prelude's clauses go after the program's own text, so their spans say whose they are.
    let prelude_at = source.len() + 1;
    let prelude = if diags.iter().any(|d| d.is_error()) {
        Vec::new()
    } else {
        // Prelude names are the scenario vocabulary; a general Datalog program (`run`) is free
        // to use them for its own relations.
        if options.require_referred {
            diags.extend(crate::prelude::redefinitions(&program));
        }
        let (names, shadowed) = crate::prelude::extend(&mut program, prelude_at);
        diags.extend(shadowed);
        // Witnesses of `min` and `max` become plain joins before anything checks the rules;
        // a scenario program is told (W0515), a general Datalog program (`run`) means them.
        let witnesses = crate::witness::expand(&mut program);
        if options.require_referred {
            diags.extend(witnesses);
        }
        names
    };
    let table = preds::collect(&program, &parsed.broken_heads, options, &mut diags);
    let inferred = types::infer(&program, &table, &mut diags);
    units::check_program(&mut program, &mut diags);
    let first_safety = diags.len();
    for c in &program.clauses {
        safety::check_clause(c, &mut diags);
        counts::check_clause(c, &mut diags);
        samples::check_clause(c, &inferred, &mut diags);
        // A general Datalog program (`run`) may fold over everything on purpose.
        if options.require_referred {
            untied::check_clause(c, &mut diags);
        }
    }
    binders::refine(source, &program, &inferred, &mut diags[first_safety..]);
    let (strata, cycle_diags) = strata::stratify(&program);
    diags.extend(cycle_diags);
    meaning::check_program(&program, &table, &inferred, &mut diags);
    range::check_program(&program, &mut diags);
    within_source(&mut diags, source.len(), prelude_at);
    diags.sort_by_key(|d| (d.span.start, d.span.end));
    diags.dedup();
    let has_error = diags.iter().any(|d| d.is_error());
    let program = if has_error {
        None
    } else {
        let mut predicates = BTreeMap::new();
        for (name, entry) in &table.preds {
            let types: Vec<ColType> = match entry.kind {
                PredKind::Catalog => catalog::relation(name)
                    .map(|r| r.types())
                    .unwrap_or_default(),
                PredKind::Derived => inferred.get(name).cloned().unwrap_or_default(),
            };
            predicates.insert(
                name.clone(),
                PredicateInfo {
                    name: name.clone(),
                    types,
                    kind: entry.kind,
                },
            );
        }
        Some(CheckedProgram {
            program,
            predicates,
            strata,
            warnings: diags.clone(),
            prelude,
        })
    };
    CheckOutcome {
        program,
        diagnostics: diags,
    }
}

/// Keeps every diagnostic on the program's own text: the prelude is checked clean on its own,
/// so a warning placed in it is dropped, an error in it (a use that does not fit it) is moved
/// to the end of the program and says where it arose, and related places in it are dropped.
fn within_source(diags: &mut Vec<Diagnostic>, len: usize, prelude_at: usize) {
    diags.retain(|d| d.is_error() || d.span.start < prelude_at);
    for d in diags.iter_mut() {
        if d.span.start >= prelude_at {
            d.message = format!("in the prelude: {}", d.message);
            d.span = Span::new(len, len);
            d.fix.clear();
        }
        d.related.retain(|(s, _)| s.start < prelude_at);
    }
}
