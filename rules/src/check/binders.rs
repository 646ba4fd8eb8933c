//! Hints and fixes for head variables nothing binds (E0201), chosen by the column's type: a
//! track is bound by `present(X, T)` with the clause's time, a time by `present(X, T)` with the
//! clause's track (never `present(T, T)`), the second object of `related` by the helper relation
//! that pairs the two objects; a fact with variables becomes a rule over every object or frame;
//! a `_` in a head becomes a variable the body binds.

use std::collections::{BTreeMap, BTreeSet};

use scenalog_facts::catalog::ColType;

use super::preds::output_arity;
use crate::ast::{Clause, ExprKind, Literal, Program, Span};
use crate::Diagnostic;

/// The column types of a head predicate: inferred for helpers, required for the outputs.
fn head_types(pred: &str, types: &BTreeMap<String, Vec<ColType>>) -> Vec<ColType> {
    match pred {
        "referred" => vec![ColType::Track, ColType::Time],
        "related" => vec![ColType::Track, ColType::Track, ColType::Time],
        _ => types.get(pred).cloned().unwrap_or_default(),
    }
}

/// Variables bound by positive atoms of the body (outside aggregates), in order.
fn body_vars(c: &Clause) -> Vec<&str> {
    let mut out = Vec::new();
    for l in &c.body {
        if let Literal::Pos(a) = l {
            for e in &a.args {
                if let Some(v) = e.as_var() {
                    if !out.contains(&v) {
                        out.push(v);
                    }
                }
            }
        }
    }
    out
}

/// Refines the E0201 diagnostics about heads of `program`'s clauses.
pub fn refine(
    source: &str,
    program: &Program,
    types: &BTreeMap<String, Vec<ColType>>,
    diags: &mut [Diagnostic],
) {
    for c in &program.clauses {
        // The clause's final `.`, where a missing literal is inserted.
        let dot = c.span.end.saturating_sub(1);
        if source.as_bytes().get(dot) != Some(&b'.') {
            continue;
        }
        let cols = head_types(&c.head.pred, types);
        let bound: BTreeSet<&str> = body_vars(c).into_iter().collect();
        // The head's variables by type, bound or not.
        let mut track_bound = None;
        let mut time_bound = None;
        let mut unbound: Vec<(&str, Option<ColType>, usize)> = Vec::new();
        for (i, e) in c.head.args.iter().enumerate() {
            let ty = cols.get(i).copied();
            match (&e.kind, e.as_var()) {
                (_, Some(v)) if bound.contains(v) => match ty {
                    Some(ColType::Track) if track_bound.is_none() => track_bound = Some(v),
                    Some(ColType::Time) if time_bound.is_none() => time_bound = Some(v),
                    _ => {}
                },
                (_, Some(v)) => unbound.push((v, ty, i)),
                (ExprKind::Wildcard, _) => wildcard(source, c, e.span, &bound, diags),
                _ => {}
            }
        }
        for (v, ty, i) in unbound {
            let Some(d) = diags.iter_mut().find(|d| {
                d.code == crate::diagnostics::UNSAFE_VARIABLE
                    && d.span.start >= c.head.span.start
                    && d.span.end <= c.head.span.end
                    && source.get(d.span.start..d.span.end) == Some(v)
            }) else {
                continue;
            };
            let atom = if c.head.pred == "related" && i == 1 {
                let x = c.head.args.first().and_then(|e| e.as_var()).unwrap_or("X");
                let t = time_bound.unwrap_or("T");
                Some(pairing(program, types, x, v, t))
            } else {
                match ty {
                    Some(ColType::Track) => {
                        Some(format!("present({v}, {})", time_bound.unwrap_or("_")))
                    }
                    Some(ColType::Time) => {
                        Some(format!("present({}, {v})", track_bound.unwrap_or("_")))
                    }
                    Some(ColType::Lane) => Some(format!("lane_type({v}, _)")),
                    _ => None,
                }
            };
            let Some(atom) = atom else { continue };
            let (edit, line) = if c.body.is_empty() {
                let head = &source[c.head.span.start..c.head.span.end];
                (
                    format!(" :- {atom}"),
                    format!(
                        "a fact's arguments are constants; for every value write `{head} :- {atom}.`"
                    ),
                )
            } else {
                let text = source[c.span.start..dot].trim_end();
                (
                    format!(", {atom}"),
                    format!("bind `{v}` in the body: `{text}, {atom}.`"),
                )
            };
            d.hint = Some(line);
            d.fix = vec![crate::Edit {
                span: Span::new(dot, dot),
                text: edit,
            }];
        }
    }
}

/// The atom that binds `Y` as the object `X` is related to at `T`: the program's own helper
/// with two track columns and one time column when there is one (the first defined), else
/// `near`.
fn pairing(
    program: &Program,
    types: &BTreeMap<String, Vec<ColType>>,
    x: &str,
    y: &str,
    t: &str,
) -> String {
    for c in &program.clauses {
        let pred = c.head.pred.as_str();
        if output_arity(pred).is_some() {
            continue;
        }
        let Some(cols) = types.get(pred) else {
            continue;
        };
        let tracks: Vec<usize> = (0..cols.len())
            .filter(|&k| cols[k] == ColType::Track)
            .collect();
        let times: Vec<usize> = (0..cols.len())
            .filter(|&k| cols[k] == ColType::Time)
            .collect();
        if tracks.len() == 2 && times.len() == 1 {
            let parts: Vec<&str> = (0..cols.len())
                .map(|k| {
                    if k == tracks[0] {
                        x
                    } else if k == tracks[1] {
                        y
                    } else if k == times[0] {
                        t
                    } else {
                        "_"
                    }
                })
                .collect();
            return format!("{pred}({})", parts.join(", "));
        }
    }
    format!("near({x}, {y}, {t}, _)")
}

/// A `_` in a head: name it after a body variable the head does not use yet.
fn wildcard(source: &str, c: &Clause, at: Span, bound: &BTreeSet<&str>, diags: &mut [Diagnostic]) {
    let in_head: Vec<&str> = c.head.args.iter().filter_map(|e| e.as_var()).collect();
    let Some(d) = diags
        .iter_mut()
        .find(|d| d.code == crate::diagnostics::UNSAFE_VARIABLE && d.span == at)
    else {
        return;
    };
    let Some(v) = body_vars(c)
        .into_iter()
        .find(|v| !in_head.contains(v) && bound.contains(v) && !v.starts_with('_'))
    else {
        return;
    };
    let head = format!(
        "{}{v}{}",
        &source[c.head.span.start..at.start],
        &source[at.end..c.head.span.end]
    );
    d.hint = Some(format!(
        "a head's columns are values the body binds: name it, e.g. `{head}`, or drop the column"
    ));
    d.fix = vec![crate::Edit {
        span: at,
        text: v.to_string(),
    }];
}
