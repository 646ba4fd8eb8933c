//! The meaning of an aggregate's braces, shared by the planner and `why_not`: an aggregate
//! folds over the matching tuples of its body, as in Soufflé. Each `_` in a positive atom of the
//! braces is a fresh variable, so two tuples that differ only in a `_` column count twice.

use scenalog_rules::ast::{Aggregate, Expr, ExprKind, Literal};

/// Prefix of the variables that stand for `_` columns; `#` cannot start a variable in rule text,
/// so the names never meet a user's.
const WILDCARD_PREFIX: &str = "#_";

/// The aggregate with every `_` argument of a positive atom in its braces replaced by a fresh
/// named variable (`#_0`, `#_1`, …), so that planning over the body's named variables counts
/// distinct matching tuples. Wildcards of negated atoms stay wildcards (they match any value
/// and bind nothing); nested aggregates keep their own braces.
pub(crate) fn name_wildcards(g: &Aggregate) -> Aggregate {
    let mut next = 0usize;
    let body = g
        .body
        .iter()
        .map(|l| match l {
            Literal::Pos(a) => {
                let mut a = a.clone();
                for e in &mut a.args {
                    if matches!(e.kind, ExprKind::Wildcard) {
                        *e = Expr {
                            kind: ExprKind::Var(format!("{WILDCARD_PREFIX}{next}")),
                            span: e.span,
                        };
                        next += 1;
                    }
                }
                Literal::Pos(a)
            }
            other => other.clone(),
        })
        .collect();
    Aggregate {
        result: g.result.clone(),
        func: g.func,
        target: g.target.clone(),
        body,
        span: g.span,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wildcards_of_positive_atoms_become_distinct_variables() {
        let src = ".decl e(A: int, B: int, C: int)\n.decl n(A: int, N: int)\n\
                   n(X, N) :- e(X, _, _), N = count : { e(X, _, _), !e(_, X, _) }.\n";
        let out = scenalog_rules::check(
            src,
            &scenalog_rules::CheckOptions {
                require_referred: false,
            },
        );
        let Some(p) = out.program else {
            panic!("the program checks: {:?}", out.diagnostics)
        };
        let clause = &p.program.clauses[0];
        let Some(Literal::Agg(g)) = clause.body.get(1) else {
            panic!("the second literal is the aggregate")
        };
        let named = name_wildcards(g);
        let Literal::Pos(a) = &named.body[0] else {
            panic!("positive atom first")
        };
        let names: Vec<Option<&str>> = a.args.iter().map(|e| e.as_var()).collect();
        assert_eq!(names, vec![Some("X"), Some("#_0"), Some("#_1")]);
        let Literal::Neg(n, _) = &named.body[1] else {
            panic!("negated atom second")
        };
        assert!(matches!(n.args[0].kind, ExprKind::Wildcard));
        assert!(matches!(n.args[2].kind, ExprKind::Wildcard));
    }
}
