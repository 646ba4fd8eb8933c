//! One atom of a join ([`AtomStep<R>`]): its arguments relative to what is bound before it, its
//! key, and the bounds ([`BoundExpr`]) a range-narrowed column is read between.

use super::*;

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
pub struct AtomStep<const R: usize> {
    /// The predicate.
    pub pred: String,
    /// One per column.
    pub args: Vec<Arg>,
    /// Filters to apply after this atom is joined.
    pub after: Vec<Filter<R>>,
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
    /// Whether the atom only tests that a matching tuple exists (`e(_)`, `p(X, _)` with `X`
    /// bound): it binds no variable used anywhere else, so every matching tuple gives the
    /// same binding and the join goes on with the first one (a semi-join, not a product).
    pub existential: bool,
    /// When this atom starts a run of atoms up to this one (two or more) that binds nothing
    /// any later atom, filter or the head reads: the join stops trying this atom's candidates
    /// once one has reached past the run (see `plan::dead`).
    pub dead_until: Option<usize>,
}

impl<const R: usize> AtomStep<R> {
    /// A step joining `pred` with these arguments, then applying `after`.
    pub fn new(pred: String, args: Vec<Arg>, after: Vec<Filter<R>>) -> Self {
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
            existential: false,
            dead_until: None,
        }
    }

    /// Whether a stored tuple passes the atom's constants and repeated variables.
    pub fn selects(&self, t: &[u64]) -> bool {
        self.consts.iter().all(|&(i, c)| t[i] == c) && self.sames.iter().all(|&(i, j)| t[i] == t[j])
    }

    /// The slots the step writes: its new variables, then its filters' results.
    pub(crate) fn writes(&self) -> Vec<usize> {
        let news = self.news.iter().map(|&(_, s)| s);
        news.chain(self.after.iter().filter_map(Filter::written))
            .collect()
    }

    /// The binding row extended with the atom's new variables.
    pub fn extend(&self, mut b: Row<R>, t: &[u64]) -> Row<R> {
        for &(i, s) in &self.news {
            b[s] = t[i];
        }
        b
    }

    /// The join key of a stored tuple (its key columns).
    pub fn tuple_key(&self, t: &[u64]) -> Row<R> {
        let mut k = [0u64; R];
        for (n, &i) in self.keys.iter().enumerate() {
            k[n] = t[i];
        }
        k
    }

    /// The join key computed from a binding row, written to `out` (one word per key column);
    /// `false` if a value does not fit its column ([`AtomStep::binding_key`] writes it into a row).
    pub fn key_into(&self, b: &Row<R>, out: &mut [u64]) -> bool {
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
    pub fn binding_key(&self, b: &Row<R>) -> Option<Row<R>> {
        let mut k = [0u64; R];
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
    pub(crate) fn plain(base: CExpr) -> BoundExpr {
        BoundExpr {
            base,
            off: None,
            strict: false,
        }
    }

    pub(crate) fn with(base: CExpr, op: BinOp, off: CExpr) -> BoundExpr {
        BoundExpr {
            base,
            off: Some((op, off)),
            strict: false,
        }
    }

    pub(crate) fn strict(self, strict: bool) -> BoundExpr {
        BoundExpr { strict, ..self }
    }

    /// The bound as a number; floats come with the slack their rounding needs (the
    /// comparison computes `X - E` where the bound computes `E + C`), so the range is never
    /// narrower than what the filter accepts.
    pub(crate) fn value<const R: usize>(&self, row: &Row<R>) -> Option<NumBound> {
        // Int slots and int constants, alone or one plus or minus the other (`XA - 100`,
        // `300 + XA`): read directly, with the results of the general path.
        let int = |e: &CExpr| match e {
            CExpr::Slot(s, ColType::Int) => row.get(*s).map(|w| crate::value::dec_int(*w)),
            CExpr::Const(V::Int(c)) => Some(*c),
            _ => None,
        };
        if let Some(x) = int(&self.base) {
            match &self.off {
                None => return Some(NumBound::Int(x)),
                Some((op @ (BinOp::Add | BinOp::Sub), e)) => {
                    if let Some(y) = int(e) {
                        return crate::value::int_op(*op, x, y).map(NumBound::Int);
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
    pub(crate) fn value_on<const R: usize>(
        &self,
        row: &Row<R>,
        ty: ColType,
        lower: bool,
    ) -> Option<NumBound> {
        match self.value(row)? {
            NumBound::Int(i) if self.strict && matches!(ty, ColType::Int | ColType::Time) => {
                let step = if lower {
                    i.checked_add(1)
                } else {
                    i.checked_sub(1)
                };
                Some(NumBound::Int(step.unwrap_or(i)))
            }
            n => Some(n),
        }
    }

    /// [`BoundExpr::value`] through the expressions.
    pub(crate) fn value_of_exprs<const R: usize>(&self, row: &Row<R>) -> Option<NumBound> {
        let a = self.base.eval(row)?;
        let Some((op, e)) = &self.off else {
            return NumBound::of(a, 0.0);
        };
        let b = e.eval(row)?;
        let slack = 1e-9 * (a.as_f64()?.abs() + b.as_f64()?.abs());
        NumBound::of(arith(*op, a, b)?, slack)
    }
}
