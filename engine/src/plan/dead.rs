//! Parts of a join order that only test existence: a run of atoms `d..=e` whose variables (and
//! the values its filters compute) nothing after `e` reads, neither a later atom, a later filter
//! nor the head. Every way of joining such a run gives the rest of the join the same binding, so
//! the join stops trying the run's candidates once one way reaches past it
//! ([`AtomStep::dead_until`]): `a(X) :- b(X), c(Y), d(Y)` joins `c` and `d` once per `b` tuple
//! until they match, not over every `c` tuple. Soufflé's `independent_body` tests are this case.

use super::*;

/// Appends the slots `e` reads.
fn cexpr_slots(e: &CExpr, out: &mut Vec<usize>) {
    e.any_slot(&mut |s| {
        out.push(s);
        false
    });
}

/// Appends the slots a filter reads.
fn filter_reads<const R: usize>(f: &Filter<R>, reads: &mut Vec<usize>) {
    match f {
        Filter::Cmp(_, a, b) | Filter::CmpText(_, a, b, _) => {
            cexpr_slots(a, reads);
            cexpr_slots(b, reads);
        }
        Filter::CmpRaw(_, s, raw) => {
            reads.push(*s);
            if let Raw::Slot(t) = raw {
                reads.push(*t);
            }
        }
        Filter::CmpInt(_, a, b) => {
            for e in [a, b] {
                e.any_slot(&mut |s| {
                    reads.push(s);
                    false
                });
            }
        }
        Filter::CmpDiff { a, b, .. } => reads.extend([*a, *b]),
        Filter::Bind(_, e, _) => cexpr_slots(e, reads),
        Filter::Neg(n) => {
            for a in &n.args {
                if let KeyArg::Val(e, _) = a {
                    cexpr_slots(e, reads);
                }
            }
            if let Some(slots) = &n.slots {
                reads.extend(slots.iter().map(|&(_, s)| s));
            }
        }
        Filter::AggRun(c, _) => reads.extend(&c.group),
        Filter::Agg { group, .. } => reads.extend(group),
    }
}

/// The slots an atom step reads (its keys, its window, its filters) and writes (its new
/// variables, its filters' results).
fn step_slots<const R: usize>(step: &AtomStep<R>) -> (Vec<usize>, Vec<usize>) {
    let mut reads = Vec::new();
    for a in &step.args {
        if let Arg::Key(e, _) = a {
            cexpr_slots(e, &mut reads);
        }
    }
    if let Some(n) = &step.narrow {
        for b in n.lo.iter().chain(&n.hi) {
            cexpr_slots(&b.base, &mut reads);
            if let Some((_, o)) = &b.off {
                cexpr_slots(o, &mut reads);
            }
        }
    }
    for f in &step.after {
        filter_reads(f, &mut reads);
    }
    (reads, step.writes())
}

/// Sets [`AtomStep::dead_until`] on each atom that starts a run of two or more atoms nothing
/// after reads (the shortest such run), given the head's expressions.
pub(crate) fn mark_dead_runs<const R: usize>(atoms: &mut [AtomStep<R>], head: &[(CExpr, ColType)]) {
    let n = atoms.len();
    let slots: Vec<(Vec<usize>, Vec<usize>)> = atoms.iter().map(step_slots).collect();
    // Per position k: the slots read by atom k and everything after it (the head included).
    let mut read_from: Vec<Vec<usize>> = vec![Vec::new(); n + 1];
    for (e, _) in head {
        cexpr_slots(e, &mut read_from[n]);
    }
    for k in (0..n).rev() {
        let mut r = read_from[k + 1].clone();
        r.extend(&slots[k].0);
        read_from[k] = r;
    }
    for (d, atom) in atoms.iter_mut().enumerate() {
        let mut written: Vec<usize> = Vec::new();
        for (e, (_, writes)) in slots.iter().enumerate().skip(d) {
            written.extend(writes);
            if e > d && !written.iter().any(|s| read_from[e + 1].contains(s)) {
                atom.dead_until = Some(e);
                break;
            }
        }
    }
}
