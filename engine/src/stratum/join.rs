//! The join of one plan over sorted sources: atoms in the planner's order, each binding's
//! constants and key values looked up as a prefix range of the atom's sorted copy (a leapjoin
//! with one extending relation per step), the planner's filters applied as soon as the atom
//! that binds their last variable is joined, and the head projected into fixed-width tuples.
//! Depth-first, so no intermediate bindings are materialised.

use crate::limits::Limits;
use std::cmp::Ordering;

use crate::plan::{apply_mut, diff_holds, raw_holds, Arg, AtomStep, CExpr, Filter, Plan, Raw};
use crate::stratum::access::{
    prefix_cmp, range_span, range_span_from, within_span, within_span_from, Access, Tup,
};
use crate::value::Row;
use crate::EngineError;
use scenalog_rules::ast::CmpOp;

/// How often (in candidate tuples) the budget and the clock are checked.
const CHECK_EVERY: usize = 1 << 16;

/// One plan's join: the plan, how each atom is read, and the sorted parts each atom reads.
pub(crate) struct Join<'a, const R: usize, const W: usize> {
    /// The plan.
    pub(crate) plan: &'a Plan<R>,
    /// One access per atom.
    pub(crate) access: &'a [Access],
    /// Per atom: the sorted slices whose union it reads.
    pub(crate) parts: Vec<Vec<&'a [Tup<W>]>>,
}

/// Candidate and output counts, for the periodic limit checks, and the last lookup per atom.
struct Progress<'l, const R: usize> {
    limits: &'l Limits<'l>,
    candidates: usize,
    /// Per atom: its last lookup, reused while the prefix and window stay the same (the
    /// later atoms of a product, e.g. `parent(Y, B)` for every `X` of one `sg(A, B)`).
    memo: Vec<Memo<R>>,
    /// Per atom: whether its lookup (keys and window) reads no slot the previous atom or
    /// that atom's filters write, so it is the same for all of the previous atom's
    /// candidates.
    invariant: Vec<bool>,
    /// Whether the last atom only tests that its key is a tuple (see [`Join::exists`]).
    exists: bool,
    /// Per depth: how many times the join went on to that atom (for runs of atoms that only
    /// test existence, [`AtomStep::dead_until`]: whether a candidate reached past its run).
    arrivals: Vec<u64>,
}

/// Parts an atom may read for its lookups to be remembered (datafrog keeps about log2(n)
/// stable batches, so 32 covers any relation that fits in memory).
const MEMO_PARTS: usize = 32;

/// One atom's last lookup: its prefix and window, and per part the prefix's range and the
/// span of that range within the window. A lookup with a greater prefix gallops on from the
/// end of the previous range (a merge when lookups arrive in key order), a smaller one
/// searches the whole part. An existence test ([`Join::exists`]) keeps only where its last
/// key was in each part, as the start of each range.
#[derive(Clone, Copy)]
struct Memo<const R: usize> {
    valid: bool,
    /// Set when the lookup was made under the current binding of every atom before the
    /// previous one and is invariant (see `Progress::invariant`): reused without computing
    /// the key. The previous atom clears it each time it starts over its candidates.
    fresh: bool,
    prefix: Row<R>,
    window: Option<(u64, u64)>,
    ranges: [(usize, usize); MEMO_PARTS],
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
struct Leaf<const R: usize> {
    /// Per head column, from the binding before the last atom or its tuple.
    direct: Vec<From>,
    /// Per head column, its slot (after the last atom's filters ran on the full binding).
    slots: Vec<usize>,
    /// When the atom's only filter is a one-column negation of one of its new variables:
    /// that variable's stored position (the negation is then looked up on the tuple).
    negated: Option<usize>,
    /// When every filter after the atom is a comparison of encoded words or an int
    /// difference ([`Filter::CmpRaw`], [`Filter::CmpDiff`]): the same checks reading the
    /// candidate tuple and the binding directly (no binding row written per candidate).
    checks: Option<Vec<Check>>,
}

/// Where a leaf check reads a word: a slot (from the candidate tuple or the binding before
/// the last atom), or a constant.
#[derive(Clone, Copy)]
enum Word {
    Slot(From),
    Const(u64),
}

/// A comparison after the last atom, read from the tuple and the binding (see `Leaf::checks`).
#[derive(Clone, Copy)]
enum Check {
    /// [`Filter::CmpRaw`].
    Raw(CmpOp, Word, Word),
    /// [`Filter::CmpDiff`].
    Diff {
        op: CmpOp,
        a: Word,
        b: Word,
        abs: bool,
        c: i64,
    },
}

impl Check {
    /// Whether the candidate `t` under binding `b` passes, as the filter would on the row
    /// the general path writes.
    #[inline(always)]
    fn holds<const R: usize, const W: usize>(self, b: &Row<R>, t: &Tup<W>) -> bool {
        let word = |w: Word| match w {
            Word::Slot(From::Tuple(p)) => t[p],
            Word::Slot(From::Binding(s)) => b[s],
            Word::Const(c) => c,
        };
        match self {
            Check::Raw(op, x, y) => raw_holds(op, word(x), word(y)),
            Check::Diff { op, a, b, abs, c } => diff_holds(op, word(a), word(b), abs, c),
        }
    }
}

impl<const R: usize> Leaf<R> {
    /// The head tuple from the binding before the last atom and the last atom's tuple `t`.
    #[inline]
    fn project<const W: usize>(&self, b: &Row<R>, t: &Tup<W>) -> Tup<W> {
        let mut o = [0u64; W];
        for (o, f) in o.iter_mut().zip(&self.direct) {
            *o = match *f {
                From::Binding(s) => b[s],
                From::Tuple(p) => t[p],
            };
        }
        o
    }

    fn of(plan: &Plan<R>, last: &Access) -> Option<Leaf<R>> {
        let negated = match plan.atoms.last().map(|a| a.after.as_slice()) {
            Some([Filter::Neg(n)]) => n.single().and_then(|(slot, _)| {
                last.news
                    .iter()
                    .find(|&&(_, s)| s == slot)
                    .map(|&(pos, _)| pos)
            }),
            _ => None,
        };
        let mut slots = Vec::new();
        for (e, ty) in &plan.head {
            match e {
                CExpr::Slot(s, t) if t == ty => slots.push(*s),
                _ => return None,
            }
        }
        // Where a slot's value is once the last atom is joined: its tuple or the binding.
        let from = |s: usize| match last.news.iter().find(|&&(_, slot)| slot == s) {
            Some(&(pos, _)) => From::Tuple(pos),
            None => From::Binding(s),
        };
        let direct = slots.iter().map(|&s| from(s)).collect();
        let word = |s: usize| Word::Slot(from(s));
        let checks = plan.atoms.last().and_then(|a| {
            a.after
                .iter()
                .map(|f| match *f {
                    Filter::CmpRaw(op, x, Raw::Slot(y)) => Some(Check::Raw(op, word(x), word(y))),
                    Filter::CmpRaw(op, x, Raw::Const(c)) => {
                        Some(Check::Raw(op, word(x), Word::Const(c)))
                    }
                    Filter::CmpDiff { op, a, b, abs, c } => Some(Check::Diff {
                        op,
                        a: word(a),
                        b: word(b),
                        abs,
                        c,
                    }),
                    _ => None,
                })
                .collect::<Option<Vec<Check>>>()
        });
        Some(Leaf {
            direct,
            slots,
            negated,
            checks,
        })
    }
}

/// Per atom of a plan: whether its keys and window read none of the slots the atom before it
/// binds (its new variables and its filters' results).
fn invariant<const R: usize>(plan: &Plan<R>) -> Vec<bool> {
    let mut out = vec![false; plan.atoms.len()];
    for (d, pair) in plan.atoms.windows(2).enumerate() {
        let [prev, step] = pair else { continue };
        let written = prev.writes();
        let keys = step.args.iter().all(|a| match a {
            Arg::Key(e, _) => !reads(e, &written),
            _ => true,
        });
        let window = step.narrow.as_ref().is_none_or(|n| {
            n.lo.iter().chain(&n.hi).all(|e| {
                !reads(&e.base, &written) && e.off.as_ref().is_none_or(|(_, o)| !reads(o, &written))
            })
        });
        out[d + 1] = keys && window;
    }
    out
}

/// Whether an expression reads one of `slots`.
fn reads(e: &CExpr, slots: &[usize]) -> bool {
    e.any_slot(&mut |s| slots.contains(&s))
}

impl<const R: usize, const W: usize> Join<'_, R, W> {
    /// Runs the join, appending head tuples to `out`.
    pub(crate) fn run(
        &self,
        out: &mut Vec<Tup<W>>,
        limits: &Limits<'_>,
    ) -> Result<(), EngineError> {
        let mut b = [0u64; R];
        if !apply_mut(&self.plan.start, &mut b) {
            return Ok(());
        }
        let memo = Memo {
            valid: false,
            fresh: false,
            prefix: [0u64; R],
            window: None,
            ranges: [(0, 0); MEMO_PARTS],
            spans: [(0, 0); MEMO_PARTS],
        };
        let mut progress = Progress {
            limits,
            candidates: 0,
            memo: vec![memo; self.plan.atoms.len()],
            invariant: invariant(self.plan),
            exists: false,
            arrivals: vec![0; self.plan.atoms.len() + 1],
        };
        let leaf = self.access.last().and_then(|a| Leaf::of(self.plan, a));
        progress.exists = leaf.is_some() && self.exists_last();
        self.step(0, &mut b, out, &mut progress, leaf.as_ref())?;
        if self.plan.sum_overflowed() {
            return Err(limits.sum_overflow());
        }
        limits.check(out.len())
    }

    fn step(
        &self,
        depth: usize,
        b: &mut Row<R>,
        out: &mut Vec<Tup<W>>,
        progress: &mut Progress<'_, R>,
        leaf: Option<&Leaf<R>>,
    ) -> Result<(), EngineError> {
        let (Some(step), Some(acc), Some(parts)) = (
            self.plan.atoms.get(depth),
            self.access.get(depth),
            self.parts.get(depth),
        ) else {
            if let Some(o) = self.plan.project(b) {
                let mut t = [0u64; W];
                t.copy_from_slice(&o[..W]);
                out.push(t);
            }
            return Ok(());
        };
        let remembered = parts.len() <= MEMO_PARTS && depth < progress.memo.len();
        // This atom's lookup is the one remembered when it reads nothing the previous atom
        // bound and the previous atom's binding has not changed since (see `Memo::fresh`).
        let fresh = remembered && progress.memo[depth].fresh;
        let mut searched = Vec::new();
        if !fresh {
            let mut prefix = [0u64; R];
            let l = acc.prefix_len();
            if !acc.prefix_into(step, b, &mut prefix) {
                return Ok(());
            }
            let prefix = &prefix[..l];
            // Comparisons with the binding that bound the next column: read its range only.
            let window = match &acc.narrow {
                Some(n) => match n.range(b) {
                    Some(r) => Some(r),
                    None => return Ok(()),
                },
                None => None,
            };
            let narrow = |part: &[Tup<W>], (a, b): (usize, usize)| match window {
                Some((lo, hi)) => {
                    let (x, y) = within_span(&part[a..b], l, lo, hi);
                    (a + x, a + y)
                }
                None => (a, b),
            };
            if remembered {
                let m = &mut progress.memo[depth];
                let order = if m.valid {
                    prefix_cmp(prefix, &m.prefix[..l])
                } else {
                    Ordering::Less
                };
                if order != Ordering::Equal || m.window != window {
                    let before = m.window;
                    for ((r, s), part) in m.ranges.iter_mut().zip(m.spans.iter_mut()).zip(parts) {
                        *r = match order {
                            Ordering::Equal => *r,
                            // Lookups in ascending key order: a merge, galloping on from the
                            // end of the previous range.
                            Ordering::Greater => range_span_from(part, prefix, r.1),
                            Ordering::Less => range_span(part, prefix),
                        };
                        *s = match (order, before, window) {
                            // The same range, another window: from the previous span.
                            (Ordering::Equal, Some(before), Some(now)) => {
                                let (a, b) = *r;
                                let prev = (s.0 - a, s.1 - a);
                                let (x, y) = within_span_from(&part[a..b], l, now, prev, before);
                                (a + x, a + y)
                            }
                            _ => narrow(part, *r),
                        };
                    }
                    m.valid = true;
                    m.prefix[..l].copy_from_slice(prefix);
                    m.window = window;
                }
                m.fresh = progress.invariant[depth];
            } else {
                searched = parts
                    .iter()
                    .map(|part| narrow(part, range_span(part, prefix)))
                    .collect();
            }
        }
        // The next atom's remembered lookup may read what this atom binds.
        if let Some(m) = progress.memo.get_mut(depth + 1) {
            m.fresh = false;
        }
        for (i, part) in parts.iter().enumerate() {
            // Deeper atoms only write their own memo, so this atom's spans stay put.
            let (from, to) = if remembered {
                progress.memo[depth].spans[i]
            } else {
                searched[i]
            };
            let matches = &part[from..to];
            progress.candidates += matches.len();
            if progress.candidates >= CHECK_EVERY {
                progress.candidates = 0;
                progress.limits.check(out.len())?;
            }
            match leaf {
                Some(leaf) if depth + 1 == self.plan.atoms.len() && step.existential => {
                    // An existence test last: the first candidate that passes stands for all.
                    for t in matches {
                        let before = out.len();
                        Self::last(leaf, step, acc, b, std::slice::from_ref(t), out);
                        if out.len() > before {
                            return Ok(());
                        }
                    }
                }
                Some(leaf) if depth + 1 == self.plan.atoms.len() => {
                    Self::last(leaf, step, acc, b, matches, out)
                }
                _ => {
                    // One binding row for the whole join: each candidate overwrites this
                    // atom's slots (and its filters' bindings), deeper atoms write only
                    // slots bound after it.
                    let exists = match leaf {
                        Some(leaf) if progress.exists && depth + 2 == self.plan.atoms.len() => {
                            Some(leaf)
                        }
                        _ => None,
                    };
                    // A run of atoms from this one that only tests existence: the atom past
                    // it, whose arrivals (or, past the last atom, the head tuples written)
                    // say that a candidate got there.
                    let last = self.plan.atoms.len();
                    let past = step.dead_until.map(|e| e + 1);
                    let reached = |progress: &Progress<'_, R>, out: &Vec<Tup<W>>, p: usize| {
                        if p < last {
                            progress.arrivals[p]
                        } else {
                            out.len() as u64
                        }
                    };
                    for t in matches {
                        for &(pos, slot) in &acc.news {
                            b[slot] = t[pos];
                        }
                        if apply_mut(&step.after, b) {
                            let before = past.map(|p| reached(progress, out, p));
                            progress.arrivals[depth + 1] += 1;
                            match exists {
                                Some(leaf) => self.exists(b, out, progress, leaf),
                                None => self.step(depth + 1, b, out, progress, leaf)?,
                            }
                            if step.existential {
                                // An existence test: every other candidate gives the same
                                // binding, so the same results.
                                return Ok(());
                            }
                            if let (Some(p), Some(before)) = (past, before) {
                                if reached(progress, out, p) > before {
                                    // The run was satisfied: its other ways give the rest of
                                    // the join the same binding.
                                    return Ok(());
                                }
                            }
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Whether the last atom (after at least one other) binds no variable, has no filter after
    /// it and every column of its copy is a constant or a key: it then matches the binding's
    /// key itself or nothing, and [`Join::exists`] looks the key up in the loop of the atom
    /// before it.
    fn exists_last(&self) -> bool {
        let (Some(step), Some(acc), Some(parts)) = (
            self.plan.atoms.last(),
            self.access.last(),
            self.parts.last(),
        ) else {
            return false;
        };
        self.plan.atoms.len() >= 2
            && acc.news.is_empty()
            && acc.narrow.is_none()
            && step.after.is_empty()
            && acc.prefix_len() == acc.sig.perm.len()
            && acc.prefix_len() <= W
            && parts.len() <= MEMO_PARTS
    }

    /// The last atom as an existence test (see [`Join::exists_last`]): the binding's key,
    /// padded with zeros as the copy's tuples are past its columns, searched in each part
    /// from where the previous key was (a gallop when keys come in ascending order, see
    /// [`crate::rows::search_from`]), and the head projected for each part that holds it, as
    /// the general path would.
    fn exists(
        &self,
        b: &Row<R>,
        out: &mut Vec<Tup<W>>,
        progress: &mut Progress<'_, R>,
        leaf: &Leaf<R>,
    ) {
        let d = self.plan.atoms.len() - 1;
        let (Some(step), Some(acc), Some(parts), Some(m)) = (
            self.plan.atoms.get(d),
            self.access.get(d),
            self.parts.get(d),
            progress.memo.get_mut(d),
        ) else {
            return;
        };
        let mut key = [0u64; W];
        if !acc.prefix_into(step, b, &mut key) {
            return;
        }
        // Per part, `r.0`: where the previous key was, or would be.
        for (r, part) in m.ranges.iter_mut().zip(parts) {
            r.0 = crate::rows::search_from(part, &key, r.0);
            if part.get(r.0) == Some(&key) {
                out.push(leaf.project(b, &key));
            }
        }
    }

    /// The last atom's candidates through the fast path (see [`Leaf<R>`]).
    fn last(
        leaf: &Leaf<R>,
        step: &AtomStep<R>,
        acc: &Access,
        b: &mut Row<R>,
        matches: &[Tup<W>],
        out: &mut Vec<Tup<W>>,
    ) {
        let direct = |t: &Tup<W>| leaf.project(b, t);
        if step.after.is_empty() {
            out.extend(matches.iter().map(direct));
            return;
        }
        // `!r(Y)` on one of the atom's own columns: a lookup of the tuple's word.
        if let Some((pos, absent)) = leaf.negated.and_then(|pos| match step.after.as_slice() {
            [Filter::Neg(n)] => n.single().map(|(_, set)| (pos, set)),
            _ => None,
        }) {
            out.extend(
                matches
                    .iter()
                    .filter(|t| !absent.contains(&t[pos]))
                    .map(direct),
            );
            return;
        }
        if let Some(checks) = &leaf.checks {
            // A plain loop: the compiler inlines the checks here, where a `filter` adapter
            // called its closure once per candidate.
            for t in matches {
                if checks.iter().all(|c| c.holds(b, t)) {
                    out.push(direct(t));
                }
            }
            return;
        }
        for t in matches {
            for &(pos, slot) in &acc.news {
                b[slot] = t[pos];
            }
            if apply_mut(&step.after, b) {
                let mut o = [0u64; W];
                for (o, &s) in o.iter_mut().zip(&leaf.slots) {
                    *o = b[s];
                }
                out.push(o);
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::plan::cmp_filter;
    use crate::rows::Rows;
    use crate::value::WIDTH;
    use crate::value::{enc_int, V};
    use crate::Options;
    use scenalog_facts::catalog::ColType;
    use scenalog_rules::ast::{BinOp, CmpOp};
    use std::time::Instant;

    /// A small deterministic generator for the kernel's property tests.
    pub(crate) fn lcg(seed: &mut u64) -> u64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        *seed >> 33
    }

    fn int(s: usize) -> CExpr {
        CExpr::Slot(s, ColType::Int)
    }

    /// The join's output under default options, sorted.
    fn sorted_output(join: &Join<'_, 12, 2>) -> Vec<Tup<2>> {
        let options = Options::default();
        let limits = Limits {
            relation: "out",
            options: &options,
            start: Instant::now(),
            held: 0,
        };
        let mut got: Vec<Tup<2>> = Vec::new();
        if let Err(e) = join.run(&mut got, &limits) {
            panic!("join failed: {e}");
        }
        got.sort_unstable();
        got
    }

    /// `out(X, Z) :- a(X, Y), [c(W),] b(Y, Z), <filters>` with head `heads`, joined by
    /// [`Join<R>`] over `b` split into sorted parts, against a nested loop over the plain
    /// tuples. With `c` (when `mid` is not empty) `b`'s lookup does not depend on the atom
    /// before it, so it is made once per `a` tuple and reused over `c`'s. With `merge`, `a`
    /// is read in `Y` order (`b`'s keys ascending: forward gallops), else in `X` order
    /// (keys going back and forth).
    fn check(
        a: &[(i64, i64)],
        mid: &[i64],
        b: &[(i64, i64)],
        after: Vec<Filter<WIDTH>>,
        head: Vec<(CExpr, ColType)>,
        merge: bool,
    ) {
        let sa = AtomStep::new("a".into(), vec![Arg::New(0), Arg::New(1)], Vec::new());
        let sc = AtomStep::new("c".into(), vec![Arg::New(3)], Vec::new());
        let sb = AtomStep::new(
            "b".into(),
            vec![Arg::Key(int(1), ColType::Int), Arg::New(2)],
            after,
        );
        let atoms = if mid.is_empty() {
            vec![sa, sb]
        } else {
            vec![sa, sc, sb]
        };
        let plan = Plan {
            start: Vec::new(),
            atoms,
            head,
        };
        let n = plan.atoms.len();
        // `c` has no keys and `b` reads `Y` of `a`: both lookups are the same for every tuple
        // of the atom before them.
        let want = if n == 3 {
            &[false, true, true][..]
        } else {
            &[false, false][..]
        };
        assert_eq!(invariant(&plan), want);
        let access: Vec<Access> = (0..n)
            .map(|i| {
                let arity = if i == 1 && n == 3 { 1 } else { 2 };
                Access::of(&plan.atoms[i], arity)
            })
            .collect();
        let rows = |v: &[(i64, i64)]| {
            Rows::from_flat(
                2,
                v.iter()
                    .flat_map(|&(x, y)| [enc_int(x), enc_int(y)])
                    .collect(),
            )
        };
        // Sorted, distinct copies (an identity copy is the relation itself, sorted already
        // in the engine; here the tuples come unsorted).
        let copy = |acc: &Access, v: &[(i64, i64)]| {
            let mut c: Vec<Tup<2>> = acc.sig.copy_rows(&rows(v));
            c.sort_unstable();
            c.dedup();
            c
        };
        let mut copy_a = copy(&access[0], a);
        if merge {
            // `a` read in `Y` order (it has no prefix, so any order serves): `b`'s lookups
            // then come in ascending key order and gallop forward.
            copy_a.sort_unstable_by_key(|t| (t[1], t[0]));
        }
        let mut copy_c: Vec<Tup<2>> = mid.iter().map(|&w| [enc_int(w), 0]).collect();
        copy_c.sort_unstable();
        copy_c.dedup();
        // `b` in three disjoint sorted parts, as a variable's stable batches and recent
        // tuples.
        let mut b = b.to_vec();
        b.sort_unstable();
        b.dedup();
        // Interleaved, so one key's tuples are spread over the parts.
        let bs: Vec<Vec<Tup<2>>> = (0..3)
            .map(|k| {
                let part: Vec<(i64, i64)> = b.iter().skip(k).step_by(3).copied().collect();
                copy(&access[n - 1], &part)
            })
            .collect();
        let mut parts = vec![vec![&copy_a[..]]];
        if n == 3 {
            parts.push(vec![&copy_c[..]]);
        }
        parts.push(bs.iter().map(|p| &p[..]).collect());
        let join = Join {
            plan: &plan,
            access: &access,
            parts,
        };
        let got = sorted_output(&join);
        // The nested loop: every combination, the filters and head through `apply`.
        let mut want: Vec<Tup<2>> = Vec::new();
        let mut a = a.to_vec();
        a.sort_unstable();
        a.dedup();
        let ws: Vec<Option<u64>> = if n == 3 {
            copy_c.iter().map(|w| Some(w[0])).collect()
        } else {
            vec![None]
        };
        for &(x, y) in &a {
            for w in &ws {
                for &(_, z) in b.iter().filter(|t| t.0 == y) {
                    let mut row = [0u64; WIDTH];
                    row[0] = enc_int(x);
                    row[1] = enc_int(y);
                    row[2] = enc_int(z);
                    row[3] = w.unwrap_or(0);
                    if let Some(r) = crate::plan::apply(&plan.atoms[n - 1].after, row) {
                        if let Some(o) = plan.project(&r) {
                            want.push([o[0], o[1]]);
                        }
                    }
                }
            }
        }
        want.sort_unstable();
        assert_eq!(got, want);
    }

    #[test]
    fn joins_agree_with_a_nested_loop_whatever_the_lookup_order() {
        let mut seed = 7;
        for case in 0..200 {
            let n = 1 + (lcg(&mut seed) % 60) as usize;
            let span = 1 + lcg(&mut seed) % 20;
            let draw = |seed: &mut u64| (lcg(seed) % span) as i64 - (span / 2) as i64;
            let a: Vec<(i64, i64)> = (0..n).map(|_| (draw(&mut seed), draw(&mut seed))).collect();
            let b: Vec<(i64, i64)> = (0..n + 3)
                .map(|_| (draw(&mut seed), draw(&mut seed)))
                .collect();
            let slots = vec![(int(0), ColType::Int), (int(2), ColType::Int)];
            let merge = case % 2 == 0;
            let mid: Vec<i64> = if case % 4 < 2 {
                Vec::new()
            } else {
                (0..1 + lcg(&mut seed) % 4)
                    .map(|_| draw(&mut seed))
                    .collect()
            };
            // No filters: the last atom writes head tuples from the binding and the tuple.
            check(&a, &mid, &b, Vec::new(), slots.clone(), merge);
            // Comparisons: the last atom's filters, read from the binding and the tuple (a
            // slot of each, a slot and a constant, and an int difference).
            let filters = vec![
                cmp_filter(CmpOp::Ne, int(0), int(2)),
                cmp_filter(CmpOp::Gt, int(2), CExpr::Const(V::Int(-(span as i64) / 3))),
                cmp_filter(
                    CmpOp::Le,
                    CExpr::Call(
                        scenalog_rules::ast::Func::Abs,
                        vec![CExpr::Bin(BinOp::Sub, Box::new(int(0)), Box::new(int(2)))],
                    ),
                    CExpr::Const(V::Int(3)),
                ),
            ];
            check(&a, &mid, &b, filters, slots, merge);
            // A computed head: no fast path, the general recursion, with a binding.
            let bind = vec![Filter::Bind(
                4,
                CExpr::Bin(BinOp::Add, Box::new(int(0)), Box::new(int(2))),
                ColType::Int,
            )];
            let computed = vec![
                (int(4), ColType::Int),
                (
                    CExpr::Bin(BinOp::Sub, Box::new(int(1)), Box::new(int(0))),
                    ColType::Int,
                ),
            ];
            check(&a, &mid, &b, bind, computed, merge);
        }
    }

    /// `out(X, Y) :- a(X, Y), U = X + 1, b(Y, U).`: `b` binds nothing, so the join tests each
    /// key for existence in `a`'s loop ([`Join::exists`]), over `b` in three parts and with
    /// `a` read in `Y` order (keys ascending) or `X` order (back and forth), against a nested
    /// loop.
    #[test]
    fn existence_tests_agree_with_a_nested_loop() {
        let mut seed = 11;
        for case in 0..200 {
            let n = 1 + (lcg(&mut seed) % 80) as usize;
            let span = 1 + lcg(&mut seed) % 12;
            let draw = |seed: &mut u64| (lcg(seed) % span) as i64 - (span / 2) as i64;
            let mut pairs = |k: usize| -> Vec<(i64, i64)> {
                let mut v: Vec<(i64, i64)> =
                    (0..k).map(|_| (draw(&mut seed), draw(&mut seed))).collect();
                v.sort_unstable();
                v.dedup();
                v
            };
            let (a, b) = (pairs(n), pairs(n + 5));
            let bind = Filter::Bind(
                2,
                CExpr::Bin(
                    BinOp::Add,
                    Box::new(int(0)),
                    Box::new(CExpr::Const(V::Int(1))),
                ),
                ColType::Int,
            );
            let sa = AtomStep::new("a".into(), vec![Arg::New(0), Arg::New(1)], vec![bind]);
            let sb = AtomStep::new(
                "b".into(),
                vec![
                    Arg::Key(int(1), ColType::Int),
                    Arg::Key(int(2), ColType::Int),
                ],
                Vec::new(),
            );
            let plan = Plan {
                start: Vec::new(),
                atoms: vec![sa, sb],
                head: vec![(int(0), ColType::Int), (int(1), ColType::Int)],
            };
            let access: Vec<Access> = plan.atoms.iter().map(|s| Access::of(s, 2)).collect();
            let enc = |v: &[(i64, i64)]| -> Vec<Tup<2>> {
                v.iter().map(|&(x, y)| [enc_int(x), enc_int(y)]).collect()
            };
            let mut copy_a = enc(&a);
            if case % 2 == 0 {
                copy_a.sort_unstable_by_key(|t| (t[1], t[0]));
            }
            let bs: Vec<Vec<Tup<2>>> = (0..3)
                .map(|k| {
                    let part: Vec<(i64, i64)> = b.iter().skip(k).step_by(3).copied().collect();
                    enc(&part)
                })
                .collect();
            let join = Join {
                plan: &plan,
                access: &access,
                parts: vec![vec![&copy_a[..]], bs.iter().map(|p| &p[..]).collect()],
            };
            assert!(join.exists_last(), "case {case}: b is an existence test");
            let got = sorted_output(&join);
            let want: Vec<Tup<2>> = enc(&a
                .iter()
                .copied()
                .filter(|&(x, y)| b.contains(&(y, x + 1)))
                .collect::<Vec<_>>());
            assert_eq!(got, want, "case {case}");
        }
    }
}
