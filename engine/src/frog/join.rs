//! The join of one plan over sorted sources: atoms in the planner's order, each binding's
//! constants and key values looked up as a prefix range of the atom's sorted copy (a leapjoin
//! with one extending relation per step), the planner's filters applied as soon as the atom
//! that binds their last variable is joined, and the head projected into fixed-width tuples.
//! Depth-first, so no intermediate bindings are materialised.

use crate::eval::Limits;
use crate::frog::access::{range_span, within_span, Access, Tup};
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

/// Candidate and output counts, for the periodic limit checks, and the last lookup per atom.
struct Progress<'l> {
    limits: &'l Limits<'l>,
    candidates: usize,
    /// Per atom: its last lookup, reused while the prefix and window stay the same (the
    /// later atoms of a product, e.g. `parent(Y, B)` for every `X` of one `sg(A, B)`).
    memo: Vec<Memo>,
}

/// Parts an atom may read for its lookups to be remembered (datafrog keeps about log2(n)
/// stable batches, so 32 covers any relation that fits in memory).
const MEMO_PARTS: usize = 32;

/// One atom's last lookup: its prefix and window, and the span found in each part.
#[derive(Clone, Copy)]
struct Memo {
    valid: bool,
    prefix: Row,
    window: Option<(u64, u64)>,
    spans: [(usize, usize); MEMO_PARTS],
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
        let memo = Memo {
            valid: false,
            prefix: [0u64; WIDTH],
            window: None,
            spans: [(0, 0); MEMO_PARTS],
        };
        let mut progress = Progress {
            limits,
            candidates: 0,
            memo: vec![memo; self.plan.atoms.len()],
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
        let span = |part: &[Tup<W>]| {
            let (a, b) = range_span(part, prefix);
            match window {
                Some((lo, hi)) => {
                    let (x, y) = within_span(&part[a..b], prefix.len(), lo, hi);
                    (a + x, a + y)
                }
                None => (a, b),
            }
        };
        let remembered = parts.len() <= MEMO_PARTS && depth < progress.memo.len();
        if remembered {
            let m = &mut progress.memo[depth];
            let l = prefix.len();
            if !(m.valid && m.prefix[..l] == *prefix && m.window == window) {
                for (s, part) in m.spans.iter_mut().zip(parts) {
                    *s = span(part);
                }
                m.valid = true;
                m.prefix[..l].copy_from_slice(prefix);
                m.window = window;
            }
        }
        for (i, part) in parts.iter().enumerate() {
            // Deeper atoms only write their own memo, so this atom's spans stay put.
            let (from, to) = if remembered {
                progress.memo[depth].spans[i]
            } else {
                span(part)
            };
            let matches = &part[from..to];
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
