//! Writes a [`Submission`] as the official pickle (protocol 4, numpy arrays), loadable by Python's
//! `pickle.load` with numpy installed.

use crate::error::EvalError;
use crate::model::{FrameData, Submission};
use std::io::Write;
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
        let width = f
            .name
            .iter()
            .map(|s| s.chars().count())
            .max()
            .unwrap_or(0)
            .max(31);
        let mut raw = Vec::with_capacity(f.name.len() * width * 4);
        for s in &f.name {
            let mut c = 0;
            for ch in s.chars() {
                raw.extend_from_slice(&(ch as u32).to_le_bytes());
                c += 1;
            }
            raw.resize(raw.len() + (width - c) * 4, 0);
        }
        let code = format!("U{width}");
        self.array(
            &[f.name.len()],
            |w| w.dtype(&code, "<", (width * 4) as i32, 4, 8),
            &raw,
        );
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

/// Encodes a submission as pickle bytes (protocol 4).
pub fn pickle_bytes(sub: &Submission) -> Vec<u8> {
    let mut w = W { out: vec![0x80, 4] };
    w.op(b'}');
    w.op(b'(');
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
    w.op(b'u');
    w.op(b'.');
    w.out
}

/// Writes a submission as a pickle file atomically (a temporary file in the same directory, then rename).
pub fn write_pickle(sub: &Submission, path: &Path) -> Result<(), EvalError> {
    let bytes = pickle_bytes(sub);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp{}", std::process::id()));
    let io = |e| EvalError::Io(path.display().to_string(), e);
    let mut f = std::fs::File::create(&tmp).map_err(io)?;
    f.write_all(&bytes).map_err(io)?;
    f.sync_all().map_err(io)?;
    drop(f);
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io(e)
    })
}
