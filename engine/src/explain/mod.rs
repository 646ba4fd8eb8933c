//! Explanations over a finished evaluation: why a tuple was *not* derived ([`why_not`]), and a
//! proof with every body literal grounded to the facts and values that made it hold
//! ([`explain`]).
//!
//! Both re-run one clause body at a time over the evaluation's final relations with a small,
//! obviously-correct interpreter of the rule AST (hash indexes built on demand per relation and
//! set of bound columns), so they do not depend on how the planner ordered the joins. Literals
//! are taken in source order, except that a literal whose variables are not bound yet (a
//! comparison written before the atom that binds its variable, say) waits until they are.
//!
//! `why_not` keeps, after each literal, every binding that survived so far; the first literal
//! that no binding survives is the one that fails, and the bindings reached just before it are
//! what the report shows, with the values that failed it (the `S` of `S < 0.5`, the tuple that
//! exists for a negation, the result of an aggregate, the closest tuples of a missing atom).

use std::cmp::Ordering;
use std::collections::{HashMap, HashSet};
use std::fmt;
use std::sync::Arc;

use scenalog_facts::catalog::ColType;
use scenalog_facts::relation::Value;
use scenalog_rules::ast::{AggFunc, Aggregate, Atom, BinOp, CmpOp, Expr, ExprKind, Func, Literal};
use scenalog_rules::walk::{aggregate_vars as agg_vars, expr_vars, outer_vars};
use scenalog_rules::{CheckedProgram, PredKind};

use crate::value::cmp_value;
use crate::{Evaluation, Stamp};

mod ground;
mod interp;
mod report;
mod values;
mod why_not;

use interp::*;
pub use report::*;
use values::*;

/// Most bindings kept after one literal; past it, the rest are dropped and the report says so.
pub const MAX_BINDINGS: usize = 100_000;

/// Most examples (bindings, values, near misses) a report lists for one failing literal.
pub const MAX_EXAMPLES: usize = 5;

/// Deepest derivation [`explain`] builds (proofs are well founded, so this only guards
/// against a stamp that names no usable clause).
pub const MAX_DEPTH: usize = 64;

/// How deep [`why_not`] follows a missing atom of a derived relation into that relation's own
/// clauses.
pub const MAX_NESTING: usize = 3;

/// Says why `relation(tuple)` is not derived: for every clause whose head could derive it, the
/// first body literal that fails, the bindings reached before it and the values that failed it;
/// or that a clause does derive it. Works on the final relations of `evaluation`, which must be
/// the evaluation of `program` (provenance is not needed).
pub fn why_not(
    program: &CheckedProgram,
    evaluation: &Evaluation,
    relation: &str,
    tuple: &[Value],
) -> Result<WhyNot, WhyNotError> {
    let pattern: Vec<Option<Value>> = tuple.iter().cloned().map(Some).collect();
    why_not_pattern(program, evaluation, relation, &pattern)
}

/// [`why_not`] for each of several tuples of one relation, sharing the indexes built over the
/// evaluation's relations (one report costs about one index build over every relation it
/// looks into, so asking many at once costs little more than asking one).
pub fn why_not_each(
    program: &CheckedProgram,
    evaluation: &Evaluation,
    relation: &str,
    tuples: &[Vec<Value>],
) -> Vec<Result<WhyNot, WhyNotError>> {
    let mut cx = Cx::new(program, evaluation);
    tuples
        .iter()
        .map(|tuple| {
            let pattern: Vec<Option<Value>> = tuple.iter().cloned().map(Some).collect();
            cx.report(relation, &pattern)
        })
        .collect()
}

/// [`why_not`] for a pattern: `None` columns may take any value.
pub fn why_not_pattern(
    program: &CheckedProgram,
    evaluation: &Evaluation,
    relation: &str,
    pattern: &[Option<Value>],
) -> Result<WhyNot, WhyNotError> {
    Cx::new(program, evaluation).report(relation, pattern)
}

impl Cx<'_> {
    /// The why-not report of one pattern, checked against the relation's columns first.
    fn report(&mut self, relation: &str, pattern: &[Option<Value>]) -> Result<WhyNot, WhyNotError> {
        let pattern = self.check_pattern(relation, pattern)?;
        Ok(self.why_not(relation, &pattern, 0, &mut HashSet::new()))
    }
}

/// The proof of a derived tuple with every body literal grounded: the matched tuples, the
/// compared values, the absent negated tuples, the aggregate results. Like
/// [`Evaluation::prove`], each tuple is derived by the clause of its stamp from tuples of lower
/// strata or earlier rounds, so the tree is finite; leaves are catalog tuples and ground facts.
/// `None` when the tuple is not in the relation or the evaluation ran without provenance.
pub fn explain(
    program: &CheckedProgram,
    evaluation: &Evaluation,
    relation: &str,
    tuple: &[Value],
) -> Result<Option<Derivation>, WhyNotError> {
    let mut cx = Cx::new(program, evaluation);
    let pattern: Vec<Option<Value>> = tuple.iter().cloned().map(Some).collect();
    cx.check_pattern(relation, &pattern)?;
    let derived = program
        .predicates
        .get(relation)
        .is_some_and(|p| p.kind == PredKind::Derived);
    let present = !cx.lookup(relation, &pattern).is_empty();
    if !present || (derived && evaluation.stamp(relation, tuple).is_none()) {
        return Ok(None);
    }
    Ok(cx.derivation(relation, tuple, 0))
}

// ---------------------------------------------------------------------------------------------
// The interpreter.
