//! Inlining: when the caller reads only some relations ([`crate::Options::reads`]), a derived
//! relation used in exactly one place (one positive atom of one rule) is replaced there by its
//! rules' bodies, so it is never stored. `referred(V, T) :- category(V, "REGULAR_VEHICLE"),
//! stopped(V, T).` over the prelude's `stopped(X, T) :- speed(X, T, S), S < 0.5 m/s.` becomes
//!
//! ```text
//! referred(V, T) :- category(V, "REGULAR_VEHICLE"), speed(V, T, S~1), S~1 < 0.5 m/s.
//! ```
//!
//! what a person writing the scenario inline gets: the speeds of regular vehicles only, and no
//! `stopped` relation beside `referred`. Soufflé does the same for relations declared `inline`.
//!
//! A relation is inlined only when the answer cannot change and no rule gets wider: it is not
//! read, not recursive, not negated nor inside an aggregate's braces, has at most
//! [`MAX_RULES`] rules, none of them a fact or holding an aggregate, each head of distinct
//! variables; its one use has variables or `_` as arguments; and each rule made fits the
//! binding rows the program already needs. Nor when a negation is involved (in its rules or in
//! the rule using it): a stored relation narrows what the catalog is asked for the atoms a
//! later stratum negates ([`crate::demand`]), and inlined, a negated catalog atom would be asked
//! for every track its body's catalog atoms hold (RefAV's imported `jaywalking_pedestrians`
//! 0.02 -> 0.16 s). The head's variables become the use's; the body's
//! others get fresh names (`S~1`: `~` is in no source name). Set semantics keep the answer: the
//! use joined the relation's tuples, and each rule made joins one rule's bindings of them.

use std::collections::{BTreeSet, HashMap};

use scenalog_rules::ast::{Clause, ExprKind, Literal};
use scenalog_rules::{CheckedProgram, PredKind};

use crate::value::{WIDEST, WIDTH};

/// Most rules a relation may have to be inlined (its one use becomes as many rules).
pub(crate) const MAX_RULES: usize = 8;

/// The program with every relation that can be inlined inlined (repeatedly: a relation whose one
/// use was in an inlined rule may be inlined next), or `None` when none can.
pub(crate) fn inline(program: &CheckedProgram, reads: &[String]) -> Option<CheckedProgram> {
    let width = crate::evaluate::row_width(program);
    let limit = if width <= WIDTH { WIDTH } else { WIDEST };
    let mut out = program.clone();
    let mut fresh = 0usize;
    let mut changed = false;
    // Each pass inlines one relation; a program has finitely many.
    for _ in 0..program.predicates.len() {
        let Some((pred, use_clause, use_literal)) = candidate(&out, reads) else {
            break;
        };
        let Some(made) = inline_one(&out, &pred, use_clause, use_literal, &mut fresh) else {
            break;
        };
        if made
            .iter()
            .any(|c| scenalog_rules::walk::binding_slots(c) > limit)
        {
            break;
        }
        let mut clauses: Vec<Clause> = Vec::with_capacity(out.program.clauses.len() + made.len());
        for (ci, c) in out.program.clauses.iter().enumerate() {
            if ci == use_clause {
                clauses.extend(made.iter().cloned());
            } else if c.head.pred != pred {
                clauses.push(c.clone());
            }
        }
        out.program.clauses = clauses;
        changed = true;
    }
    changed.then(|| crate::magic::restratified(out)).flatten()
}

/// The first relation that can be inlined: its name, the clause using it and the literal.
fn candidate(program: &CheckedProgram, reads: &[String]) -> Option<(String, usize, usize)> {
    let (uses, refused) = crate::magic::uses_of(program, reads);
    uses.iter().find_map(|(pred, at)| {
        let &[(ci, li)] = at.as_slice() else {
            return None;
        };
        let derived = program
            .predicates
            .get(*pred)
            .is_some_and(|p| p.kind == PredKind::Derived);
        let rules: Vec<&Clause> = program
            .program
            .clauses
            .iter()
            .filter(|c| c.head.pred == **pred)
            .collect();
        let use_clause = program.program.clauses.get(ci)?;
        let inlinable = derived
            && !refused.contains(*pred)
            && use_clause.head.pred != **pred
            && !rules.is_empty()
            && rules.len() <= MAX_RULES
            && rules.iter().all(|c| plain_rule(c))
            && !use_clause
                .body
                .iter()
                .any(|l| matches!(l, Literal::Neg(..)))
            && matches!(use_clause.body.get(li), Some(Literal::Pos(a))
                if a.args.iter().all(|e| matches!(e.kind, ExprKind::Var(_) | ExprKind::Wildcard)));
        inlinable.then(|| (pred.to_string(), ci, li))
    })
}

/// A rule with a body, no aggregate nor negation, and a head of distinct variables.
fn plain_rule(c: &Clause) -> bool {
    let mut seen = BTreeSet::new();
    !c.body.is_empty()
        && !c
            .body
            .iter()
            .any(|l| matches!(l, Literal::Agg(_) | Literal::Neg(..)))
        && c.head
            .args
            .iter()
            .all(|e| e.as_var().is_some_and(|v| seen.insert(v)))
}

/// The rules replacing clause `ci`: one per rule of `pred`, its body in place of literal `li`.
fn inline_one(
    program: &CheckedProgram,
    pred: &str,
    ci: usize,
    li: usize,
    fresh: &mut usize,
) -> Option<Vec<Clause>> {
    let use_clause = program.program.clauses.get(ci)?;
    let Some(Literal::Pos(used)) = use_clause.body.get(li) else {
        return None;
    };
    let mut made = Vec::new();
    for rule in program
        .program
        .clauses
        .iter()
        .filter(|c| c.head.pred == pred)
    {
        *fresh += 1;
        let n = *fresh;
        // The head's variables take the use's (a `_` there: a fresh variable), the others
        // fresh names.
        let mut names: HashMap<&str, String> = HashMap::new();
        for (h, u) in rule.head.args.iter().zip(&used.args) {
            let v = h.as_var()?;
            let to = u
                .as_var()
                .map_or_else(|| format!("{v}~{n}"), str::to_string);
            names.insert(v, to);
        }
        let rename = |v: &str| Some(names.get(v).cloned().unwrap_or_else(|| format!("{v}~{n}")));
        let mut body = rule.body.clone();
        body.iter_mut()
            .for_each(|l| scenalog_rules::walk::rename_literal(l, &rename));
        let mut clause = use_clause.clone();
        clause.body.splice(li..=li, body);
        made.push(clause);
    }
    Some(made)
}
