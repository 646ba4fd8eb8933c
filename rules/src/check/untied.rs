//! W0510: an aggregate tied to nothing. No variable of its braces (or target) occurs in the
//! head or the rest of the body, so it folds over the whole log and is the same number for
//! every object and frame the clause is about: `count : { category(P, "PEDESTRIAN") }` counts
//! the log's pedestrians, not those at the clause's frame or near its object.

use std::collections::HashSet;

use crate::ast::{AggFunc, Clause, Literal};
use crate::diagnostics::{self, warning};
use crate::walk::{aggregate_vars, expr_vars, outer_vars};
use crate::Diagnostic;

/// Reports W0510 for the aggregates of one clause whose head has a variable besides their
/// results (something to be tied to).
pub fn check_clause(c: &Clause, diags: &mut Vec<Diagnostic>) {
    for (i, l) in c.body.iter().enumerate() {
        let Literal::Agg(g) = l else { continue };
        let mut result = Vec::new();
        expr_vars(&g.result, &mut result);
        let mut head = Vec::new();
        c.head.args.iter().for_each(|e| expr_vars(e, &mut head));
        head.retain(|v| !result.contains(v));
        if head.is_empty() {
            continue;
        }
        let mut outside: Vec<&str> = head.clone();
        for (j, other) in c.body.iter().enumerate() {
            if j != i {
                outer_vars(other, &mut outside);
            }
        }
        let outside: HashSet<&str> = outside.into_iter().collect();
        let inner = aggregate_vars(g);
        if inner.iter().any(|v| outside.contains(v)) {
            continue;
        }
        let what = match g.func {
            AggFunc::Count => "count",
            AggFunc::Min => "min",
            AggFunc::Max => "max",
            AggFunc::Sum => "sum",
        };
        let object = head.first().copied().unwrap_or("X");
        let time = head.last().copied().unwrap_or("T");
        let counted = inner.first().copied().unwrap_or("P");
        diags.push(
            warning(
                diagnostics::UNTIED_AGGREGATE,
                g.span,
                format!(
                    "this `{what}` shares no variable with the rest of the clause: it folds over \
                     the whole log and is the same for every {}",
                    head.join(", ")
                ),
            )
            .with_hint(format!(
                "tie it to the clause inside the braces: to the frame with `{time}` (e.g. \
                 `present({counted}, {time})`), to the object with a relation between `{object}` \
                 and `{counted}` (e.g. `near({object}, {counted}, {time}, D), D < 10.0`)"
            )),
        );
    }
}
