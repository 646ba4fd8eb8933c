//! Hints and fixes for head variables nothing binds (E0201), chosen by the column's type: a
//! track is bound by `present(X, T)` with the clause's time, a time by `present(X, T)` with the
//! clause's track (never `present(T, T)`), the second object of `related` by the helper relation
//! that pairs the two objects; a fact with variables becomes a rule over every object or frame;
//! a `_` in a head becomes a variable the body binds.

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

use scenalog_facts::catalog::ColType;

use super::preds::output_arity;
use crate::ast::{AggFunc, Clause, ExprKind, Literal, Program, Span};
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
    let mut seen = HashSet::new();
    for l in &c.body {
        if let Literal::Pos(a) = l {
            for e in &a.args {
                if let Some(v) = e.as_var() {
                    if seen.insert(v) {
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
    // The E0201 diagnostics by where they start, so each clause finds its own by binary search
    // instead of scanning them all.
    let mut unsafe_at: Vec<(usize, usize)> = diags
        .iter()
        .enumerate()
        .filter(|(_, d)| d.code == crate::diagnostics::UNSAFE_VARIABLE)
        .map(|(i, d)| (d.span.start, i))
        .collect();
    unsafe_at.sort_unstable();
    let in_span = |at: Span| {
        let from = unsafe_at.partition_point(|&(start, _)| start < at.start);
        let to = unsafe_at.partition_point(|&(start, _)| start < at.end.max(at.start));
        unsafe_at[from..to].iter().map(|&(_, i)| i)
    };
    // The program's helper pairing two objects at a time, looked up once.
    let pair_helper = pair_helper(program, types);
    for c in &program.clauses {
        // The clause's final `.`, where a missing literal is inserted.
        let dot = c.span.end.saturating_sub(1);
        if source.as_bytes().get(dot) != Some(&b'.') {
            continue;
        }
        let cols = head_types(&c.head.pred, types);
        let in_body = body_vars(c);
        let bound: BTreeSet<&str> = in_body.iter().copied().collect();
        let in_head: HashSet<&str> = c.head.args.iter().filter_map(|e| e.as_var()).collect();
        // The first E0201 inside the head for each text it covers (a variable's name).
        let mut head_diags: HashMap<&str, usize> = HashMap::new();
        let mut wildcard_diags: HashMap<Span, usize> = HashMap::new();
        for i in in_span(c.head.span) {
            let d = &diags[i];
            if d.span.end <= c.head.span.end {
                if let Some(text) = source.get(d.span.start..d.span.end) {
                    let first = head_diags.entry(text).or_insert(i);
                    *first = (*first).min(i);
                }
                let first = wildcard_diags.entry(d.span).or_insert(i);
                *first = (*first).min(i);
            }
        }
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
                (ExprKind::Wildcard, _) => {
                    if let Some(&i) = wildcard_diags.get(&e.span) {
                        wildcard(source, c, e.span, &in_body, &in_head, &bound, &mut diags[i]);
                    }
                }
                _ => {}
            }
        }
        for (v, ty, i) in unbound {
            let Some(&at) = head_diags.get(v) else {
                continue;
            };
            let d = &mut diags[at];
            if let Some(func) = folded_only(c, v) {
                d.hint = Some(format!(
                    "`{v}` is bound only inside the braces of a `{func}`, and a `{func}` has no witness \
                     (only `min` and `max` name the tuples that reach them, as in Soufflé); to get \
                     one result per `{v}`, bind `{v}` outside the braces too"
                ));
                continue;
            }
            let atom = if c.head.pred == "related" && i == 1 {
                let x = c.head.args.first().and_then(|e| e.as_var()).unwrap_or("X");
                let t = time_bound.unwrap_or("T");
                Some(pairing(pair_helper.as_ref(), x, v, t))
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
                let head = excerpt(&source[c.head.span.start..c.head.span.end]);
                (
                    format!(" :- {atom}"),
                    format!(
                        "a fact's arguments are constants; for every value write `{head} :- {atom}.`"
                    ),
                )
            } else {
                let text = excerpt(source[c.span.start..dot].trim_end());
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

/// The program's own helper with two track columns and one time column (the first defined), with
/// its column types: what pairs the objects of `related`.
fn pair_helper<'a>(
    program: &'a Program,
    types: &'a BTreeMap<String, Vec<ColType>>,
) -> Option<(&'a str, &'a [ColType])> {
    program.clauses.iter().find_map(|c| {
        let pred = c.head.pred.as_str();
        if output_arity(pred).is_some() {
            return None;
        }
        let cols = types.get(pred)?;
        let count = |t: ColType| cols.iter().filter(|&&c| c == t).count();
        (count(ColType::Track) == 2 && count(ColType::Time) == 1).then_some((pred, cols.as_slice()))
    })
}

/// The atom that binds `Y` as the object `X` is related to at `T`: the program's pairing helper
/// ([`pair_helper`]) when there is one, else `near`.
fn pairing(helper: Option<&(&str, &[ColType])>, x: &str, y: &str, t: &str) -> String {
    let Some((pred, cols)) = helper else {
        return format!("near({x}, {y}, {t}, _)");
    };
    let tracks: Vec<usize> = (0..cols.len())
        .filter(|&k| cols[k] == ColType::Track)
        .collect();
    let time = cols.iter().position(|&c| c == ColType::Time);
    let parts: Vec<&str> = (0..cols.len())
        .map(|k| {
            if k == tracks[0] {
                x
            } else if k == tracks[1] {
                y
            } else if Some(k) == time {
                t
            } else {
                "_"
            }
        })
        .collect();
    format!("{pred}({})", parts.join(", "))
}

/// A `_` in a head (`d` its E0201): name it after a body variable the head does not use yet.
fn wildcard(
    source: &str,
    c: &Clause,
    at: Span,
    in_body: &[&str],
    in_head: &HashSet<&str>,
    bound: &BTreeSet<&str>,
    d: &mut Diagnostic,
) {
    let Some(v) = in_body
        .iter()
        .copied()
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
        "a head's columns are values the body binds: name it, e.g. `{}`, or drop the column",
        excerpt(&head)
    ));
    d.fix = vec![crate::Edit {
        span: at,
        text: v.to_string(),
    }];
}

/// Most bytes of program text a hint quotes: a longer clause or head is quoted by its start and
/// end around `…`, so the hints of a huge clause do not each copy it whole.
const QUOTE_MAX: usize = 240;

/// `text` as a hint quotes it: whole up to [`QUOTE_MAX`] bytes, else its first and last
/// `QUOTE_MAX / 2` bytes around `…`.
pub(crate) fn excerpt(text: &str) -> String {
    if text.len() <= QUOTE_MAX {
        return text.to_string();
    }
    let mut head = QUOTE_MAX / 2;
    while !text.is_char_boundary(head) {
        head -= 1;
    }
    let mut tail = text.len() - QUOTE_MAX / 2;
    while !text.is_char_boundary(tail) {
        tail += 1;
    }
    format!("{} … {}", &text[..head], &text[tail..])
}

/// The function of a `count` or `sum` of the clause whose braces hold `v`, if any (such a
/// variable is no witness: only `min` and `max` have them, see `crate::witness`).
fn folded_only(c: &Clause, v: &str) -> Option<&'static str> {
    c.body.iter().find_map(|l| match l {
        Literal::Agg(g)
            if matches!(g.func, AggFunc::Count | AggFunc::Sum)
                && crate::walk::aggregate_vars(g).contains(&v) =>
        {
            Some(g.func.as_str())
        }
        _ => None,
    })
}
