//! Order-preserving encoding of values into `u64`, the runtime values of expressions, and the
//! per-evaluation symbol table.

use std::cmp::Ordering;
use std::collections::{HashMap, HashSet};
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::{Arc, RwLock};

use scenalog_facts::catalog::ColType;
use scenalog_facts::map::LaneId;
use scenalog_facts::relation::Value;
use scenalog_facts::scene::TrackId;

/// The binding-row width of most programs: every relation at most this wide and every rule
/// binding at most this many slots ([`scenalog_rules::walk::binding_slots`]). Such programs are
/// evaluated with rows of this width, the engine's fast path.
pub const WIDTH: usize = 12;

/// The widest row the engine evaluates: programs with a relation or a rule wider than
/// [`WIDTH`] and at most this wide are evaluated with rows of this width (the checker's limit,
/// E0406, `scenalog_rules::check::meaning::MAX_VARIABLES`, which a test keeps equal).
pub const WIDEST: usize = 64;

/// One tuple or one rule's variable bindings: `R` words (the evaluation's width, [`WIDTH`] or
/// [`WIDEST`]), no heap allocation.
pub type Row<const R: usize = WIDTH> = [u64; R];

const SIGN: u64 = 1 << 63;

/// A fast, non-cryptographic hasher for rows of encoded values (multiply-rotate per 64-bit
/// word). The keys are the engine's own encoded tuples, not attacker-controlled input, so
/// SipHash's flood resistance buys nothing and costs most of a join's lookup time.
#[derive(Debug, Default, Clone, Copy)]
pub struct RowHasher(u64);

impl RowHasher {
    #[inline]
    fn add(&mut self, w: u64) {
        self.0 = (self.0.rotate_left(5) ^ w).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
}

impl Hasher for RowHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            let mut w = [0u8; 8];
            w.copy_from_slice(c);
            self.add(u64::from_le_bytes(w));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut w = [0u8; 8];
            w[..rest.len()].copy_from_slice(rest);
            self.add(u64::from_le_bytes(w));
        }
    }

    #[inline]
    fn write_u64(&mut self, i: u64) {
        self.add(i);
    }

    #[inline]
    fn write_u32(&mut self, i: u32) {
        self.add(u64::from(i));
    }

    #[inline]
    fn write_usize(&mut self, i: usize) {
        self.add(i as u64);
    }

    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }
}

/// A hash map keyed by rows (or other small keys), hashed with [`RowHasher`].
pub type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<RowHasher>>;

/// A hash set of rows, hashed with [`RowHasher`].
pub type FastSet<K> = HashSet<K, BuildHasherDefault<RowHasher>>;

/// Encodes an integer so that unsigned order equals signed order.
pub fn enc_int(i: i64) -> u64 {
    (i as u64) ^ SIGN
}

/// Inverse of [`enc_int`].
pub fn dec_int(u: u64) -> i64 {
    (u ^ SIGN) as i64
}

/// Encodes a float so that unsigned order equals the float total order (-0.0 as 0.0).
pub fn enc_float(f: f64) -> u64 {
    let f = if f == 0.0 { 0.0 } else { f };
    let bits = f.to_bits();
    if bits & SIGN != 0 {
        !bits
    } else {
        bits | SIGN
    }
}

/// Inverse of [`enc_float`].
pub fn dec_float(u: u64) -> f64 {
    if u & SIGN != 0 {
        f64::from_bits(u & !SIGN)
    } else {
        f64::from_bits(!u)
    }
}

/// Strings interned for one evaluation: an id per distinct string, in the order first met;
/// the texts by id are the [`Texts`] the comparisons by text share.
#[derive(Debug, Default)]
pub struct Symbols {
    ids: HashMap<Arc<str>, u64>,
    texts: Texts,
}

impl Clone for Symbols {
    /// A copy with its own [`Texts`] (a shared one would see the copy's new strings under
    /// ids the original gives to others).
    fn clone(&self) -> Symbols {
        Symbols {
            ids: self.ids.clone(),
            texts: Texts(Arc::new(RwLock::new(self.texts.read().clone()))),
        }
    }
}

/// The text of each interned string by id, shared by the comparisons that order strings by
/// text (`<` on strings, `min` and `max` of strings): strings interned after a comparison was
/// planned (a later clause's constants, a later stratum's inputs) are seen by it too.
#[derive(Debug, Default, Clone)]
pub struct Texts(Arc<RwLock<Vec<Arc<str>>>>);

impl Texts {
    /// The order of two interned strings' texts; `None` for an id never interned.
    pub fn cmp(&self, a: u64, b: u64) -> Option<Ordering> {
        if a == b {
            return Some(Ordering::Equal);
        }
        let names = self.read();
        let x = names.get(usize::try_from(a).ok()?)?;
        let y = names.get(usize::try_from(b).ok()?)?;
        Some(x.as_ref().cmp(y.as_ref()))
    }

    /// Orders two values: strings by text, anything else as [`V::compare`] does.
    pub fn compare(&self, a: V, b: V) -> Option<Ordering> {
        match (a, b) {
            (V::Sym(x), V::Sym(y)) => self.cmp(x, y),
            _ => a.compare(b),
        }
    }

    fn read(&self) -> std::sync::RwLockReadGuard<'_, Vec<Arc<str>>> {
        self.0.read().unwrap_or_else(|e| e.into_inner())
    }

    fn push(&self, s: Arc<str>) {
        self.0.write().unwrap_or_else(|e| e.into_inner()).push(s);
    }
}

impl Symbols {
    /// The id of `s`, interning it if new.
    pub fn intern(&mut self, s: &str) -> u64 {
        match self.ids.get(s) {
            Some(&id) => id,
            None => self.insert(Arc::from(s)),
        }
    }

    /// The id of an `Arc<str>` (no copy of the text when new).
    pub fn intern_arc(&mut self, s: &Arc<str>) -> u64 {
        match self.ids.get(s) {
            Some(&id) => id,
            None => self.insert(s.clone()),
        }
    }

    /// Interns a string not interned yet: the next id.
    fn insert(&mut self, s: Arc<str>) -> u64 {
        let id = self.ids.len() as u64;
        self.texts.push(s.clone());
        self.ids.insert(s, id);
        id
    }

    /// The texts of this table's strings, for comparisons by text (see [`Texts`]).
    pub fn texts(&self) -> Texts {
        self.texts.clone()
    }

    /// The id of `s` if it was interned.
    pub fn lookup(&self, s: &str) -> Option<u64> {
        self.ids.get(s).copied()
    }

    /// The string of an id.
    pub fn name(&self, id: u64) -> Arc<str> {
        self.texts
            .read()
            .get(id as usize)
            .cloned()
            .unwrap_or_else(|| Arc::from("?"))
    }
}

/// Integer arithmetic as the language defines it: `None` on overflow or division by zero.
pub(crate) fn int_op(op: scenalog_rules::ast::BinOp, x: i64, y: i64) -> Option<i64> {
    use scenalog_rules::ast::BinOp;
    match op {
        BinOp::Add => x.checked_add(y),
        BinOp::Sub => x.checked_sub(y),
        BinOp::Mul => x.checked_mul(y),
        BinOp::Div => x.checked_div(y),
        BinOp::Mod => x.checked_rem(y),
        BinOp::Pow => int_pow(x, y),
    }
}

/// `x ^ y` on integers: `None` on overflow; a negative exponent gives the power's integer
/// part, truncated toward zero as Soufflé's does (`2 ^ -1` is 0, `-1 ^ -3` is -1).
fn int_pow(x: i64, y: i64) -> Option<i64> {
    match x {
        0 if y < 0 => None,
        0 => Some(i64::from(y == 0)),
        1 => Some(1),
        -1 => Some(if y % 2 == 0 { 1 } else { -1 }),
        _ if y < 0 => Some(0),
        _ => x.checked_pow(u32::try_from(y).ok()?),
    }
}

/// Float arithmetic as the language defines it: `None` when the result is not finite.
pub(crate) fn float_op(op: scenalog_rules::ast::BinOp, x: f64, y: f64) -> Option<f64> {
    use scenalog_rules::ast::BinOp;
    let r = match op {
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Mul => x * y,
        BinOp::Div => x / y,
        BinOp::Mod => x % y,
        BinOp::Pow => x.powf(y),
    };
    r.is_finite().then_some(r)
}

/// A value while evaluating expressions: numbers, or an opaque symbol (track, lane, string).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum V {
    /// Integer or time.
    Int(i64),
    /// Float.
    Float(f64),
    /// Track, lane or interned string: compared by identity.
    Sym(u64),
}

impl V {
    pub(crate) fn as_f64(self) -> Option<f64> {
        match self {
            V::Int(i) => Some(i as f64),
            V::Float(f) => Some(f),
            V::Sym(_) => None,
        }
    }

    /// Compares two values: numerically across int and float, by identity for symbols (strings
    /// by text need their [`Texts`]: [`Texts::compare`]).
    pub fn compare(self, other: V) -> Option<Ordering> {
        match (self, other) {
            (V::Int(a), V::Int(b)) => Some(a.cmp(&b)),
            (V::Sym(a), V::Sym(b)) => Some(a.cmp(&b)),
            (a, b) => a.as_f64()?.partial_cmp(&b.as_f64()?),
        }
    }
}

/// Decodes an encoded column value into an expression value.
pub fn decode(raw: u64, ty: ColType) -> V {
    match ty {
        ColType::Track | ColType::Lane | ColType::Str => V::Sym(raw),
        ColType::Time => V::Int(raw as i64),
        ColType::Int => V::Int(dec_int(raw)),
        ColType::Float => V::Float(dec_float(raw)),
    }
}

/// Encodes an expression value into a column of type `ty`; `None` when it does not fit
/// (a negative time, a fractional value in an int column, a number in a symbol column).
pub fn encode(v: V, ty: ColType) -> Option<u64> {
    match (ty, v) {
        (ColType::Track | ColType::Lane | ColType::Str, V::Sym(s)) => Some(s),
        (ColType::Time, V::Int(i)) => u32::try_from(i).ok().map(u64::from),
        (ColType::Int, V::Int(i)) => Some(enc_int(i)),
        (ColType::Float, V::Float(f)) if !f.is_nan() => Some(enc_float(f)),
        (ColType::Float, V::Int(i)) => Some(enc_float(i as f64)),
        (ColType::Time | ColType::Int, V::Float(f)) if f.fract() == 0.0 => {
            encode(V::Int(f as i64), ty)
        }
        _ => None,
    }
}

/// Encodes an input value into a column of type `ty`.
pub fn encode_value(v: &Value, ty: ColType, symbols: &mut Symbols) -> Option<u64> {
    match (ty, v) {
        (ColType::Track, Value::Track(t)) => Some(u64::from(t.0)),
        (ColType::Lane, Value::Lane(l)) => Some(enc_int(l.0)),
        (ColType::Str, Value::Str(s)) => Some(symbols.intern_arc(s)),
        (_, Value::Time(t)) => encode(V::Int(i64::from(*t)), ty),
        (_, Value::Int(i)) => encode(V::Int(*i), ty),
        (_, Value::Float(f)) => encode(V::Float(*f), ty),
        _ => None,
    }
}

/// Decodes a stored value of a column of type `ty`.
pub fn decode_value(raw: u64, ty: ColType, symbols: &Symbols) -> Value {
    match ty {
        ColType::Track => Value::Track(TrackId(raw as u32)),
        ColType::Time => Value::Time(raw as u32),
        ColType::Lane => Value::Lane(LaneId(dec_int(raw))),
        ColType::Str => Value::Str(symbols.name(raw)),
        ColType::Float => Value::Float(dec_float(raw)),
        ColType::Int => Value::Int(dec_int(raw)),
    }
}

/// Total order on decoded values (strings by text, floats by total order).
pub fn cmp_value(a: &Value, b: &Value) -> Ordering {
    fn rank(v: &Value) -> u8 {
        match v {
            Value::Track(_) => 0,
            Value::Time(_) => 1,
            Value::Lane(_) => 2,
            Value::Str(_) => 3,
            Value::Float(_) => 4,
            Value::Int(_) => 5,
        }
    }
    match (a, b) {
        (Value::Track(x), Value::Track(y)) => x.cmp(y),
        (Value::Time(x), Value::Time(y)) => x.cmp(y),
        (Value::Lane(x), Value::Lane(y)) => x.cmp(y),
        (Value::Str(x), Value::Str(y)) => x.cmp(y),
        (Value::Float(x), Value::Float(y)) => x.total_cmp(y),
        (Value::Int(x), Value::Int(y)) => x.cmp(y),
        _ => rank(a).cmp(&rank(b)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn float_and_int_encodings_preserve_order() {
        let fs = [-1e9, -2.5, -0.0, 0.0, 1e-9, 3.0, 1e300];
        for w in fs.windows(2) {
            assert!(enc_float(w[0]) <= enc_float(w[1]), "{w:?}");
            assert_eq!(dec_float(enc_float(w[1])), w[1]);
        }
        let is = [i64::MIN, -5, 0, 7, i64::MAX];
        for w in is.windows(2) {
            assert!(enc_int(w[0]) < enc_int(w[1]));
            assert_eq!(dec_int(enc_int(w[0])), w[0]);
        }
    }
}

#[cfg(test)]
mod width_tests {
    /// The checker rejects (E0406) exactly the rules the engine's widest tuples cannot hold.
    #[test]
    fn the_checker_and_the_engine_agree_on_the_widest_rule() {
        assert_eq!(super::WIDEST, scenalog_rules::check::meaning::MAX_VARIABLES);
    }
}
