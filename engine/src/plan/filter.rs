//! The checks and computations run on a binding row ([`Filter<R>`]): comparisons on encoded
//! words or decoded values, bindings, negation lookups ([`NegSet<R>`]), applied in place.

use super::*;

/// The right operand of a comparison on encoded values.
#[derive(Debug, Clone, Copy)]
pub enum Raw {
    /// A bound slot of the same column type as the left operand.
    Slot(usize),
    /// A constant encoded in the left operand's column type.
    Const(u64),
}

/// A check or computation on a binding row.
#[derive(Debug, Clone)]
pub enum Filter<const R: usize> {
    /// A comparison that must hold.
    Cmp(CmpOp, CExpr, CExpr),
    /// A comparison of a slot with a slot or constant of its own type, done on the encoded
    /// words (the encoding preserves each type's order, so no decoding is needed).
    CmpRaw(CmpOp, usize, Raw),
    /// A comparison of two integer expressions.
    CmpInt(CmpOp, IExpr, IExpr),
    /// An order comparison (`<`, `<=`, `>`, `>=`) of strings, by their text.
    CmpText(CmpOp, CExpr, CExpr, Texts),
    /// `a - b op c` (`abs(a - b) op c` with `abs`) on int slots `a`, `b` and a constant:
    /// the common shape of distance and duration checks, evaluated without an expression
    /// tree (the same results as [`Filter::CmpInt`]: an overflow fails the comparison).
    CmpDiff {
        /// The comparison.
        op: CmpOp,
        /// The left slot.
        a: usize,
        /// The right slot.
        b: usize,
        /// Whether the difference's absolute value is compared.
        abs: bool,
        /// The constant.
        c: i64,
    },
    /// `X = expr` binding a new slot.
    Bind(usize, CExpr, ColType),
    /// A negated atom: the key built from the row must not be in the set.
    Neg(Arc<NegSet<R>>),
    /// An aggregate run for each binding (see [`Correlated<R>`]), writing its result to a slot.
    AggRun(Arc<Correlated<R>>, usize),
    /// An aggregate: the group key (outer slots) looks up the encoded result, written to a slot;
    /// a group with no binding gets the default (0 for count and sum, none for min and max).
    Agg {
        /// Slots of the grouping variables.
        group: Vec<usize>,
        /// Encoded result by group key.
        table: Arc<FastMap<Row<R>, u64>>,
        /// Result of an empty group.
        default: Option<u64>,
        /// Slot receiving the result.
        out: usize,
    },
}

impl<const R: usize> Filter<R> {
    /// The slot this filter writes (a binding's or an aggregate's result), if any.
    pub(crate) fn written(&self) -> Option<usize> {
        match self {
            Filter::Bind(s, ..) | Filter::AggRun(_, s) => Some(*s),
            Filter::Agg { out, .. } => Some(*out),
            _ => None,
        }
    }
}

/// The tuples of a negated atom (a completed relation), keyed for lookups by binding.
#[derive(Debug)]
pub struct NegSet<const R: usize> {
    /// How each argument is computed.
    pub(crate) args: Vec<KeyArg>,
    /// When every argument is a wildcard or a slot of its column's own type: the slot of each
    /// other column (the key is then copied, not computed).
    pub(crate) slots: Option<Vec<(usize, usize)>>,
    /// With exactly one such column: its values.
    pub(crate) one: FastSet<u64>,
    /// With no wildcard (and not a one-column set): the relation itself, sorted and distinct,
    /// searched by binary search without building a set.
    pub(crate) rows: Rows,
    /// Otherwise: the tuples, wildcard columns zeroed.
    pub(crate) set: FastSet<Row<R>>,
    /// Where the last search of `rows` ended (see [`Rows::contains_from`]).
    pub(crate) hint: std::sync::atomic::AtomicUsize,
}

impl<const R: usize> NegSet<R> {
    /// With one key column copied from a slot: that slot and the set of values it must not
    /// take.
    pub(crate) fn single(&self) -> Option<(usize, &FastSet<u64>)> {
        match self.slots.as_deref() {
            Some([(_, s)]) => Some((*s, &self.one)),
            _ => None,
        }
    }

    /// Whether the binding's key is in the relation; `None` when an argument fails to
    /// evaluate.
    pub(crate) fn contains(&self, row: &Row<R>) -> Option<bool> {
        if let Some([(_, s)]) = self.slots.as_deref() {
            return Some(self.one.contains(&row[*s]));
        }
        // A value that cannot be stored in its column is in no tuple: the negation holds.
        let Some(key) = self.key(row)? else {
            return Some(false);
        };
        Some(if self.rows.is_empty() {
            self.set.contains(&key)
        } else {
            self.rows.contains_from(&key, &self.hint)
        })
    }

    /// The binding's key in column order, wildcard columns zero: copied from slots when it
    /// can be, else computed. `None` when an argument fails to evaluate, `Some(None)` when a
    /// value cannot be stored in its column.
    pub(crate) fn key(&self, row: &Row<R>) -> Option<Option<Row<R>>> {
        let mut key = [0u64; R];
        if let Some(slots) = self.slots.as_deref() {
            for &(c, s) in slots {
                key[c] = row[s];
            }
            return Some(Some(key));
        }
        for (k, a) in key.iter_mut().zip(&self.args) {
            if let KeyArg::Val(e, ty) = a {
                match e.word(row, *ty)? {
                    Some(v) => *k = v,
                    None => return Some(None),
                }
            }
        }
        Some(Some(key))
    }
}

/// How a negated atom's argument is computed from a binding row.
#[derive(Debug, Clone)]
pub enum KeyArg {
    /// A value computed from the binding (encoded to the column's type).
    Val(CExpr, ColType),
    /// A wildcard: zero in both the key and the stored projection.
    Wild,
}

pub(crate) fn holds(op: CmpOp, ord: std::cmp::Ordering) -> bool {
    match op {
        CmpOp::Lt => ord.is_lt(),
        CmpOp::Le => ord.is_le(),
        CmpOp::Gt => ord.is_gt(),
        CmpOp::Ge => ord.is_ge(),
        CmpOp::Eq => ord.is_eq(),
        CmpOp::Ne => ord.is_ne(),
    }
}

/// The filter for `a op b` in a rule: strings ordered by text ([`Filter::CmpText`]; their
/// encoded words are interning ids, equal exactly when the strings are), anything else as
/// [`cmp_filter`] compiles it.
pub fn compare_filter<const R: usize>(
    op: CmpOp,
    a: CExpr,
    b: CExpr,
    symbols: &Symbols,
) -> Filter<R> {
    let ordering = !matches!(op, CmpOp::Eq | CmpOp::Ne);
    if ordering && (expr_type(&a) == ColType::Str || expr_type(&b) == ColType::Str) {
        return Filter::CmpText(op, a, b, symbols.texts());
    }
    cmp_filter(op, a, b)
}

/// The filter for `a op b`: on encoded words when one side is a slot and the other a slot of
/// the same type or a constant that encodes exactly in that type, else on decoded values.
pub fn cmp_filter<const R: usize>(op: CmpOp, a: CExpr, b: CExpr) -> Filter<R> {
    let raw = |x: &CExpr, y: &CExpr| -> Option<(usize, Raw)> {
        let CExpr::Slot(s, ty) = x else { return None };
        match y {
            CExpr::Slot(t, ty2) if ty2 == ty => Some((*s, Raw::Slot(*t))),
            CExpr::Const(c) => {
                let e = encode(*c, *ty)?;
                (decode(e, *ty).compare(*c) == Some(std::cmp::Ordering::Equal))
                    .then_some((*s, Raw::Const(e)))
            }
            _ => None,
        }
    };
    if let Some((s, r)) = raw(&a, &b) {
        return Filter::CmpRaw(op, s, r);
    }
    if let Some((s, r)) = raw(&b, &a) {
        return Filter::CmpRaw(op.flipped(), s, r);
    }
    if let (Some(x), Some(y)) = (IExpr::from(&a), IExpr::from(&b)) {
        let diff = |op: CmpOp, x: &IExpr, y: &IExpr| {
            let IExpr::Const(c) = *y else { return None };
            match *x {
                IExpr::Diff(a, b) => Some(Filter::CmpDiff {
                    op,
                    a,
                    b,
                    abs: false,
                    c,
                }),
                IExpr::AbsDiff(a, b) => Some(Filter::CmpDiff {
                    op,
                    a,
                    b,
                    abs: true,
                    c,
                }),
                _ => None,
            }
        };
        if let Some(f) = diff(op, &x, &y).or_else(|| diff(op.flipped(), &y, &x)) {
            return f;
        }
        return Filter::CmpInt(op, x, y);
    }
    Filter::Cmp(op, a, b)
}

/// Applies filters in order; `None` if one fails.
pub fn apply<const R: usize>(filters: &[Filter<R>], mut row: Row<R>) -> Option<Row<R>> {
    apply_mut(filters, &mut row).then_some(row)
}

/// Applies filters in order to `row` in place (bindings write their slots); `false` if one
/// fails, the row's later slots then holding partial results.
pub fn apply_mut<const R: usize>(filters: &[Filter<R>], row: &mut Row<R>) -> bool {
    apply_in(filters, row).is_some()
}

/// [`Filter::CmpRaw`] on the two encoded words.
#[inline]
pub(crate) fn raw_holds(op: CmpOp, x: u64, y: u64) -> bool {
    holds(op, x.cmp(&y))
}

/// [`Filter::CmpDiff`] on the two slots' encoded words: `a - b op c` (`abs(a - b) op c`),
/// failing on overflow.
#[inline]
pub(crate) fn diff_holds(op: CmpOp, a: u64, b: u64, abs: bool, c: i64) -> bool {
    let Some(d) = crate::value::dec_int(a).checked_sub(crate::value::dec_int(b)) else {
        return false;
    };
    match if abs { d.checked_abs() } else { Some(d) } {
        Some(d) => holds(op, d.cmp(&c)),
        None => false,
    }
}

pub(crate) fn apply_in<const R: usize>(filters: &[Filter<R>], row: &mut Row<R>) -> Option<()> {
    for f in filters {
        match f {
            Filter::CmpRaw(op, a, b) => {
                let y = match b {
                    Raw::Slot(s) => row[*s],
                    Raw::Const(c) => *c,
                };
                if !raw_holds(*op, row[*a], y) {
                    return None;
                }
            }
            Filter::CmpDiff { op, a, b, abs, c } => {
                if !diff_holds(*op, row[*a], row[*b], *abs, *c) {
                    return None;
                }
            }
            Filter::CmpInt(op, a, b) => {
                if !holds(*op, a.eval(row)?.cmp(&b.eval(row)?)) {
                    return None;
                }
            }
            Filter::Cmp(op, a, b) => {
                let ord = a.eval(row)?.compare(b.eval(row)?)?;
                if !holds(*op, ord) {
                    return None;
                }
            }
            Filter::CmpText(op, a, b, texts) => {
                if !holds(*op, texts.compare(a.eval(row)?, b.eval(row)?)?) {
                    return None;
                }
            }
            Filter::Bind(slot, e, ty) => row[*slot] = e.word(row, *ty)??,
            Filter::Neg(n) => {
                if n.contains(row)? {
                    return None;
                }
            }
            Filter::AggRun(c, out) => row[*out] = c.run(row)?,
            Filter::Agg {
                group,
                table,
                default,
                out,
            } => {
                let mut key = [0u64; R];
                for (i, s) in group.iter().enumerate() {
                    key[i] = row[*s];
                }
                row[*out] = match table.get(&key) {
                    Some(v) => *v,
                    None => (*default)?,
                };
            }
        }
    }
    Some(())
}
