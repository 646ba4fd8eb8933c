//! W0505: a `count` whose braces have no variable of their own. Every variable of its body also
//! occurs outside the braces, so each one groups the count and the count is 0 or 1; usually a
//! variable meant to be counted was reused from outside by mistake.

use std::collections::{HashMap, HashSet};

use crate::ast::{AggFunc, Clause, ExprKind, Literal};
use crate::diagnostics::{self, warning};
use crate::walk::{expr_vars as vars, literal_vars};
use crate::Diagnostic;

/// Reports W0505 for the `count`s of one clause's body. The clause's variables are counted once
/// (head and every literal), so each `count` finds what occurs outside its braces by taking its
/// own occurrences away: linear in the clause however many `count`s it holds.
pub fn check_clause(c: &Clause, diags: &mut Vec<Diagnostic>) {
    if !c
        .body
        .iter()
        .any(|l| matches!(l, Literal::Agg(g) if g.func == AggFunc::Count))
    {
        return;
    }
    let mut all = Vec::new();
    c.head.args.iter().for_each(|e| vars(e, &mut all));
    for l in &c.body {
        literal_vars(std::slice::from_ref(l), &mut all);
    }
    let mut total: HashMap<&str, usize> = HashMap::new();
    for v in all {
        *total.entry(v).or_default() += 1;
    }
    for l in &c.body {
        let Literal::Agg(g) = l else { continue };
        if g.func != AggFunc::Count {
            continue;
        }
        let mut own_vars = Vec::new();
        literal_vars(std::slice::from_ref(l), &mut own_vars);
        let mut own: HashMap<&str, usize> = HashMap::new();
        for v in own_vars {
            *own.entry(v).or_default() += 1;
        }
        let outside =
            |v: &str| total.get(v).copied().unwrap_or(0) > own.get(v).copied().unwrap_or(0);
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
        // Braces with no variable (`count : { a(1) }`) count constant tuples: 0 or 1 on
        // purpose, an existence test, with no variable to name.
        if !has_atom || wildcard || inner.is_empty() || inner.iter().any(|v| !outside(v)) {
            continue;
        }
        let mut seen = HashSet::new();
        inner.retain(|v| seen.insert(*v));
        let mut head = Vec::new();
        c.head.args.iter().for_each(|e| vars(e, &mut head));
        let head: HashSet<&str> = head.into_iter().collect();
        let counted = inner.iter().find(|v| !head.contains(*v)).unwrap_or(&"Y");
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
