//! Aggregate witnesses, as Soufflé means them: in a `min` or `max` aggregate, a variable of the
//! braces that the rest of the rule uses but nothing outside binds (`tallest(S, H) :- H = max X :
//! { height(S, X) }.`) takes the values of the tuples that reach the minimum or maximum: "the
//! student whose height is the maximum", every such student on a tie.
//!
//! [`expand`] rewrites such an aggregate before the checks, so the checker and the engine see
//! plain Datalog: the aggregate with its witnesses made local to the braces, then the braces'
//! literals again outside them with the target equal to the result:
//!
//! ```text
//! tallest(S, H) :- H = max X : { height(_w1_S, X) }, height(S, _w1_X), _w1_X = H.
//! ```
//!
//! The copy's other variables are renamed (`_wN_…`, so they clash with nothing and are not
//! singletons), its spans kept. `count` and `sum` have no witnesses (Soufflé refuses them too): a
//! variable bound only in their braces stays unsafe (E0201). A variable bound only in a nested
//! aggregate's braces is not a witness of the outer one.

use std::collections::{BTreeMap, BTreeSet};

use crate::ast::{AggFunc, Aggregate, CmpOp, Comparison, Expr, ExprKind, Literal, Program};
use crate::diagnostics::{self, warning};
use crate::walk::{self, expr_names, rename_expr, rename_literal};
use crate::Diagnostic;

/// The variables a literal outside an aggregate binds for the rest of the rule: those of its
/// positive atoms, the result of an aggregate, either side of an `=`.
fn binds_outside(l: &Literal, out: &mut BTreeSet<String>) {
    match l {
        Literal::Pos(a) => {
            for e in &a.args {
                out.extend(expr_names(e).into_iter().map(str::to_string));
            }
        }
        Literal::Agg(g) => out.extend(expr_names(&g.result).into_iter().map(str::to_string)),
        Literal::Cmp(c) if c.op == CmpOp::Eq => {
            out.extend(expr_names(&c.lhs).into_iter().map(str::to_string));
            out.extend(expr_names(&c.rhs).into_iter().map(str::to_string));
        }
        Literal::Neg(..) | Literal::Cmp(_) => {}
    }
}

/// The witnesses of the aggregate at `body[i]`: variables of its braces' own level that the head
/// or another literal uses and no other literal binds; with the variables the other literals
/// bind (which group the aggregate).
fn witnesses(
    head: &[Expr],
    body: &[Literal],
    i: usize,
    g: &Aggregate,
) -> (Vec<String>, BTreeSet<String>) {
    let mut bound_outside = BTreeSet::new();
    if !matches!(g.func, AggFunc::Min | AggFunc::Max) {
        return (Vec::new(), bound_outside);
    }
    let mut used_outside: BTreeSet<String> = head
        .iter()
        .flat_map(expr_names)
        .map(str::to_string)
        .collect();
    for (j, l) in body.iter().enumerate() {
        if j != i {
            binds_outside(l, &mut bound_outside);
            let mut vs = Vec::new();
            walk::outer_vars(l, &mut vs);
            used_outside.extend(vs.into_iter().map(str::to_string));
        }
    }
    let result: BTreeSet<&str> = expr_names(&g.result).into_iter().collect();
    // The braces' own variables (their atoms, comparisons and target; a nested aggregate's
    // result): the copy outside binds them as the braces do, or the checker says it cannot.
    let ws = walk::aggregate_level_vars(g)
        .into_iter()
        .map(str::to_string)
        .filter(|v| {
            used_outside.contains(v) && !bound_outside.contains(v) && !result.contains(v.as_str())
        })
        .collect();
    (ws, bound_outside)
}

/// Rewrites every `min`/`max` aggregate with witnesses (see the module documentation), and
/// returns a W0515 for each: someone who meant one extremum per witness (as if it grouped the
/// aggregate) gets another answer, silently without it.
pub fn expand(program: &mut Program) -> Vec<Diagnostic> {
    let mut said = Vec::new();
    let mut next = 0usize;
    for clause in &mut program.clauses {
        let mut i = 0;
        while i < clause.body.len() {
            let Literal::Agg(g) = &clause.body[i] else {
                i += 1;
                continue;
            };
            let (ws, outside) = witnesses(&clause.head.args, &clause.body, i, g);
            if ws.is_empty() {
                i += 1;
                continue;
            }
            next += 1;
            let tag = format!("_w{next}_");
            let names = ws
                .iter()
                .map(|w| format!("`{w}`"))
                .collect::<Vec<_>>()
                .join(", ");
            let func = g.func.as_str();
            said.push(
                warning(
                    diagnostics::WITNESS,
                    g.span,
                    format!(
                        "{names} bound only inside this `{func}`'s braces: the tuples that reach the \
                         {func} over everything the braces match (a witness), not one {func} per value"
                    ),
                )
                .with_hint(format!(
                    "for one {func} per value, bind {names} outside the braces too (with the atom \
                     that gives its values); for the tuples reaching the overall {func}, keep it"
                )),
            );
            // The copy, from the original braces: the witnesses and the variables the rest of
            // the rule binds (the group) keep their names, the rest is renamed; then the target
            // equal to the result.
            let keep: BTreeSet<String> = ws.iter().cloned().chain(outside).collect();
            let rename = |v: &str| (!keep.contains(v)).then(|| format!("{tag}{v}"));
            let mut copy: Vec<Literal> = g.body.clone();
            copy.iter_mut().for_each(|l| rename_literal(l, &rename));
            let target = g.target.clone();
            // The aggregate itself: the witnesses become local to its braces.
            let mut g = g.clone();
            let local: BTreeMap<String, String> = ws
                .iter()
                .map(|w| (w.clone(), format!("{tag}{w}")))
                .collect();
            g.body
                .iter_mut()
                .for_each(|l| rename_literal(l, &|v| local.get(v).cloned()));
            if let Some(t) = &mut g.target {
                rename_expr(t, &|v| local.get(v).cloned());
            }
            // A `_` result gets a name, for the copy's equality.
            if matches!(g.result.kind, ExprKind::Wildcard) {
                g.result = Expr {
                    kind: ExprKind::Var(format!("{tag}result")),
                    span: g.result.span,
                };
            }
            if let Some(mut t) = target {
                rename_expr(&mut t, &rename);
                copy.push(Literal::Cmp(Comparison {
                    op: CmpOp::Eq,
                    lhs: t,
                    rhs: g.result.clone(),
                    span: g.span,
                }));
            }
            let n = copy.len();
            clause.body[i] = Literal::Agg(g);
            clause.body.splice(i + 1..i + 1, copy);
            i += 1 + n;
        }
    }
    said
}

#[cfg(test)]
mod tests {
    use super::*;

    fn expanded(src: &str) -> String {
        let (mut program, diags) = crate::parser::parse(src);
        assert!(diags.is_empty(), "{diags:?}");
        let _ = expand(&mut program);
        let text = crate::printer::print_program(&program);
        text.split_whitespace().collect::<Vec<_>>().join(" ")
    }

    #[test]
    fn min_and_max_witnesses_are_joined_again_outside_the_braces() {
        let out = expanded("tallest(S, H) :- H = max X : { height(S, X) }.\n");
        assert!(
            out.contains("H = max X : { height(_w1_S, X) }, height(S, _w1_X), _w1_X = H"),
            "{out}"
        );
        // A group variable bound outside keeps its name in both; count has no witnesses.
        let out = expanded("r(A, S, D) :- a(A), D = min X : { b(A, S, X) }.\n");
        assert!(
            out.contains("b(A, _w1_S, X) }, b(A, S, _w1_X), _w1_X = D"),
            "{out}"
        );
        let out = expanded("c(S, N) :- N = count : { b(S) }.\n");
        assert_eq!(out, "c(S, N) :- N = count : { b(S) }.", "{out}");
        // A `_` result is named for the equality.
        let out = expanded("f(X, Y) :- _ = min X + Y : { d(X, Y) }.\n");
        assert!(
            out.contains("_w1_result = min _w1_X + _w1_Y : { d(_w1_X, _w1_Y) }"),
            "{out}"
        );
        assert!(out.contains("d(X, Y), X + Y = _w1_result"), "{out}");
    }
}
