//! Which variables an expression, a literal or an aggregate holds, and which atoms a body holds
//! ([`body_atoms`]), and their renaming ([`rename_literal`]): the AST walks that the checker, the prelude, the engine's planner and its
//! explanations all ask, written once.
//!
//! Every walk visits named variables only (never `_`) in source order, repeats included; the
//! `*_spanned` forms keep each occurrence's span for diagnostics.

use crate::ast::{Aggregate, Atom, Clause, Expr, ExprKind, Literal, Span};

/// Calls `f` with each named variable of `e` and its span, in order.
pub fn each_var<'a>(e: &'a Expr, f: &mut dyn FnMut(&'a str, Span)) {
    match &e.kind {
        ExprKind::Var(v) => f(v, e.span),
        ExprKind::Neg(x) => each_var(x, f),
        ExprKind::Binary(_, a, b) => {
            each_var(a, f);
            each_var(b, f);
        }
        ExprKind::Call(_, args) => args.iter().for_each(|a| each_var(a, f)),
        ExprKind::Wildcard
        | ExprKind::Str(_)
        | ExprKind::Int(_)
        | ExprKind::Float(_)
        | ExprKind::Quantity(_) => {}
    }
}

/// Appends the named variables of `e` to `out`, in order.
pub fn expr_vars<'a>(e: &'a Expr, out: &mut Vec<&'a str>) {
    each_var(e, &mut |v, _| out.push(v));
}

/// Appends the named variables of `e` with their spans to `out`, in order.
pub fn expr_vars_spanned<'a>(e: &'a Expr, out: &mut Vec<(&'a str, Span)>) {
    each_var(e, &mut |v, s| out.push((v, s)));
}

/// The named variables of `e`, in order.
pub fn expr_names(e: &Expr) -> Vec<&str> {
    let mut out = Vec::new();
    expr_vars(e, &mut out);
    out
}

/// Appends the spans of the wildcards (`_`) of `e` to `out`, in order.
pub fn wildcards(e: &Expr, out: &mut Vec<Span>) {
    match &e.kind {
        ExprKind::Wildcard => out.push(e.span),
        ExprKind::Neg(x) => wildcards(x, out),
        ExprKind::Binary(_, a, b) => {
            wildcards(a, out);
            wildcards(b, out);
        }
        ExprKind::Call(_, args) => args.iter().for_each(|a| wildcards(a, out)),
        ExprKind::Var(_)
        | ExprKind::Str(_)
        | ExprKind::Int(_)
        | ExprKind::Float(_)
        | ExprKind::Quantity(_) => {}
    }
}

/// Calls `f` with each named variable of `l`, descending into an aggregate: its result, its
/// target and its braces (nested aggregates too).
pub fn each_literal_var<'a>(l: &'a Literal, f: &mut dyn FnMut(&'a str, Span)) {
    match l {
        Literal::Pos(a) | Literal::Neg(a, _) => a.args.iter().for_each(|e| each_var(e, f)),
        Literal::Cmp(c) => {
            each_var(&c.lhs, f);
            each_var(&c.rhs, f);
        }
        Literal::Agg(g) => {
            each_var(&g.result, f);
            if let Some(t) = &g.target {
                each_var(t, f);
            }
            g.body.iter().for_each(|l| each_literal_var(l, f));
        }
    }
}

/// Appends the named variables of every literal of `body` (inside aggregates too) to `out`.
pub fn literal_vars<'a>(body: &'a [Literal], out: &mut Vec<&'a str>) {
    for l in body {
        each_literal_var(l, &mut |v, _| out.push(v));
    }
}

/// Appends the named variables of every literal of `body` (inside aggregates too) with their
/// spans to `out`.
pub fn literal_vars_spanned<'a>(body: &'a [Literal], out: &mut Vec<(&'a str, Span)>) {
    for l in body {
        each_literal_var(l, &mut |v, s| out.push((v, s)));
    }
}

/// Appends the named variables `l` shows to the body around it: all of an atom's or a
/// comparison's, and of an aggregate only its result (what is inside the braces is local).
pub fn outer_vars<'a>(l: &'a Literal, out: &mut Vec<&'a str>) {
    match l {
        Literal::Agg(g) => expr_vars(&g.result, out),
        other => each_literal_var(other, &mut |v, _| out.push(v)),
    }
}

/// The distinct named variables of an aggregate's braces and target (nested aggregates' results,
/// targets and braces included), in order of first occurrence; not its result.
pub fn aggregate_vars(g: &Aggregate) -> Vec<&str> {
    let mut vs = Vec::new();
    literal_vars(&g.body, &mut vs);
    if let Some(t) = &g.target {
        expr_vars(t, &mut vs);
    }
    let mut seen = std::collections::HashSet::new();
    vs.retain(|v| seen.insert(*v));
    vs
}

/// The distinct named variables an aggregate's braces bind at their own level, in order of
/// first occurrence: those of its atoms, comparisons and target, and of a nested aggregate
/// only its result (what is inside the nested braces is local to them). The tuples a `count`
/// or `sum` folds are distinct in these.
pub fn aggregate_level_vars(g: &Aggregate) -> Vec<&str> {
    let mut vs = Vec::new();
    for l in &g.body {
        outer_vars(l, &mut vs);
    }
    if let Some(t) = &g.target {
        expr_vars(t, &mut vs);
    }
    let mut seen = std::collections::HashSet::new();
    vs.retain(|v| seen.insert(*v));
    vs
}

/// Every atom of a clause's body, including inside aggregates, with whether it is negated.
pub fn body_atoms(body: &[Literal]) -> Vec<(&Atom, bool)> {
    let mut out = Vec::new();
    for l in body {
        match l {
            Literal::Pos(a) => out.push((a, false)),
            Literal::Neg(a, _) => out.push((a, true)),
            Literal::Cmp(_) => {}
            Literal::Agg(g) => out.extend(body_atoms(&g.body)),
        }
    }
    out
}

/// An upper bound on the binding slots the engine's plans of `clause` use, the width its rows
/// need: each distinct named variable, each `_` inside an aggregate's braces (the braces fold
/// distinct tuples, so their wildcards are bound too), each argument of a positive atom that is
/// neither a variable nor `_` and holds a variable (read into a hidden slot when joined before its
/// variables are bound) and each aggregate (its result). The checker's E0406 and the engine's
/// choice of row width both use it, so they agree on what runs.
pub fn binding_slots(clause: &Clause) -> usize {
    fn literals(body: &[Literal], in_braces: bool, n: &mut usize) {
        for l in body {
            match l {
                Literal::Pos(a) => {
                    for e in &a.args {
                        *n += match e.kind {
                            ExprKind::Var(_) => 0,
                            ExprKind::Wildcard => usize::from(in_braces),
                            _ => usize::from(!expr_names(e).is_empty()),
                        };
                    }
                }
                Literal::Neg(..) | Literal::Cmp(_) => {}
                Literal::Agg(g) => {
                    *n += 1;
                    literals(&g.body, true, n);
                }
            }
        }
    }
    let mut names: Vec<&str> = clause.head.args.iter().flat_map(expr_names).collect();
    literal_vars(&clause.body, &mut names);
    let mut seen = std::collections::HashSet::new();
    names.retain(|v| seen.insert(*v));
    let mut n = names.len();
    literals(&clause.body, false, &mut n);
    n
}

/// Renames the variables of `e` in place: each named variable `v` becomes `f(v)` when that is
/// `Some` (`_` is left alone).
pub fn rename_expr(e: &mut Expr, f: &dyn Fn(&str) -> Option<String>) {
    match &mut e.kind {
        ExprKind::Var(v) => {
            if let Some(n) = f(v) {
                *v = n;
            }
        }
        ExprKind::Neg(x) => rename_expr(x, f),
        ExprKind::Binary(_, a, b) => {
            rename_expr(a, f);
            rename_expr(b, f);
        }
        ExprKind::Call(_, args) => args.iter_mut().for_each(|a| rename_expr(a, f)),
        ExprKind::Wildcard
        | ExprKind::Str(_)
        | ExprKind::Int(_)
        | ExprKind::Float(_)
        | ExprKind::Quantity(_) => {}
    }
}

/// Renames the variables of a literal in place as [`rename_expr`] does, inside aggregates too.
pub fn rename_literal(l: &mut Literal, f: &dyn Fn(&str) -> Option<String>) {
    match l {
        Literal::Pos(a) | Literal::Neg(a, _) => a.args.iter_mut().for_each(|e| rename_expr(e, f)),
        Literal::Cmp(c) => {
            rename_expr(&mut c.lhs, f);
            rename_expr(&mut c.rhs, f);
        }
        Literal::Agg(g) => {
            rename_expr(&mut g.result, f);
            if let Some(t) = &mut g.target {
                rename_expr(t, f);
            }
            g.body.iter_mut().for_each(|l| rename_literal(l, f));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ast::Clause;

    fn clause(src: &str) -> Clause {
        let (program, diags) = crate::parser::parse(src);
        assert!(diags.is_empty(), "{diags:?}");
        program.clauses.into_iter().next().expect("one clause")
    }

    #[test]
    fn aggregate_vars_include_nested_targets_once_and_not_the_result() {
        let c = clause("h(X, N) :- p(X), N = count : { q(X, Y), M = sum Z : { r(Y, Z) }, M > 1 }.");
        let Literal::Agg(g) = &c.body[1] else {
            panic!("aggregate expected")
        };
        assert_eq!(aggregate_vars(g), vec!["X", "Y", "M", "Z"]);
        let mut outer = Vec::new();
        c.body.iter().for_each(|l| outer_vars(l, &mut outer));
        assert_eq!(outer, vec!["X", "N"]);
    }

    #[test]
    fn walks_skip_wildcards_and_constants_and_keep_repeats() {
        let c = clause("h(X) :- p(X, _, \"a\", 3), X + abs(_ - X) > 2.0.");
        let mut names = Vec::new();
        literal_vars(&c.body, &mut names);
        assert_eq!(names, vec!["X", "X", "X"]);
        let Literal::Cmp(cmp) = &c.body[1] else {
            panic!("comparison expected")
        };
        let mut w = Vec::new();
        wildcards(&cmp.lhs, &mut w);
        assert_eq!(w.len(), 1);
        let mut spanned = Vec::new();
        expr_vars_spanned(&cmp.lhs, &mut spanned);
        assert_eq!(spanned.len(), 2);
        assert!(spanned[0].1.start < spanned[1].1.start);
    }

    #[test]
    fn binding_slots_count_variables_braced_wildcards_computed_arguments_and_aggregates() {
        // A, B, T; no computed argument, no aggregate.
        assert_eq!(
            binding_slots(&clause("h(A, T) :- p(A, B, T), !q(A, _), B > 1.")),
            3
        );
        // X, N; X + 1 in an atom; -3 holds no variable.
        assert_eq!(binding_slots(&clause("g(X) :- g(X + 1), v(X, -3).")), 2);
        // N, C, Z (nested result and brace variables once), two `_` in braces, two aggregates.
        let c = clause("c(N, C) :- a(N), C = count : { b(N, _, Z), Z = min W : { d(W, _) } }.");
        assert_eq!(binding_slots(&c), 4 + 2 + 2);
    }
}
