//! The pickle machine: opcodes of protocols 0–5 run over the input into an arena of objects
//! (an object repeated by reference stored once, arrays pointing at their raw bytes); a global
//! is only ever one of a fixed list of names, read as data.

use super::*;

pub(crate) struct Machine<'a> {
    pub(crate) data: &'a [u8],
    pub(crate) pos: usize,
    pub(crate) arena: Vec<Obj>,
    pub(crate) stack: Vec<usize>,
    pub(crate) marks: Vec<usize>,
    pub(crate) memo: std::collections::HashMap<usize, usize>,
    /// The top level must be a dict: checked at every opcode (see [`Machine::check_top`]).
    pub(crate) top_dict: bool,
}

impl<'a> Machine<'a> {
    pub(crate) fn take(&mut self, n: usize) -> Result<&'a [u8], EvalError> {
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
    pub(crate) fn u8(&mut self) -> Result<u8, EvalError> {
        Ok(self.take(1)?[0])
    }
    pub(crate) fn u32(&mut self) -> Result<u32, EvalError> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    pub(crate) fn u64(&mut self) -> Result<u64, EvalError> {
        let b = self.take(8)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(u64::from_le_bytes(a))
    }
    pub(crate) fn push(&mut self, o: Obj) {
        self.arena.push(o);
        self.stack.push(self.arena.len() - 1);
    }
    pub(crate) fn pop(&mut self) -> Result<usize, EvalError> {
        self.stack
            .pop()
            .ok_or_else(|| perr(format!("stack underflow at byte {}", self.pos)))
    }
    pub(crate) fn pop_mark(&mut self) -> Result<Vec<usize>, EvalError> {
        let m = self
            .marks
            .pop()
            .ok_or_else(|| perr(format!("no MARK at byte {}", self.pos)))?;
        if m > self.stack.len() {
            return Err(perr(format!("corrupt MARK at byte {}", self.pos)));
        }
        Ok(self.stack.split_off(m))
    }
    pub(crate) fn string(&mut self, n: usize) -> Result<String, EvalError> {
        let at = self.pos;
        let b = self.take(n)?;
        String::from_utf8(b.to_vec())
            .map_err(|_| perr(format!("invalid UTF-8 string at byte {at}")))
    }
    /// A protocol-0 argument: the bytes up to the next newline (which is consumed).
    pub(crate) fn line(&mut self) -> Result<&'a [u8], EvalError> {
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
    pub(crate) fn text_line(&mut self) -> Result<&'a str, EvalError> {
        let at = self.pos;
        let line = self.line()?;
        std::str::from_utf8(line).map_err(|_| perr(format!("non-ASCII argument at byte {at}")))
    }
    /// A protocol-0 integer argument (`INT`, `LONG`, `PUT`, `GET`).
    pub(crate) fn int_line(&mut self, at: usize) -> Result<i64, EvalError> {
        let text = self.text_line()?;
        let digits = text.trim().trim_end_matches('L');
        digits.parse().map_err(|_| {
            perr(format!(
                "integer {text:?} out of range or malformed at byte {at}"
            ))
        })
    }
    /// A protocol-0 memo index.
    pub(crate) fn memo_line(&mut self, at: usize) -> Result<usize, EvalError> {
        let i = self.int_line(at)?;
        usize::try_from(i).map_err(|_| perr(format!("negative memo index at byte {at}")))
    }
    /// Sign-extends a little-endian two's-complement integer of at most 8 bytes (`LONG1`/`LONG4`).
    pub(crate) fn long(&mut self, n: usize, at: usize) -> Result<Obj, EvalError> {
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
    pub(crate) fn top_mut(&mut self) -> Result<usize, EvalError> {
        self.stack
            .last()
            .copied()
            .ok_or_else(|| perr(format!("stack underflow at byte {}", self.pos)))
    }

    /// With no MARK open, the bottom of the stack is what the pickle returns, or the first item
    /// of the top-level tuple a `TUPLE1`-`TUPLE3` will make (Python's pickler writes the
    /// top-level object first and never pops it). When the top level must be a dict, anything
    /// there but a dict or a global still to be called means it is not one, said before the rest
    /// of the file is decoded, naming what the pickle starts with.
    pub(crate) fn check_top(&self, at: usize) -> Result<(), EvalError> {
        if !self.top_dict || !self.marks.is_empty() {
            return Ok(());
        }
        match self.stack.first().map(|&i| &self.arena[i]) {
            None | Some(Obj::Dict(_) | Obj::Global(..)) => Ok(()),
            Some(other) => {
                let kind = other.kind();
                let a = if kind.starts_with(['a', 'i', 'n']) && kind != "None" {
                    "an"
                } else {
                    "a"
                };
                Err(perr(format!(
                    "the top level is not a dict: it starts with {a} {kind} (seen at byte \
                     {at}, before reading the rest)"
                )))
            }
        }
    }

    pub(crate) fn run(&mut self) -> Result<usize, EvalError> {
        loop {
            let at = self.pos;
            self.check_top(at)?;
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

    pub(crate) fn memo_put(&mut self, i: usize) -> Result<(), EvalError> {
        let top = self.top_mut()?;
        self.memo.insert(i, top);
        Ok(())
    }

    pub(crate) fn memo_get(&mut self, i: usize) -> Result<(), EvalError> {
        match self.memo.get(&i).copied() {
            Some(v) => {
                self.stack.push(v);
                Ok(())
            }
            None => Err(perr(format!("memo {i} not set at byte {}", self.pos))),
        }
    }

    pub(crate) fn tuple(&self, i: usize) -> Option<&Vec<usize>> {
        match &self.arena[i] {
            Obj::Tuple(v) => Some(v),
            _ => None,
        }
    }

    /// What a call of a global makes, for the few globals read as data; any other is an error.
    pub(crate) fn reduce(&self, f: usize, args: usize, at: usize) -> Result<Obj, EvalError> {
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
    pub(crate) fn shape(&self, items: &[usize], at: usize) -> Result<Vec<usize>, EvalError> {
        items
            .iter()
            .map(|&i| match self.arena[i] {
                Obj::Int(n) if n >= 0 => Ok(n as usize),
                _ => Err(perr(format!("bad ndarray shape at byte {at}"))),
            })
            .collect()
    }

    pub(crate) fn build(
        &mut self,
        target: usize,
        state: usize,
        at: usize,
    ) -> Result<(), EvalError> {
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
