//! Value arithmetic for the explanation interpreter, on decoded [`Value`]s: keys for hashing,
//! coercion into a column's type, comparisons and how far a comparison missed.

use super::*;

/// A hashable form of a value (floats by their bits, -0.0 as 0.0).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub(crate) enum Key {
    Track(u32),
    Time(u32),
    Lane(i64),
    Str(Arc<str>),
    Float(u64),
    Int(i64),
}

pub(crate) fn key(v: &Value) -> Key {
    match v {
        Value::Track(t) => Key::Track(t.0),
        Value::Time(t) => Key::Time(*t),
        Value::Lane(l) => Key::Lane(l.0),
        Value::Str(s) => Key::Str(s.clone()),
        Value::Float(f) => Key::Float(if *f == 0.0 { 0.0f64 } else { *f }.to_bits()),
        Value::Int(i) => Key::Int(*i),
    }
}

/// Equality of stored values (floats by value, so -0.0 equals 0.0).
pub(crate) fn same(a: &Value, b: &Value) -> bool {
    a == b
}

/// A hash of some column values, for the on-demand indexes (collisions are checked).
pub(crate) fn fingerprint(vs: &[&Value]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for v in vs {
        match v {
            Value::Track(t) => (0u8, t.0).hash(&mut h),
            Value::Time(t) => (1u8, *t).hash(&mut h),
            Value::Lane(l) => (2u8, l.0).hash(&mut h),
            Value::Str(s) => (3u8, s.as_ref()).hash(&mut h),
            Value::Float(x) => (4u8, if *x == 0.0 { 0.0f64 } else { *x }.to_bits()).hash(&mut h),
            Value::Int(i) => (5u8, *i).hash(&mut h),
        }
    }
    h.finish()
}

/// A value as a value of a column of type `ty` (as the engine encodes it), if it fits.
pub(crate) fn coerce(v: &Value, ty: ColType) -> Option<Value> {
    let whole = |f: f64| f.is_finite() && f.fract() == 0.0;
    Some(match (ty, v) {
        (ColType::Track, Value::Track(_))
        | (ColType::Lane, Value::Lane(_))
        | (ColType::Str, Value::Str(_)) => v.clone(),
        (ColType::Time, Value::Time(t)) => Value::Time(*t),
        (ColType::Time, Value::Int(i)) => Value::Time(u32::try_from(*i).ok()?),
        (ColType::Time, Value::Float(f)) if whole(*f) => {
            Value::Time(u32::try_from(*f as i64).ok()?)
        }
        (ColType::Int, Value::Int(i)) => Value::Int(*i),
        (ColType::Int, Value::Time(t)) => Value::Int(i64::from(*t)),
        (ColType::Int, Value::Float(f)) if whole(*f) => Value::Int(*f as i64),
        (ColType::Float, Value::Float(f)) if !f.is_nan() => {
            Value::Float(if *f == 0.0 { 0.0 } else { *f })
        }
        (ColType::Float, Value::Int(i)) => Value::Float(*i as f64),
        (ColType::Float, Value::Time(t)) => Value::Float(f64::from(*t)),
        _ => return None,
    })
}

#[derive(Clone, Copy)]
pub(crate) enum Num {
    I(i64),
    F(f64),
}

pub(crate) fn num(v: &Value) -> Option<Num> {
    match v {
        Value::Int(i) => Some(Num::I(*i)),
        Value::Time(t) => Some(Num::I(i64::from(*t))),
        Value::Float(f) => Some(Num::F(*f)),
        _ => None,
    }
}

pub(crate) fn f(n: Num) -> f64 {
    match n {
        Num::I(i) => i as f64,
        Num::F(x) => x,
    }
}

pub(crate) fn from_num(n: Num) -> Value {
    match n {
        Num::I(i) => Value::Int(i),
        Num::F(x) => Value::Float(x),
    }
}

/// Compares as the engine does: numbers numerically (int with int exactly), other values of the
/// same kind by identity (strings by text).
pub(crate) fn compare(a: &Value, b: &Value) -> Option<Ordering> {
    match (num(a), num(b)) {
        (Some(Num::I(x)), Some(Num::I(y))) => Some(x.cmp(&y)),
        (Some(x), Some(y)) => f(x).partial_cmp(&f(y)),
        (None, None) => match (a, b) {
            (Value::Track(x), Value::Track(y)) => Some(x.cmp(y)),
            (Value::Lane(x), Value::Lane(y)) => Some(x.cmp(y)),
            (Value::Str(x), Value::Str(y)) => Some(x.cmp(y)),
            _ => None,
        },
        _ => None,
    }
}

pub(crate) fn cmp_holds(op: CmpOp, a: &Value, b: &Value) -> bool {
    let Some(o) = compare(a, b) else {
        return false;
    };
    match op {
        CmpOp::Lt => o.is_lt(),
        CmpOp::Le => o.is_le(),
        CmpOp::Gt => o.is_gt(),
        CmpOp::Ge => o.is_ge(),
        CmpOp::Eq => o.is_eq(),
        CmpOp::Ne => o.is_ne(),
    }
}

/// How far a comparison is from holding (0 when it holds; infinite when not numeric).
pub(crate) fn gap(op: CmpOp, a: Option<&Value>, b: Option<&Value>) -> f64 {
    let (Some(a), Some(b)) = (a, b) else {
        return f64::INFINITY;
    };
    if cmp_holds(op, a, b) {
        return 0.0;
    }
    match (num(a), num(b)) {
        (Some(x), Some(y)) => (f(x) - f(y)).abs(),
        _ => f64::INFINITY,
    }
}

pub(crate) fn arith(op: BinOp, a: Num, b: Num) -> Option<Num> {
    match (a, b) {
        (Num::I(x), Num::I(y)) => crate::value::int_op(op, x, y).map(Num::I),
        (a, b) => crate::value::float_op(op, f(a), f(b)).map(Num::F),
    }
}
