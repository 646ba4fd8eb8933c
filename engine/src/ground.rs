//! Strata whose clauses have no atoms (ground facts such as `edge(1, 2).`, or bodies of
//! comparisons, negations of lower strata and aggregates only): each clause derives at most one
//! tuple, from its constants alone, in one round. They are evaluated here directly, without
//! setting up a datafrog iteration per clause, so a program with thousands of facts loads
//! them in one pass; a stratum of facts alone (no bodies) is not even planned ([`facts`]).

use std::collections::{HashMap, HashSet};
use std::time::Instant;

use scenalog_facts::catalog::ColType;

use scenalog_rules::ast::Clause;

use crate::limits::Limits;
use crate::plan::{apply, ground_head, Plan};
use crate::prove::Origins;
use crate::rows::stored_width;
use crate::rows::Rows;
use crate::value::{Row, Symbols};
use crate::{EngineError, Options};

/// Whether every clause of a stratum (its plans) is atom-free, so [`run`] can evaluate it.
pub(crate) fn applies<const R: usize>(plans: &[(String, Plan<R>)]) -> bool {
    plans.iter().all(|(_, p)| p.atoms.is_empty())
}

/// Evaluates an atom-free stratum: each plan's start filters on the empty binding, then its
/// head. Returns the relations the stratum defines (sorted, distinct) and, with provenance,
/// the first plan (in order) that derived each tuple, all in round 0: the same answer and
/// stamps as running the plans on datafrog.
pub(crate) fn run<const R: usize>(
    plans: &[(String, Plan<R>)],
    defined: &HashSet<&str>,
    types: &HashMap<String, Vec<ColType>>,
    options: &Options,
    start: Instant,
    held: usize,
) -> Result<(HashMap<String, Rows>, Origins), EngineError> {
    let heads = plans.iter().map(|(head, p)| {
        let tuple = apply(&p.start, [0u64; R]).and_then(|b| p.project(&b));
        if p.sum_overflowed() {
            let limits = Limits {
                relation: head,
                options,
                start,
                held,
            };
            return Err(limits.sum_overflow());
        }
        Ok((head.as_str(), tuple))
    });
    collect(heads, defined, types, options, start, held)
}

/// Evaluates a stratum of ground facts (clauses without bodies, such as `pos(3, 0, 12, 1).`)
/// without planning them: each head's expressions are computed and encoded as the plan of a
/// fact would ([`ground_head`]). The `i`th clause is plan `i` of the stamps, as in [`run`].
/// A stratum of thousands of facts would otherwise plan each one.
pub(crate) fn facts<const R: usize>(
    clauses: &[&Clause],
    defined: &HashSet<&str>,
    types: &HashMap<String, Vec<ColType>>,
    symbols: &mut Symbols,
    cx: (&Options, Instant, usize),
) -> Result<(HashMap<String, Rows>, Origins), EngineError> {
    let (options, start, held) = cx;
    // The previous head's types: facts of one relation usually come together.
    let mut last: Option<(&str, Option<&[ColType]>)> = None;
    let heads = clauses.iter().map(|c| {
        let pred = c.head.pred.as_str();
        let ty = match last {
            Some((p, t)) if p == pred => t,
            _ => {
                let t = types.get(pred).map(Vec::as_slice);
                last = Some((pred, t));
                t
            }
        };
        Ok((pred, ground_head::<R>(&c.head.args, ty, symbols)?))
    });
    collect(heads, defined, types, options, start, held)
}

/// The relations of an atom-free stratum from each clause's head (in clause order; `None`
/// for a clause that derives nothing): sorted and distinct, and with provenance each tuple's
/// first clause, in round 0. Heads of relations the stratum does not define are skipped.
fn collect<'a, const R: usize>(
    heads: impl Iterator<Item = Result<(&'a str, Option<Row<R>>), EngineError>>,
    defined: &HashSet<&str>,
    types: &HashMap<String, Vec<ColType>>,
    options: &Options,
    start: Instant,
    held: usize,
) -> Result<(HashMap<String, Rows>, Origins), EngineError> {
    // Per relation: the derived tuples in plan order, and each one's plan (a stratum defines
    // a few relations: found by a scan, not a hash).
    let mut derived: Vec<(&str, (Rows, Vec<usize>))> = defined
        .iter()
        .map(|&n| (n, (Rows::new(stored_width(types, n)), Vec::new())))
        .collect();
    let mut produced = 0usize;
    for (pi, head) in heads.enumerate() {
        let (name, tuple) = head?;
        let entry = derived.iter_mut().find(|(n, _)| *n == name);
        let (Some(t), Some((_, (rows, from)))) = (tuple, entry) else {
            continue;
        };
        rows.push(&t);
        from.push(pi);
        produced += 1;
        // The clock is read once per 4,096 clauses; the budget is counted exactly.
        if produced.is_multiple_of(4096) || held + produced > options.max_tuples {
            let limits = Limits {
                relation: name,
                options,
                start,
                held,
            };
            limits.check(produced)?;
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
                    first.push(crate::prove::pack(0, plan));
                }
            }
            origins.insert(name.to_string(), crate::prove::Packed::ready(first));
            rows = sorted;
        } else {
            rows.sort_dedup();
        }
        done.insert(name.to_string(), rows);
    }
    Ok((done, origins))
}
