//! Compiled expressions: [`CExpr`] over a binding row, [`IExpr`] on integer and time slots
//! without decoding, and compiling a rule's expression into them with its type.

use super::*;

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
    /// Whether `f` holds for some slot the expression reads (each is passed to `f` until it
    /// does): the one walk over an expression's slots, for what it reads and whether it reads
    /// a given set.
    pub(crate) fn any_slot(&self, f: &mut dyn FnMut(usize) -> bool) -> bool {
        match self {
            CExpr::Slot(s, _) => f(*s),
            CExpr::Const(_) => false,
            CExpr::Neg(a) => a.any_slot(f),
            CExpr::Bin(_, a, b) => a.any_slot(f) || b.any_slot(f),
            CExpr::Call(_, args) => args.iter().any(|a| a.any_slot(f)),
        }
    }

    /// The value encoded into a column of type `ty`: `encode(self.eval(row)?, ty)`, with the
    /// outer `None` when evaluation fails and the inner one when the value cannot be stored
    /// in the column. A slot of the column's own type is copied, and an int or time slot plus
    /// or minus an int constant (`T - 1`, `T + 1`) computed on its word without decoding.
    #[inline]
    pub fn word<const R: usize>(&self, row: &Row<R>, ty: ColType) -> Option<Option<u64>> {
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
    pub fn eval<const R: usize>(&self, row: &Row<R>) -> Option<V> {
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
pub(crate) fn int_diff(e: &CExpr) -> Option<(usize, usize)> {
    match e {
        CExpr::Bin(BinOp::Sub, x, y) => match (&**x, &**y) {
            (CExpr::Slot(p, ColType::Int), CExpr::Slot(q, ColType::Int)) => Some((*p, *q)),
            _ => None,
        },
        _ => None,
    }
}

impl IExpr {
    /// Whether `f` holds for some slot the expression reads (see [`CExpr::any_slot`]).
    pub(crate) fn any_slot(&self, f: &mut dyn FnMut(usize) -> bool) -> bool {
        match self {
            IExpr::Int(s) | IExpr::Time(s) => f(*s),
            IExpr::Const(_) => false,
            IExpr::Neg(a) | IExpr::Abs(a) => a.any_slot(f),
            IExpr::Bin(_, a, b) => a.any_slot(f) || b.any_slot(f),
            IExpr::Diff(a, b) | IExpr::AbsDiff(a, b) => f(*a) || f(*b),
        }
    }

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
    pub fn eval<const R: usize>(&self, row: &Row<R>) -> Option<i64> {
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

pub(crate) fn arith(op: BinOp, a: V, b: V) -> Option<V> {
    match (a, b) {
        (V::Int(x), V::Int(y)) => crate::value::int_op(op, x, y).map(V::Int),
        (V::Sym(_), _) | (_, V::Sym(_)) => None,
        (a, b) => crate::value::float_op(op, to_f(a), to_f(b)).map(V::Float),
    }
}

pub(crate) fn to_f(v: V) -> f64 {
    match v {
        V::Int(i) => i as f64,
        V::Float(f) => f,
        V::Sym(_) => f64::NAN,
    }
}

pub(crate) fn compile_expr(
    e: &Expr,
    scope: &Scope,
    symbols: &mut Symbols,
) -> Result<CExpr, EngineError> {
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
        ExprKind::Quantity(q) => CExpr::Const(match q.number() {
            Number::Int(i) => V::Int(i),
            Number::Float(f) => V::Float(f),
        }),
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

pub(crate) fn join_types(a: ColType, b: ColType) -> ColType {
    match (a, b) {
        (ColType::Float, _) | (_, ColType::Float) => ColType::Float,
        (ColType::Time, _) | (_, ColType::Time) => ColType::Time,
        (t, _) => t,
    }
}
