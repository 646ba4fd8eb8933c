//! W0505: a `count` whose braces have no variable of their own. Every variable of its body also
//! occurs outside the braces, so each one groups the count and the count is 0 or 1; usually a
//! variable meant to be counted was reused from outside by mistake.

use crate::ast::{AggFunc, Clause, Expr, ExprKind, Literal};
use crate::diagnostics::{self, warning};
use crate::Diagnostic;

/// Names of the variables of `e`, in order.
fn vars<'a>(e: &'a Expr, out: &mut Vec<&'a str>) {
    let mut with_spans = Vec::new();
    super::safety::vars(e, &mut with_spans);
    out.extend(with_spans.into_iter().map(|(v, _)| v));
}

/// Names of the variables of a literal (inside aggregates too), in order.
fn literal_vars<'a>(l: &'a Literal, out: &mut Vec<&'a str>) {
    let mut with_spans = Vec::new();
    super::safety::lit_vars(std::slice::from_ref(l), &mut with_spans);
    out.extend(with_spans.into_iter().map(|(v, _)| v));
}

/// Reports W0505 for the `count`s of one clause's body.
pub fn check_clause(c: &Clause, diags: &mut Vec<Diagnostic>) {
    for (i, l) in c.body.iter().enumerate() {
        let Literal::Agg(g) = l else { continue };
        if g.func != AggFunc::Count {
            continue;
        }
        let mut outer = Vec::new();
        c.head.args.iter().for_each(|e| vars(e, &mut outer));
        for (j, other) in c.body.iter().enumerate() {
            if j != i {
                literal_vars(other, &mut outer);
            }
        }
        let mut inner = Vec::new();
        let mut has_atom = false;
        let mut wildcard = false;
        for b in &g.body {
            if let Literal::Pos(a) = b {
                has_atom = true;
                wildcard |= a.args.iter().any(|e| matches!(e.kind, ExprKind::Wildcard));
                a.args.iter().for_each(|e| vars(e, &mut inner));
            }
        }
        if !has_atom || wildcard || inner.iter().any(|v| !outer.contains(v)) {
            continue;
        }
        let mut seen = Vec::new();
        inner.retain(|v| {
            !seen.contains(v) && {
                seen.push(*v);
                true
            }
        });
        let mut head = Vec::new();
        c.head.args.iter().for_each(|e| vars(e, &mut head));
        let counted = inner.iter().find(|v| !head.contains(v)).unwrap_or(&"Y");
        diags.push(
            warning(
                diagnostics::COUNT_OF_ONE,
                g.span,
                format!(
                    "every variable of this `count` also occurs outside its braces ({}), so they \
                     group it and it is 0 or 1",
                    inner.join(", ")
                ),
            )
            .with_hint(format!(
                "to count the values of `{counted}`, give it a name of its own inside the braces \
                 (e.g. `{counted}2`), or write `_` there"
            )),
        );
    }
}
