//! Programs that check clean but do not say what was meant, and rules the engine cannot hold:
//!
//! - E0406: a rule, an aggregate's braces or a relation wider than the engine's tuples
//!   ([`MAX_VARIABLES`]), so the checker and the engine agree on what runs;
//! - W0506: an atom that shares no variable with the rest of its body, a cross product (usually a
//!   `_` meant to join: `count : { near(V, _, T, D), category(_, "PEDESTRIAN") }` counts every
//!   neighbour whenever some pedestrian exists);
//! - W0507: a `_` (or an unconstrained variable of its own) in the time column of an aggregate's
//!   atom while the clause is about a frame: it folds over every frame, not the clause's;
//! - W0508: a `related` rule whose first object need not be referred at that frame;
//! - E0201 on a negation whose own variable a comparison then tests (`!near(X, V, T, D), D < 5.0`
//!   for "no vehicle within 5 m"): the hint and fix move the atom and its conditions into a
//!   helper and negate that, where "write `_`" would say "no `near` fact at all".
//!
//! Each warning's hint, applied as written (most carry a machine-applicable fix), gives the program
//! that was meant.

use std::collections::{BTreeMap, BTreeSet};

use scenalog_facts::catalog::ColType;

use super::preds::PredTable;
use crate::ast::{Atom, Clause, Expr, ExprKind, Literal, Program, Span};
use crate::diagnostics::{self, error, warning};
use crate::walk::{self, expr_names};
use crate::Diagnostic;

/// Most values one rule may bind ([`walk::binding_slots`]), and most columns a relation may have:
/// the width of the engine's widest tuples (`scenalog_engine::value::WIDEST`, which a test there
/// keeps equal to this).
pub const MAX_VARIABLES: usize = 64;

/// Most W0506 warnings one body gets: past that, the rest are the same mistake again.
const MAX_CROSS_PRODUCTS: usize = 64;

/// Most E0201 diagnostics given a helper-rule fix in one program: each costs a pass over its
/// clause.
const MAX_NEGATION_FIXES: usize = 64;

/// Most `related` rules compared with the `referred` rules for W0508: each comparison costs a
/// pass over both bodies.
const MAX_RELATED_CHECKED: usize = 64;

/// Runs every check of this module over the program.
pub fn check_program(
    program: &Program,
    table: &PredTable,
    inferred: &BTreeMap<String, Vec<ColType>>,
    diags: &mut Vec<Diagnostic>,
) {
    let types = |pred: &str| super::column_types(pred, inferred);
    for (name, entry) in &table.preds {
        if entry.arity > MAX_VARIABLES {
            if let Some(c) = program.clauses.iter().find(|c| &c.head.pred == name) {
                diags.push(
                    error(
                        diagnostics::TOO_MANY_VARIABLES,
                        c.head.span,
                        format!(
                            "`{name}` has {} columns; the engine holds at most {MAX_VARIABLES}",
                            entry.arity
                        ),
                    )
                    .with_hint("split it into two relations that share the columns that join them"),
                );
            }
        }
    }
    for c in &program.clauses {
        too_many_variables(c, diags);
        cross_products(c, &types, diags);
        aggregates_over_time(c, &types, diags);
    }
    related_not_referred(program, diags);
    negation_helpers(program, diags);
}

/// The variable an E0201 names (`unsafe variable `D` in the negation of …`).
fn unsafe_name(d: &Diagnostic) -> Option<&str> {
    let rest = d.message.strip_prefix("unsafe variable `")?;
    if !rest.contains("in the negation of") {
        return None;
    }
    rest.split('`').next()
}

/// For each E0201 on a negation whose variable a comparison of the same body tests, a hint and
/// fix that move the negated atom, those comparisons and the atoms only about its own variables
/// into a helper rule, and negate the helper.
fn negation_helpers(program: &Program, diags: &mut [Diagnostic]) {
    let mut fixed = 0;
    for d in diags.iter_mut() {
        if d.code != diagnostics::UNSAFE_VARIABLE || fixed >= MAX_NEGATION_FIXES {
            continue;
        }
        let Some(var) = unsafe_name(d).map(str::to_string) else {
            continue;
        };
        let Some(c) = program
            .clauses
            .iter()
            .find(|c| c.span.start <= d.span.start && d.span.end <= c.span.end)
        else {
            continue;
        };
        let Some(n) = c.body.iter().position(|l| {
            matches!(l, Literal::Neg(..))
                && l.span().start <= d.span.start
                && d.span.end <= l.span().end
        }) else {
            continue;
        };
        fixed += 1;
        let Some((helper, rewritten)) = negation_helper(c, n, &var) else {
            continue;
        };
        let helper_text = crate::printer::print_clause(&helper);
        let clause_text = crate::printer::print_clause(&rewritten);
        d.hint = Some(format!(
            "a negation cannot put a condition on a variable of its own: `!{}` followed by a test of `{var}` does not say \"no such fact\". Put the atom and its conditions in a helper and negate it: `{}` then `!{}`",
            crate::printer::print_atom(match &c.body[n] {
                Literal::Neg(a, _) => a,
                _ => &helper.head,
            }),
            helper_text.trim_end(),
            crate::printer::print_atom(&helper.head)
        ).split_whitespace().collect::<Vec<_>>().join(" "));
        d.fix = vec![crate::Edit {
            span: c.span,
            text: format!("{}\n{}", helper_text.trim_end(), clause_text.trim_end()),
        }];
    }
}

/// The helper rule and the rewritten clause for the negated literal `n` of `c`, when a
/// comparison of the body tests its unsafe variable `var`.
fn negation_helper(c: &Clause, n: usize, var: &str) -> Option<(Clause, Clause)> {
    let Literal::Neg(atom, _) = &c.body[n] else {
        return None;
    };
    let tests = |l: &Literal| matches!(l, Literal::Cmp(_)) && literal_names(l).contains(&var);
    if !c.body.iter().any(tests) {
        return None;
    }
    let head_vars: BTreeSet<&str> = c.head.args.iter().flat_map(expr_names).collect();
    let mut moved: BTreeSet<usize> = [n].into_iter().collect();
    let mut own: BTreeSet<&str> = atom.args.iter().flat_map(expr_names).collect();
    own.retain(|v| !head_vars.contains(v));
    loop {
        let before = moved.len();
        for (i, l) in c.body.iter().enumerate() {
            if moved.contains(&i) || matches!(l, Literal::Agg(_) | Literal::Neg(..)) {
                continue;
            }
            let vs = literal_names(l);
            let about_own = vs.iter().any(|v| own.contains(v));
            let only_own_or_outer = vs
                .iter()
                .all(|v| own.contains(v) || !is_local_elsewhere(c, i, n, v, &moved));
            if about_own
                && only_own_or_outer
                && (matches!(l, Literal::Cmp(_)) || vs.iter().all(|v| own.contains(v)))
            {
                moved.insert(i);
                own.extend(vs.iter().filter(|v| !head_vars.contains(*v)));
            }
        }
        if moved.len() == before {
            break;
        }
    }
    // The helper keeps the variables the rest of the clause (or its head) still needs.
    let rest_vars: BTreeSet<&str> = c
        .body
        .iter()
        .enumerate()
        .filter(|(i, _)| !moved.contains(i))
        .flat_map(|(_, l)| literal_names(l))
        .chain(head_vars.iter().copied())
        .collect();
    let mut keep: Vec<&str> = Vec::new();
    for i in &moved {
        for v in literal_names(&c.body[*i]) {
            if rest_vars.contains(v) && !keep.contains(&v) {
                keep.push(v);
            }
        }
    }
    let used: BTreeSet<String> = std::iter::once(c.head.pred.clone())
        .chain(c.body.iter().filter_map(|l| match l {
            Literal::Pos(a) | Literal::Neg(a, _) => Some(a.pred.clone()),
            _ => None,
        }))
        .collect();
    let name = free_relation_name(&format!("some_{}", atom.pred), |n| used.contains(n))?;
    let span = Span::default();
    let head = Atom {
        pred: name,
        pred_span: span,
        args: keep.iter().map(|v| Expr::var(v)).collect(),
        span,
    };
    let mut body = vec![Literal::Pos(atom.clone())];
    body.extend(
        c.body
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != n && moved.contains(i))
            .map(|(_, l)| l.clone()),
    );
    let helper = Clause {
        head: head.clone(),
        body,
        span,
    };
    let mut rewritten = c.clone();
    rewritten.body = c
        .body
        .iter()
        .enumerate()
        .filter_map(|(i, l)| {
            if i == n {
                Some(Literal::Neg(head.clone(), span))
            } else if moved.contains(&i) {
                None
            } else {
                Some(l.clone())
            }
        })
        .collect();
    Some((helper, rewritten))
}

/// Whether variable `v` occurs in a literal of `c` other than `i`, the negation `n` and the
/// literals already moved.
fn is_local_elsewhere(c: &Clause, i: usize, n: usize, v: &str, moved: &BTreeSet<usize>) -> bool {
    c.head.args.iter().flat_map(expr_names).any(|x| x == v)
        || c.body
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i && *j != n && !moved.contains(j))
            .any(|(_, l)| literal_names(l).contains(&v))
}

fn distinct<'a>(vs: impl IntoIterator<Item = &'a str>) -> BTreeSet<&'a str> {
    vs.into_iter().collect()
}

/// The name a fix gives a helper relation it writes: `base`, else `base_1`, `base_2`, … the
/// first that `taken` refuses (`None` after a hundred).
pub(super) fn free_relation_name(base: &str, taken: impl Fn(&str) -> bool) -> Option<String> {
    (0..100)
        .map(|i| match i {
            0 => base.to_string(),
            i => format!("{base}_{i}"),
        })
        .find(|n| !taken(n))
}

/// The variables a literal mentions.
pub(super) fn literal_names(l: &Literal) -> Vec<&str> {
    let mut out = Vec::new();
    walk::literal_vars(std::slice::from_ref(l), &mut out);
    out
}

/// E0406 for one clause: more binding slots ([`walk::binding_slots`]: its variables, each `_` in
/// braces, each computed atom argument, each aggregate) than the engine's widest row.
fn too_many_variables(c: &Clause, diags: &mut Vec<Diagnostic>) {
    let n = walk::binding_slots(c);
    if n > MAX_VARIABLES {
        diags.push(
            error(
                diagnostics::TOO_MANY_VARIABLES,
                c.head.span,
                format!(
                    "this rule binds {n} values (its variables, each `_` inside braces, each computed atom argument and each aggregate); the engine holds at most {MAX_VARIABLES} in one rule"
                ),
            )
            .with_hint(
                "move some atoms into a helper rule whose head keeps only the variables the rest of the rule needs",
            ),
        );
    }
}

/// The spans and column types of the `_` arguments of an atom.
fn wildcard_columns(
    a: &Atom,
    types: &dyn Fn(&str) -> Option<Vec<ColType>>,
) -> Vec<(Span, Option<ColType>)> {
    let cols = types(&a.pred).unwrap_or_default();
    a.args
        .iter()
        .enumerate()
        .filter(|(_, e)| matches!(e.kind, ExprKind::Wildcard))
        .map(|(i, e)| (e.span, cols.get(i).copied()))
        .collect()
}

/// A variable name not used in the clause, starting from `base`.
fn fresh_name(c: &Clause, base: &str) -> String {
    let mut used: Vec<&str> = c.head.args.iter().flat_map(expr_names).collect();
    used.extend(c.body.iter().flat_map(literal_names));
    (1..)
        .map(|i| format!("{base}{i}"))
        .find(|n| !used.contains(&n.as_str()))
        .unwrap_or_else(|| base.to_string())
}

/// W0506 in one body: `body` with the variables `outside` it (the head's, or for an aggregate's
/// braces the rest of the clause's).
fn cross_products_in(
    c: &Clause,
    body: &[Literal],
    outside: &[&str],
    in_aggregate: bool,
    types: &dyn Fn(&str) -> Option<Vec<ColType>>,
    diags: &mut Vec<Diagnostic>,
) {
    let atoms = body.iter().filter(|l| matches!(l, Literal::Pos(_))).count();
    if atoms < 2 {
        return;
    }
    // In how many literals each variable occurs, and the `_` columns of each atom by type: each
    // atom's questions are then answered without another pass over the body (linear in it).
    let mut occurs: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
    for l in body {
        for v in distinct(literal_names(l)) {
            *occurs.entry(v).or_default() += 1;
        }
    }
    let outside: BTreeSet<&str> = outside.iter().copied().collect();
    let wild_of: Vec<Vec<(Span, Option<ColType>)>> = body
        .iter()
        .map(|l| match l {
            Literal::Pos(a) => wildcard_columns(a, types),
            _ => Vec::new(),
        })
        .collect();
    let mut by_type: std::collections::HashMap<ColType, Vec<(usize, Span)>> =
        std::collections::HashMap::new();
    for (j, w) in wild_of.iter().enumerate() {
        for (s, t) in w {
            if let Some(t) = t {
                by_type.entry(*t).or_default().push((j, *s));
            }
        }
    }
    let mut fresh: Option<String> = None;
    let mut reported = 0;
    for (i, l) in body.iter().enumerate() {
        let Literal::Pos(a) = l else { continue };
        if reported >= MAX_CROSS_PRODUCTS {
            break;
        }
        let own: BTreeSet<&str> = a.args.iter().flat_map(expr_names).collect();
        let wild = &wild_of[i];
        if wild.is_empty() && own.is_empty() {
            continue;
        }
        // At top level a named variable used nowhere else is W0501's; here only atoms with a `_`.
        if !in_aggregate && wild.is_empty() {
            continue;
        }
        let shared = own
            .iter()
            .any(|v| outside.contains(v) || occurs.get(v).copied().unwrap_or(0) > 1);
        // An atom about an unnamed object: a `_` in a track column and no named track, whatever
        // time it shares (`stopped(_, T)`: some object is stopped at T).
        let cols = types(&a.pred).unwrap_or_default();
        let unnamed_object = wild.iter().any(|(_, t)| *t == Some(ColType::Track))
            && !a
                .args
                .iter()
                .zip(&cols)
                .any(|(e, t)| *t == ColType::Track && e.as_var().is_some());
        if shared && !unnamed_object {
            continue;
        }
        // A `_` of another atom of the same body in a column of the same type: the join meant.
        let mut partners: Vec<(Span, Span)> = Vec::new();
        for (mine, t) in wild {
            let Some(t) = t else { continue };
            let others = by_type.get(t).map(Vec::as_slice).unwrap_or_default();
            partners.extend(
                others
                    .iter()
                    .filter(|(j, _)| *j != i)
                    .take(2)
                    .map(|(_, theirs)| (*mine, *theirs)),
            );
            if partners.len() > 1 {
                break;
            }
        }
        reported += 1;
        let mut d = warning(
            diagnostics::CROSS_PRODUCT,
            a.span,
            format!(
                "`{}` names no object the rest of its {} uses: it only tests that some such fact exists, and every other match is paired with it",
                a.pred,
                if in_aggregate { "braces" } else { "rule" }
            ),
        );
        if let [(mine, theirs)] = partners.as_slice() {
            let name = fresh.get_or_insert_with(|| fresh_name(c, "Y")).clone();
            d = d
                .with_hint(format!(
                    "`_` is a fresh variable at each use and joins nothing: name the column in both atoms (`{name}`) to say they are the same object"
                ))
                .with_edit(*mine, name.clone())
                .with_edit(*theirs, name);
        } else {
            d = d.with_hint(
                "`_` is a fresh variable at each use and joins nothing: give the column a name and use the same name where that object occurs",
            );
        }
        diags.push(d);
    }
}

fn cross_products(
    c: &Clause,
    types: &dyn Fn(&str) -> Option<Vec<ColType>>,
    diags: &mut Vec<Diagnostic>,
) {
    let head: Vec<&str> = c.head.args.iter().flat_map(expr_names).collect();
    cross_products_in(c, &c.body, &head, false, types, diags);
    for (i, l) in c.body.iter().enumerate() {
        let Literal::Agg(g) = l else { continue };
        let mut outside = head.clone();
        for (j, o) in c.body.iter().enumerate() {
            if j != i {
                outside.extend(literal_names(o));
            }
        }
        outside.extend(expr_names(&g.result));
        cross_products_in(c, &g.body, &outside, true, types, diags);
    }
}

/// The time variables of a clause outside its aggregates, the head's first.
fn outer_time_vars<'a>(
    c: &'a Clause,
    types: &dyn Fn(&str) -> Option<Vec<ColType>>,
) -> Vec<&'a str> {
    let mut out: Vec<&str> = Vec::new();
    let mut take = |a: &'a Atom| {
        let cols = types(&a.pred).unwrap_or_default();
        for (e, t) in a.args.iter().zip(cols) {
            if let (Some(v), ColType::Time) = (e.as_var(), t) {
                if !out.contains(&v) {
                    out.push(v);
                }
            }
        }
    };
    take(&c.head);
    for l in &c.body {
        if let Literal::Pos(a) = l {
            take(a);
        }
    }
    out
}

/// W0507 for one clause.
fn aggregates_over_time(
    c: &Clause,
    types: &dyn Fn(&str) -> Option<Vec<ColType>>,
    diags: &mut Vec<Diagnostic>,
) {
    let outer = outer_time_vars(c, types);
    let Some(frame) = outer.first() else { return };
    for l in &c.body {
        let Literal::Agg(g) = l else { continue };
        // Variables the braces constrain with a comparison (a window) are meant.
        let compared: BTreeSet<&str> = g
            .body
            .iter()
            .filter(|l| matches!(l, Literal::Cmp(_)))
            .flat_map(literal_names)
            .collect();
        let mentioned: BTreeSet<&str> = g.body.iter().flat_map(literal_names).collect();
        if outer.iter().any(|v| mentioned.contains(v)) {
            continue;
        }
        for b in &g.body {
            let Literal::Pos(a) = b else { continue };
            let cols = types(&a.pred).unwrap_or_default();
            for (e, t) in a.args.iter().zip(cols) {
                if t != ColType::Time {
                    continue;
                }
                let free = match &e.kind {
                    ExprKind::Wildcard => true,
                    ExprKind::Var(v) => !compared.contains(v.as_str()),
                    _ => false,
                };
                if !free {
                    continue;
                }
                diags.push(
                    warning(
                        diagnostics::AGGREGATE_OVER_TIME,
                        e.span,
                        format!(
                            "this time column is free inside the `{}`: it folds over every frame of the log, not over frame `{frame}`",
                            g.func.as_str()
                        ),
                    )
                    .with_hint(format!(
                        "write `{frame}` here to {} at the rule's time (or, over a window of time, bound it in seconds, e.g. `U >= {frame} - 2 s, U <= {frame}`, and compare a count with the window's `present` count, never with a number of samples)",
                        g.func.as_str()
                    ))
                    .with_edit(e.span, frame.to_string()),
                );
            }
        }
    }
}

/// A literal as text with its variables renamed, for comparing bodies.
fn renamed(l: &Literal, map: &BTreeMap<&str, &str>) -> String {
    let mut text = crate::printer::print_literal(l);
    // Rename whole identifiers only.
    for (from, to) in map {
        text = replace_ident(&text, from, to);
    }
    text
}

fn replace_ident(text: &str, from: &str, to: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < text.len() {
        let is_ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
        if text[i..].starts_with(from)
            && (i == 0 || !is_ident(bytes[i - 1]))
            && bytes.get(i + from.len()).is_none_or(|b| !is_ident(*b))
        {
            out.push_str(to);
            i += from.len();
        } else {
            let ch = text[i..].chars().next().unwrap_or(' ');
            out.push(ch);
            i += ch.len_utf8();
        }
    }
    out
}

/// Whether a `related` clause's body implies its first object is referred at its frame: it has
/// `referred(A, T)`, or it contains every literal of some `referred` rule's body (that rule's
/// object and frame renamed to the related rule's; a `_` there matches any argument).
fn tied(r: &Clause, referred: &[&Clause]) -> bool {
    let (Some(a), Some(t)) = (
        r.head.args.first().and_then(|e| e.as_var()),
        r.head.args.get(2).and_then(|e| e.as_var()),
    ) else {
        return true;
    };
    let has_referred = r.body.iter().any(|l| match l {
        Literal::Pos(x) => {
            x.pred == "referred"
                && x.args.first().and_then(|e| e.as_var()) == Some(a)
                && x.args.get(1).and_then(|e| e.as_var()) == Some(t)
        }
        _ => false,
    });
    if has_referred {
        return true;
    }
    let body: Vec<String> = r.body.iter().map(crate::printer::print_literal).collect();
    referred.iter().any(|q| {
        let (Some(x), Some(s)) = (
            q.head.args.first().and_then(|e| e.as_var()),
            q.head.args.get(1).and_then(|e| e.as_var()),
        ) else {
            return false;
        };
        let map: BTreeMap<&str, &str> = [(x, a), (s, t)].into_iter().collect();
        q.body.iter().all(|l| {
            let want = renamed(l, &map);
            body.iter().any(|have| matches_with_wildcards(&want, have))
        })
    })
}

/// Whether `have` is `want` with each `_` argument of `want` filled by anything.
fn matches_with_wildcards(want: &str, have: &str) -> bool {
    if want == have {
        return true;
    }
    let split = |s: &str| -> Option<(String, Vec<String>)> {
        let open = s.find('(')?;
        let inner = s.get(open + 1..s.len().checked_sub(1)?)?;
        Some((
            s[..open].to_string(),
            inner.split(", ").map(str::to_string).collect(),
        ))
    };
    match (split(want), split(have)) {
        (Some((p, xs)), Some((q, ys))) => {
            p == q && xs.len() == ys.len() && xs.iter().zip(&ys).all(|(x, y)| x == "_" || x == y)
        }
        _ => false,
    }
}

/// W0508: every `related` clause not tied to `referred`.
fn related_not_referred(program: &Program, diags: &mut Vec<Diagnostic>) {
    let referred: Vec<&Clause> = program
        .clauses
        .iter()
        .filter(|c| c.head.pred == "referred" && c.head.args.len() == 2)
        .collect();
    if referred.is_empty() {
        return;
    }
    for r in program
        .clauses
        .iter()
        .filter(|c| c.head.pred == "related" && c.head.args.len() == 3 && !c.body.is_empty())
        .take(MAX_RELATED_CHECKED)
    {
        if tied(r, &referred) {
            continue;
        }
        let (Some(a), Some(t)) = (
            r.head.args.first().map(crate::printer::print_expr),
            r.head.args.get(2).map(crate::printer::print_expr),
        ) else {
            continue;
        };
        // The referred object written second: the fix swaps the columns (adding
        // `referred(B, T)` would tie the rule to an object never referred, and empty it).
        let mut swapped = r.clone();
        swapped.head.args.swap(0, 1);
        if tied(&swapped, &referred) {
            let b = r
                .head
                .args
                .get(1)
                .map(crate::printer::print_expr)
                .unwrap_or_default();
            let fixed = crate::printer::print_atom(&swapped.head);
            diags.push(
                warning(
                    diagnostics::RELATED_NOT_REFERRED,
                    r.head.span,
                    format!(
                        "this `related` rule has its columns swapped: its body requires `referred({b}, {t})`, so the referred object is {b}, and `related` takes it first"
                    ),
                )
                .with_hint(format!("write the head as `{fixed}`"))
                .with_edit(r.head.span, fixed),
            );
            continue;
        }
        let at = r.body.first().map_or(r.span, |l| l.span());
        diags.push(
            warning(
                diagnostics::RELATED_NOT_REFERRED,
                r.head.span,
                format!(
                    "this `related` rule does not require `referred({a}, {t})`: it can pair objects at frames where {a} is not referred, and those pairs are reported"
                ),
            )
            .with_hint(format!(
                "add `referred({a}, {t})` to its body so a related object is only given where its referred one holds"
            ))
            .with_edit(Span::new(at.start, at.start), format!("referred({a}, {t}), ")),
        );
    }
}
