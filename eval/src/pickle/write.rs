//! Writes a [`Submission`] as the official pickle (protocol 4, numpy arrays), loadable by Python's
//! `pickle.load` with numpy installed.

use crate::error::EvalError;
use crate::model::{FrameData, Submission};
use std::path::Path;

const MODULE: &str = "numpy.core.multiarray";

struct W {
    out: Vec<u8>,
}

impl W {
    fn op(&mut self, b: u8) {
        self.out.push(b);
    }
    fn str(&mut self, s: &str) {
        self.op(b'X');
        self.out.extend_from_slice(&(s.len() as u32).to_le_bytes());
        self.out.extend_from_slice(s.as_bytes());
    }
    fn int(&mut self, v: i32) {
        self.op(b'J');
        self.out.extend_from_slice(&v.to_le_bytes());
    }
    fn bytes(&mut self, b: &[u8]) {
        self.op(b'B');
        self.out.extend_from_slice(&(b.len() as u32).to_le_bytes());
        self.out.extend_from_slice(b);
    }
    fn global(&mut self, module: &str, name: &str) {
        self.str(module);
        self.str(name);
        self.op(0x93);
    }
    fn none(&mut self) {
        self.op(b'N');
    }
    fn bool(&mut self, b: bool) {
        self.op(if b { 0x88 } else { 0x89 });
    }
    /// `numpy.dtype(code)` with its BUILD state; `elsize` is -1 except for string dtypes.
    fn dtype(&mut self, code: &str, endian: &str, elsize: i32, alignment: i32, flags: i32) {
        self.global("numpy", "dtype");
        self.str(code);
        self.bool(false);
        self.bool(true);
        self.op(0x87);
        self.op(b'R');
        self.op(b'(');
        self.int(3);
        self.str(endian);
        self.none();
        self.none();
        self.none();
        self.int(elsize);
        self.int(alignment);
        self.int(flags);
        self.op(b't');
        self.op(b'b');
    }
    fn num_dtype(&mut self, code: &str) {
        let endian = if code == "b1" { "|" } else { "<" };
        self.dtype(code, endian, -1, -1, 0);
    }
    fn scalar(&mut self, code: &str, raw: &[u8]) {
        self.global(MODULE, "scalar");
        self.num_dtype(code);
        self.bytes(raw);
        self.op(0x86);
        self.op(b'R');
    }
    /// An ndarray of `shape` whose dtype is written by `dtype`.
    fn array(&mut self, shape: &[usize], dtype: impl FnOnce(&mut W), raw: &[u8]) {
        self.global(MODULE, "_reconstruct");
        self.global("numpy", "ndarray");
        self.int(0);
        self.op(0x85);
        self.op(b'C');
        self.op(1);
        self.op(b'b');
        self.op(0x87);
        self.op(b'R');
        self.op(b'(');
        self.int(1);
        self.op(b'(');
        for &d in shape {
            self.int(d as i32);
        }
        self.op(b't');
        dtype(self);
        self.bool(false);
        self.bytes(raw);
        self.op(b't');
        self.op(b'b');
    }
    /// A 1-d unicode array, `U<n>` with n the longest string (at least `min_width`).
    fn str_array(&mut self, items: &[String], min_width: usize) {
        let width = items
            .iter()
            .map(|s| s.chars().count())
            .max()
            .unwrap_or(0)
            .max(min_width);
        let mut raw = Vec::with_capacity(items.len() * width * 4);
        for s in items {
            let mut c = 0;
            for ch in s.chars() {
                raw.extend_from_slice(&(ch as u32).to_le_bytes());
                c += 1;
            }
            raw.resize(raw.len() + (width - c) * 4, 0);
        }
        let code = format!("U{width}");
        self.array(
            &[items.len()],
            |w| w.dtype(&code, "<", (width * 4) as i32, 4, 8),
            &raw,
        );
    }

    fn frame(&mut self, key: &(String, String), f: &FrameData) {
        let n = f.len();
        self.op(b'}');
        self.op(b'(');
        self.str("seq_id");
        self.str(&key.0);
        self.str(&key.1);
        self.op(0x86);
        self.str("timestamp_ns");
        self.scalar("i8", &f.timestamp_ns.to_le_bytes());
        self.str("ego_translation_m");
        self.op(b']');
        self.op(b'(');
        for v in f.ego_translation_m {
            self.scalar("f8", &v.to_le_bytes());
        }
        self.op(b'e');
        if let Some(d) = &f.description {
            self.str("description");
            self.str(d);
        }
        let f64s = |rows: &[[f64; 3]]| -> Vec<u8> {
            rows.iter()
                .flatten()
                .flat_map(|v| v.to_le_bytes())
                .collect()
        };
        self.str("translation_m");
        self.array(&[n, 3], |w| w.num_dtype("f8"), &f64s(&f.translation_m));
        self.str("size");
        let raw: Vec<u8> = f
            .size
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        self.array(&[f.size.len(), 3], |w| w.num_dtype("f4"), &raw);
        self.str("yaw");
        let raw: Vec<u8> = f.yaw.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.array(&[f.yaw.len()], |w| w.num_dtype("f4"), &raw);
        self.str("velocity_m_per_s");
        self.array(
            &[f.velocity_m_per_s.len(), 3],
            |w| w.num_dtype("f8"),
            &f64s(&f.velocity_m_per_s),
        );
        self.str("label");
        let raw: Vec<u8> = f.label.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.array(&[f.label.len()], |w| w.num_dtype("i4"), &raw);
        self.str("name");
        self.str_array(&f.name, 31);
        self.str("track_id");
        let raw: Vec<u8> = f.track_id.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.array(&[f.track_id.len()], |w| w.num_dtype("i4"), &raw);
        if let Some(s) = &f.score {
            self.str("score");
            let raw: Vec<u8> = s.iter().flat_map(|v| v.to_le_bytes()).collect();
            self.array(&[s.len()], |w| w.num_dtype("f4"), &raw);
        }
        if let Some(p) = f.is_positive {
            self.str("is_positive");
            match p {
                None => self.none(),
                Some(b) => self.bool(b),
            }
        }
        self.op(b'u');
    }
}

/// A Python value to pickle with [`encode_value`]: the few shapes other formats of the benchmark
/// need (the 3D-tracking submission: a dict of lists of dicts of numpy arrays).
#[derive(Debug, Clone, PartialEq)]
pub enum PyValue {
    /// A `str`.
    Str(String),
    /// A numpy `int64` scalar.
    I64(i64),
    /// A `list`.
    List(Vec<PyValue>),
    /// A `dict`, items in this order.
    Dict(Vec<(PyValue, PyValue)>),
    /// A `float64` ndarray of this shape (row-major values).
    F64Array(Vec<usize>, Vec<f64>),
    /// A `float32` ndarray of this shape.
    F32Array(Vec<usize>, Vec<f32>),
    /// A 1-d `int64` ndarray.
    I64Array(Vec<i64>),
    /// A 1-d unicode ndarray (`U<n>`, n the longest string, at least 1).
    StrArray(Vec<String>),
}

impl W {
    fn value(&mut self, v: &PyValue) {
        match v {
            PyValue::Str(s) => self.str(s),
            PyValue::I64(i) => self.scalar("i8", &i.to_le_bytes()),
            PyValue::List(items) => {
                self.op(b']');
                if !items.is_empty() {
                    self.op(b'(');
                    for i in items {
                        self.value(i);
                    }
                    self.op(b'e');
                }
            }
            PyValue::Dict(items) => {
                self.op(b'}');
                if !items.is_empty() {
                    self.op(b'(');
                    for (k, v) in items {
                        self.value(k);
                        self.value(v);
                    }
                    self.op(b'u');
                }
            }
            PyValue::F64Array(shape, vals) => {
                let raw: Vec<u8> = vals.iter().flat_map(|v| v.to_le_bytes()).collect();
                self.array(shape, |w| w.num_dtype("f8"), &raw);
            }
            PyValue::F32Array(shape, vals) => {
                let raw: Vec<u8> = vals.iter().flat_map(|v| v.to_le_bytes()).collect();
                self.array(shape, |w| w.num_dtype("f4"), &raw);
            }
            PyValue::I64Array(vals) => {
                let raw: Vec<u8> = vals.iter().flat_map(|v| v.to_le_bytes()).collect();
                self.array(&[vals.len()], |w| w.num_dtype("i8"), &raw);
            }
            PyValue::StrArray(items) => self.str_array(items, 1),
        }
    }
}

/// Encodes one Python value as pickle bytes (protocol 4, numpy arrays as `pickle.dump` writes
/// them).
pub fn encode_value(v: &PyValue) -> Vec<u8> {
    let mut w = W { out: vec![0x80, 4] };
    w.value(v);
    w.op(b'.');
    w.out
}

/// The bytes a submission pickle starts with (protocol 4, an empty dict, a MARK).
pub const SUBMISSION_HEAD: &[u8] = &[0x80, 4, b'}', b'('];
/// The bytes a submission pickle ends with (SETITEMS, STOP).
pub const SUBMISSION_TAIL: &[u8] = b"u.";

/// The middle of a submission pickle: each sequence's key and frames, in key order. A file made
/// of [`SUBMISSION_HEAD`], the bodies of submissions with disjoint keys in key order, and
/// [`SUBMISSION_TAIL`] is byte for byte [`pickle_bytes`] of their union, so a run can write its
/// submission one log at a time.
pub fn sequences_bytes(sub: &Submission) -> Vec<u8> {
    let mut w = W { out: Vec::new() };
    for (key, frames) in &sub.sequences {
        w.str(&key.0);
        w.str(&key.1);
        w.op(0x86);
        w.op(b']');
        w.op(b'(');
        for f in frames {
            w.frame(key, f);
        }
        w.op(b'e');
    }
    w.out
}

/// Encodes a submission as pickle bytes (protocol 4).
pub fn pickle_bytes(sub: &Submission) -> Vec<u8> {
    let mut out = SUBMISSION_HEAD.to_vec();
    out.extend(sequences_bytes(sub));
    out.extend_from_slice(SUBMISSION_TAIL);
    out
}

/// Writes a submission as a pickle file atomically (a temporary file in the same directory, then rename).
pub fn write_pickle(sub: &Submission, path: &Path) -> Result<(), EvalError> {
    let bytes = pickle_bytes(sub);
    // The temporary file is removed on any failure (a full disk must not stay full of it).
    scenalog_input::out_dir::write_atomic(path, &bytes, true)
        .map_err(|e| EvalError::Io(path.display().to_string(), e))
}
