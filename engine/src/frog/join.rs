//! The join of one plan over sorted sources: atoms in the planner's order, each binding's
//! constants and key values looked up as a prefix range of the atom's sorted copy (a leapjoin
//! with one extending relation per step), the planner's filters applied as soon as the atom
//! that binds their last variable is joined, and the head projected into fixed-width tuples.
//! Depth-first, so no intermediate bindings are materialised.

use crate::eval::Limits;
use crate::frog::access::{range, within, Access, Tup};
use crate::plan::{apply, Plan};
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
        self.step(0, b, out, &mut progress)?;
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
            for t in matches {
                let mut nb = b;
                for &(pos, slot) in &acc.news {
                    nb[slot] = t[pos];
                }
                if let Some(nb) = apply(&step.after, nb) {
                    self.step(depth + 1, nb, out, progress)?;
                }
            }
        }
        Ok(())
    }
}
