//! Demand for derived relations (a magic-set transformation, one level deep): when the caller
//! reads only some relations ([`crate::Options::reads`]), a derived relation that every use binds
//! in the same columns, by constants or by atoms computed before it, is derived only for those
//! values. `referred(X, T) :- category(X, "REGULAR_VEHICLE"), stopped(X, T).` becomes
//!
//! ```text
//! magic_stopped_0(X) :- category(X, "REGULAR_VEHICLE").
//! stopped(X, T) :- magic_stopped_0(X), speed(X, T, V), V < 0.5 m/s.
//! ```
//!
//! so `stopped` (and the `speed` request, through the catalog pushdown of [`crate::demand`]) holds
//! regular vehicles only, not every track. A relation is restricted only when nothing else can
//! see the difference: it is not read by the caller, not negated, not inside an aggregate's
//! braces, not recursive, and each use's other atoms it is bound through come from earlier
//! strata (or the catalog), so each use still finds every tuple it can join. Relations derived
//! for the restricted one (its own body's relations) are left whole: one level, where the
//! prelude's concepts meet the program's filters.
//!
//! Two choices keep a magic rule cheaper than what it saves: only selections bind (one column,
//! or a constant among at most three: `ego(E)`, `category(X, "BUS")`; not `stopped(A, T)`,
//! whose times restrict little and cost a join), and each bound column has its own magic
//! relation (`magic_moving_0(P)`), so columns bound by unrelated atoms are never paired in a
//! product. `mine` and every command that reads a scenario's `referred` and `related` evaluate
//! this way (after [`crate::inline`]); explanations (provenance) and `run` without `--print` read every
//! relation and do not (`run --print REL` reads those). Measured on the library (three sample logs, one thread, against 1eb78af): its
//! evaluation falls from 1.36 to 0.71 s, `mine` from 3.14 to 2.55 s (median wall), the same
//! matches (`vehicle_making_a_u_turn` 0.176 → 0.045 s, `bicycle_and_vehicle_near_each_other`
//! 0.133 → 0.003 s); the 255 imported RefAV programs take the same time (wall ratio 1.00 and
//! 1.01) with the same matches. Those needed the extractor to answer a narrowed request from a
//! kept broader one (`Extractor::extract_within`): without it, requests narrowed by demand
//! missed the answers other programs on the log had left, and imported programs ran 1.11x.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use scenalog_rules::ast::{Atom, Clause, ExprKind, Literal};
use scenalog_rules::{CheckedProgram, PredKind, PredicateInfo};

/// One use of a relation: the clause, the positive atom and its index among the literals.
struct Use<'a> {
    clause: &'a Clause,
    atom: &'a Atom,
    literal: usize,
}

/// The transformed program, or `None` when no relation can be restricted.
pub(crate) fn restrict(program: &CheckedProgram, reads: &[String]) -> Option<CheckedProgram> {
    let stratum_of: HashMap<&str, usize> = program
        .strata
        .iter()
        .enumerate()
        .flat_map(|(i, s)| s.predicates.iter().map(move |p| (p.as_str(), i)))
        .collect();
    // Where each derived relation may be restricted, and its uses.
    let (positive, refused) = uses_of(program, reads);
    let uses: BTreeMap<&str, Vec<Use>> = positive
        .into_iter()
        .map(|(pred, at)| {
            let found = at
                .into_iter()
                .filter_map(|(ci, li)| {
                    let clause = program.program.clauses.get(ci)?;
                    match clause.body.get(li) {
                        Some(Literal::Pos(atom)) => Some(Use {
                            clause,
                            atom,
                            literal: li,
                        }),
                        _ => None,
                    }
                })
                .collect();
            (pred, found)
        })
        .collect();
    let mut out = program.clone();
    let mut changed = false;
    for (pred, pred_uses) in &uses {
        let Some(info) = program.predicates.get(*pred) else {
            continue;
        };
        if info.kind != PredKind::Derived || refused.contains(pred) {
            continue;
        }
        let Some(&sp) = stratum_of.get(pred) else {
            continue;
        };
        // Per use: the bound columns and the atoms binding them.
        let mut bound: Vec<(BTreeSet<usize>, Vec<&Atom>)> = Vec::new();
        for u in pred_uses {
            let binders: Vec<&Atom> = u
                .clause
                .body
                .iter()
                .enumerate()
                .filter_map(|(i, l)| match l {
                    Literal::Pos(a) if i != u.literal => Some(a),
                    _ => None,
                })
                .filter(|a| {
                    program.predicates.get(&a.pred).is_some_and(|p| {
                        p.kind == PredKind::Catalog
                            || stratum_of.get(a.pred.as_str()).is_some_and(|&s| s < sp)
                    })
                })
                // Only selections (one column, or a constant among at most three: `ego(E)`,
                // `category(X, "BUS")`): a magic rule re-runs its body, and a join there can
                // cost more than the whole relation it restricts; `stopped(A, T)` binding T
                // restricts little (most times have a stopped vehicle) at the price of a join.
                .filter(|a| {
                    a.args.len() == 1
                        || a.args
                            .iter()
                            .any(|e| matches!(e.kind, ExprKind::Int(_) | ExprKind::Str(_)))
                            && a.args.len() <= 3
                })
                .collect();
            let vars: BTreeSet<&str> = binders
                .iter()
                .flat_map(|a| a.args.iter().filter_map(|e| e.as_var()))
                .collect();
            let cols: BTreeSet<usize> = u
                .atom
                .args
                .iter()
                .enumerate()
                .filter(|(_, e)| match &e.kind {
                    ExprKind::Var(v) => vars.contains(v.as_str()),
                    ExprKind::Int(_) | ExprKind::Str(_) => true,
                    _ => false,
                })
                .map(|(i, _)| i)
                .collect();
            bound.push((cols, binders));
        }
        let Some(cols) = bound
            .iter()
            .map(|(c, _)| c.clone())
            .reduce(|a, b| a.intersection(&b).copied().collect())
        else {
            continue;
        };
        if cols.is_empty() {
            continue;
        }
        // One magic relation per bound column: the columns' sets are joined in the guard, never
        // as a product in a magic rule (a pedestrian column and a time column bound by
        // unrelated atoms would otherwise make every pair of them).
        for i in cols {
            let magic = fresh_name(&out, &format!("{pred}_{i}"));
            // The magic relation's rules: per use, its bound argument from its binders.
            for (u, (_, binders)) in pred_uses.iter().zip(&bound) {
                let (c, atom) = (u.clause, u.atom);
                let args = vec![atom.args[i].clone()];
                let body = magic_body(c, &args, binders);
                out.program.clauses.push(Clause {
                    head: Atom {
                        pred: magic.clone(),
                        pred_span: atom.pred_span,
                        args,
                        span: atom.span,
                    },
                    body,
                    span: c.span,
                });
            }
            // The restricted relation's rules start from the magic relation.
            for c in out
                .program
                .clauses
                .iter_mut()
                .filter(|c| c.head.pred == *pred)
            {
                let guard = Atom {
                    pred: magic.clone(),
                    pred_span: c.head.pred_span,
                    args: vec![c.head.args[i].clone()],
                    span: c.head.span,
                };
                c.body.insert(0, Literal::Pos(guard));
            }
            out.predicates.insert(
                magic.clone(),
                PredicateInfo {
                    name: magic.clone(),
                    types: vec![info.types[i]],
                    kind: PredKind::Derived,
                },
            );
        }
        changed = true;
    }
    changed.then(|| restratified(out)).flatten()
}

/// Per relation, the (clause, literal) indices of its positive uses.
pub(crate) type PositiveUses<'p> = BTreeMap<&'p str, Vec<(usize, usize)>>;

/// Per relation, where it is used positively (clause, literal), and the relations a rewrite must
/// leave whole: those read, recursive, negated or inside an aggregate's braces.
pub(crate) fn uses_of<'p>(
    program: &'p CheckedProgram,
    reads: &'p [String],
) -> (PositiveUses<'p>, BTreeSet<&'p str>) {
    let mut uses: PositiveUses = BTreeMap::new();
    let mut refused: BTreeSet<&str> = reads.iter().map(String::as_str).collect();
    for s in &program.strata {
        if s.recursive || s.predicates.len() > 1 {
            refused.extend(s.predicates.iter().map(String::as_str));
        }
    }
    for (ci, c) in program.program.clauses.iter().enumerate() {
        for (li, l) in c.body.iter().enumerate() {
            match l {
                Literal::Pos(a) => uses.entry(a.pred.as_str()).or_default().push((ci, li)),
                Literal::Neg(a, _) => {
                    refused.insert(a.pred.as_str());
                }
                Literal::Cmp(_) => {}
                Literal::Agg(g) => {
                    for (a, _) in scenalog_rules::walk::body_atoms(&g.body) {
                        refused.insert(a.pred.as_str());
                    }
                }
            }
        }
    }
    (uses, refused)
}

/// `out` with its strata computed again after a rewrite, or `None` if they cannot be.
pub(crate) fn restratified(mut out: CheckedProgram) -> Option<CheckedProgram> {
    let (strata, diags) = scenalog_rules::strata::stratify(&out.program);
    if diags.iter().any(|d| d.is_error()) {
        return None;
    }
    out.strata = strata;
    Some(out)
}

/// The body of a use's magic rule: the binders connected to the bound arguments' variables
/// (through shared variables, so `ego(E), direction(E, B, …)` keeps the ego that narrows the
/// direction request), then the clause's comparisons over their variables alone (the bounds the
/// catalog requests carry in the original rule).
fn magic_body(c: &Clause, args: &[scenalog_rules::ast::Expr], binders: &[&Atom]) -> Vec<Literal> {
    let mut vars: BTreeSet<&str> = args.iter().filter_map(|e| e.as_var()).collect();
    let mut taken = vec![false; binders.len()];
    let mut grew = true;
    while grew {
        grew = false;
        for (i, a) in binders.iter().enumerate() {
            let names: Vec<&str> = a
                .args
                .iter()
                .flat_map(scenalog_rules::walk::expr_names)
                .collect();
            if !taken[i] && names.iter().any(|v| vars.contains(v)) {
                taken[i] = true;
                vars.extend(names);
                grew = true;
            }
        }
    }
    let mut body: Vec<Literal> = binders
        .iter()
        .zip(&taken)
        .filter(|(_, t)| **t)
        .map(|(a, _)| Literal::Pos((*a).clone()))
        .collect();
    let bound: BTreeSet<&str> = binders
        .iter()
        .zip(&taken)
        .filter(|(_, t)| **t)
        .flat_map(|(a, _)| a.args.iter().filter_map(|e| e.as_var()))
        .collect();
    for l in &c.body {
        if let Literal::Cmp(cmp) = l {
            let mut names = scenalog_rules::walk::expr_names(&cmp.lhs);
            names.extend(scenalog_rules::walk::expr_names(&cmp.rhs));
            if !names.is_empty() && names.iter().all(|v| bound.contains(v)) {
                body.push(l.clone());
            }
        }
    }
    body
}

/// `magic_{pred}` (`pred` names the relation and column), with a number when the program already has that name.
fn fresh_name(program: &CheckedProgram, pred: &str) -> String {
    let base = format!("magic_{pred}");
    (0..)
        .map(|i| match i {
            0 => base.clone(),
            i => format!("{base}_{i}"),
        })
        .find(|n| !program.predicates.contains_key(n))
        .unwrap_or(base)
}
