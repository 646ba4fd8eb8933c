//! The join of one plan over sorted sources: atoms in the planner's order, each binding's
//! constants and key values looked up as a prefix range of the atom's sorted copy (a leapjoin
//! with one extending relation per step), the planner's filters applied as soon as the atom
//! that binds their last variable is joined, and the head projected into fixed-width tuples.
//! Depth-first, so no intermediate bindings are materialised.

use crate::eval::Limits;
use crate::frog::access::{range, within, Access, Tup};
use crate::plan::{apply, AtomStep, CExpr, Plan};
use crate::value::{Row, WIDTH};
use crate::EngineError;

/// How often (in candidate tuples) the budget and the clock are checked.
const CHECK_EVERY: usize = 1 << 16;

/// One plan's join: the plan, how each atom is read, and the sorted parts each atom reads.
pub(crate) struct Join<'a, const W: usize> {
    /// The plan.
    pub(crate) plan: &'a Plan,
    /// One access per atom.
    pub(crate) access: &'a [Access],
    /// Per atom: the sorted slices whose union it reads.
    pub(crate) parts: Vec<Vec<&'a [Tup<W>]>>,
}

/// Candidate and output counts, for the periodic limit checks.
struct Progress<'l> {
    limits: &'l Limits<'l>,
    candidates: usize,
}

/// Where a head column comes from when the head is a projection of slots: the binding before
/// the last atom, or the last atom's tuple (stored position).
#[derive(Clone, Copy)]
enum From {
    Binding(usize),
    Tuple(usize),
}

/// The last atom's fast path, for heads that are a projection of slots: head tuples are
/// written straight from the binding and the candidate tuple (no binding row built when the
/// atom has no filters after it, and no recursion either way).
struct Leaf {
    /// Per head column, from the binding before the last atom or its tuple.
    direct: Vec<From>,
    /// Per head column, its slot (after the last atom's filters ran on the full binding).
    slots: Vec<usize>,
}

impl Leaf {
    fn of(plan: &Plan, last: &Access) -> Option<Leaf> {
        let mut slots = Vec::new();
        for (e, ty) in &plan.head {
            match e {
                CExpr::Slot(s, t) if t == ty => slots.push(*s),
                _ => return None,
            }
        }
        let direct = slots
            .iter()
            .map(|&s| match last.news.iter().find(|&&(_, slot)| slot == s) {
                Some(&(pos, _)) => From::Tuple(pos),
                None => From::Binding(s),
            })
            .collect();
        Some(Leaf { direct, slots })
    }
}

impl<const W: usize> Join<'_, W> {
    /// Runs the join, appending head tuples to `out`.
    pub(crate) fn run(
        &self,
        out: &mut Vec<Tup<W>>,
        limits: &Limits<'_>,
    ) -> Result<(), EngineError> {
        let Some(b) = apply(&self.plan.start, [0u64; WIDTH]) else {
            return Ok(());
        };
        let mut progress = Progress {
            limits,
            candidates: 0,
        };
        let leaf = self.access.last().and_then(|a| Leaf::of(self.plan, a));
        self.step(0, b, out, &mut progress, leaf.as_ref())?;
        if self.plan.sum_overflowed() {
            return Err(limits.sum_overflow());
        }
        limits.check(out.len())
    }

    fn step(
        &self,
        depth: usize,
        b: Row,
        out: &mut Vec<Tup<W>>,
        progress: &mut Progress<'_>,
        leaf: Option<&Leaf>,
    ) -> Result<(), EngineError> {
        let (Some(step), Some(acc), Some(parts)) = (
            self.plan.atoms.get(depth),
            self.access.get(depth),
            self.parts.get(depth),
        ) else {
            if let Some(o) = self.plan.project(&b) {
                let mut t = [0u64; W];
                t.copy_from_slice(&o[..W]);
                out.push(t);
            }
            return Ok(());
        };
        let mut prefix = [0u64; WIDTH];
        let nc = acc.consts.len();
        prefix[..nc].copy_from_slice(&acc.consts);
        if acc.nkeys > 0 {
            // A key value that does not fit its column matches no tuple.
            let Some(k) = step.binding_key(&b) else {
                return Ok(());
            };
            prefix[nc..nc + acc.nkeys].copy_from_slice(&k[..acc.nkeys]);
        }
        let prefix = &prefix[..acc.prefix_len()];
        // Comparisons with the binding that bound the next column: read its range only.
        let window = match &acc.narrow {
            Some(n) => match n.range(&b) {
                Some(r) => Some(r),
                None => return Ok(()),
            },
            None => None,
        };
        for part in parts {
            let mut matches = range(part, prefix);
            if let Some((lo, hi)) = window {
                matches = within(matches, prefix.len(), lo, hi);
            }
            progress.candidates += matches.len();
            if progress.candidates >= CHECK_EVERY {
                progress.candidates = 0;
                progress.limits.check(out.len())?;
            }
            match leaf {
                Some(leaf) if depth + 1 == self.plan.atoms.len() => {
                    Self::last(leaf, step, acc, &b, matches, out)
                }
                _ => {
                    for t in matches {
                        let mut nb = b;
                        for &(pos, slot) in &acc.news {
                            nb[slot] = t[pos];
                        }
                        if let Some(nb) = apply(&step.after, nb) {
                            self.step(depth + 1, nb, out, progress, leaf)?;
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// The last atom's candidates through the fast path (see [`Leaf`]).
    fn last(
        leaf: &Leaf,
        step: &AtomStep,
        acc: &Access,
        b: &Row,
        matches: &[Tup<W>],
        out: &mut Vec<Tup<W>>,
    ) {
        if step.after.is_empty() {
            out.reserve(matches.len());
            for t in matches {
                let mut o = [0u64; W];
                for (o, f) in o.iter_mut().zip(&leaf.direct) {
                    *o = match *f {
                        From::Binding(s) => b[s],
                        From::Tuple(p) => t[p],
                    };
                }
                out.push(o);
            }
            return;
        }
        for t in matches {
            let mut nb = *b;
            for &(pos, slot) in &acc.news {
                nb[slot] = t[pos];
            }
            if let Some(nb) = apply(&step.after, nb) {
                let mut o = [0u64; W];
                for (o, &s) in o.iter_mut().zip(&leaf.slots) {
                    *o = nb[s];
                }
                out.push(o);
            }
        }
    }
}
