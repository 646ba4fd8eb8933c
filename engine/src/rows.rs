//! Stored relations: tuples of one arity packed flat in a `Vec<u64>` (`arity` words a tuple,
//! one word for a nullary relation), so a 2-column tuple costs 16 bytes, not a full-width
//! [`Row`]. Sorting, deduplication, merging and searching are specialised by arity: each
//! dispatches once on the stride to code over `[u64; N]` chunks, which the compiler compares
//! and moves as fixed-size values. No tuple is ever a heap allocation of its own.

use crate::value::Row;

/// A set or bag of tuples of one arity, stored flat.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Rows {
    stride: usize,
    data: Vec<u64>,
}

/// Calls `$f::<N>($args…)` for the stride `N` of `$stride` (1 to [`WIDTH`]), or for a wider
/// stride `wide::$f($stride, $args…)`, the same on slices (relations that wide are rare).
macro_rules! by_stride {
    ($stride:expr, $f:ident ( $($a:expr),* )) => {
        match $stride {
            1 => $f::<1>($($a),*),
            2 => $f::<2>($($a),*),
            3 => $f::<3>($($a),*),
            4 => $f::<4>($($a),*),
            5 => $f::<5>($($a),*),
            6 => $f::<6>($($a),*),
            7 => $f::<7>($($a),*),
            8 => $f::<8>($($a),*),
            9 => $f::<9>($($a),*),
            10 => $f::<10>($($a),*),
            11 => $f::<11>($($a),*),
            12 => $f::<12>($($a),*),
            s => wide::$f(s, $($a),*),
        }
    };
}

fn chunks<const N: usize>(data: &[u64]) -> &[[u64; N]] {
    data.as_chunks::<N>().0
}

/// Slices shorter than this are sorted by comparisons; longer ones by radix.
const RADIX_FROM: usize = 512;

/// Sorts tuples of `N` words by `key` in lexicographic order. Long slices whose words vary
/// in at most 32 bits in all (found in one pass: small numbers such as ids and frame indexes;
/// the padding of a narrow relation in a wide stratum does not vary) are radix sorted
/// (`radsort`) on those bits packed into one `u32`, first word highest (each key computed
/// once, sorted paired with its tuple's index, then the tuples gathered); others by
/// `sort_unstable_by`.
pub(crate) fn sort_by_words<T: Copy, const N: usize>(v: &mut [T], key: impl Fn(&T) -> &[u64; N]) {
    let Some(first) = v.first().map(|t| *key(t)) else {
        return;
    };
    let by_comparison = |v: &mut [T]| v.sort_unstable_by(|a, b| key(a).cmp(key(b)));
    if v.len() < RADIX_FROM {
        return by_comparison(v);
    }
    // One pass: whether the tuples are in order already (a projection onto a prefix of the
    // order they were read in, e.g. `sustained(A, B, S) :- run(A, B, S, T), ...`), and which
    // bits of each word vary.
    let mut differ = [0u64; N];
    let mut sorted = true;
    let mut prev = &first;
    for t in v.iter() {
        let k = key(t);
        sorted &= prev <= k;
        prev = k;
        for ((d, w), f) in differ.iter_mut().zip(k).zip(&first) {
            *d |= w ^ f;
        }
    }
    if sorted {
        return;
    }
    // Per word: how many low bits vary. Above them every tuple holds the same bits, so the
    // order of the low bits is the order of the words. Each varying word's bits go to a shift
    // in one key, the first word highest.
    let bits = differ.map(|d| 64 - d.leading_zeros());
    let total: u32 = bits.iter().sum();
    // Wider keys (floats, timestamps, hashes vary in most of their bits) sorted by radix were
    // slower than by comparison on the real logs: `scenalog mine`'s extract + evaluate took
    // about 10 % longer with radix keys up to 128 bits.
    if total > 32 {
        return by_comparison(v);
    }
    let mut fields = [(0usize, 0u32, 0u64); N];
    let mut m = 0;
    let mut shift = total;
    for (i, &b) in bits.iter().enumerate() {
        if b > 0 {
            shift -= b;
            fields[m] = (i, shift, u64::MAX >> (64 - b));
            m += 1;
        }
    }
    let fields = &fields[..m];
    // Each key is computed once into a pair with the tuple's index, the 8-byte pairs are radix
    // sorted, and the tuples are gathered in their order: radix passes move pairs, not whole
    // tuples, and do not recompute the key each pass.
    if u32::try_from(v.len()).is_err() {
        return by_comparison(v);
    }
    let mut order: Vec<(u32, u32)> = Vec::with_capacity(v.len());
    for (i, t) in v.iter().enumerate() {
        // `i < v.len() <= u32::MAX`, checked above.
        order.push((packed(key(t), fields), i as u32));
    }
    radsort::sort_by_key(&mut order, |&(k, _)| k);
    let sorted: Vec<T> = order.iter().map(|&(_, i)| v[i as usize]).collect();
    v.copy_from_slice(&sorted);
}

/// The varying low bits of each word (`fields`: word, shift, mask; at most 32 bits in all) in
/// one key.
#[inline]
fn packed<const N: usize>(words: &[u64; N], fields: &[(usize, u32, u64)]) -> u32 {
    let mut k: u32 = 0;
    for &(i, shift, mask) in fields {
        // The field fits below bit 32 (`shift + its width <= 32`), so the cast loses nothing.
        k |= ((words[i] & mask) << shift) as u32;
    }
    k
}

/// Sorts tuples of `N` words in lexicographic order (see [`sort_by_words`]).
pub(crate) fn sort_tuples<const N: usize>(v: &mut [[u64; N]]) {
    sort_by_words(v, |t| t);
}

fn sort_dedup_n<const N: usize>(data: &mut Vec<u64>) {
    let (rows, _) = data.as_chunks_mut::<N>();
    sort_tuples(rows);
    let mut w = 0;
    for r in 0..rows.len() {
        if w == 0 || rows[r] != rows[w - 1] {
            rows[w] = rows[r];
            w += 1;
        }
    }
    data.truncate(w * N);
}

fn merge_n<const N: usize>(a: &[u64], b: &[u64]) -> Vec<u64> {
    let (a, b) = (chunks::<N>(a), chunks::<N>(b));
    let mut out: Vec<u64> = Vec::with_capacity((a.len() + b.len()) * N);
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        if a[i] < b[j] {
            out.extend_from_slice(&a[i]);
            i += 1;
        } else {
            out.extend_from_slice(&b[j]);
            j += 1;
        }
    }
    for r in &a[i..] {
        out.extend_from_slice(r);
    }
    for r in &b[j..] {
        out.extend_from_slice(r);
    }
    out
}

/// The part of a sorted slice after every element less than `x` (exponential then binary
/// search from the front, so a sorted sequence of probes walks the slice once).
fn skip_below<'a, const N: usize>(mut s: &'a [[u64; N]], x: &[u64; N]) -> &'a [[u64; N]] {
    if s.first().is_some_and(|f| f < x) {
        let mut step = 1;
        while step < s.len() && s[step] < *x {
            s = &s[step..];
            step <<= 1;
        }
        step >>= 1;
        while step > 0 {
            if step < s.len() && s[step] < *x {
                s = &s[step..];
            }
            step >>= 1;
        }
        s = &s[1..];
    }
    s
}

fn positions_n<const N: usize>(all: &[u64], subset: &[u64]) -> Vec<usize> {
    let all = chunks::<N>(all);
    let mut s = all;
    let mut out = Vec::with_capacity(subset.len() / N);
    for x in chunks::<N>(subset) {
        s = skip_below(s, x);
        out.push(all.len() - s.len());
    }
    out
}

fn contains_n<const N: usize>(data: &[u64], row: &[u64]) -> bool {
    let mut key = [0u64; N];
    key.copy_from_slice(&row[..N]);
    chunks::<N>(data).binary_search(&key).is_ok()
}

fn contains_from_n<const N: usize>(
    data: &[u64],
    row: &[u64],
    hint: &std::sync::atomic::AtomicUsize,
) -> bool {
    use std::sync::atomic::Ordering::Relaxed;
    let mut key = [0u64; N];
    key.copy_from_slice(&row[..N]);
    let rows = chunks::<N>(data);
    let pos = search_from(rows, &key, hint.load(Relaxed));
    hint.store(pos, Relaxed);
    rows.get(pos) == Some(&key)
}

/// The position of the first element of sorted, distinct `s` not below `key`, searched from
/// `hint` (where the previous, usually smaller, key was): every element before `hint` is below
/// the one at `hint`, so when that one is not above `key` the search gallops on from `hint`
/// (a merge when keys come in order), else it bisects the whole slice.
pub(crate) fn search_from<T: Ord>(s: &[T], key: &T, hint: usize) -> usize {
    match s.get(hint) {
        Some(at) if at <= key => hint + gallop(&s[hint..], |x| x < key),
        _ => s.partition_point(|x| x < key),
    }
}

/// The length of the prefix of `s` whose elements satisfy `pred` (which holds for a prefix
/// only), found by doubling steps then bisection.
pub(crate) fn gallop<T>(s: &[T], pred: impl Fn(&T) -> bool) -> usize {
    if s.first().is_none_or(|t| !pred(t)) {
        return 0;
    }
    // Invariant: pred(s[lo]) holds; hi is past the end or fails.
    let mut lo = 0;
    let mut step = 1;
    while lo + step < s.len() && pred(&s[lo + step]) {
        lo += step;
        step <<= 1;
    }
    let mut hi = (lo + step).min(s.len());
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if pred(&s[mid]) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo + 1
}

impl Rows {
    /// An empty set of tuples of `arity` columns.
    pub fn new(arity: usize) -> Rows {
        Rows {
            stride: arity.max(1),
            data: Vec::new(),
        }
    }

    /// Tuples of `arity` columns from their words, in the order given (not sorted).
    pub fn from_flat(arity: usize, data: Vec<u64>) -> Rows {
        let stride = arity.max(1);
        let mut data = data;
        data.truncate(data.len() / stride * stride);
        Rows { stride, data }
    }

    /// Words per stored tuple: the arity, or 1 for a nullary relation.
    pub fn arity(&self) -> usize {
        self.stride
    }

    /// Number of tuples.
    pub fn len(&self) -> usize {
        self.data.len() / self.stride.max(1)
    }

    /// Words stored (tuples × arity: no per-tuple overhead).
    #[cfg(test)]
    pub fn words(&self) -> usize {
        self.data.len()
    }

    /// Whether there are no tuples.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// The `i`th tuple (its stride words: the columns, or one zero for a nullary relation).
    pub fn get(&self, i: usize) -> Option<&[u64]> {
        let s = self.stride;
        self.data.get(i * s..(i + 1) * s)
    }

    /// The tuples in order.
    pub fn iter(&self) -> std::slice::ChunksExact<'_, u64> {
        self.data.chunks_exact(self.stride.max(1))
    }

    /// The tuples as `N`-word arrays, when the arity is `N` (no copy).
    pub(crate) fn as_tuples<const N: usize>(&self) -> Option<&[[u64; N]]> {
        (self.stride == N).then(|| chunks::<N>(&self.data))
    }

    /// Appends the first columns of a full-width row.
    pub fn push<const R: usize>(&mut self, row: &Row<R>) {
        self.data.extend_from_slice(&row[..self.stride]);
    }

    /// A tuple widened to a full row (zeros past the arity).
    pub fn row<const R: usize>(t: &[u64]) -> Row<R> {
        let mut r = [0u64; R];
        r[..t.len()].copy_from_slice(t);
        r
    }

    /// Sorts and removes duplicates.
    pub fn sort_dedup(&mut self) {
        by_stride!(self.stride, sort_dedup_n(&mut self.data));
    }

    /// The sorted union of two sorted sets of the same arity.
    pub fn merge(&self, other: &Rows) -> Rows {
        if self.is_empty() {
            return other.clone();
        }
        Rows {
            stride: self.stride,
            data: by_stride!(self.stride, merge_n(&self.data, &other.data)),
        }
    }

    /// For each tuple of `subset` (sorted, all in `self`), its index in `self` (sorted).
    pub fn positions(&self, subset: &Rows) -> Vec<usize> {
        if subset.is_empty() {
            return Vec::new();
        }
        by_stride!(self.stride, positions_n(&self.data, &subset.data))
    }

    /// The index of tuple `t` in a sorted set.
    pub fn position(&self, t: &[u64]) -> Option<usize> {
        let p = self.positions(&Rows {
            stride: self.stride,
            data: t.get(..self.stride)?.to_vec(),
        });
        let i = *p.first()?;
        (self.get(i)? == &t[..self.stride]).then_some(i)
    }

    /// Appends a tuple of this arity (or longer: the extra words are ignored).
    pub fn push_slice(&mut self, t: &[u64]) {
        self.data.extend_from_slice(&t[..self.stride]);
    }

    /// Whether a sorted set holds the tuple `t` (its first stride words).
    pub fn contains(&self, t: &[u64]) -> bool {
        !self.is_empty()
            && t.len() >= self.stride
            && by_stride!(self.stride, contains_n(&self.data, t))
    }

    /// [`Rows::contains`], searching on from `hint` (where the previous search ended, updated
    /// here) when the tuple there is not above `t`: lookups in ascending order (a negation
    /// checked along a sorted scan) gallop forward instead of searching the whole relation.
    /// The hint only speeds the search; any value gives the same answer.
    pub fn contains_from(&self, t: &[u64], hint: &std::sync::atomic::AtomicUsize) -> bool {
        !self.is_empty()
            && t.len() >= self.stride
            && by_stride!(self.stride, contains_from_n(&self.data, t, hint))
    }
}

/// The operations of [`Rows`] on tuples wider than [`crate::value::WIDTH`] words, on slices of
/// `stride` words (the arrays of the narrow paths would be monomorphised for every width).
mod wide {
    use std::cmp::Ordering;

    fn tuples(data: &[u64], stride: usize) -> impl Iterator<Item = &[u64]> {
        data.chunks_exact(stride)
    }

    fn nth(data: &[u64], stride: usize, i: usize) -> &[u64] {
        &data[i * stride..(i + 1) * stride]
    }

    /// The index of the first tuple not below `key`.
    fn lower_bound(data: &[u64], stride: usize, key: &[u64]) -> usize {
        let (mut lo, mut hi) = (0, data.len() / stride);
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            if nth(data, stride, mid) < key {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        lo
    }

    pub(super) fn sort_dedup_n(stride: usize, data: &mut Vec<u64>) {
        let mut ts: Vec<&[u64]> = tuples(data, stride).collect();
        ts.sort_unstable();
        ts.dedup();
        *data = ts.concat();
    }

    pub(super) fn merge_n(stride: usize, a: &[u64], b: &[u64]) -> Vec<u64> {
        let mut out = Vec::with_capacity(a.len() + b.len());
        let (mut a, mut b) = (tuples(a, stride).peekable(), tuples(b, stride).peekable());
        loop {
            let next = match (a.peek(), b.peek()) {
                (Some(x), Some(y)) if x.cmp(y) == Ordering::Less => a.next(),
                (Some(_), Some(_)) | (None, Some(_)) => b.next(),
                (Some(_), None) => a.next(),
                (None, None) => break,
            };
            out.extend_from_slice(next.unwrap_or_default());
        }
        out
    }

    pub(super) fn positions_n(stride: usize, all: &[u64], subset: &[u64]) -> Vec<usize> {
        tuples(subset, stride)
            .map(|x| lower_bound(all, stride, x))
            .collect()
    }

    pub(super) fn contains_n(stride: usize, data: &[u64], row: &[u64]) -> bool {
        let key = &row[..stride];
        let i = lower_bound(data, stride, key);
        data.get(i * stride..(i + 1) * stride) == Some(key)
    }

    pub(super) fn contains_from_n(
        stride: usize,
        data: &[u64],
        row: &[u64],
        _hint: &std::sync::atomic::AtomicUsize,
    ) -> bool {
        contains_n(stride, data, row)
    }
}

/// Words a stored tuple of relation `name` takes, as [`Rows`] stores it: its arity, or one for
/// a nullary (or unknown) relation.
pub(crate) fn stored_width(
    types: &std::collections::HashMap<String, Vec<scenalog_facts::catalog::ColType>>,
    name: &str,
) -> usize {
    types.get(name).map_or(0, |t| t.len()).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(arity: usize, ts: &[&[u64]]) -> Rows {
        let mut r = Rows::new(arity);
        for t in ts {
            let mut w = t.to_vec();
            w.resize(r.arity().max(t.len()), 0);
            r.push_slice(&w);
        }
        r
    }

    #[test]
    fn sort_dedup_and_merge_by_arity() {
        let mut a = rows(2, &[&[3, 1], &[1, 2], &[3, 1], &[1, 1]]);
        a.sort_dedup();
        assert_eq!(
            a.iter().collect::<Vec<_>>(),
            vec![&[1, 1], &[1, 2], &[3, 1]]
        );
        let mut b = rows(2, &[&[2, 0], &[1, 2]]);
        b.sort_dedup();
        let m = a.merge(&b);
        assert_eq!(m.len(), 5);
        assert!(m.contains(&[2, 0]) && !m.contains(&[2, 1]));
        assert_eq!(a.words(), 2 * a.len());
        let mut unit = rows(0, &[&[], &[]]);
        unit.sort_dedup();
        assert_eq!(unit.len(), 1);
        let mut wide = rows(12, &[&[1; 12], &[0; 12], &[1; 12]]);
        wide.sort_dedup();
        assert_eq!(wide.len(), 2);
    }

    /// Relations wider than the arrays' widths take the slice path: the same sets, unions,
    /// positions and lookups as a sorted set of vectors.
    #[test]
    fn wide_tuples_sort_merge_and_search_as_a_sorted_set_does() {
        use std::collections::BTreeSet;
        let mut seed = 11u64;
        let mut next = || crate::stratum::join::tests::lcg(&mut seed);
        for stride in [13, 20, 64] {
            for _ in 0..20 {
                let mut make = |n: usize| {
                    let ts: Vec<Vec<u64>> = (0..n)
                        .map(|_| (0..stride).map(|c| next() % (2 + c as u64 % 3)).collect())
                        .collect();
                    let mut r = Rows::new(stride);
                    for t in &ts {
                        r.push_slice(t);
                    }
                    r.sort_dedup();
                    (r, ts.into_iter().collect::<BTreeSet<_>>())
                };
                let (a, sa) = make(40);
                let (b, sb) = make(30);
                let listed = |r: &Rows| r.iter().map(<[u64]>::to_vec).collect::<Vec<_>>();
                assert_eq!(listed(&a), sa.iter().cloned().collect::<Vec<_>>());
                let m = a.merge(&b);
                let mut union: Vec<Vec<u64>> = sa.iter().chain(&sb).cloned().collect();
                union.sort();
                assert_eq!(listed(&m), union, "a merge keeps both sides' tuples");
                let hint = std::sync::atomic::AtomicUsize::new(0);
                for (i, t) in a.iter().enumerate() {
                    assert_eq!(a.position(t), Some(i));
                    assert!(a.contains(t) && a.contains_from(t, &hint));
                }
                for t in sb.difference(&sa) {
                    assert!(!a.contains(t) && !a.contains_from(t, &hint));
                    assert_eq!(a.position(t), None);
                }
                assert_eq!(m.positions(&a).len(), a.len());
            }
        }
    }

    #[test]
    fn radix_sorts_order_tuples_as_comparisons_do() {
        let mut seed = 5u64;
        let mut next = || crate::stratum::join::tests::lcg(&mut seed);
        for case in 0..60 {
            // Words of every width: small numbers, encoded ints near zero (high bit set), full
            // 64-bit words (so some cases pass 128 varying bits and sort by comparison), and a
            // constant padding word.
            let n = if case % 3 == 0 {
                100
            } else {
                600 + (next() % 3000) as usize
            };
            let widths = [next() % 65, next() % 65, next() % 65];
            let mut v: Vec<[u64; 4]> = (0..n)
                .map(|_| {
                    let mut t = [0u64; 4];
                    for (w, &b) in t.iter_mut().zip(&widths) {
                        let r = (next() << 31) ^ next();
                        *w = (1 << 63) | if b == 0 { 0 } else { r >> (64 - b.min(62)) };
                        if b == 64 {
                            *w = r.wrapping_mul(0x9e37_79b9_7f4a_7c15);
                        }
                    }
                    t
                })
                .collect();
            let mut want = v.clone();
            want.sort_unstable();
            sort_tuples(&mut v);
            assert_eq!(v, want, "case {case}, widths {widths:?}");
            // In order already (duplicates and all): left as it is; one pair of distinct
            // tuples out of order: sorted again.
            sort_tuples(&mut v);
            assert_eq!(v, want, "case {case}: sorted input");
            if let Some(i) = (1..v.len()).find(|&i| v[i - 1] != v[i]) {
                v.swap(i - 1, i);
                sort_tuples(&mut v);
                assert_eq!(v, want, "case {case}: one swap");
            }
            // Sorting by a key inside another element, as provenance's (tuple, stamp) pairs.
            let mut tagged: Vec<([u64; 4], usize)> = want.iter().rev().copied().zip(0..).collect();
            sort_by_words(&mut tagged, |p| &p.0);
            assert!(tagged.iter().map(|p| p.0).eq(want.iter().copied()));
        }
    }

    #[test]
    fn searches_from_a_hint_find_what_a_fresh_search_finds() {
        let mut seed = 9u64;
        let mut next = || crate::stratum::join::tests::lcg(&mut seed);
        for _ in 0..100 {
            let n = (next() % 300) as usize;
            let mut r = Rows::new(2);
            for _ in 0..n {
                r.push_slice(&[next() % 40, next() % 40]);
            }
            r.sort_dedup();
            let hint = std::sync::atomic::AtomicUsize::new((next() % 400) as usize);
            let mut key = [0u64, 0];
            for _ in 0..200 {
                // Keys mostly ascending, sometimes jumping back.
                key = if next() % 6 == 0 {
                    [next() % 42, next() % 42]
                } else {
                    [key[0] + next() % 2, next() % 42]
                };
                let t = Rows::row::<{ crate::value::WIDTH }>(&key);
                assert_eq!(r.contains_from(&t, &hint), r.contains(&t), "{key:?}");
            }
        }
    }
}
