//! Strata whose clauses have no atoms (ground facts such as `edge(1, 2).`, or bodies of
//! comparisons, negations of lower strata and aggregates only): each clause derives at most one
//! tuple, from its constants alone, in one round. They are evaluated here directly, without
//! setting up a datafrog iteration per clause, so a program with thousands of facts loads
//! them in one pass.

use std::collections::{HashMap, HashSet};
use std::time::Instant;

use scenalog_facts::catalog::ColType;

use crate::eval::{Limits, Origins};
use crate::frog::stored_width;
use crate::plan::{apply, Plan};
use crate::rows::Rows;
use crate::value::WIDTH;
use crate::{EngineError, Options};

/// Whether every clause of a stratum (its plans) is atom-free, so [`run`] can evaluate it.
pub(crate) fn applies(plans: &[(String, Plan)]) -> bool {
    plans.iter().all(|(_, p)| p.atoms.is_empty())
}

/// Evaluates an atom-free stratum: each plan's start filters on the empty binding, then its
/// head. Returns the relations the stratum defines (sorted, distinct) and, with provenance,
/// the first plan (in order) that derived each tuple, all in round 0: the same answer and
/// stamps as running the plans on datafrog.
pub(crate) fn run(
    plans: &[(String, Plan)],
    defined: &HashSet<&str>,
    types: &HashMap<String, Vec<ColType>>,
    options: &Options,
    start: Instant,
    held: usize,
) -> Result<(HashMap<String, Rows>, Origins), EngineError> {
    // Per relation: the derived tuples in plan order, and each one's plan.
    let mut derived: HashMap<&str, (Rows, Vec<usize>)> = defined
        .iter()
        .map(|&n| (n, (Rows::new(stored_width(types, n)), Vec::new())))
        .collect();
    let mut produced = 0usize;
    for (pi, (head, p)) in plans.iter().enumerate() {
        let Some((rows, from)) = derived.get_mut(head.as_str()) else {
            continue;
        };
        let limits = Limits {
            relation: head,
            options,
            start,
            held,
        };
        let tuple = apply(&p.start, [0u64; WIDTH]).and_then(|b| p.project(&b));
        if p.sum_overflowed() {
            return Err(limits.sum_overflow());
        }
        if let Some(t) = tuple {
            rows.push(&t);
            from.push(pi);
            produced += 1;
            // The clock is read once per 4,096 clauses; the budget is counted exactly.
            if produced.is_multiple_of(4096) || held + produced > options.max_tuples {
                limits.check(produced)?;
            }
        }
    }
    let mut done = HashMap::new();
    let mut origins = Origins::new();
    for (name, (mut rows, from)) in derived {
        if options.provenance {
            // A stable sort by tuple keeps each tuple's first plan first.
            let mut order: Vec<usize> = (0..rows.len()).collect();
            order.sort_by(|&a, &b| rows.get(a).cmp(&rows.get(b)));
            order.dedup_by(|a, b| rows.get(*a) == rows.get(*b));
            let mut sorted = Rows::new(rows.arity());
            let mut first = Vec::with_capacity(order.len());
            for i in order {
                if let (Some(t), Some(&plan)) = (rows.get(i), from.get(i)) {
                    sorted.push_slice(t);
                    first.push((0, plan));
                }
            }
            origins.insert(name.to_string(), first);
            rows = sorted;
        } else {
            rows.sort_dedup();
        }
        done.insert(name.to_string(), rows);
    }
    Ok((done, origins))
}
