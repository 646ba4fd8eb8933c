//! One plan joined once over relations completed before it: an aggregate's body (`count : {
//! edge(X, _) }`), which is folded over its matching tuples before the rule using it runs. The
//! join is the stratum's own ([`super::join`]) over sorted copies of the complete relations,
//! with no iteration around it.

use std::collections::HashMap;

use super::access::{Access, Tup};
use super::join::Join;
use crate::eval::Limits;
use crate::plan::Plan;
use crate::rows::Rows;
use crate::value::WIDTH;
use crate::EngineError;

/// The distinct head tuples of `plan` over `complete` (an absent relation is empty), sorted.
/// `arity` gives each relation's stored width.
pub(crate) fn run_plan(
    plan: &Plan,
    complete: &HashMap<String, Rows>,
    arity: &dyn Fn(&str) -> usize,
    limits: &Limits<'_>,
) -> Result<Rows, EngineError> {
    let width = plan
        .atoms
        .iter()
        .map(|a| arity(&a.pred))
        .chain([plan.head.len(), 1])
        .max()
        .unwrap_or(1);
    match width {
        1 => run::<1>(plan, complete, arity, limits),
        2 => run::<2>(plan, complete, arity, limits),
        3 => run::<3>(plan, complete, arity, limits),
        4 => run::<4>(plan, complete, arity, limits),
        5 | 6 => run::<6>(plan, complete, arity, limits),
        7 | 8 => run::<8>(plan, complete, arity, limits),
        _ => run::<WIDTH>(plan, complete, arity, limits),
    }
}

fn run<const W: usize>(
    plan: &Plan,
    complete: &HashMap<String, Rows>,
    arity: &dyn Fn(&str) -> usize,
    limits: &Limits<'_>,
) -> Result<Rows, EngineError> {
    let empty = Rows::new(1);
    let access: Vec<Access> = plan
        .atoms
        .iter()
        .map(|a| Access::of(a, arity(&a.pred)))
        .collect();
    let copies: Vec<Vec<Tup<W>>> = access
        .iter()
        .map(|acc| {
            acc.sig
                .copy_rows(complete.get(&acc.sig.pred).unwrap_or(&empty))
        })
        .collect();
    let join = Join {
        plan,
        access: &access,
        parts: copies.iter().map(|c| vec![&c[..]]).collect(),
    };
    let mut out: Vec<Tup<W>> = Vec::new();
    join.run(&mut out, limits)?;
    let mut rows = Rows::new(plan.head.len());
    for t in &out {
        rows.push_slice(t);
    }
    rows.sort_dedup();
    Ok(rows)
}
