//! Compiling rule bodies into join plans: atom patterns, expressions and filters, with
//! comparisons applied as soon as their variables are bound and atoms joined in order of how
//! many of their arguments are already bound.

use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use scenalog_facts::catalog::ColType;
use scenalog_rules::ast::{
    AggFunc, Aggregate, Atom, BinOp, CmpOp, Expr, ExprKind, Func, Literal, Span,
};

use crate::eval::Limits;
use crate::rows::Rows;
use crate::value::{decode, encode, FastMap, FastSet, Row, Symbols, V, WIDTH};
use crate::EngineError;

/// A compiled expression over a binding row.
#[derive(Debug, Clone)]
pub enum CExpr {
    /// A bound variable's slot and type.
    Slot(usize, ColType),
    /// A constant.
    Const(V),
    /// Unary minus.
    Neg(Box<CExpr>),
    /// Arithmetic.
    Bin(BinOp, Box<CExpr>, Box<CExpr>),
    /// abs, min, max.
    Call(Func, Vec<CExpr>),
}

impl CExpr {
    /// The value encoded into a column of type `ty`: `encode(self.eval(row)?, ty)`, with the
    /// outer `None` when evaluation fails and the inner one when the value cannot be stored
    /// in the column. A slot of the column's own type is copied, and an int or time slot plus
    /// or minus an int constant (`T - 1`, `T + 1`) computed on its word without decoding.
    #[inline]
    pub fn word(&self, row: &Row, ty: ColType) -> Option<Option<u64>> {
        match self {
            // Decoding then encoding a stored word of the same type gives it back.
            CExpr::Slot(s, t) if *t == ty => return Some(Some(row[*s])),
            CExpr::Bin(op @ (BinOp::Add | BinOp::Sub), a, c) => {
                if let (CExpr::Slot(s, from), CExpr::Const(V::Int(c))) = (&**a, &**c) {
                    match (from, ty) {
                        (ColType::Int, ColType::Int) => {
                            let x = crate::value::int_op(*op, crate::value::dec_int(row[*s]), *c)?;
                            return Some(Some(crate::value::enc_int(x)));
                        }
                        (ColType::Time, ColType::Time) => {
                            // A time decodes to its word as an int; stored times fit in u32.
                            let x = crate::value::int_op(*op, row[*s] as i64, *c)?;
                            return Some(u32::try_from(x).ok().map(u64::from));
                        }
                        _ => {}
                    }
                }
            }
            _ => {}
        }
        Some(encode(self.eval(row)?, ty))
    }

    /// Evaluates; `None` on a type error, overflow or division by zero.
    pub fn eval(&self, row: &Row) -> Option<V> {
        match self {
            CExpr::Slot(s, ty) => Some(decode(row[*s], *ty)),
            CExpr::Const(v) => Some(*v),
            CExpr::Neg(e) => match e.eval(row)? {
                V::Int(i) => i.checked_neg().map(V::Int),
                V::Float(f) => Some(V::Float(-f)),
                V::Sym(_) => None,
            },
            CExpr::Bin(op, a, b) => arith(*op, a.eval(row)?, b.eval(row)?),
            CExpr::Call(f, args) => {
                let a = args.first()?.eval(row)?;
                match f {
                    Func::Abs => match a {
                        V::Int(i) => i.checked_abs().map(V::Int),
                        V::Float(x) => Some(V::Float(x.abs())),
                        V::Sym(_) => None,
                    },
                    Func::Min | Func::Max => {
                        let b = args.get(1)?.eval(row)?;
                        let ord = a.compare(b)?;
                        let take_a = (ord.is_le()) == (*f == Func::Min);
                        Some(if take_a { a } else { b })
                    }
                }
            }
        }
    }
}

/// An expression over integer and time slots and integer constants only, evaluated on `i64`
/// without decoding into [`V`] (same results as [`CExpr::eval`] on such expressions: checked
/// arithmetic, `None` on overflow or division by zero).
#[derive(Debug, Clone)]
pub enum IExpr {
    /// An int slot.
    Int(usize),
    /// A time slot.
    Time(usize),
    /// A constant.
    Const(i64),
    /// Unary minus.
    Neg(Box<IExpr>),
    /// `abs`.
    Abs(Box<IExpr>),
    /// Arithmetic.
    Bin(BinOp, Box<IExpr>, Box<IExpr>),
    /// `a - b` of two int slots (a common shape, evaluated in one step).
    Diff(usize, usize),
    /// `abs(a - b)` of two int slots.
    AbsDiff(usize, usize),
}

/// The slots of `a - b` over two int slots.
fn int_diff(e: &CExpr) -> Option<(usize, usize)> {
    match e {
        CExpr::Bin(BinOp::Sub, x, y) => match (&**x, &**y) {
            (CExpr::Slot(p, ColType::Int), CExpr::Slot(q, ColType::Int)) => Some((*p, *q)),
            _ => None,
        },
        _ => None,
    }
}

impl IExpr {
    /// The integer form of an expression, when it is one.
    pub fn from(e: &CExpr) -> Option<IExpr> {
        let b = |e: &CExpr| IExpr::from(e).map(Box::new);
        Some(match e {
            CExpr::Slot(s, ColType::Int) => IExpr::Int(*s),
            CExpr::Slot(s, ColType::Time) => IExpr::Time(*s),
            CExpr::Const(V::Int(i)) => IExpr::Const(*i),
            CExpr::Neg(a) => IExpr::Neg(b(a)?),
            CExpr::Bin(op, x, y) => match int_diff(e) {
                Some((p, q)) => IExpr::Diff(p, q),
                None => IExpr::Bin(*op, b(x)?, b(y)?),
            },
            CExpr::Call(Func::Abs, args) if args.len() == 1 => {
                match args.first().and_then(int_diff) {
                    Some((p, q)) => IExpr::AbsDiff(p, q),
                    None => IExpr::Abs(b(args.first()?)?),
                }
            }
            _ => return None,
        })
    }

    /// Evaluates; `None` on overflow or division by zero.
    pub fn eval(&self, row: &Row) -> Option<i64> {
        match self {
            IExpr::Int(s) => Some(crate::value::dec_int(row[*s])),
            IExpr::Time(s) => Some(row[*s] as i64),
            IExpr::Const(i) => Some(*i),
            IExpr::Neg(a) => a.eval(row)?.checked_neg(),
            IExpr::Abs(a) => a.eval(row)?.checked_abs(),
            IExpr::Diff(a, b) => {
                crate::value::dec_int(row[*a]).checked_sub(crate::value::dec_int(row[*b]))
            }
            IExpr::AbsDiff(a, b) => crate::value::dec_int(row[*a])
                .checked_sub(crate::value::dec_int(row[*b]))?
                .checked_abs(),
            IExpr::Bin(op, a, b) => crate::value::int_op(*op, a.eval(row)?, b.eval(row)?),
        }
    }
}

fn arith(op: BinOp, a: V, b: V) -> Option<V> {
    match (a, b) {
        (V::Int(x), V::Int(y)) => crate::value::int_op(op, x, y).map(V::Int),
        (V::Sym(_), _) | (_, V::Sym(_)) => None,
        (a, b) => crate::value::float_op(op, to_f(a), to_f(b)).map(V::Float),
    }
}

fn to_f(v: V) -> f64 {
    match v {
        V::Int(i) => i as f64,
        V::Float(f) => f,
        V::Sym(_) => f64::NAN,
    }
}

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
pub enum Filter {
    /// A comparison that must hold.
    Cmp(CmpOp, CExpr, CExpr),
    /// A comparison of a slot with a slot or constant of its own type, done on the encoded
    /// words (the encoding preserves each type's order, so no decoding is needed).
    CmpRaw(CmpOp, usize, Raw),
    /// A comparison of two integer expressions.
    CmpInt(CmpOp, IExpr, IExpr),
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
    Neg(Arc<NegSet>),
    /// An aggregate run for each binding (see [`Correlated`]), writing its result to a slot.
    AggRun(Arc<Correlated>, usize),
    /// An aggregate: the group key (outer slots) looks up the encoded result, written to a slot;
    /// a group with no binding gets the default (0 for count and sum, none for min and max).
    Agg {
        /// Slots of the grouping variables.
        group: Vec<usize>,
        /// Encoded result by group key.
        table: Arc<FastMap<Row, u64>>,
        /// Result of an empty group.
        default: Option<u64>,
        /// Slot receiving the result.
        out: usize,
    },
}

/// The tuples of a negated atom (a completed relation), keyed for lookups by binding.
#[derive(Debug)]
pub struct NegSet {
    /// How each argument is computed.
    args: Vec<KeyArg>,
    /// When every argument is a wildcard or a slot of its column's own type: the slot of each
    /// other column (the key is then copied, not computed).
    slots: Option<Vec<(usize, usize)>>,
    /// With exactly one such column: its values.
    one: FastSet<u64>,
    /// With no wildcard (and not a one-column set): the relation itself, sorted and distinct,
    /// searched by binary search without building a set.
    rows: Rows,
    /// Otherwise: the tuples, wildcard columns zeroed.
    set: FastSet<Row>,
    /// Where the last search of `rows` ended (see [`Rows::contains_from`]).
    hint: std::sync::atomic::AtomicUsize,
}

impl NegSet {
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
    fn contains(&self, row: &Row) -> Option<bool> {
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
    fn key(&self, row: &Row) -> Option<Option<Row>> {
        let mut key = [0u64; WIDTH];
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

fn holds(op: CmpOp, ord: std::cmp::Ordering) -> bool {
    match op {
        CmpOp::Lt => ord.is_lt(),
        CmpOp::Le => ord.is_le(),
        CmpOp::Gt => ord.is_gt(),
        CmpOp::Ge => ord.is_ge(),
        CmpOp::Eq => ord.is_eq(),
        CmpOp::Ne => ord.is_ne(),
    }
}

/// The comparison with its sides swapped (`a < b` is `b > a`).
pub(crate) fn flipped(op: CmpOp) -> CmpOp {
    match op {
        CmpOp::Lt => CmpOp::Gt,
        CmpOp::Le => CmpOp::Ge,
        CmpOp::Gt => CmpOp::Lt,
        CmpOp::Ge => CmpOp::Le,
        other => other,
    }
}

/// The filter for `a op b`: on encoded words when one side is a slot and the other a slot of
/// the same type or a constant that encodes exactly in that type, else on decoded values.
pub fn cmp_filter(op: CmpOp, a: CExpr, b: CExpr) -> Filter {
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
        return Filter::CmpRaw(flipped(op), s, r);
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
        if let Some(f) = diff(op, &x, &y).or_else(|| diff(flipped(op), &y, &x)) {
            return f;
        }
        return Filter::CmpInt(op, x, y);
    }
    Filter::Cmp(op, a, b)
}

/// Applies filters in order; `None` if one fails.
pub fn apply(filters: &[Filter], mut row: Row) -> Option<Row> {
    apply_mut(filters, &mut row).then_some(row)
}

/// Applies filters in order to `row` in place (bindings write their slots); `false` if one
/// fails, the row's later slots then holding partial results.
pub fn apply_mut(filters: &[Filter], row: &mut Row) -> bool {
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

fn apply_in(filters: &[Filter], row: &mut Row) -> Option<()> {
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
                let mut key = [0u64; WIDTH];
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

/// An atom argument relative to what is bound before the atom is joined.
#[derive(Debug, Clone)]
pub enum Arg {
    /// Must equal this encoded constant.
    Const(u64),
    /// Must equal a value computed from the binding (a join key).
    Key(CExpr, ColType),
    /// Binds a new slot.
    New(usize),
    /// Must equal the column that first bound this slot in the same atom.
    Same(usize),
    /// Ignored.
    Wild,
}

/// One atom to join.
#[derive(Debug, Clone)]
pub struct AtomStep {
    /// The predicate.
    pub pred: String,
    /// One per column.
    pub args: Vec<Arg>,
    /// Filters to apply after this atom is joined.
    pub after: Vec<Filter>,
    /// Derived from `args`: (column, slot) of each new variable.
    pub(crate) news: Vec<(usize, usize)>,
    /// Derived from `args`: the key columns, in order.
    pub(crate) keys: Vec<usize>,
    /// Derived from `args`: (column, constant) selections.
    pub(crate) consts: Vec<(usize, u64)>,
    /// Derived from `args`: (column, column that first bound the same variable) equalities.
    pub(crate) sames: Vec<(usize, usize)>,
    /// A new column whose candidates the comparisons after the atom bound by values known
    /// before it (`T2 > T1, T2 - T1 <= 10`): the join reads that column's range only.
    pub narrow: Option<Narrow>,
    /// The body literal this atom is (its index among the body's literals): the same in
    /// every plan of one clause, whatever the join order.
    pub lit: usize,
}

impl AtomStep {
    /// A step joining `pred` with these arguments, then applying `after`.
    pub fn new(pred: String, args: Vec<Arg>, after: Vec<Filter>) -> AtomStep {
        let mut news = Vec::new();
        let mut keys = Vec::new();
        let mut consts = Vec::new();
        let mut sames = Vec::new();
        for (i, a) in args.iter().enumerate() {
            match a {
                Arg::New(s) => news.push((i, *s)),
                Arg::Key(..) => keys.push(i),
                Arg::Const(c) => consts.push((i, *c)),
                Arg::Same(slot) => {
                    let first = args
                        .iter()
                        .position(|b| matches!(b, Arg::New(s) if s == slot))
                        .unwrap_or(i);
                    sames.push((i, first));
                }
                Arg::Wild => {}
            }
        }
        AtomStep {
            pred,
            args,
            after,
            news,
            keys,
            consts,
            sames,
            narrow: None,
            lit: 0,
        }
    }

    /// Whether a stored tuple passes the atom's constants and repeated variables.
    pub fn selects(&self, t: &[u64]) -> bool {
        self.consts.iter().all(|&(i, c)| t[i] == c) && self.sames.iter().all(|&(i, j)| t[i] == t[j])
    }

    /// The binding row extended with the atom's new variables.
    pub fn extend(&self, mut b: Row, t: &[u64]) -> Row {
        for &(i, s) in &self.news {
            b[s] = t[i];
        }
        b
    }

    /// The join key of a stored tuple (its key columns).
    pub fn tuple_key(&self, t: &[u64]) -> Row {
        let mut k = [0u64; WIDTH];
        for (n, &i) in self.keys.iter().enumerate() {
            k[n] = t[i];
        }
        k
    }

    /// The join key computed from a binding row, written to `out` (one word per key column);
    /// `false` if a value does not fit its column ([`AtomStep::binding_key`] writes it into a row).
    pub fn key_into(&self, b: &Row, out: &mut [u64]) -> bool {
        for (o, &c) in out.iter_mut().zip(&self.keys) {
            let Some(Arg::Key(e, ty)) = self.args.get(c) else {
                return false;
            };
            *o = match e.word(b, *ty) {
                Some(Some(w)) => w,
                _ => return false,
            };
        }
        true
    }

    /// The join key computed from a binding row; `None` if a value does not fit its column.
    pub fn binding_key(&self, b: &Row) -> Option<Row> {
        let mut k = [0u64; WIDTH];
        self.key_into(b, &mut k[..self.keys.len()]).then_some(k)
    }
}

/// One side of a column bound: `base`, or `base + off` / `base - off`, evaluated on the binding
/// before the atom is joined.
#[derive(Debug, Clone)]
pub struct BoundExpr {
    /// The value, or the left operand.
    pub base: CExpr,
    /// The operator (`Add` or `Sub`) and right operand, if any.
    pub off: Option<(BinOp, CExpr)>,
    /// Whether the comparison excludes the bound itself (`<`, `>`): on an int or time column
    /// an integer bound then moves one step inward.
    pub strict: bool,
}

impl BoundExpr {
    fn plain(base: CExpr) -> BoundExpr {
        BoundExpr {
            base,
            off: None,
            strict: false,
        }
    }

    fn with(base: CExpr, op: BinOp, off: CExpr) -> BoundExpr {
        BoundExpr {
            base,
            off: Some((op, off)),
            strict: false,
        }
    }

    fn strict(self, strict: bool) -> BoundExpr {
        BoundExpr { strict, ..self }
    }

    /// The bound as a number; floats come with the slack their rounding needs (the
    /// comparison computes `X - E` where the bound computes `E + C`), so the range is never
    /// narrower than what the filter accepts.
    fn value(&self, row: &Row) -> Option<Num> {
        // Int slots and int constants, alone or one plus or minus the other (`XA - 100`,
        // `300 + XA`): read directly, with the results of the general path.
        let int = |e: &CExpr| match e {
            CExpr::Slot(s, ColType::Int) => row.get(*s).map(|w| crate::value::dec_int(*w)),
            CExpr::Const(V::Int(c)) => Some(*c),
            _ => None,
        };
        if let Some(x) = int(&self.base) {
            match &self.off {
                None => return Some(Num::Int(x)),
                Some((op @ (BinOp::Add | BinOp::Sub), e)) => {
                    if let Some(y) = int(e) {
                        return crate::value::int_op(*op, x, y).map(Num::Int);
                    }
                }
                Some(_) => {}
            }
        }
        self.value_of_exprs(row)
    }

    /// [`BoundExpr::value`] moved one step inward when the bound is strict and integer and
    /// the column holds integers (`x > 5` is `x >= 6` there); a float bound, or one at the
    /// end of the `i64` range, stays inclusive, which admits a superset.
    fn value_on(&self, row: &Row, ty: ColType, lower: bool) -> Option<Num> {
        match self.value(row)? {
            Num::Int(i) if self.strict && matches!(ty, ColType::Int | ColType::Time) => {
                let step = if lower {
                    i.checked_add(1)
                } else {
                    i.checked_sub(1)
                };
                Some(Num::Int(step.unwrap_or(i)))
            }
            n => Some(n),
        }
    }

    /// [`BoundExpr::value`] through the expressions.
    fn value_of_exprs(&self, row: &Row) -> Option<Num> {
        let a = self.base.eval(row)?;
        let Some((op, e)) = &self.off else {
            return Num::of(a, 0.0);
        };
        let b = e.eval(row)?;
        let slack = 1e-9 * (a.as_f64()?.abs() + b.as_f64()?.abs());
        Num::of(arith(*op, a, b)?, slack)
    }
}

/// A numeric bound: an exact integer, or a float with its slack.
#[derive(Debug, Clone, Copy)]
enum Num {
    Int(i64),
    Float(f64, f64),
}

impl Num {
    fn of(v: V, slack: f64) -> Option<Num> {
        match v {
            V::Int(i) => Some(Num::Int(i)),
            V::Float(f) if !f.is_nan() => Some(Num::Float(f, slack)),
            _ => None,
        }
    }

    /// The encoded word in a column of `ty` at or below (`lower`) / at or above every value
    /// the bound admits; `None` when no word bounds it (the side is then left open).
    fn word(self, ty: ColType, lower: bool) -> Option<u64> {
        let int = |i: i64| -> Option<u64> {
            match ty {
                ColType::Int => Some(crate::value::enc_int(i)),
                // Times are stored as `u32`: clamp into (and one past) that range.
                ColType::Time => Some(i.clamp(0, i64::from(u32::MAX) + 1) as u64),
                _ => None,
            }
        };
        match (self, ty) {
            (Num::Int(i), ColType::Float) => {
                let f = i as f64;
                Num::Float(f, f.abs() * 1e-9).word(ty, lower)
            }
            (Num::Float(f, slack), ColType::Float) => {
                let w = slack + f64::MIN_POSITIVE + f.abs() * 1e-12;
                let g = if lower { f - w } else { f + w };
                (!g.is_nan()).then(|| crate::value::enc_float(g))
            }
            (Num::Int(i), _) => int(i),
            (Num::Float(f, slack), _) => {
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
    pub fn range(&self, b: &Row) -> Option<(u64, u64)> {
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
                Some(Num::Int(i)) if self.ty == ColType::Time && i < 0 => return None,
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
fn reads_new(e: &CExpr, from: usize) -> bool {
    match e {
        CExpr::Slot(s, _) => *s >= from,
        CExpr::Const(_) => false,
        CExpr::Neg(a) => reads_new(a, from),
        CExpr::Bin(_, a, b) => reads_new(a, from) || reads_new(b, from),
        CExpr::Call(_, args) => args.iter().any(|a| reads_new(a, from)),
    }
}

/// The bounds `x op r` puts on slot `x`, when `l` is `x`, `x ± e`, `e - x` or `abs(x - e)`
/// (`abs(e - x)`) and `e`, `r` read only slots below `from`: (lower, upper).
fn solve(
    op: CmpOp,
    l: &CExpr,
    r: &CExpr,
    x: usize,
    from: usize,
) -> Option<(Option<BoundExpr>, Option<BoundExpr>)> {
    if !reads_new(l, from) {
        return solve(flipped(op), r, l, x, from);
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
            flipped(op),
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
fn narrowing(
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
fn cmp_rank(op: CmpOp, windowed: bool) -> u8 {
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
fn place(
    f: Filter,
    rank: u8,
    atoms: &mut [AtomStep],
    ranks: &mut [Vec<u8>],
    start: &mut Vec<Filter>,
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
fn order_comparisons(after: &mut [Filter], ranks: &[u8]) {
    let is_cmp = |f: &Filter| {
        matches!(
            f,
            Filter::Cmp(..) | Filter::CmpRaw(..) | Filter::CmpInt(..) | Filter::CmpDiff { .. }
        )
    };
    let mut i = 0;
    while i < after.len() {
        let mut j = i;
        while j < after.len() && is_cmp(&after[j]) {
            j += 1;
        }
        if j - i > 1 {
            let mut run: Vec<(u8, Filter)> = after[i..j]
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

/// A compiled body: filters on the empty binding, then atoms in join order, then a projection.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Filters before any atom (bodies without atoms, constant comparisons).
    pub start: Vec<Filter>,
    /// Atoms in join order, each with the filters that become ready after it.
    pub atoms: Vec<AtomStep>,
    /// The output row: one expression per column, with its type.
    pub head: Vec<(CExpr, ColType)>,
}

impl Plan {
    /// Whether a correlated `sum` of this plan (or of an aggregate nested in it) overflowed
    /// the 64-bit integer range while it ran.
    pub fn sum_overflowed(&self) -> bool {
        let filters = self
            .start
            .iter()
            .chain(self.atoms.iter().flat_map(|a| &a.after));
        filters.into_iter().any(|f| match f {
            Filter::AggRun(c, _) => {
                c.overflowed.load(std::sync::atomic::Ordering::Relaxed) || c.plan.sum_overflowed()
            }
            _ => false,
        })
    }

    /// The output row of a complete binding.
    pub fn project(&self, b: &Row) -> Option<Row> {
        let mut out = [0u64; WIDTH];
        for (i, (e, ty)) in self.head.iter().enumerate() {
            out[i] = e.word(b, *ty)??;
        }
        Some(out)
    }
}

/// What the planner needs to know about the program's relations.
pub struct Ctx<'a> {
    /// Column types by predicate.
    pub types: &'a HashMap<String, Vec<ColType>>,
    /// Completed relations (for negation sets).
    pub complete: &'a HashMap<String, Rows>,
    /// Symbols.
    pub symbols: &'a mut Symbols,
    /// Limits for evaluating aggregate bodies.
    pub limits: &'a Limits<'a>,
}

/// Variables collected from expressions.
pub fn expr_vars<'e>(e: &'e Expr, out: &mut Vec<&'e str>) {
    match &e.kind {
        ExprKind::Var(v) => out.push(v),
        ExprKind::Neg(a) => expr_vars(a, out),
        ExprKind::Binary(_, a, b) => {
            expr_vars(a, out);
            expr_vars(b, out);
        }
        ExprKind::Call(_, args) => args.iter().for_each(|a| expr_vars(a, out)),
        _ => {}
    }
}

struct Scope {
    slots: HashMap<String, (usize, ColType)>,
}

impl Scope {
    fn bound(&self, e: &Expr) -> bool {
        let mut vs = Vec::new();
        expr_vars(e, &mut vs);
        vs.iter().all(|v| self.slots.contains_key(*v))
    }

    fn new_slot(&mut self, name: &str, ty: ColType) -> Result<usize, EngineError> {
        let s = self.slots.len();
        if s >= WIDTH {
            return Err(EngineError::Unsupported(format!(
                "a rule has more than {WIDTH} variables"
            )));
        }
        self.slots.insert(name.to_string(), (s, ty));
        Ok(s)
    }
}

fn compile_expr(e: &Expr, scope: &Scope, symbols: &mut Symbols) -> Result<CExpr, EngineError> {
    Ok(match &e.kind {
        ExprKind::Var(v) => {
            let (s, ty) = scope.slots.get(v).ok_or_else(|| {
                EngineError::Unsupported(format!("variable `{v}` used before it is bound"))
            })?;
            CExpr::Slot(*s, *ty)
        }
        ExprKind::Wildcard => {
            return Err(EngineError::Unsupported("`_` in an expression".to_string()))
        }
        ExprKind::Str(s) => CExpr::Const(V::Sym(symbols.intern(s))),
        ExprKind::Int(i) => CExpr::Const(V::Int(*i)),
        ExprKind::Float(f) => CExpr::Const(V::Float(*f)),
        ExprKind::Neg(a) => CExpr::Neg(Box::new(compile_expr(a, scope, symbols)?)),
        ExprKind::Binary(op, a, b) => CExpr::Bin(
            *op,
            Box::new(compile_expr(a, scope, symbols)?),
            Box::new(compile_expr(b, scope, symbols)?),
        ),
        ExprKind::Call(f, args) => CExpr::Call(
            *f,
            args.iter()
                .map(|a| compile_expr(a, scope, symbols))
                .collect::<Result<_, _>>()?,
        ),
    })
}

/// The type of an expression's value.
pub fn expr_type(e: &CExpr) -> ColType {
    match e {
        CExpr::Slot(_, t) => *t,
        CExpr::Const(V::Int(_)) => ColType::Int,
        CExpr::Const(V::Float(_)) => ColType::Float,
        CExpr::Const(V::Sym(_)) => ColType::Str,
        CExpr::Neg(a) => expr_type(a),
        CExpr::Bin(_, a, b) => join_types(expr_type(a), expr_type(b)),
        CExpr::Call(_, args) => match args.as_slice() {
            [a, b, ..] => join_types(expr_type(a), expr_type(b)),
            [a] => expr_type(a),
            [] => ColType::Int,
        },
    }
}

fn join_types(a: ColType, b: ColType) -> ColType {
    match (a, b) {
        (ColType::Float, _) | (_, ColType::Float) => ColType::Float,
        (ColType::Time, _) | (_, ColType::Time) => ColType::Time,
        (t, _) => t,
    }
}

/// A body literal the planner schedules (aggregates are rewritten to atoms beforehand).
pub enum BodyLit<'a> {
    /// A positive atom.
    Pos(&'a Atom),
    /// A negated atom.
    Neg(&'a Atom),
    /// A comparison or binding.
    Cmp(CmpOp, &'a Expr, &'a Expr),
    /// An aggregate over completed relations.
    Agg(&'a Aggregate),
}

/// Collects the literals of a body.
pub fn body_lits(body: &[Literal]) -> Vec<BodyLit<'_>> {
    body.iter()
        .map(|l| match l {
            Literal::Pos(a) => BodyLit::Pos(a),
            Literal::Neg(a, _) => BodyLit::Neg(a),
            Literal::Cmp(c) => BodyLit::Cmp(c.op, &c.lhs, &c.rhs),
            Literal::Agg(g) => BodyLit::Agg(g),
        })
        .collect()
}

/// Plans a body and a head (output expressions; `head_types` gives the output column types,
/// `None` to infer them from the expressions).
pub fn plan(
    lits: &[BodyLit<'_>],
    head: &[Expr],
    head_types: Option<&[ColType]>,
    ctx: &mut Ctx<'_>,
) -> Result<Plan, EngineError> {
    plan_seeded(lits, head, head_types, ctx, &[], None)
}

/// [`plan`] with the positive atom `lits[first]` joined first (the semi-naive variant that
/// reads that atom's recent tuples scans them and looks the other atoms up).
pub fn plan_first(
    lits: &[BodyLit<'_>],
    head: &[Expr],
    head_types: Option<&[ColType]>,
    ctx: &mut Ctx<'_>,
    first: usize,
) -> Result<Plan, EngineError> {
    plan_seeded(lits, head, head_types, ctx, &[], Some(first))
}

/// The tuple a ground fact's head derives (`None` if a value cannot be stored in its column),
/// computed as the plan of a body-less clause would ([`plan`] then [`Plan::project`]), without
/// building the plan. `head_types` gives the column types, `None` to infer them.
pub(crate) fn ground_head(
    head: &[Expr],
    head_types: Option<&[ColType]>,
    symbols: &mut Symbols,
) -> Result<Option<Row>, EngineError> {
    let scope = Scope {
        slots: HashMap::new(),
    };
    let empty = [0u64; WIDTH];
    let mut out = [0u64; WIDTH];
    for (i, e) in head.iter().enumerate() {
        // A literal (`3`, `-2`, `1.5`, `"BUS"`: nearly every argument of a fact) is its value;
        // anything else is compiled and evaluated as a plan would.
        let value = match literal(e, symbols) {
            Some(v) => v,
            None => {
                let Some(v) = compile_expr(e, &scope, symbols)?.eval(&empty) else {
                    return Ok(None);
                };
                v
            }
        };
        let ty = match head_types {
            Some(t) => t.get(i).copied().unwrap_or(ColType::Int),
            None => expr_type(&CExpr::Const(value)),
        };
        let Some(word) = out.get_mut(i) else {
            return Ok(None);
        };
        match encode(value, ty) {
            Some(w) => *word = w,
            None => return Ok(None),
        }
    }
    Ok(Some(out))
}

/// The value of a literal or a negated number literal, as [`compile_expr`] then
/// [`CExpr::eval`] would compute it; `None` for any other expression (and for a negation that
/// overflows, which the general path then reports the same way).
fn literal(e: &Expr, symbols: &mut Symbols) -> Option<V> {
    match &e.kind {
        ExprKind::Int(i) => Some(V::Int(*i)),
        ExprKind::Float(f) => Some(V::Float(*f)),
        ExprKind::Str(s) => Some(V::Sym(symbols.intern(s))),
        ExprKind::Neg(a) => match &a.kind {
            ExprKind::Int(i) => i.checked_neg().map(V::Int),
            ExprKind::Float(f) => Some(V::Float(-f)),
            _ => None,
        },
        _ => None,
    }
}

/// [`plan`] with variables already bound, in slots `0..seed.len()`.
fn plan_seeded(
    lits: &[BodyLit<'_>],
    head: &[Expr],
    head_types: Option<&[ColType]>,
    ctx: &mut Ctx<'_>,
    seed: &[(&str, ColType)],
    first: Option<usize>,
) -> Result<Plan, EngineError> {
    if lits.is_empty() && seed.is_empty() {
        // A ground fact (or a head over no body): nothing to schedule.
        let scope = Scope {
            slots: HashMap::new(),
        };
        let mut out = Vec::new();
        for (i, e) in head.iter().enumerate() {
            let ce = compile_expr(e, &scope, ctx.symbols)?;
            let ty = match head_types {
                Some(t) => t.get(i).copied().unwrap_or(ColType::Int),
                None => expr_type(&ce),
            };
            out.push((ce, ty));
        }
        return Ok(Plan {
            start: Vec::new(),
            atoms: Vec::new(),
            head: out,
        });
    }
    let mut scope = Scope {
        slots: HashMap::new(),
    };
    for (v, ty) in seed {
        scope.new_slot(v, *ty)?;
    }
    let mut done = vec![false; lits.len()];
    let mut outer: HashSet<&str> = HashSet::new();
    {
        let mut vs = Vec::new();
        for e in head {
            expr_vars(e, &mut vs);
        }
        for l in lits {
            match l {
                BodyLit::Pos(a) | BodyLit::Neg(a) => {
                    a.args.iter().for_each(|e| expr_vars(e, &mut vs))
                }
                BodyLit::Cmp(_, a, b) => {
                    expr_vars(a, &mut vs);
                    expr_vars(b, &mut vs);
                }
                BodyLit::Agg(g) => expr_vars(&g.result, &mut vs),
            }
        }
        outer.extend(vs);
    }
    let mut start = Vec::new();
    let mut atoms: Vec<AtomStep> = Vec::new();
    // Per atom, per filter after it: its rank among comparisons (see `cmp_rank`); the body
    // literals whose comparisons bound an atom's range.
    let mut ranks: Vec<Vec<u8>> = Vec::new();
    let mut windowed: HashSet<usize> = HashSet::new();
    loop {
        // Ready filters first (comparisons, bindings, negations).
        let mut progress = true;
        while progress {
            progress = false;
            for (i, l) in lits.iter().enumerate() {
                if done[i] {
                    continue;
                }
                let f = match l {
                    BodyLit::Cmp(op, a, b) => {
                        if scope.bound(a) && scope.bound(b) {
                            Some(cmp_filter(
                                *op,
                                compile_expr(a, &scope, ctx.symbols)?,
                                compile_expr(b, &scope, ctx.symbols)?,
                            ))
                        } else if *op == CmpOp::Eq {
                            let (var, e) = match (a.as_var(), b.as_var()) {
                                (Some(v), _) if !scope.slots.contains_key(v) && scope.bound(b) => {
                                    (v, b)
                                }
                                (_, Some(v)) if !scope.slots.contains_key(v) && scope.bound(a) => {
                                    (v, a)
                                }
                                _ => continue,
                            };
                            let ce = compile_expr(e, &scope, ctx.symbols)?;
                            let ty = expr_type(&ce);
                            let s = scope.new_slot(var, ty)?;
                            Some(Filter::Bind(s, ce, ty))
                        } else {
                            None
                        }
                    }
                    BodyLit::Neg(a) => {
                        let ready = a
                            .args
                            .iter()
                            .all(|e| matches!(e.kind, ExprKind::Wildcard) || scope.bound(e));
                        if ready {
                            Some(neg_filter(a, &scope, ctx)?)
                        } else {
                            None
                        }
                    }
                    BodyLit::Agg(g) => {
                        let group: Vec<&str> = agg_vars(g)
                            .into_iter()
                            .filter(|v| outer.contains(v))
                            .collect();
                        if group.iter().all(|v| scope.slots.contains_key(*v)) {
                            let (f, extra) = agg_filter(g, &group, &mut scope, ctx)?;
                            if let Some(x) = extra {
                                place(f, 0, &mut atoms, &mut ranks, &mut start);
                                Some(x)
                            } else {
                                Some(f)
                            }
                        } else {
                            None
                        }
                    }
                    BodyLit::Pos(_) => None,
                };
                if let Some(f) = f {
                    done[i] = true;
                    progress = true;
                    let rank = match l {
                        BodyLit::Cmp(op, ..) => cmp_rank(*op, windowed.contains(&i)),
                        _ => 0,
                    };
                    place(f, rank, &mut atoms, &mut ranks, &mut start);
                }
            }
        }
        // Next atom: the one with most bound or constant arguments.
        let mut best: Option<(usize, usize)> = None;
        for (i, l) in lits.iter().enumerate() {
            if let (false, BodyLit::Pos(a)) = (done[i], l) {
                let score = a
                    .args
                    .iter()
                    .filter(|e| !matches!(e.kind, ExprKind::Wildcard) && scope.bound(e))
                    .count();
                let forced = atoms.is_empty() && first == Some(i);
                if forced || best.is_none_or(|(_, s)| score > s) {
                    best = Some((i, if forced { usize::MAX } else { score }));
                }
            }
        }
        let Some((i, _)) = best else { break };
        done[i] = true;
        let BodyLit::Pos(a) = lits[i] else { break };
        let types = ctx.types.get(&a.pred).cloned().unwrap_or_default();
        if types.len() != a.args.len() {
            return Err(EngineError::Unsupported(format!(
                "`{}` used with {} arguments but has {} columns",
                a.pred,
                a.args.len(),
                types.len()
            )));
        }
        let from = scope.slots.len();
        let mut args = Vec::new();
        for (e, &ty) in a.args.iter().zip(&types) {
            let arg = match &e.kind {
                ExprKind::Wildcard => Arg::Wild,
                ExprKind::Var(v) => match scope.slots.get(v) {
                    Some(&(s, _)) if args.iter().any(|x| matches!(x, Arg::New(n) if *n == s)) => {
                        Arg::Same(s)
                    }
                    Some(_) => Arg::Key(compile_expr(e, &scope, ctx.symbols)?, ty),
                    None => Arg::New(scope.new_slot(v, ty)?),
                },
                _ if scope.bound(e) => {
                    let ce = compile_expr(e, &scope, ctx.symbols)?;
                    match ce {
                        CExpr::Const(c) => match encode(c, ty) {
                            Some(c) => Arg::Const(c),
                            None => Arg::Const(u64::MAX),
                        },
                        ce => Arg::Key(ce, ty),
                    }
                }
                _ => {
                    return Err(EngineError::Unsupported(format!(
                        "an expression argument of `{}` uses a variable bound nowhere before it",
                        a.pred
                    )))
                }
            };
            args.push(arg);
        }
        let mut step = AtomStep::new(a.pred.clone(), args, Vec::new());
        step.lit = i;
        // The comparisons ready once this atom is joined may bound one of its new columns.
        let mut ready = Vec::new();
        let mut ready_lits = Vec::new();
        for (j, l) in lits.iter().enumerate() {
            if let (false, BodyLit::Cmp(op, x, y)) = (done[j], l) {
                if scope.bound(x) && scope.bound(y) {
                    ready.push((
                        *op,
                        compile_expr(x, &scope, ctx.symbols)?,
                        compile_expr(y, &scope, ctx.symbols)?,
                    ));
                    ready_lits.push(j);
                }
            }
        }
        if let Some((n, used)) = narrowing(&step.news, &types, &ready, from) {
            step.narrow = Some(n);
            windowed.extend(used.iter().filter_map(|&u| ready_lits.get(u)));
        }
        atoms.push(step);
        ranks.push(Vec::new());
    }
    for (a, r) in atoms.iter_mut().zip(&ranks) {
        order_comparisons(&mut a.after, r);
    }
    if let Some(i) = done.iter().position(|d| !d) {
        let _ = i;
        return Err(EngineError::Unsupported(
            "a rule body whose variables cannot all be bound".to_string(),
        ));
    }
    let mut out = Vec::new();
    for (i, e) in head.iter().enumerate() {
        let ce = compile_expr(e, &scope, ctx.symbols)?;
        let ty = match head_types {
            Some(t) => t.get(i).copied().unwrap_or(ColType::Int),
            None => expr_type(&ce),
        };
        out.push((ce, ty));
    }
    Ok(Plan {
        start,
        atoms,
        head: out,
    })
}

fn neg_filter(a: &Atom, scope: &Scope, ctx: &mut Ctx<'_>) -> Result<Filter, EngineError> {
    let types = ctx.types.get(&a.pred).cloned().unwrap_or_default();
    let mut args = Vec::new();
    for (e, &ty) in a.args.iter().zip(&types) {
        args.push(match e.kind {
            ExprKind::Wildcard => KeyArg::Wild,
            _ => KeyArg::Val(compile_expr(e, scope, ctx.symbols)?, ty),
        });
    }
    let slots: Option<Vec<(usize, usize)>> = args
        .iter()
        .enumerate()
        .filter_map(|(c, x)| match x {
            KeyArg::Val(CExpr::Slot(s, t), ty) if t == ty => Some(Some((c, *s))),
            KeyArg::Val(..) => Some(None),
            KeyArg::Wild => None,
        })
        .collect();
    let mut set = FastSet::default();
    let mut one = FastSet::default();
    // No wildcard (and not the one-column set): the sorted relation itself is searched.
    let whole =
        args.iter().all(|x| matches!(x, KeyArg::Val(..))) && !matches!(slots.as_deref(), Some([_]));
    let mut kept = Rows::new(types.len());
    match ctx.complete.get(&a.pred) {
        Some(rows) if whole => kept = rows.clone(),
        Some(rows) => {
            for r in rows.iter() {
                if let Some([(c, _)]) = slots.as_deref() {
                    one.insert(r[*c]);
                    continue;
                }
                let mut k = Rows::row(r);
                for (i, x) in args.iter().enumerate() {
                    if matches!(x, KeyArg::Wild) {
                        k[i] = 0;
                    }
                }
                set.insert(k);
            }
        }
        None => {}
    }
    Ok(Filter::Neg(Arc::new(NegSet {
        args,
        slots,
        one,
        rows: kept,
        set,
        hint: std::sync::atomic::AtomicUsize::new(0),
    })))
}

/// Named variables of an aggregate's body, in order of first occurrence.
fn agg_vars(g: &Aggregate) -> Vec<&str> {
    let mut vs = Vec::new();
    fn lit_vars<'e>(l: &'e Literal, vs: &mut Vec<&'e str>) {
        match l {
            Literal::Pos(a) | Literal::Neg(a, _) => a.args.iter().for_each(|e| expr_vars(e, vs)),
            Literal::Cmp(c) => {
                expr_vars(&c.lhs, vs);
                expr_vars(&c.rhs, vs);
            }
            Literal::Agg(g) => {
                expr_vars(&g.result, vs);
                g.body.iter().for_each(|l| lit_vars(l, vs));
            }
        }
    }
    g.body.iter().for_each(|l| lit_vars(l, &mut vs));
    if let Some(t) = &g.target {
        expr_vars(t, &mut vs);
    }
    let mut seen = HashSet::new();
    vs.retain(|v| seen.insert(*v));
    vs
}

fn var_expr(name: &str) -> Expr {
    Expr {
        kind: ExprKind::Var(name.to_string()),
        span: Span::default(),
    }
}

/// A `sum` of integers left the 64-bit range (the fold's error: never a saturated result).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SumOverflow;

/// Aggregates rows `group prefix (g_len columns) ++ … ++ target (column last)` by group.
fn fold(
    func: AggFunc,
    rows: &Rows,
    g_len: usize,
    last: usize,
    target_ty: ColType,
    out_ty: ColType,
) -> Result<FastMap<Row, u64>, SumOverflow> {
    let mut acc: FastMap<Row, V> = FastMap::default();
    for r in rows.iter() {
        let mut key = [0u64; WIDTH];
        key[..g_len].copy_from_slice(&r[..g_len]);
        let x = decode(r[last], target_ty);
        let slot = acc.entry(key);
        match func {
            AggFunc::Count => {
                let e = slot.or_insert(V::Int(0));
                if let V::Int(n) = e {
                    *n += 1;
                }
            }
            AggFunc::Sum => {
                let e = slot.or_insert(if out_ty == ColType::Float {
                    V::Float(0.0)
                } else {
                    V::Int(0)
                });
                *e = match (*e, x) {
                    (V::Int(a), V::Int(b)) => V::Int(a.checked_add(b).ok_or(SumOverflow)?),
                    (V::Float(a), V::Float(b)) => V::Float(a + b),
                    (V::Float(a), V::Int(b)) => V::Float(a + b as f64),
                    (a, _) => a,
                };
            }
            AggFunc::Min | AggFunc::Max => {
                let want = if func == AggFunc::Min {
                    std::cmp::Ordering::Less
                } else {
                    std::cmp::Ordering::Greater
                };
                slot.and_modify(|e| {
                    if x.compare(*e) == Some(want) {
                        *e = x;
                    }
                })
                .or_insert(x);
            }
        }
    }
    let mut table = FastMap::default();
    for (k, v) in acc {
        if let Some(u) = encode(v, out_ty) {
            table.insert(k, u);
        }
    }
    Ok(table)
}

/// An aggregate whose body uses outer variables only in comparisons or expressions: its body
/// is run for each outer binding, with the group variables bound first.
#[derive(Debug)]
pub struct Correlated {
    plan: Plan,
    /// Per inner atom: its selected tuples by join key.
    indexes: Vec<FastMap<Row, Vec<Row>>>,
    group: Vec<usize>,
    func: AggFunc,
    g_len: usize,
    last: usize,
    target_ty: ColType,
    out_ty: ColType,
    default: Option<u64>,
    /// Set when a `sum` overflowed for some binding; the evaluation then fails (see
    /// [`Plan::sum_overflowed`]) instead of using a wrong number.
    overflowed: std::sync::atomic::AtomicBool,
}

impl Correlated {
    fn run(&self, outer: &Row) -> Option<u64> {
        let mut start = [0u64; WIDTH];
        for (i, s) in self.group.iter().enumerate() {
            start[i] = outer[*s];
        }
        let mut bindings: Vec<Row> = apply(&self.plan.start, start).into_iter().collect();
        for (step, index) in self.plan.atoms.iter().zip(&self.indexes) {
            let mut next = Vec::new();
            for b in &bindings {
                let Some(k) = step.binding_key(b) else {
                    continue;
                };
                for t in index.get(&k).into_iter().flatten() {
                    next.extend(apply(&step.after, step.extend(*b, t)));
                }
            }
            bindings = next;
        }
        let mut rows = Rows::new(self.plan.head.len());
        for b in &bindings {
            if let Some(r) = self.plan.project(b) {
                rows.push(&r);
            }
        }
        rows.sort_dedup();
        let table = match fold(
            self.func,
            &rows,
            self.g_len,
            self.last,
            self.target_ty,
            self.out_ty,
        ) {
            Ok(t) => t,
            Err(SumOverflow) => {
                self.overflowed
                    .store(true, std::sync::atomic::Ordering::Relaxed);
                return None;
            }
        };
        match table.into_values().next() {
            Some(v) => Some(v),
            None => self.default,
        }
    }
}

/// Evaluates an aggregate's body over the completed relations and returns the filter that
/// looks its result up by group, plus a comparison when the result is not a fresh variable.
fn agg_filter(
    g: &Aggregate,
    group: &[&str],
    scope: &mut Scope,
    ctx: &mut Ctx<'_>,
) -> Result<(Filter, Option<Filter>), EngineError> {
    // The body's matching tuples, not its named bindings: `_` columns are fresh variables.
    let named = crate::agg_body::name_wildcards(g);
    let g = &named;
    let lits = body_lits(&g.body);
    let mut head: Vec<Expr> = group.iter().map(|v| var_expr(v)).collect();
    let g_len = head.len();
    if matches!(g.func, AggFunc::Count | AggFunc::Sum) {
        for v in agg_vars(g) {
            if !group.contains(&v) {
                head.push(var_expr(v));
            }
        }
    }
    if g.func != AggFunc::Count {
        match &g.target {
            Some(t) => head.push(t.clone()),
            None => {
                return Err(EngineError::Unsupported(format!(
                    "`{}` without a target expression",
                    g.func.as_str()
                )))
            }
        }
    }
    if head.len() > WIDTH {
        return Err(EngineError::Unsupported(format!(
            "an aggregate with more than {WIDTH} variables"
        )));
    }
    let mut in_atoms = Vec::new();
    for l in &lits {
        if let BodyLit::Pos(a) = l {
            a.args.iter().for_each(|e| expr_vars(e, &mut in_atoms));
        }
    }
    if !group.iter().all(|v| in_atoms.contains(v)) {
        return correlated(g, group, head, g_len, scope, ctx);
    }
    let inner = plan(&lits, &head, None, ctx)?;
    let rows = crate::frog::once::run_plan(&inner, ctx.complete, ctx.types, ctx.limits)?;
    let target_ty = inner.head.last().map_or(ColType::Int, |(_, t)| *t);
    let out_ty = match g.func {
        AggFunc::Count => ColType::Int,
        AggFunc::Sum if target_ty == ColType::Float => ColType::Float,
        AggFunc::Sum => ColType::Int,
        AggFunc::Min | AggFunc::Max => target_ty,
    };
    let table = fold(g.func, &rows, g_len, head.len() - 1, target_ty, out_ty)
        .map_err(|SumOverflow| ctx.limits.sum_overflow())?;
    let default = match g.func {
        AggFunc::Count => encode(V::Int(0), ColType::Int),
        AggFunc::Sum if out_ty == ColType::Float => encode(V::Float(0.0), ColType::Float),
        AggFunc::Sum => encode(V::Int(0), ColType::Int),
        AggFunc::Min | AggFunc::Max => None,
    };
    let group_slots = group
        .iter()
        .map(|v| scope.slots.get(*v).map(|s| s.0))
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| EngineError::Unsupported("an aggregate's group is unbound".into()))?;
    let fresh = match g.result.as_var() {
        Some(v) if !scope.slots.contains_key(v) => Some(v),
        _ => None,
    };
    let out = match fresh {
        Some(v) => scope.new_slot(v, out_ty)?,
        None => scope.new_slot(&format!("#agg{}", scope.slots.len()), out_ty)?,
    };
    let f = Filter::Agg {
        group: group_slots,
        table: Arc::new(table),
        default,
        out,
    };
    if fresh.is_some() {
        return Ok((f, None));
    }
    let cmp = Filter::Cmp(
        CmpOp::Eq,
        compile_expr(&g.result, scope, ctx.symbols)?,
        CExpr::Slot(out, out_ty),
    );
    Ok((f, Some(cmp)))
}

/// Plans a correlated aggregate (see [`Correlated`]).
fn correlated(
    g: &Aggregate,
    group: &[&str],
    head: Vec<Expr>,
    g_len: usize,
    scope: &mut Scope,
    ctx: &mut Ctx<'_>,
) -> Result<(Filter, Option<Filter>), EngineError> {
    let lits = body_lits(&g.body);
    let mut seed = Vec::new();
    let mut group_slots = Vec::new();
    for v in group {
        let (s, ty) = *scope
            .slots
            .get(*v)
            .ok_or_else(|| EngineError::Unsupported("an aggregate's group is unbound".into()))?;
        seed.push((*v, ty));
        group_slots.push(s);
    }
    let inner = plan_seeded(&lits, &head, None, ctx, &seed, None)?;
    let empty = Rows::new(0);
    let indexes = inner
        .atoms
        .iter()
        .map(|step| {
            let mut index: FastMap<Row, Vec<Row>> = FastMap::default();
            for t in ctx.complete.get(&step.pred).unwrap_or(&empty).iter() {
                if step.selects(t) {
                    index
                        .entry(step.tuple_key(t))
                        .or_default()
                        .push(Rows::row(t));
                }
            }
            index
        })
        .collect();
    let target_ty = inner.head.last().map_or(ColType::Int, |(_, t)| *t);
    let out_ty = match g.func {
        AggFunc::Count => ColType::Int,
        AggFunc::Sum if target_ty == ColType::Float => ColType::Float,
        AggFunc::Sum => ColType::Int,
        AggFunc::Min | AggFunc::Max => target_ty,
    };
    let default = match g.func {
        AggFunc::Count => encode(V::Int(0), ColType::Int),
        AggFunc::Sum if out_ty == ColType::Float => encode(V::Float(0.0), ColType::Float),
        AggFunc::Sum => encode(V::Int(0), ColType::Int),
        AggFunc::Min | AggFunc::Max => None,
    };
    let c = Correlated {
        plan: inner,
        indexes,
        group: group_slots,
        func: g.func,
        g_len,
        last: head.len() - 1,
        target_ty,
        out_ty,
        default,
        overflowed: std::sync::atomic::AtomicBool::new(false),
    };
    let fresh = match g.result.as_var() {
        Some(v) if !scope.slots.contains_key(v) => Some(v),
        _ => None,
    };
    let out = match fresh {
        Some(v) => scope.new_slot(v, out_ty)?,
        None => scope.new_slot(&format!("#agg{}", scope.slots.len()), out_ty)?,
    };
    let f = Filter::AggRun(Arc::new(c), out);
    if fresh.is_some() {
        return Ok((f, None));
    }
    let cmp = Filter::Cmp(
        CmpOp::Eq,
        compile_expr(&g.result, scope, ctx.symbols)?,
        CExpr::Slot(out, out_ty),
    );
    Ok((f, Some(cmp)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::value::enc_int;

    #[test]
    fn integer_expressions_agree_with_the_general_evaluator() {
        let slot = |s| Box::new(CExpr::Slot(s, ColType::Int));
        let exprs = [
            CExpr::Call(Func::Abs, vec![CExpr::Bin(BinOp::Sub, slot(0), slot(1))]),
            CExpr::Bin(BinOp::Sub, slot(1), slot(0)),
            CExpr::Bin(BinOp::Mul, slot(0), Box::new(CExpr::Const(V::Int(3)))),
            CExpr::Neg(Box::new(CExpr::Bin(BinOp::Div, slot(0), slot(1)))),
            CExpr::Bin(
                BinOp::Add,
                Box::new(CExpr::Slot(2, ColType::Time)),
                Box::new(CExpr::Const(V::Int(-20))),
            ),
        ];
        for (a, b) in [(5, 9), (-7, 3), (i64::MIN, 1), (i64::MAX, -1), (4, 0)] {
            let mut row = [0u64; WIDTH];
            row[0] = enc_int(a);
            row[1] = enc_int(b);
            row[2] = 17;
            for e in &exprs {
                let want = e.eval(&row).and_then(|v| match v {
                    V::Int(i) => Some(i),
                    _ => None,
                });
                let Some(ie) = IExpr::from(e) else {
                    panic!("{e:?} is an integer expression");
                };
                assert_eq!(ie.eval(&row), want, "{e:?} on {a}, {b}");
            }
        }
    }

    #[test]
    fn compiled_differences_agree_with_the_general_comparison() {
        let mut seed = 5u64;
        let mut next = || crate::frog::join::tests::lcg(&mut seed);
        let ops = [
            CmpOp::Lt,
            CmpOp::Le,
            CmpOp::Gt,
            CmpOp::Ge,
            CmpOp::Eq,
            CmpOp::Ne,
        ];
        let edges = [i64::MIN, i64::MIN + 1, -1, 0, 1, i64::MAX - 1, i64::MAX];
        let slot = |s| Box::new(CExpr::Slot(s, ColType::Int));
        for case in 0..20_000 {
            let mut pick = |small: bool| -> i64 {
                let r = next();
                match r % 4 {
                    0 => edges[(r / 4) as usize % edges.len()],
                    _ if small => (r / 4 % 41) as i64 - 20,
                    _ => ((r as i64) << 29) - (1i64 << 59),
                }
            };
            let (x, y, c) = (pick(case % 2 == 0), pick(case % 2 == 0), pick(true));
            let op = ops[case % ops.len()];
            let diff = CExpr::Bin(BinOp::Sub, slot(0), slot(1));
            let e = if case % 3 == 0 {
                CExpr::Call(Func::Abs, vec![diff])
            } else {
                diff
            };
            let k = CExpr::Const(V::Int(c));
            // Both sides: `e op c` and `c op e`.
            let (l, r) = if case % 5 == 0 { (k, e) } else { (e, k) };
            let compiled = cmp_filter(op, l.clone(), r.clone());
            assert!(matches!(compiled, Filter::CmpDiff { .. }), "{compiled:?}");
            let general = Filter::Cmp(op, l, r);
            let mut row = [0u64; WIDTH];
            row[0] = enc_int(x);
            row[1] = enc_int(y);
            assert_eq!(
                apply(&[compiled], row).is_some(),
                apply(&[general], row).is_some(),
                "{op:?} on {x}, {y}, {c} (case {case})"
            );
        }
    }

    #[test]
    fn words_agree_with_evaluating_then_encoding() {
        let mut seed = 7u64;
        let mut next = || crate::frog::join::tests::lcg(&mut seed);
        let edges = [i64::MIN, i64::MIN + 1, -1, 0, 1, i64::MAX - 1, i64::MAX];
        let types = [ColType::Int, ColType::Time, ColType::Float, ColType::Str];
        for case in 0..20_000usize {
            let r = next();
            let c = match r % 3 {
                0 => edges[(r / 3) as usize % edges.len()],
                _ => (r / 3 % 21) as i64 - 10,
            };
            let from = types[case % types.len()];
            let to = types[(case / 4) % types.len()];
            let op = if case % 2 == 0 {
                BinOp::Add
            } else {
                BinOp::Sub
            };
            let slot = Box::new(CExpr::Slot(0, from));
            let e = match case % 3 {
                0 => CExpr::Slot(0, from),
                1 => CExpr::Bin(op, slot, Box::new(CExpr::Const(V::Int(c)))),
                _ => CExpr::Bin(op, Box::new(CExpr::Const(V::Int(c))), slot),
            };
            // A stored word of the slot's type: times fit in u32, floats are not NaN.
            let w = next() << 31 ^ next();
            let word = match from {
                ColType::Int => enc_int(edges.get(w as usize % 9).copied().unwrap_or(w as i64)),
                ColType::Time => w % (1 << 32),
                ColType::Float => crate::value::enc_float((w % 1000) as f64 - 500.5),
                _ => w % 50,
            };
            let mut row = [0u64; WIDTH];
            row[0] = word;
            let want = e.eval(&row).map(|v| encode(v, to));
            assert_eq!(e.word(&row, to), want, "{e:?} into {to:?} on {word}");
        }
    }

    #[test]
    fn strict_windows_hold_every_value_their_comparisons_accept() {
        let mut seed = 13u64;
        let mut next = || crate::frog::join::tests::lcg(&mut seed);
        let ops = [CmpOp::Lt, CmpOp::Le, CmpOp::Gt, CmpOp::Ge, CmpOp::Eq];
        for case in 0..10_000usize {
            // Int columns (any sign) or time columns (from 0, stored as the number itself).
            let ty = if case % 2 == 0 {
                ColType::Int
            } else {
                ColType::Time
            };
            let (word, xs, y) = match ty {
                ColType::Int => (
                    enc_int as fn(i64) -> u64,
                    -45..=45,
                    (next() % 41) as i64 - 20,
                ),
                _ => (
                    (|x: i64| x as u64) as fn(i64) -> u64,
                    0..=45,
                    (next() % 41) as i64,
                ),
            };
            let slot = |s| Box::new(CExpr::Slot(s, ty));
            let op = ops[(case / 2) % ops.len()];
            let c = (next() % 21) as i64 - 10;
            let k = Box::new(CExpr::Const(V::Int(c)));
            // Slot 0 is bound before the atom; slot 1 (x) is the atom's new column.
            let shape = (case / 10) % 4;
            let (l, r) = match shape {
                0 => (CExpr::Slot(1, ty), CExpr::Slot(0, ty)),
                1 => (CExpr::Bin(BinOp::Sub, slot(1), slot(0)), (*k).clone()),
                2 => (CExpr::Bin(BinOp::Sub, slot(0), slot(1)), (*k).clone()),
                _ => (
                    CExpr::Call(Func::Abs, vec![CExpr::Bin(BinOp::Sub, slot(1), slot(0))]),
                    (*k).clone(),
                ),
            };
            let cmps = [(op, l.clone(), r.clone())];
            let Some((n, used)) = narrowing(&[(0, 1)], &[ty], &cmps, 1) else {
                continue;
            };
            assert_eq!(used, vec![0]);
            let mut row = [0u64; WIDTH];
            row[0] = word(y);
            let range = n.range(&row);
            for x in xs {
                row[1] = word(x);
                let passes = apply(&[Filter::Cmp(op, l.clone(), r.clone())], row).is_some();
                let inside = range.is_some_and(|(lo, hi)| (lo..=hi).contains(&word(x)));
                assert!(
                    !passes || inside,
                    "{l:?} {op:?} {r:?}: x = {x}, y = {y}, {range:?}"
                );
                // Strict bounds step inward, so on ints and times the window is exact (but
                // for `abs(x - y) = c`, two values at the ends of a range).
                if !(shape == 3 && op == CmpOp::Eq) {
                    assert_eq!(
                        passes, inside,
                        "{l:?} {op:?} {r:?}: x = {x}, y = {y}, {range:?}"
                    );
                }
            }
        }
    }
}
