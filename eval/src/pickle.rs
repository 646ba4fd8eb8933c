//! A reader for the subset of Python pickle the official scenario-mining files and trackers'
//! outputs use, into [`crate::Submission`]: every protocol (0–5, what `pickle.dump` writes by
//! default in any Python 3), plain containers, strings, numbers, and numpy arrays (C or Fortran
//! order, in-band protocol-5 buffers, any byte order and int/float width, object arrays of
//! strings or numbers), dtypes and scalars. Nothing is ever executed: a global is only ever one
//! of a fixed list of names (numpy's array, dtype and scalar constructors, `bytes`, `bytearray`,
//! `_codecs.encode`, `set`, `OrderedDict`), read as data; any other is an error saying what to
//! write instead.
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
use crate::numpy_data::{decode, fortran_to_c, scalar_i64, width, Dtype};
use crate::pickle_text::{quoted_string, raw_unicode_escape};
use std::collections::BTreeMap;

/// What to do with a pickle this reader refuses, appended to the error.
const WRITE_HINT: &str = "write the file with `pickle.dump(obj, f)` (any protocol 0-5) from \
     plain dicts, lists, tuples, str, int, float, bool, None and numpy arrays or scalars";

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
    /// An ndarray: dtype, shape, fortran order, the arena index of its data (filled by BUILD):
    /// raw bytes, or a list of objects for numpy's object dtype.
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
    /// A protocol-0 argument: the bytes up to the next newline (which is consumed).
    fn line(&mut self) -> Result<&'a [u8], EvalError> {
        let rest = &self.data[self.pos.min(self.data.len())..];
        let n = rest.iter().position(|&b| b == b'\n').ok_or_else(|| {
            perr(format!(
                "truncated at byte {} (a text argument without its newline)",
                self.pos
            ))
        })?;
        self.pos += n + 1;
        Ok(&rest[..n])
    }
    /// A protocol-0 argument line as ASCII text.
    fn text_line(&mut self) -> Result<&'a str, EvalError> {
        let at = self.pos;
        let line = self.line()?;
        std::str::from_utf8(line).map_err(|_| perr(format!("non-ASCII argument at byte {at}")))
    }
    /// A protocol-0 integer argument (`INT`, `LONG`, `PUT`, `GET`).
    fn int_line(&mut self, at: usize) -> Result<i64, EvalError> {
        let text = self.text_line()?;
        let digits = text.trim().trim_end_matches('L');
        digits.parse().map_err(|_| {
            perr(format!(
                "integer {text:?} out of range or malformed at byte {at}"
            ))
        })
    }
    /// A protocol-0 memo index.
    fn memo_line(&mut self, at: usize) -> Result<usize, EvalError> {
        let i = self.int_line(at)?;
        usize::try_from(i).map_err(|_| perr(format!("negative memo index at byte {at}")))
    }
    /// Sign-extends a little-endian two's-complement integer of at most 8 bytes (`LONG1`/`LONG4`).
    fn long(&mut self, n: usize, at: usize) -> Result<Obj, EvalError> {
        if n > 8 {
            return Err(perr(format!(
                "integer of {n} bytes at byte {at}: larger than 64 bits"
            )));
        }
        let b = self.take(n)?;
        let mut v: i64 = 0;
        for (i, &x) in b.iter().enumerate() {
            v |= (x as i64) << (8 * i);
        }
        if n > 0 && n < 8 && b[n - 1] & 0x80 != 0 {
            v -= 1i64 << (8 * n);
        }
        Ok(Obj::Int(v))
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
                        return Err(perr(format!(
                            "pickle protocol {v} is newer than 5, the highest read here: \
                             write it with `pickle.dump(obj, f, protocol=5)` or lower"
                        )));
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
                    let o = self.long(n, at)?;
                    self.push(o);
                }
                0x8b => {
                    let n = self.u32()? as usize;
                    let o = self.long(n, at)?;
                    self.push(o);
                }
                // Protocol 0 and 1: arguments as text lines.
                b'I' => {
                    let text = self.text_line()?;
                    let o = match text {
                        "00" => Obj::Bool(false),
                        "01" => Obj::Bool(true),
                        t => Obj::Int(t.trim().parse().map_err(|_| {
                            perr(format!(
                                "integer {t:?} out of range or malformed at byte {at}"
                            ))
                        })?),
                    };
                    self.push(o);
                }
                b'L' => {
                    let v = self.int_line(at)?;
                    self.push(Obj::Int(v));
                }
                b'F' => {
                    let text = self.text_line()?;
                    let v = text
                        .trim()
                        .parse::<f64>()
                        .map_err(|_| perr(format!("float {text:?} malformed at byte {at}")))?;
                    self.push(Obj::Float(v));
                }
                b'V' => {
                    let line = self.line()?;
                    let s =
                        raw_unicode_escape(line).map_err(|e| perr(format!("{e} at byte {at}")))?;
                    self.push(Obj::Str(s));
                }
                b'S' => {
                    let line = self.line()?;
                    let b = quoted_string(line).map_err(|e| perr(format!("{e} at byte {at}")))?;
                    // Python 3 reads a STRING as str (ASCII by default).
                    let s = String::from_utf8(b)
                        .map_err(|_| perr(format!("non-ASCII STRING at byte {at}")))?;
                    self.push(Obj::Str(s));
                }
                b'U' => {
                    let n = self.u8()? as usize;
                    let b = self.take(n)?.to_vec();
                    self.push(Obj::Bytes(b));
                }
                b'T' => {
                    let n = self.u32()? as usize;
                    let b = self.take(n)?.to_vec();
                    self.push(Obj::Bytes(b));
                }
                b'p' => {
                    let i = self.memo_line(at)?;
                    self.memo_put(i)?;
                }
                b'g' => {
                    let i = self.memo_line(at)?;
                    self.memo_get(i)?;
                }
                b'c' => {
                    let module = self.text_line()?.to_string();
                    let name = self.text_line()?.to_string();
                    self.push(Obj::Global(module, name));
                }
                b'l' => {
                    let items = self.pop_mark()?;
                    self.push(Obj::List(items));
                }
                b'd' => {
                    let items = self.pop_mark()?;
                    if items.len() % 2 != 0 {
                        return Err(perr(format!("odd DICT at byte {at}")));
                    }
                    let pairs = items.chunks(2).map(|c| (c[0], c[1])).collect();
                    self.push(Obj::Dict(pairs));
                }
                b'0' => {
                    self.pop()?;
                }
                b'1' => {
                    self.pop_mark()?;
                }
                b'2' => {
                    let top = self.top_mut()?;
                    self.stack.push(top);
                }
                // Sets (protocol 4) are read as lists of their items.
                0x8f => self.push(Obj::List(Vec::new())),
                0x90 => {
                    let items = self.pop_mark()?;
                    let l = self.top_mut()?;
                    match &mut self.arena[l] {
                        Obj::List(v) => v.extend(items),
                        _ => return Err(perr(format!("ADDITEMS to a non-set at byte {at}"))),
                    }
                }
                0x91 => {
                    let items = self.pop_mark()?;
                    self.push(Obj::List(items));
                }
                // Protocol 5: a bytearray, and in-band buffers (already bytes).
                0x96 => {
                    let n = usize::try_from(self.u64()?).map_err(|_| perr("bytearray too long"))?;
                    let b = self.take(n)?.to_vec();
                    self.push(Obj::Bytes(b));
                }
                0x98 => {
                    self.top_mut()?;
                }
                0x97 => {
                    return Err(perr(format!(
                        "out-of-band buffer (NEXT_BUFFER) at byte {at}: the file was written with \
                         `pickle.dump(..., protocol=5, buffer_callback=...)` and its array data is \
                         not in it; write it without `buffer_callback`"
                    )))
                }
                0x81 | 0x92 => {
                    if op == 0x92 {
                        // NEWOBJ_EX's keyword arguments: only an empty dict is read.
                        let kwargs = self.pop()?;
                        if !matches!(&self.arena[kwargs], Obj::Dict(d) if d.is_empty()) {
                            return Err(perr(format!(
                                "NEWOBJ_EX with keyword arguments at byte {at}; {WRITE_HINT}"
                            )));
                        }
                    }
                    let args = self.pop()?;
                    let cls = self.pop()?;
                    let o = self.reduce(cls, args, at)?;
                    self.push(o);
                }
                b'P' | b'Q' | b'i' | b'o' | 0x82..=0x84 => {
                    let what = match op {
                        b'P' | b'Q' => "a persistent id (a custom Pickler.persistent_id)",
                        b'i' | b'o' => "an instance of a class (INST/OBJ)",
                        _ => "a copyreg extension code (EXT)",
                    };
                    return Err(perr(format!(
                        "{what} at byte {at} is not read (nothing is executed); {WRITE_HINT}"
                    )));
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
                _ => {
                    return Err(perr(format!(
                        "unknown opcode 0x{op:02x} at byte {at} (not a pickle, or a corrupt one); \
                         {WRITE_HINT}"
                    )))
                }
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

    /// What a call of a global makes, for the few globals read as data; any other is an error.
    fn reduce(&self, f: usize, args: usize, at: usize) -> Result<Obj, EvalError> {
        let (module, name) = match &self.arena[f] {
            Obj::Global(m, n) => (m.as_str(), n.as_str()),
            _ => return Err(perr(format!("REDUCE on a non-global at byte {at}"))),
        };
        let args = self
            .tuple(args)
            .ok_or_else(|| perr(format!("REDUCE args not a tuple at byte {at}")))?;
        let arg = |k: usize| args.get(k).map(|&a| &self.arena[a]);
        let numpy_core = |sub: &str| {
            module
                .strip_prefix("numpy.core.")
                .or_else(|| module.strip_prefix("numpy._core."))
                == Some(sub)
        };
        let builtins = matches!(module, "builtins" | "__builtin__");
        match (module, name) {
            ("numpy", "dtype") => match arg(0) {
                Some(Obj::Str(code)) => Ok(Obj::Dtype(Dtype {
                    code: code.clone(),
                    endian: '=',
                })),
                _ => Err(perr(format!(
                    "numpy.dtype without a type code at byte {at}"
                ))),
            },
            (_, "_reconstruct") if numpy_core("multiarray") => match arg(0) {
                Some(Obj::Global(m, n)) if m == "numpy" && n == "ndarray" => {
                    Ok(Obj::Array(None, Vec::new(), false, None))
                }
                Some(Obj::Global(m, n)) => Err(perr(format!(
                    "a numpy array subclass {m}.{n} at byte {at}: store `np.asarray(x)` instead"
                ))),
                _ => Err(perr(format!(
                    "numpy _reconstruct without a class at byte {at}"
                ))),
            },
            (_, "_frombuffer") if numpy_core("numeric") => {
                let (Some(Obj::Bytes(_)), Some(Obj::Dtype(d)), Some(Obj::Tuple(shape))) =
                    (arg(0), arg(1), arg(2))
                else {
                    return Err(perr(format!(
                        "numpy _frombuffer with unexpected arguments at byte {at}"
                    )));
                };
                let fortran = match arg(3) {
                    Some(Obj::Str(o)) => o == "F",
                    _ => false,
                };
                let shape = self.shape(shape, at)?;
                Ok(Obj::Array(Some(d.clone()), shape, fortran, Some(args[0])))
            }
            (_, "scalar") if numpy_core("multiarray") => {
                let (d, bi) = match args.as_slice() {
                    [d, b] => (&self.arena[*d], *b),
                    _ => return Err(perr(format!("numpy scalar needs 2 arguments at byte {at}"))),
                };
                match (d, &self.arena[bi]) {
                    (Obj::Dtype(d), Obj::Bytes(_)) => Ok(Obj::Scalar(d.clone(), bi)),
                    (Obj::Dtype(d), _) => Err(perr(format!(
                        "a numpy scalar of dtype {:?} at byte {at} (an object scalar?): store a \
                         number or a string",
                        d.code
                    ))),
                    _ => Err(perr(format!(
                        "numpy scalar with unexpected arguments at byte {at}"
                    ))),
                }
            }
            // How protocols 0-2 write bytes: `_codecs.encode(text, "latin1")`, `bytes()`.
            ("_codecs", "encode") => match (arg(0), arg(1)) {
                (Some(Obj::Str(text)), Some(Obj::Str(enc)))
                    if enc == "latin1" || enc == "latin-1" =>
                {
                    text.chars()
                        .map(|c| u8::try_from(u32::from(c)).ok())
                        .collect::<Option<Vec<u8>>>()
                        .map(Obj::Bytes)
                        .ok_or_else(|| perr(format!("non-Latin-1 bytes text at byte {at}")))
                }
                _ => Err(perr(format!(
                    "_codecs.encode with unexpected arguments at byte {at}"
                ))),
            },
            (_, "bytes" | "bytearray") if builtins => match arg(0) {
                None => Ok(Obj::Bytes(Vec::new())),
                Some(Obj::Bytes(b)) => Ok(Obj::Bytes(b.clone())),
                _ => Err(perr(format!(
                    "{name}() with unexpected arguments at byte {at}"
                ))),
            },
            (_, "set" | "frozenset") if builtins => match arg(0) {
                None => Ok(Obj::List(Vec::new())),
                Some(Obj::List(items)) => Ok(Obj::List(items.clone())),
                _ => Err(perr(format!(
                    "{name}() with unexpected arguments at byte {at}"
                ))),
            },
            ("collections", "OrderedDict" | "defaultdict") => Ok(Obj::Dict(Vec::new())),
            _ => {
                let hint = if module.starts_with("pandas") {
                    "a pandas object: store plain numpy arrays (`df[[...]].to_numpy()`) in dicts"
                } else {
                    WRITE_HINT
                };
                Err(perr(format!(
                    "global {module}.{name} at byte {at} is not read (nothing is executed); {hint}"
                )))
            }
        }
    }

    /// An array shape: a tuple of non-negative ints.
    fn shape(&self, items: &[usize], at: usize) -> Result<Vec<usize>, EvalError> {
        items
            .iter()
            .map(|&i| match self.arena[i] {
                Obj::Int(n) if n >= 0 => Ok(n as usize),
                _ => Err(perr(format!("bad ndarray shape at byte {at}"))),
            })
            .collect()
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
                    Obj::Tuple(v) => self.shape(v, at)?,
                    _ => return Err(perr(format!("bad ndarray shape at byte {at}"))),
                };
                let dtype = match &self.arena[*dtype] {
                    Obj::Dtype(d) => d.clone(),
                    _ => return Err(perr(format!("ndarray without dtype at byte {at}"))),
                };
                let fortran = matches!(self.arena[*fortran], Obj::Bool(true));
                let raw = match &self.arena[*raw] {
                    Obj::Bytes(_) => *raw,
                    Obj::List(_) if dtype.is_object() => *raw,
                    _ => {
                        return Err(perr(format!(
                            "ndarray data of dtype {:?} is neither raw bytes nor a list of \
                             objects at byte {at}",
                            dtype.code
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

    /// A numeric numpy array decoded to `f64` in row-major order (Fortran-order data reordered,
    /// object arrays of numbers read item by item), charged to the budget; the error says what
    /// is wrong (not an array, an unsupported dtype, data of the wrong size).
    pub fn num_array(&self) -> Result<NumArray, String> {
        let Obj::Array(Some(d), shape, fortran, Some(raw)) = self.obj() else {
            return Err(format!("expected a numpy array, got {}", self.kind()));
        };
        let want = shape.iter().try_fold(1usize, |a, &d| a.checked_mul(d));
        let values = if let Obj::List(items) = &self.pickle.arena[*raw] {
            if Some(items.len()) != want {
                return Err(format!("{} objects for shape {shape:?}", items.len()));
            }
            self.pickle.charge(items.len() * 8)?;
            items
                .iter()
                .map(|&i| {
                    let n = self.pickle.node(i);
                    n.float().ok_or_else(|| {
                        format!("an object array holding a {}, not numbers", n.kind())
                    })
                })
                .collect::<Result<Vec<f64>, String>>()?
        } else {
            let raw = self.pickle.raw(*raw);
            let width = width(d).ok_or_else(|| crate::numpy_data::unsupported(d))?;
            if want.and_then(|n| n.checked_mul(width)) != Some(raw.len()) {
                return Err(format!(
                    "{} bytes of {} data for shape {shape:?}",
                    raw.len(),
                    d.code
                ));
            }
            self.pickle.charge(raw.len() / width * 8)?;
            decode(d, raw)?
        };
        let values = if *fortran {
            fortran_to_c(&values, shape)
        } else {
            values
        };
        Ok(NumArray {
            values,
            shape: shape.clone(),
            dtype: d.bare().to_string(),
        })
    }

    /// A 1-d array of strings as Rust strings, charged to the budget: numpy unicode (`U<n>`,
    /// either byte order), bytes (`S<n>`, UTF-8) or an object array of `str` (what pandas'
    /// `.to_numpy()` gives for a text column).
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
        let n = shape[0];
        if let Obj::List(items) = &self.pickle.arena[*raw] {
            if items.len() != n {
                return Err(format!("{} objects for shape {shape:?}", items.len()));
            }
            self.pickle.charge(n * 24)?;
            return items
                .iter()
                .map(|&i| {
                    let node = self.pickle.node(i);
                    node.str().map(str::to_string).ok_or_else(|| {
                        format!("an object array holding a {}, not strings", node.kind())
                    })
                })
                .collect();
        }
        let raw = self.pickle.raw(*raw);
        let (kind, chars) = d.bare().split_at(1.min(d.bare().len()));
        let chars: usize = chars
            .parse()
            .ok()
            .filter(|_| kind == "U" || kind == "S")
            .ok_or_else(|| format!("expected a string dtype (U or S), got {:?}", d.code))?;
        let unit = if kind == "U" { 4 } else { 1 };
        if n.checked_mul(chars).and_then(|x| x.checked_mul(unit)) != Some(raw.len()) {
            return Err("string array data of the wrong size".into());
        }
        self.pickle.charge(raw.len() / unit + n * 24)?;
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            let item = &raw[i * chars * unit..(i + 1) * chars * unit];
            let s = if unit == 1 {
                let end = item.iter().position(|&b| b == 0).unwrap_or(item.len());
                String::from_utf8(item[..end].to_vec())
                    .map_err(|_| "a bytes string that is not UTF-8".to_string())?
            } else {
                let mut s = String::new();
                for c in item.chunks_exact(4) {
                    let b = [c[0], c[1], c[2], c[3]];
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
                s
            };
            out.push(s);
        }
        Ok(out)
    }
}

/// Reads a scenario-mining pickle from bytes; `what` names the source in errors.
pub fn read_pickle_bytes(data: &[u8], what: &str) -> Result<Submission, EvalError> {
    let pickle = parse_pickle(data, what)?;
    let sub = Conv { pickle: &pickle }.submission(pickle.root)?;
    sub.validate(what)?;
    Ok(sub)
}

/// Reads a scenario-mining pickle file.
pub fn read_pickle(path: &std::path::Path) -> Result<Submission, EvalError> {
    let data = scenalog_input::read_regular_file(path, scenalog_input::DATA_LIMIT)
        .map_err(|p| EvalError::File(path.display().to_string(), p))?;
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
                        Obj::Scalar(d, b) if d.bare() == "b1" || d.bare() == "?" => {
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

/// Parses the string form "('log', 'prompt')" of a sequence key.
fn parse_seq_str(s: &str) -> Option<SeqKey> {
    let inner = s.strip_prefix("('")?.strip_suffix("')")?;
    let (a, b) = inner.split_once("', '")?;
    Some((a.to_string(), b.to_string()))
}
