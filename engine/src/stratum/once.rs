//! One plan joined once over relations completed before it: an aggregate's body (`count : {
//! edge(X, _) }`), which is folded over its matching tuples before the rule using it runs. The
//! join is the stratum's own ([`super::join`]) over sorted copies of the complete relations,
//! with no iteration around it.

use std::collections::HashMap;

use scenalog_facts::catalog::ColType;

use super::access::{Access, Tup};
use super::join::Join;
use crate::limits::Limits;
use crate::plan::Plan;
use crate::rows::stored_width;
use crate::rows::Rows;
use crate::EngineError;

/// The distinct head tuples of `plan` over `complete` (an absent relation is empty), sorted;
/// `types` gives the relations' column types.
pub(crate) fn run_plan<const R: usize>(
    plan: &Plan<R>,
    complete: &HashMap<String, Rows>,
    types: &HashMap<String, Vec<ColType>>,
    limits: &Limits<'_>,
) -> Result<Rows, EngineError> {
    let width = plan
        .atoms
        .iter()
        .map(|a| stored_width(types, &a.pred))
        .chain([plan.head.len(), 1])
        .max()
        .unwrap_or(1);
    with_width!(width, run::<R>(plan, complete, types, limits))
}

fn run<const R: usize, const W: usize>(
    plan: &Plan<R>,
    complete: &HashMap<String, Rows>,
    types: &HashMap<String, Vec<ColType>>,
    limits: &Limits<'_>,
) -> Result<Rows, EngineError> {
    let empty = Rows::new(1);
    let access: Vec<Access> = plan
        .atoms
        .iter()
        .map(|a| Access::of(a, stored_width(types, &a.pred)))
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
