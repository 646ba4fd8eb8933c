//! Range narrowing and comparison order: which column of an atom comparisons with earlier
//! values bound to a range ([`Narrow`]), and the order the comparisons after an atom run in.

use super::*;

/// A numeric bound: an exact integer, or a float with its slack.
#[derive(Debug, Clone, Copy)]
pub(crate) enum NumBound {
    Int(i64),
    Float(f64, f64),
}

impl NumBound {
    pub(crate) fn of(v: V, slack: f64) -> Option<NumBound> {
        match v {
            V::Int(i) => Some(NumBound::Int(i)),
            V::Float(f) if !f.is_nan() => Some(NumBound::Float(f, slack)),
            _ => None,
        }
    }

    /// The encoded word in a column of `ty` at or below (`lower`) / at or above every value
    /// the bound admits; `None` when no word bounds it (the side is then left open).
    pub(crate) fn word(self, ty: ColType, lower: bool) -> Option<u64> {
        let int = |i: i64| -> Option<u64> {
            match ty {
                ColType::Int => Some(crate::value::enc_int(i)),
                // Times are stored as `u32`: clamp into (and one past) that range.
                ColType::Time => Some(i.clamp(0, i64::from(u32::MAX) + 1) as u64),
                _ => None,
            }
        };
        match (self, ty) {
            (NumBound::Int(i), ColType::Float) => {
                let f = i as f64;
                NumBound::Float(f, f.abs() * 1e-9).word(ty, lower)
            }
            (NumBound::Float(f, slack), ColType::Float) => {
                let w = slack + f64::MIN_POSITIVE + f.abs() * 1e-12;
                let g = if lower { f - w } else { f + w };
                (!g.is_nan()).then(|| crate::value::enc_float(g))
            }
            (NumBound::Int(i), _) => int(i),
            (NumBound::Float(f, slack), _) => {
                // A fractional bound on an integer column: one past it on either side.
                let g = if lower { f - slack } else { f + slack };
                if !g.is_finite() || g.abs() > 4.0e15 {
                    return None;
                }
                int(if lower {
                    g.floor() as i64 - 1
                } else {
                    g.ceil() as i64 + 1
                })
            }
        }
    }
}

/// A column of an atom whose candidates are narrowed to a range by comparisons with values
/// bound before the atom (see [`narrowing`]).
#[derive(Debug, Clone)]
pub struct Narrow {
    /// The atom's column.
    pub col: usize,
    /// Its type (numeric: int, time or float).
    pub ty: ColType,
    /// Lower bounds (inclusive; each one that evaluates applies).
    pub lo: Vec<BoundExpr>,
    /// Upper bounds (inclusive).
    pub hi: Vec<BoundExpr>,
}

impl Narrow {
    /// The inclusive range of encoded words the column may hold under binding `b`; `None`
    /// when it is empty. Every candidate outside it fails a comparison the planner applies
    /// after the atom (which still runs on the candidates inside it).
    pub fn range<const R: usize>(&self, b: &Row<R>) -> Option<(u64, u64)> {
        let mut lo = 0u64;
        let mut hi = u64::MAX;
        for e in &self.lo {
            if let Some(w) = e
                .value_on(b, self.ty, true)
                .and_then(|n| n.word(self.ty, true))
            {
                lo = lo.max(w);
            }
        }
        for e in &self.hi {
            match e.value_on(b, self.ty, false) {
                // An upper bound below every time: nothing qualifies.
                Some(NumBound::Int(i)) if self.ty == ColType::Time && i < 0 => return None,
                Some(n) => {
                    if let Some(w) = n.word(self.ty, false) {
                        hi = hi.min(w);
                    }
                }
                None => {}
            }
        }
        (lo <= hi).then_some((lo, hi))
    }
}

/// Whether an expression reads a slot at or past `from` (a variable the atom binds).
pub(crate) fn reads_new(e: &CExpr, from: usize) -> bool {
    e.any_slot(&mut |s| s >= from)
}

/// The bounds `x op r` puts on slot `x`, when `l` is `x`, `x ± e`, `e - x` or `abs(x - e)`
/// (`abs(e - x)`) and `e`, `r` read only slots below `from`: (lower, upper).
pub(crate) fn solve(
    op: CmpOp,
    l: &CExpr,
    r: &CExpr,
    x: usize,
    from: usize,
) -> Option<(Option<BoundExpr>, Option<BoundExpr>)> {
    if !reads_new(l, from) {
        return solve(op.flipped(), r, l, x, from);
    }
    if reads_new(r, from) {
        return None;
    }
    let is_x = |e: &CExpr| matches!(e, CExpr::Slot(s, _) if *s == x);
    let old = |e: &CExpr| !reads_new(e, from);
    // `x op bound`, as (lower, upper).
    let side = |op: CmpOp, b: BoundExpr| match op {
        CmpOp::Lt => Some((None, Some(b.strict(true)))),
        CmpOp::Gt => Some((Some(b.strict(true)), None)),
        CmpOp::Le => Some((None, Some(b))),
        CmpOp::Ge => Some((Some(b), None)),
        CmpOp::Eq => Some((Some(b.clone()), Some(b))),
        CmpOp::Ne => None,
    };
    match l {
        e if is_x(e) => side(op, BoundExpr::plain(r.clone())),
        CExpr::Bin(BinOp::Sub, a, e) if is_x(a) && old(e) => {
            side(op, BoundExpr::with(r.clone(), BinOp::Add, (**e).clone()))
        }
        CExpr::Bin(BinOp::Sub, e, a) if is_x(a) && old(e) => side(
            op.flipped(),
            BoundExpr::with((**e).clone(), BinOp::Sub, r.clone()),
        ),
        CExpr::Bin(BinOp::Add, a, e) | CExpr::Bin(BinOp::Add, e, a) if is_x(a) && old(e) => {
            side(op, BoundExpr::with(r.clone(), BinOp::Sub, (**e).clone()))
        }
        CExpr::Call(Func::Abs, args) if matches!(op, CmpOp::Lt | CmpOp::Le | CmpOp::Eq) => {
            let e = match args.as_slice() {
                [CExpr::Bin(BinOp::Sub, a, e)] | [CExpr::Bin(BinOp::Sub, e, a)]
                    if is_x(a) && old(e) =>
                {
                    (**e).clone()
                }
                _ => return None,
            };
            // `abs(x - e) < r` excludes both ends of `e - r ..= e + r`.
            let strict = op == CmpOp::Lt;
            Some((
                Some(BoundExpr::with(e.clone(), BinOp::Sub, r.clone()).strict(strict)),
                Some(BoundExpr::with(e, BinOp::Add, r.clone()).strict(strict)),
            ))
        }
        _ => None,
    }
}

/// The range narrowing for an atom just planned: `news` are its (column, slot) new variables
/// (slots from `from` on), `cmps` the comparisons that become ready once it is joined. The
/// column with bounds on both sides (else one side) that comes first is chosen; with it, the
/// positions in `cmps` of the comparisons that bound it.
pub(crate) fn narrowing(
    news: &[(usize, usize)],
    types: &[ColType],
    cmps: &[(CmpOp, CExpr, CExpr)],
    from: usize,
) -> Option<(Narrow, Vec<usize>)> {
    let mut best: Option<(Narrow, Vec<usize>)> = None;
    for &(col, x) in news {
        let ty = *types.get(col)?;
        if !matches!(ty, ColType::Int | ColType::Time | ColType::Float) {
            continue;
        }
        let mut n = Narrow {
            col,
            ty,
            lo: Vec::new(),
            hi: Vec::new(),
        };
        let mut used = Vec::new();
        for (i, (op, l, r)) in cmps.iter().enumerate() {
            if let Some((lo, hi)) = solve(*op, l, r, x, from) {
                n.lo.extend(lo);
                n.hi.extend(hi);
                used.push(i);
            }
        }
        let sides = |n: &Narrow| usize::from(!n.lo.is_empty()) + usize::from(!n.hi.is_empty());
        if sides(&n) > best.as_ref().map_or(0, |(b, _)| sides(b)) {
            best = Some((n, used));
        }
    }
    best
}

/// How early a comparison runs among the comparisons placed after one atom (lower first; the
/// order of a conjunction of checks does not change what passes it, only how soon a
/// candidate that fails is dropped).
pub(crate) fn cmp_rank(op: CmpOp, windowed: bool) -> u8 {
    match (windowed, op) {
        // The atom's range already enforces it, up to the range's ends: it rejects few.
        (true, _) => 2,
        // Most pairs of values differ.
        (false, CmpOp::Ne) => 1,
        (false, _) => 0,
    }
}

/// Places a ready filter after the last atom planned, with its rank (`ranks` stays aligned
/// with each atom's `after`), or before any atom when none is planned yet.
pub(crate) fn place<const R: usize>(
    f: Filter<R>,
    rank: u8,
    atoms: &mut [AtomStep<R>],
    ranks: &mut [Vec<u8>],
    start: &mut Vec<Filter<R>>,
) {
    match (atoms.last_mut(), ranks.last_mut()) {
        (Some(a), Some(r)) => {
            a.after.push(f);
            r.push(rank);
        }
        _ => start.push(f),
    }
}

/// Puts each run of consecutive comparisons in `after` in the order of `ranks` (stable);
/// bindings, negations and aggregates stay where they are, and nothing moves across them.
pub(crate) fn order_comparisons<const R: usize>(after: &mut [Filter<R>], ranks: &[u8]) {
    let is_cmp = |f: &Filter<R>| {
        matches!(
            f,
            Filter::Cmp(..)
                | Filter::CmpRaw(..)
                | Filter::CmpInt(..)
                | Filter::CmpDiff { .. }
                | Filter::CmpText(..)
        )
    };
    let mut i = 0;
    while i < after.len() {
        let mut j = i;
        while j < after.len() && is_cmp(&after[j]) {
            j += 1;
        }
        if j - i > 1 {
            let mut run: Vec<(u8, Filter<R>)> = after[i..j]
                .iter()
                .zip(&ranks[i..j])
                .map(|(f, &r)| (r, f.clone()))
                .collect();
            run.sort_by_key(|(r, _)| *r);
            for (slot, (_, f)) in after[i..j].iter_mut().zip(run) {
                *slot = f;
            }
        }
        i = j.max(i + 1);
    }
}
