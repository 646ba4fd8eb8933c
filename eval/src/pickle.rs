//! A reader for exactly the subset of Python pickle (protocol 2-5) the official scenario-mining files use,
//! numpy arrays, dtypes and scalars included, into [`crate::Submission`].
//!
//! Two layers: [`parse_pickle`] runs the pickle machine into a [`Pickle`] (an arena of objects; an
//! object repeated by reference is stored once, and arrays point at their raw bytes instead of
//! copying them, so the arena is linear in the input), and [`Node`] is a lazy, generic view of it that
//! other formats (the 3D-tracking submission) read without a second unpickler. Decoding arrays and
//! strings out of the arena is charged to an expansion budget ([`Pickle::budget`]): a pickle whose
//! objects repeat by reference (a memo bomb) is an error once it would decode to more than
//! [`EXPANSION_FACTOR`] times its own size, instead of growing without bound.

use crate::error::EvalError;
use crate::model::{FrameData, SeqKey, Submission};
use std::collections::BTreeMap;

/// A numpy dtype as far as this reader needs it.
#[derive(Debug, Clone, PartialEq)]
struct Dtype {
    /// e.g. "f8", "i4", "U31", "b1".
    code: String,
    /// '<', '>', '|' or '='.
    endian: char,
}

#[derive(Debug, Clone)]
enum Obj {
    None,
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
    Bytes(Vec<u8>),
    Tuple(Vec<usize>),
    List(Vec<usize>),
    Dict(Vec<(usize, usize)>),
    Global(String, String),
    Dtype(Dtype),
    /// An ndarray: dtype, shape, fortran order, the arena index of its raw bytes (filled by BUILD).
    Array(Option<Dtype>, Vec<usize>, bool, Option<usize>),
    /// A numpy scalar: dtype and the arena index of its raw bytes.
    Scalar(Dtype, usize),
}

struct Machine<'a> {
    data: &'a [u8],
    pos: usize,
    arena: Vec<Obj>,
    stack: Vec<usize>,
    marks: Vec<usize>,
    memo: std::collections::HashMap<usize, usize>,
}

fn perr(msg: impl Into<String>) -> EvalError {
    EvalError::Pickle(msg.into())
}

impl<'a> Machine<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], EvalError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.data.len());
        match end {
            Some(e) => {
                let s = &self.data[self.pos..e];
                self.pos = e;
                Ok(s)
            }
            None => Err(perr(format!(
                "truncated at byte {} (wanted {n} more bytes)",
                self.pos
            ))),
        }
    }
    fn u8(&mut self) -> Result<u8, EvalError> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32, EvalError> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn u64(&mut self) -> Result<u64, EvalError> {
        let b = self.take(8)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(u64::from_le_bytes(a))
    }
    fn push(&mut self, o: Obj) {
        self.arena.push(o);
        self.stack.push(self.arena.len() - 1);
    }
    fn pop(&mut self) -> Result<usize, EvalError> {
        self.stack
            .pop()
            .ok_or_else(|| perr(format!("stack underflow at byte {}", self.pos)))
    }
    fn pop_mark(&mut self) -> Result<Vec<usize>, EvalError> {
        let m = self
            .marks
            .pop()
            .ok_or_else(|| perr(format!("no MARK at byte {}", self.pos)))?;
        if m > self.stack.len() {
            return Err(perr(format!("corrupt MARK at byte {}", self.pos)));
        }
        Ok(self.stack.split_off(m))
    }
    fn string(&mut self, n: usize) -> Result<String, EvalError> {
        let at = self.pos;
        let b = self.take(n)?;
        String::from_utf8(b.to_vec())
            .map_err(|_| perr(format!("invalid UTF-8 string at byte {at}")))
    }
    fn top_mut(&mut self) -> Result<usize, EvalError> {
        self.stack
            .last()
            .copied()
            .ok_or_else(|| perr(format!("stack underflow at byte {}", self.pos)))
    }

    fn run(&mut self) -> Result<usize, EvalError> {
        loop {
            let at = self.pos;
            let op = self.u8()?;
            match op {
                0x80 => {
                    let v = self.u8()?;
                    if v > 5 {
                        return Err(perr(format!("unsupported protocol {v}")));
                    }
                }
                0x95 => {
                    self.u64()?;
                }
                b'.' => return self.pop(),
                b'}' => self.push(Obj::Dict(Vec::new())),
                b']' => self.push(Obj::List(Vec::new())),
                b')' => self.push(Obj::Tuple(Vec::new())),
                0x94 => {
                    let top = self.top_mut()?;
                    let n = self.memo.len();
                    self.memo.insert(n, top);
                }
                b'q' => {
                    let i = self.u8()? as usize;
                    self.memo_put(i)?;
                }
                b'r' => {
                    let i = self.u32()? as usize;
                    self.memo_put(i)?;
                }
                b'h' => {
                    let i = self.u8()? as usize;
                    self.memo_get(i)?;
                }
                b'j' => {
                    let i = self.u32()? as usize;
                    self.memo_get(i)?;
                }
                b'(' => self.marks.push(self.stack.len()),
                0x8c => {
                    let n = self.u8()? as usize;
                    let s = self.string(n)?;
                    self.push(Obj::Str(s));
                }
                b'X' => {
                    let n = self.u32()? as usize;
                    let s = self.string(n)?;
                    self.push(Obj::Str(s));
                }
                0x8d => {
                    let n = usize::try_from(self.u64()?).map_err(|_| perr("string too long"))?;
                    let s = self.string(n)?;
                    self.push(Obj::Str(s));
                }
                b'C' => {
                    let n = self.u8()? as usize;
                    let b = self.take(n)?.to_vec();
                    self.push(Obj::Bytes(b));
                }
                b'B' => {
                    let n = self.u32()? as usize;
                    let b = self.take(n)?.to_vec();
                    self.push(Obj::Bytes(b));
                }
                0x8e => {
                    let n = usize::try_from(self.u64()?).map_err(|_| perr("bytes too long"))?;
                    let b = self.take(n)?.to_vec();
                    self.push(Obj::Bytes(b));
                }
                b'N' => self.push(Obj::None),
                0x88 => self.push(Obj::Bool(true)),
                0x89 => self.push(Obj::Bool(false)),
                b'K' => {
                    let v = self.u8()?;
                    self.push(Obj::Int(v as i64));
                }
                b'M' => {
                    let b = self.take(2)?;
                    self.push(Obj::Int(u16::from_le_bytes([b[0], b[1]]) as i64));
                }
                b'J' => {
                    let v = self.u32()? as i32;
                    self.push(Obj::Int(v as i64));
                }
                0x8a => {
                    let n = self.u8()? as usize;
                    let b = self.take(n)?;
                    if n > 8 {
                        return Err(perr(format!("integer too large at byte {at}")));
                    }
                    let mut v: i64 = 0;
                    for (i, &x) in b.iter().enumerate() {
                        v |= (x as i64) << (8 * i);
                    }
                    if n > 0 && n < 8 && b[n - 1] & 0x80 != 0 {
                        v -= 1i64 << (8 * n);
                    }
                    self.push(Obj::Int(v));
                }
                b'G' => {
                    let b = self.take(8)?;
                    let mut a = [0u8; 8];
                    a.copy_from_slice(b);
                    self.push(Obj::Float(f64::from_be_bytes(a)));
                }
                0x85..=0x87 => {
                    let n = (op - 0x84) as usize;
                    if self.stack.len() < n {
                        return Err(perr(format!("stack underflow at byte {at}")));
                    }
                    let items = self.stack.split_off(self.stack.len() - n);
                    self.push(Obj::Tuple(items));
                }
                b't' => {
                    let items = self.pop_mark()?;
                    self.push(Obj::Tuple(items));
                }
                b'a' => {
                    let v = self.pop()?;
                    let l = self.top_mut()?;
                    match &mut self.arena[l] {
                        Obj::List(items) => items.push(v),
                        _ => return Err(perr(format!("APPEND to a non-list at byte {at}"))),
                    }
                }
                b'e' => {
                    let items = self.pop_mark()?;
                    let l = self.top_mut()?;
                    match &mut self.arena[l] {
                        Obj::List(v) => v.extend(items),
                        _ => return Err(perr(format!("APPENDS to a non-list at byte {at}"))),
                    }
                }
                b's' | b'u' => {
                    let items = if op == b's' {
                        let v = self.pop()?;
                        let k = self.pop()?;
                        vec![k, v]
                    } else {
                        self.pop_mark()?
                    };
                    if items.len() % 2 != 0 {
                        return Err(perr(format!("odd SETITEMS at byte {at}")));
                    }
                    let d = self.top_mut()?;
                    match &mut self.arena[d] {
                        Obj::Dict(v) => v.extend(items.chunks(2).map(|c| (c[0], c[1]))),
                        _ => return Err(perr(format!("SETITEMS on a non-dict at byte {at}"))),
                    }
                }
                0x93 => {
                    let name = self.pop()?;
                    let module = self.pop()?;
                    match (&self.arena[module], &self.arena[name]) {
                        (Obj::Str(m), Obj::Str(n)) => {
                            let g = Obj::Global(m.clone(), n.clone());
                            self.push(g)
                        }
                        _ => {
                            return Err(perr(format!("STACK_GLOBAL without strings at byte {at}")))
                        }
                    }
                }
                b'R' => {
                    let args = self.pop()?;
                    let f = self.pop()?;
                    let o = self.reduce(f, args, at)?;
                    self.push(o);
                }
                b'b' => {
                    let state = self.pop()?;
                    let target = self.top_mut()?;
                    self.build(target, state, at)?;
                }
                _ => return Err(perr(format!("unsupported opcode 0x{op:02x} at byte {at}"))),
            }
        }
    }

    fn memo_put(&mut self, i: usize) -> Result<(), EvalError> {
        let top = self.top_mut()?;
        self.memo.insert(i, top);
        Ok(())
    }

    fn memo_get(&mut self, i: usize) -> Result<(), EvalError> {
        match self.memo.get(&i).copied() {
            Some(v) => {
                self.stack.push(v);
                Ok(())
            }
            None => Err(perr(format!("memo {i} not set at byte {}", self.pos))),
        }
    }

    fn tuple(&self, i: usize) -> Option<&Vec<usize>> {
        match &self.arena[i] {
            Obj::Tuple(v) => Some(v),
            _ => None,
        }
    }

    fn reduce(&self, f: usize, args: usize, at: usize) -> Result<Obj, EvalError> {
        let (module, name) = match &self.arena[f] {
            Obj::Global(m, n) => (m.as_str(), n.as_str()),
            _ => return Err(perr(format!("REDUCE on a non-global at byte {at}"))),
        };
        let args = self
            .tuple(args)
            .ok_or_else(|| perr(format!("REDUCE args not a tuple at byte {at}")))?;
        let numpy_mod = matches!(module, "numpy.core.multiarray" | "numpy._core.multiarray");
        match (module, name) {
            ("numpy", "dtype") => match args.first().map(|&a| &self.arena[a]) {
                Some(Obj::Str(code)) => Ok(Obj::Dtype(Dtype {
                    code: code.clone(),
                    endian: '=',
                })),
                _ => Err(perr(format!(
                    "numpy.dtype without a type code at byte {at}"
                ))),
            },
            (_, "_reconstruct") if numpy_mod => Ok(Obj::Array(None, Vec::new(), false, None)),
            (_, "scalar") if numpy_mod => {
                let (d, bi) = match args.as_slice() {
                    [d, b] => (&self.arena[*d], *b),
                    _ => return Err(perr(format!("numpy scalar needs 2 arguments at byte {at}"))),
                };
                match (d, &self.arena[bi]) {
                    (Obj::Dtype(d), Obj::Bytes(_)) => Ok(Obj::Scalar(d.clone(), bi)),
                    _ => Err(perr(format!(
                        "numpy scalar with unexpected arguments at byte {at}"
                    ))),
                }
            }
            _ => Err(perr(format!(
                "unsupported global {module}.{name} at byte {at}"
            ))),
        }
    }

    fn build(&mut self, target: usize, state: usize, at: usize) -> Result<(), EvalError> {
        let st = self
            .tuple(state)
            .cloned()
            .ok_or_else(|| perr(format!("BUILD state not a tuple at byte {at}")))?;
        let new = match &self.arena[target] {
            Obj::Dtype(d) => {
                let endian = match st.get(1).map(|&i| &self.arena[i]) {
                    Some(Obj::Str(s)) => s.chars().next().unwrap_or('='),
                    _ => return Err(perr(format!("dtype state without byte order at byte {at}"))),
                };
                Obj::Dtype(Dtype {
                    code: d.code.clone(),
                    endian,
                })
            }
            Obj::Array(..) => {
                let [_, shape, dtype, fortran, raw] = st.as_slice() else {
                    return Err(perr(format!(
                        "ndarray state of {} items at byte {at}",
                        st.len()
                    )));
                };
                let shape = match &self.arena[*shape] {
                    Obj::Tuple(v) => v
                        .iter()
                        .map(|&i| match self.arena[i] {
                            Obj::Int(n) if n >= 0 => Ok(n as usize),
                            _ => Err(perr(format!("bad ndarray shape at byte {at}"))),
                        })
                        .collect::<Result<Vec<_>, _>>()?,
                    _ => return Err(perr(format!("bad ndarray shape at byte {at}"))),
                };
                let dtype = match &self.arena[*dtype] {
                    Obj::Dtype(d) => d.clone(),
                    _ => return Err(perr(format!("ndarray without dtype at byte {at}"))),
                };
                let fortran = matches!(self.arena[*fortran], Obj::Bool(true));
                let raw = match &self.arena[*raw] {
                    Obj::Bytes(_) => *raw,
                    _ => {
                        return Err(perr(format!(
                            "ndarray data is not raw bytes (object array?) at byte {at}"
                        )))
                    }
                };
                Obj::Array(Some(dtype), shape, fortran, Some(raw))
            }
            _ => return Err(perr(format!("BUILD on an unsupported object at byte {at}"))),
        };
        self.arena[target] = new;
        Ok(())
    }
}

/// How many times its own size a pickle may decode to (arrays widened to `f64`, strings), before
/// [`Node`] accessors fail: a legitimate file decodes to a few times its size; a memo bomb would
/// decode to without bound.
pub const EXPANSION_FACTOR: usize = 16;
/// Bytes every pickle may decode to whatever its size (small files with many tiny arrays).
const EXPANSION_FLOOR: usize = 64 << 20;

/// A parsed pickle: the objects its opcodes built, each once (see the module documentation).
pub struct Pickle {
    arena: Vec<Obj>,
    root: usize,
    /// Bytes still allowed to be decoded out of the arena.
    budget: std::sync::atomic::AtomicUsize,
    what: String,
}

/// A lazy view of one object of a [`Pickle`].
#[derive(Clone, Copy)]
pub struct Node<'a> {
    pickle: &'a Pickle,
    index: usize,
}

/// A numeric numpy array decoded to `f64`, row-major, with its shape.
#[derive(Debug, Clone, PartialEq)]
pub struct NumArray {
    /// The values, row-major.
    pub values: Vec<f64>,
    /// The shape.
    pub shape: Vec<usize>,
    /// The numpy type code, e.g. "f8", "f4", "i8".
    pub dtype: String,
}

/// Runs the pickle machine over `data`; `what` names the source in errors.
pub fn parse_pickle(data: &[u8], what: &str) -> Result<Pickle, EvalError> {
    let mut m = Machine {
        data,
        pos: 0,
        arena: Vec::new(),
        stack: Vec::new(),
        marks: Vec::new(),
        memo: Default::default(),
    };
    let root = m.run().map_err(|e| match e {
        EvalError::Pickle(s) => EvalError::Pickle(format!("{what}: {s}")),
        e => e,
    })?;
    let budget = data
        .len()
        .saturating_mul(EXPANSION_FACTOR)
        .saturating_add(EXPANSION_FLOOR);
    Ok(Pickle {
        arena: m.arena,
        root,
        budget: std::sync::atomic::AtomicUsize::new(budget),
        what: what.to_string(),
    })
}

impl Pickle {
    /// The object the pickle returns.
    pub fn root(&self) -> Node<'_> {
        Node {
            pickle: self,
            index: self.root,
        }
    }

    /// What the pickle was read from (for error messages).
    pub fn source(&self) -> &str {
        &self.what
    }

    /// Bytes still allowed to be decoded out of this pickle.
    pub fn budget(&self) -> usize {
        self.budget.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Charges `bytes` of decoded output to the budget.
    fn charge(&self, bytes: usize) -> Result<(), String> {
        use std::sync::atomic::Ordering::Relaxed;
        let charged = self
            .budget
            .fetch_update(Relaxed, Relaxed, |left| left.checked_sub(bytes));
        if charged.is_err() {
            self.budget.store(0, Relaxed);
            return Err(format!(
                "decodes to more than {EXPANSION_FACTOR} times the file's size (objects repeated \
                 by reference without bound?)"
            ));
        }
        Ok(())
    }

    fn raw(&self, i: usize) -> &[u8] {
        match &self.arena[i] {
            Obj::Bytes(b) => b,
            _ => &[],
        }
    }

    fn node(&self, index: usize) -> Node<'_> {
        Node {
            pickle: self,
            index,
        }
    }
}

impl<'a> Node<'a> {
    fn obj(&self) -> &'a Obj {
        &self.pickle.arena[self.index]
    }

    /// A short name of the object's type, for error messages ("dict", "list", "ndarray", …).
    pub fn kind(&self) -> &'static str {
        match self.obj() {
            Obj::None => "None",
            Obj::Bool(_) => "bool",
            Obj::Int(_) => "int",
            Obj::Float(_) => "float",
            Obj::Str(_) => "str",
            Obj::Bytes(_) => "bytes",
            Obj::Tuple(_) => "tuple",
            Obj::List(_) => "list",
            Obj::Dict(_) => "dict",
            Obj::Global(..) => "global",
            Obj::Dtype(_) => "dtype",
            Obj::Array(..) => "ndarray",
            Obj::Scalar(..) => "numpy scalar",
        }
    }

    /// The items of a dict, in the pickle's order.
    pub fn dict(&self) -> Option<Vec<(Node<'a>, Node<'a>)>> {
        match self.obj() {
            Obj::Dict(items) => Some(
                items
                    .iter()
                    .map(|&(k, v)| (self.pickle.node(k), self.pickle.node(v)))
                    .collect(),
            ),
            _ => None,
        }
    }

    /// The items of a list or tuple.
    pub fn items(&self) -> Option<Vec<Node<'a>>> {
        match self.obj() {
            Obj::List(items) | Obj::Tuple(items) => {
                Some(items.iter().map(|&i| self.pickle.node(i)).collect())
            }
            _ => None,
        }
    }

    /// A string.
    pub fn str(&self) -> Option<&'a str> {
        match self.obj() {
            Obj::Str(s) => Some(s),
            _ => None,
        }
    }

    /// An integer: a Python int or an integer numpy scalar (exactly, even past 2^53).
    pub fn int(&self) -> Option<i64> {
        match self.obj() {
            Obj::Int(i) => Some(*i),
            Obj::Bool(b) => Some(*b as i64),
            Obj::Scalar(d, b) => scalar_i64(d, self.pickle.raw(*b)),
            _ => None,
        }
    }

    /// A number: a Python int or float, or a numeric numpy scalar.
    pub fn float(&self) -> Option<f64> {
        match self.obj() {
            Obj::Int(i) => Some(*i as f64),
            Obj::Float(f) => Some(*f),
            Obj::Scalar(d, b) => decode(d, self.pickle.raw(*b))
                .ok()
                .and_then(|x| x.first().copied()),
            _ => None,
        }
    }

    /// A numeric numpy array (C order), decoded to `f64` and charged to the budget; the error
    /// says what is wrong (not an array, an unsupported dtype, data of the wrong size).
    pub fn num_array(&self) -> Result<NumArray, String> {
        let Obj::Array(Some(d), shape, fortran, Some(raw)) = self.obj() else {
            return Err(format!("expected a numpy array, got {}", self.kind()));
        };
        if *fortran && shape.len() > 1 {
            return Err("Fortran-order arrays are not supported".into());
        }
        let raw = self.pickle.raw(*raw);
        let want = shape.iter().try_fold(1usize, |a, &d| a.checked_mul(d));
        let width = dtype_width(d).ok_or_else(|| format!("unsupported dtype {:?}", d.code))?;
        if want.and_then(|n| n.checked_mul(width)) != Some(raw.len()) {
            return Err(format!(
                "{} bytes of {} data for shape {shape:?}",
                raw.len(),
                d.code
            ));
        }
        self.pickle.charge(raw.len() / width * 8)?;
        let values = decode(d, raw)?;
        Ok(NumArray {
            values,
            shape: shape.clone(),
            dtype: d.code.trim_start_matches(['<', '>', '=', '|']).to_string(),
        })
    }

    /// A 1-d numpy unicode array (`U<n>`) as strings, charged to the budget.
    pub fn str_array(&self) -> Result<Vec<String>, String> {
        let Obj::Array(Some(d), shape, _, Some(raw)) = self.obj() else {
            return Err(format!(
                "expected a numpy string array, got {}",
                self.kind()
            ));
        };
        if shape.len() != 1 {
            return Err(format!("expected a 1-d array, got shape {shape:?}"));
        }
        let raw = self.pickle.raw(*raw);
        let chars: usize = d
            .code
            .strip_prefix('U')
            .and_then(|n| n.parse().ok())
            .ok_or_else(|| format!("expected a unicode dtype, got {:?}", d.code))?;
        let n = shape[0];
        if n.checked_mul(chars).and_then(|x| x.checked_mul(4)) != Some(raw.len()) {
            return Err("string array data of the wrong size".into());
        }
        self.pickle.charge(raw.len() / 4 + n * 24)?;
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            let mut s = String::new();
            for c in 0..chars {
                let o = (i * chars + c) * 4;
                let b = [raw[o], raw[o + 1], raw[o + 2], raw[o + 3]];
                let cp = if d.endian == '>' {
                    u32::from_be_bytes(b)
                } else {
                    u32::from_le_bytes(b)
                };
                if cp == 0 {
                    break;
                }
                s.push(char::from_u32(cp).ok_or("invalid code point")?);
            }
            out.push(s);
        }
        Ok(out)
    }
}

/// Bytes per value of a numeric dtype.
fn dtype_width(d: &Dtype) -> Option<usize> {
    match d.code.trim_start_matches(['<', '>', '=', '|']) {
        "f8" | "i8" | "u8" => Some(8),
        "f4" | "i4" | "u4" => Some(4),
        "i2" | "u2" => Some(2),
        "i1" | "u1" | "b1" => Some(1),
        _ => None,
    }
}

/// Reads a scenario-mining pickle from bytes; `what` names the source in errors.
pub fn read_pickle_bytes(data: &[u8], what: &str) -> Result<Submission, EvalError> {
    let pickle = parse_pickle(data, what)?;
    Conv { pickle: &pickle }.submission(pickle.root)
}

/// Reads a scenario-mining pickle file.
pub fn read_pickle(path: &std::path::Path) -> Result<Submission, EvalError> {
    let data = std::fs::read(path).map_err(|e| EvalError::Io(path.display().to_string(), e))?;
    read_pickle_bytes(&data, &path.display().to_string())
}

struct Conv<'a> {
    pickle: &'a Pickle,
}

impl Conv<'_> {
    fn ferr(&self, place: &str, msg: impl std::fmt::Display) -> EvalError {
        EvalError::Format(format!("{}: {place}: {msg}", self.pickle.what))
    }

    fn node(&self, i: usize) -> Node<'_> {
        self.pickle.node(i)
    }

    fn submission(&self, root: usize) -> Result<Submission, EvalError> {
        let Obj::Dict(items) = &self.pickle.arena[root] else {
            return Err(self.ferr("top level", "expected a dict of (log_id, prompt) -> frames"));
        };
        let mut sequences = BTreeMap::new();
        for &(k, v) in items {
            let key = self.seq_key(k)?;
            let place = format!("sequence {key:?}");
            let Obj::List(frames) = &self.pickle.arena[v] else {
                return Err(self.ferr(&place, "expected a list of frames"));
            };
            let mut out = Vec::with_capacity(frames.len());
            for (i, &f) in frames.iter().enumerate() {
                out.push(self.frame(f, &format!("{place} frame {i}"))?);
            }
            if sequences.insert(key, out).is_some() {
                return Err(self.ferr(&place, "duplicate sequence"));
            }
        }
        Ok(Submission { sequences })
    }

    fn seq_key(&self, k: usize) -> Result<SeqKey, EvalError> {
        match &self.pickle.arena[k] {
            Obj::Tuple(v) if v.len() == 2 => {
                match (&self.pickle.arena[v[0]], &self.pickle.arena[v[1]]) {
                    (Obj::Str(a), Obj::Str(b)) => Ok((a.clone(), b.clone())),
                    _ => Err(self.ferr("sequence key", "expected (log_id, prompt) strings")),
                }
            }
            Obj::Str(s) => parse_seq_str(s)
                .ok_or_else(|| self.ferr("sequence key", format!("cannot parse {s:?}"))),
            _ => Err(self.ferr("sequence key", "expected a (log_id, prompt) tuple")),
        }
    }

    fn frame(&self, f: usize, place: &str) -> Result<FrameData, EvalError> {
        let Obj::Dict(items) = &self.pickle.arena[f] else {
            return Err(self.ferr(place, "expected a dict"));
        };
        let mut fr = FrameData::default();
        let mut n: Option<(usize, &'static str)> = None;
        let mut has_ts = false;
        for &(k, v) in items {
            let Obj::Str(key) = &self.pickle.arena[k] else {
                return Err(self.ferr(place, "non-string key"));
            };
            let fp = format!("{place} field {key:?}");
            let mut check = |len: usize, name: &'static str| -> Result<(), EvalError> {
                match n {
                    Some((m, other)) if m != len => {
                        Err(self.ferr(&fp, format!("has {len} objects but {other:?} has {m}")))
                    }
                    _ => {
                        n = Some((len, name));
                        Ok(())
                    }
                }
            };
            match key.as_str() {
                "timestamp_ns" => {
                    fr.timestamp_ns = self
                        .int(v)
                        .ok_or_else(|| self.ferr(&fp, "expected an integer"))?;
                    has_ts = true;
                }
                "ego_translation_m" => {
                    let vals = self
                        .float_list(v)
                        .ok_or_else(|| self.ferr(&fp, "expected 3 numbers"))?;
                    let [a, b, c] = vals.as_slice() else {
                        return Err(self.ferr(&fp, "expected 3 numbers"));
                    };
                    fr.ego_translation_m = [*a, *b, *c];
                }
                "description" => match &self.pickle.arena[v] {
                    Obj::Str(s) => fr.description = Some(s.clone()),
                    Obj::None => {}
                    _ => return Err(self.ferr(&fp, "expected a string")),
                },
                "is_positive" => {
                    fr.is_positive = Some(match &self.pickle.arena[v] {
                        Obj::None => None,
                        Obj::Bool(b) => Some(*b),
                        Obj::Int(i) => Some(*i != 0),
                        Obj::Scalar(d, b) if d.code == "b1" || d.code == "?" => {
                            Some(self.pickle.raw(*b).first().copied().unwrap_or(0) != 0)
                        }
                        _ => return Err(self.ferr(&fp, "expected True, False or None")),
                    })
                }
                "translation_m" | "velocity_m_per_s" => {
                    let a = self.num(v, &fp)?;
                    let rows = self.rows3(&a, &fp)?;
                    check(
                        rows.len(),
                        if key == "translation_m" {
                            "translation_m"
                        } else {
                            "velocity_m_per_s"
                        },
                    )?;
                    if key == "translation_m" {
                        fr.translation_m = rows;
                    } else {
                        fr.velocity_m_per_s = rows;
                    }
                }
                "size" => {
                    let a = self.num(v, &fp)?;
                    let rows = self.rows3(&a, &fp)?;
                    check(rows.len(), "size")?;
                    fr.size = rows
                        .iter()
                        .map(|r| [r[0] as f32, r[1] as f32, r[2] as f32])
                        .collect();
                }
                "yaw" | "score" => {
                    let a = self.num(v, &fp)?;
                    if a.shape.len() != 1 {
                        return Err(self.ferr(
                            &fp,
                            format!("expected a 1-d array, got shape {:?}", a.shape),
                        ));
                    }
                    check(a.values.len(), if key == "yaw" { "yaw" } else { "score" })?;
                    let v32: Vec<f32> = a.values.iter().map(|&x| x as f32).collect();
                    if key == "yaw" {
                        fr.yaw = v32;
                    } else {
                        fr.score = Some(v32);
                    }
                }
                "label" | "track_id" => {
                    let a = self.num(v, &fp)?;
                    if a.shape.len() != 1 {
                        return Err(self.ferr(
                            &fp,
                            format!("expected a 1-d array, got shape {:?}", a.shape),
                        ));
                    }
                    check(
                        a.values.len(),
                        if key == "label" { "label" } else { "track_id" },
                    )?;
                    let mut out = Vec::with_capacity(a.values.len());
                    for &x in &a.values {
                        if x.fract() != 0.0 || x < i32::MIN as f64 || x > i32::MAX as f64 {
                            return Err(
                                self.ferr(&fp, format!("value {x} is not a 32-bit integer"))
                            );
                        }
                        out.push(x as i32);
                    }
                    if key == "label" {
                        fr.label = out;
                    } else {
                        fr.track_id = out;
                    }
                }
                "name" => {
                    let names = self.strings(v, &fp)?;
                    check(names.len(), "name")?;
                    fr.name = names;
                }
                _ => {}
            }
        }
        if !has_ts {
            return Err(self.ferr(place, "missing field \"timestamp_ns\""));
        }
        if let Some((len, _)) = n {
            let checks: [(&str, usize); 6] = [
                ("translation_m", fr.translation_m.len()),
                ("size", fr.size.len()),
                ("yaw", fr.yaw.len()),
                ("label", fr.label.len()),
                ("name", fr.name.len()),
                ("track_id", fr.track_id.len()),
            ];
            for (name, l) in checks {
                if l != len {
                    return Err(self.ferr(
                        place,
                        format!("field {name:?} missing or of length {l}, expected {len}"),
                    ));
                }
            }
        }
        Ok(fr)
    }

    fn int(&self, v: usize) -> Option<i64> {
        match &self.pickle.arena[v] {
            Obj::Bool(_) => None,
            _ => self.node(v).int(),
        }
    }

    fn float_list(&self, v: usize) -> Option<Vec<f64>> {
        let node = self.node(v);
        if let Ok(a) = node.num_array() {
            return Some(a.values);
        }
        node.items()?.iter().map(|n| n.float()).collect()
    }

    fn num(&self, v: usize, fp: &str) -> Result<NumArray, EvalError> {
        self.node(v).num_array().map_err(|m| self.ferr(fp, m))
    }

    fn rows3(&self, a: &NumArray, fp: &str) -> Result<Vec<[f64; 3]>, EvalError> {
        match a.shape.as_slice() {
            [_, 3] => Ok(a.values.chunks(3).map(|c| [c[0], c[1], c[2]]).collect()),
            [0] | [0, _] => Ok(Vec::new()),
            s => Err(self.ferr(fp, format!("expected shape (N, 3), got {s:?}"))),
        }
    }

    fn strings(&self, v: usize, fp: &str) -> Result<Vec<String>, EvalError> {
        self.node(v).str_array().map_err(|m| self.ferr(fp, m))
    }
}

/// An integer numpy scalar, exactly (timestamps exceed f64 precision).
fn scalar_i64(d: &Dtype, b: &[u8]) -> Option<i64> {
    let code = d.code.trim_start_matches(['<', '>', '=', '|']);
    let be = d.endian == '>';
    let mut a = [0u8; 8];
    match (code, b.len()) {
        ("i8" | "u8", 8) => {
            a.copy_from_slice(b);
            let v = if be {
                u64::from_be_bytes(a)
            } else {
                u64::from_le_bytes(a)
            };
            if code == "i8" {
                Some(v as i64)
            } else {
                i64::try_from(v).ok()
            }
        }
        _ => decode(d, b)
            .ok()
            .and_then(|x| x.first().copied())
            .filter(|x| x.fract() == 0.0)
            .map(|x| x as i64),
    }
}

/// Decodes raw numeric numpy bytes to f64.
#[allow(clippy::modulo_one)]
fn decode(d: &Dtype, raw: &[u8]) -> Result<Vec<f64>, String> {
    let be = d.endian == '>';
    let code = d.code.trim_start_matches(['<', '>', '=', '|']);
    macro_rules! dec {
        ($t:ty, $n:expr) => {{
            if raw.len() % $n != 0 {
                return Err(format!(
                    "{} bytes is not a whole number of {} values",
                    raw.len(),
                    code
                ));
            }
            raw.chunks($n)
                .map(|c| {
                    let mut a = [0u8; $n];
                    a.copy_from_slice(c);
                    (if be {
                        <$t>::from_be_bytes(a)
                    } else {
                        <$t>::from_le_bytes(a)
                    }) as f64
                })
                .collect()
        }};
    }
    Ok(match code {
        "f8" => dec!(f64, 8),
        "f4" => dec!(f32, 4),
        "i8" => dec!(i64, 8),
        "i4" => dec!(i32, 4),
        "i2" => dec!(i16, 2),
        "i1" => dec!(i8, 1),
        "u8" => dec!(u64, 8),
        "u4" => dec!(u32, 4),
        "u2" => dec!(u16, 2),
        "u1" | "b1" => dec!(u8, 1),
        other => return Err(format!("unsupported dtype {other:?}")),
    })
}

/// Parses the string form "('log', 'prompt')" of a sequence key.
fn parse_seq_str(s: &str) -> Option<SeqKey> {
    let inner = s.strip_prefix("('")?.strip_suffix("')")?;
    let (a, b) = inner.split_once("', '")?;
    Some((a.to_string(), b.to_string()))
}
