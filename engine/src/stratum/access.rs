//! How a join reaches an atom's tuples: each atom reads a sorted copy of its relation whose
//! columns are permuted so that its constants come first, then its join-key columns, then the
//! rest; constants and key values then select one contiguous range by a prefix search.
//! Repeated variables within the atom (`p(X, X)`) are applied when the copy is made.

use crate::plan::{Arg, AtomStep, CExpr, Narrow};
use crate::rows::{gallop, Rows};
use crate::value::Row;

/// A stored tuple of a stratum: `W` words, the columns first (permuted for an index), zeros
/// after the arity.
pub(crate) type Tup<const W: usize> = [u64; W];

/// Which copy of a relation an atom reads: the relation, its column order, and the equalities
/// between its columns that the copy keeps.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub(crate) struct Sig {
    /// The relation.
    pub(crate) pred: String,
    /// Source column of each stored position.
    pub(crate) perm: Vec<usize>,
    /// (column, column) pairs that must hold equal values.
    pub(crate) sames: Vec<(usize, usize)>,
}

impl Sig {
    /// Whether the copy is the relation itself (natural column order, nothing filtered).
    pub(crate) fn is_identity(&self) -> bool {
        self.sames.is_empty() && self.perm.iter().enumerate().all(|(i, &c)| i == c)
    }

    /// The copy of one tuple, or `None` when it fails the equalities.
    pub(crate) fn apply<const W: usize>(&self, t: &[u64]) -> Option<Tup<W>> {
        if !self.sames.iter().all(|&(i, j)| t.get(i) == t.get(j)) {
            return None;
        }
        let mut out = [0u64; W];
        for (o, &c) in out.iter_mut().zip(&self.perm) {
            *o = t.get(c).copied().unwrap_or(0);
        }
        Some(out)
    }

    /// The sorted, distinct copy of a stored relation.
    pub(crate) fn copy_rows<const W: usize>(&self, rows: &Rows) -> Vec<Tup<W>> {
        if self.is_identity() {
            // The relation as it is (stored rows are sorted and distinct): words copied.
            return rows
                .iter()
                .map(|t| {
                    let mut o = [0u64; W];
                    let n = t.len().min(W);
                    o[..n].copy_from_slice(&t[..n]);
                    o
                })
                .collect();
        }
        let mut v: Vec<Tup<W>> = rows.iter().filter_map(|t| self.apply(t)).collect();
        crate::rows::sort_tuples(&mut v);
        v.dedup();
        v
    }
}

/// How one atom of a plan is read: from which copy, with which constant prefix, how many
/// binding-key words follow the constants, and where its new variables sit in the copy.
#[derive(Debug, Clone)]
pub(crate) struct Access {
    /// The copy read.
    pub(crate) sig: Sig,
    /// The constants, in stored order (the first stored positions).
    pub(crate) consts: Vec<u64>,
    /// Number of join-key words after the constants.
    pub(crate) nkeys: usize,
    /// (stored position, binding slot) of each new variable.
    pub(crate) news: Vec<(usize, usize)>,
    /// The column bounded by comparisons with the binding, stored right after the keys.
    pub(crate) narrow: Option<Narrow>,
}

impl Access {
    /// The access for an atom step over a relation of `arity` stored words.
    pub(crate) fn of<const R: usize>(step: &AtomStep<R>, arity: usize) -> Access {
        Access::ordered(step, arity, &[])
    }

    /// [`Access::of`] with the copy sorted, after its constants, keys and narrowed column, by
    /// the columns `lead` (see [`lead_columns`]).
    pub(crate) fn ordered<const R: usize>(
        step: &AtomStep<R>,
        arity: usize,
        lead: &[usize],
    ) -> Access {
        let mut perm: Vec<usize> = step.consts.iter().map(|&(c, _)| c).collect();
        perm.extend(step.keys.iter().copied());
        // A range-narrowed column comes right after the keys, so that within one prefix
        // range the copy is sorted by it.
        perm.extend(step.narrow.as_ref().map(|n| n.col));
        for &c in lead {
            if c < arity && !perm.contains(&c) {
                perm.push(c);
            }
        }
        for c in 0..arity {
            if !perm.contains(&c) {
                perm.push(c);
            }
        }
        let news = step
            .news
            .iter()
            .map(|&(c, s)| (perm.iter().position(|&p| p == c).unwrap_or(0), s))
            .collect();
        Access {
            sig: Sig {
                pred: step.pred.clone(),
                perm,
                sames: step.sames.clone(),
            },
            consts: step.consts.iter().map(|&(_, v)| v).collect(),
            nkeys: step.keys.len(),
            news,
            narrow: step.narrow.clone(),
        }
    }

    /// Words of the lookup prefix.
    pub(crate) fn prefix_len(&self) -> usize {
        self.consts.len() + self.nkeys
    }

    /// Writes the prefix a binding looks up into `out[..self.prefix_len()]`: the constants,
    /// then the key values computed from `b` (`step` is the atom this access reads). `false`
    /// when a key value does not fit its column: the atom then matches no tuple.
    pub(crate) fn prefix_into<const R: usize>(
        &self,
        step: &AtomStep<R>,
        b: &Row<R>,
        out: &mut [u64],
    ) -> bool {
        let nc = self.consts.len();
        out[..nc].copy_from_slice(&self.consts);
        self.nkeys == 0 || step.key_into(b, &mut out[nc..self.prefix_len()])
    }
}

/// The tuples of a sorted slice whose first `p.len()` words equal `p`: a galloping search
/// for the start, then for the end (ranges are usually short).
#[cfg(test)]
pub(crate) fn range<'a, const W: usize>(s: &'a [Tup<W>], p: &[u64]) -> &'a [Tup<W>] {
    let (a, b) = range_span(s, p);
    &s[a..b]
}

/// The columns of atom `first` by which to sort its copy so that the lookups of the atom
/// `next` joined after it come in ascending order: the columns whose variables are `next`'s
/// leading keys, then the one its window bounds are computed from (`abs(XA - XB) < 100`
/// bounds `XB` by `XA ± 100`, which grow with `XA`). Each lookup then gallops on from the
/// previous one, or reuses it, instead of searching the whole copy (a merge join).
pub(crate) fn lead_columns<const R: usize>(first: &AtomStep<R>, next: &AtomStep<R>) -> Vec<usize> {
    let col_of = |e: &CExpr| match e {
        CExpr::Slot(s, _) => first
            .news
            .iter()
            .find(|&&(_, slot)| slot == *s)
            .map(|&(c, _)| c),
        _ => None,
    };
    let mut lead = Vec::new();
    for &k in &next.keys {
        match next.args.get(k) {
            Some(Arg::Key(e, _)) => match col_of(e) {
                Some(c) => lead.push(c),
                None => return lead,
            },
            _ => return lead,
        }
    }
    let window = next
        .narrow
        .as_ref()
        .and_then(|n| n.lo.first().or(n.hi.first()));
    lead.extend(window.and_then(|b| col_of(&b.base)));
    lead
}

/// [`range`] as start and end indices.
pub(crate) fn range_span<const W: usize>(s: &[Tup<W>], p: &[u64]) -> (usize, usize) {
    match p.len() {
        0 => (0, s.len()),
        1 => {
            let k = p[0];
            let lo = s.partition_point(|t| t[0] < k);
            (lo, lo + gallop(&s[lo..], |t| t[0] == k))
        }
        _ => {
            let lo = s.partition_point(|t| prefix_cmp(t, p).is_lt());
            (lo, lo + gallop(&s[lo..], |t| prefix_cmp(t, p).is_eq()))
        }
    }
}

/// How a tuple's first `p.len()` words compare with `p` (a word loop: prefixes are a few
/// words, shorter than a `memcmp` call is worth).
#[inline]
pub(crate) fn prefix_cmp(t: &[u64], p: &[u64]) -> std::cmp::Ordering {
    for (a, b) in t.iter().zip(p) {
        if a != b {
            return a.cmp(b);
        }
    }
    std::cmp::Ordering::Equal
}

/// [`range_span`] for a prefix at or after every tuple before `from` (the previous lookup's
/// range end, when lookups come in ascending order): gallops forward from `from` for the
/// start, then for the end.
pub(crate) fn range_span_from<const W: usize>(
    s: &[Tup<W>],
    p: &[u64],
    from: usize,
) -> (usize, usize) {
    let from = from.min(s.len());
    let lo = from
        + match p.len() {
            0 => 0,
            1 => gallop(&s[from..], |t| t[0] < p[0]),
            _ => gallop(&s[from..], |t| prefix_cmp(t, p).is_lt()),
        };
    let n = match p.len() {
        0 => s.len() - lo,
        1 => gallop(&s[lo..], |t| t[0] == p[0]),
        _ => gallop(&s[lo..], |t| prefix_cmp(t, p).is_eq()),
    };
    (lo, lo + n)
}

/// The tuples of a slice sorted by word `pos` (one prefix range of a copy) whose word `pos`
/// lies in `lo..=hi`: two binary searches.
#[cfg(test)]
pub(crate) fn within<const W: usize>(s: &[Tup<W>], pos: usize, lo: u64, hi: u64) -> &[Tup<W>] {
    let (a, b) = within_span(s, pos, lo, hi);
    &s[a..b]
}

/// [`within`] as start and end indices.
pub(crate) fn within_span<const W: usize>(
    s: &[Tup<W>],
    pos: usize,
    lo: u64,
    hi: u64,
) -> (usize, usize) {
    let a = s.partition_point(|t| t[pos] < lo);
    (a, a + s[a..].partition_point(|t| t[pos] <= hi))
}

/// [`within_span`] for a window `(lo, hi)` on the same slice as an earlier window `before`
/// whose span was `span`: each end gallops on from the earlier one when the window moved up
/// (lookups in ascending order), else is searched below it.
pub(crate) fn within_span_from<const W: usize>(
    s: &[Tup<W>],
    pos: usize,
    (lo, hi): (u64, u64),
    span: (usize, usize),
    before: (u64, u64),
) -> (usize, usize) {
    let (a0, b0) = (span.0.min(s.len()), span.1.min(s.len()));
    let a = if lo >= before.0 {
        a0 + gallop(&s[a0..], |t| t[pos] < lo)
    } else {
        s[..a0].partition_point(|t| t[pos] < lo)
    };
    let upto = b0.max(a);
    let b = if hi >= before.1 {
        upto + gallop(&s[upto..], |t| t[pos] <= hi)
    } else {
        a + s[a..upto].partition_point(|t| t[pos] <= hi)
    };
    (a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_select_exactly_the_prefix_matches() {
        let s: Vec<Tup<2>> = vec![[1, 1], [2, 0], [2, 5], [2, 9], [3, 1], [3, 2]];
        assert_eq!(range(&s, &[2]), &s[1..4]);
        assert_eq!(range(&s, &[3]), &s[4..6]);
        assert!(range(&s, &[4]).is_empty());
        assert!(range(&s, &[0]).is_empty());
        assert_eq!(range(&s, &[2, 5]), &s[2..3]);
        assert_eq!(range(&s, &[]).len(), 6);
        assert_eq!(within(range(&s, &[2]), 1, 1, 5), &s[2..3]);
        assert_eq!(within(range(&s, &[2]), 1, 0, 9), &s[1..4]);
        assert!(within(range(&s, &[2]), 1, 6, 8).is_empty());
        assert!(within(range(&s, &[3]), 1, 5, 0).is_empty());
        // Galloping forward from the previous range's end finds the same ranges.
        assert_eq!(range_span_from(&s, &[3], 4), (4, 6));
        assert_eq!(range_span_from(&s, &[2, 9], 2), (3, 4));
        assert_eq!(range_span_from(&s, &[4], 6), (6, 6));
        let many: Vec<Tup<1>> = (0..1000).map(|i| [i / 100]).collect();
        for k in 0..10 {
            assert_eq!(range(&many, &[k]).len(), 100);
        }
    }

    #[test]
    fn forward_gallops_match_searches_in_any_lookup_order() {
        let mut seed = 11u64;
        let mut next = || crate::stratum::join::tests::lcg(&mut seed);
        for _ in 0..300 {
            let n = (next() % 200) as usize;
            let k = 1 + next() % 30;
            let mut s: Vec<Tup<3>> = (0..n).map(|_| [next() % k, next() % 4, next()]).collect();
            s.sort_unstable();
            // The previous lookup's range end, as the join's memo keeps it.
            let mut last: Option<(Vec<u64>, usize)> = None;
            for _ in 0..50 {
                let p: Vec<u64> = if next() % 2 == 0 {
                    vec![next() % (k + 1)]
                } else {
                    vec![next() % (k + 1), next() % 5]
                };
                let want = range_span(&s, &p);
                let got = match &last {
                    Some((q, end)) if q.len() == p.len() && p > *q => range_span_from(&s, &p, *end),
                    _ => range_span(&s, &p),
                };
                assert_eq!(got, want, "prefix {p:?}, previous {last:?}");
                assert!(s[want.0..want.1].iter().all(|t| t[..p.len()] == p[..]));
                last = Some((p, want.1));
            }
        }
    }

    #[test]
    fn window_spans_from_the_previous_one_match_fresh_searches() {
        let mut seed = 23u64;
        let mut next = || crate::stratum::join::tests::lcg(&mut seed);
        for _ in 0..300 {
            let n = (next() % 150) as usize;
            let spread = 1 + next() % 100;
            let mut s: Vec<Tup<2>> = (0..n).map(|_| [next() % spread, next()]).collect();
            s.sort_unstable();
            let mut before: Option<((u64, u64), (usize, usize))> = None;
            for _ in 0..40 {
                // Windows mostly moving up, as along a sorted scan, sometimes down or empty.
                let lo = next() % (spread + 10);
                let hi = if next() % 8 == 0 {
                    lo.saturating_sub(1)
                } else {
                    lo + next() % 20
                };
                let want = within_span(&s, 0, lo, hi);
                let got = match before {
                    Some((w, span)) => within_span_from(&s, 0, (lo, hi), span, w),
                    None => want,
                };
                assert_eq!(got, want, "window {lo}..={hi} after {before:?} in {s:?}");
                before = Some(((lo, hi), want));
            }
        }
    }
}
