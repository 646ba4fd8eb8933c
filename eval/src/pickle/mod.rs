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

pub mod join;
mod machine;
mod node;
mod submission;
pub mod write;

use machine::Machine;
pub use node::{Node, NumArray};
pub use submission::{read_pickle, read_pickle_bytes};

/// What to do with a pickle this reader refuses, appended to the error.
pub(crate) const WRITE_HINT: &str =
    "write the file with `pickle.dump(obj, f)` (any protocol 0-5) from \
     plain dicts, lists, tuples, str, int, float, bool, None and numpy arrays or scalars";

#[derive(Debug, Clone)]
pub(crate) enum Obj {
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

impl Obj {
    /// A short name of the object's type, for error messages ("dict", "list", "ndarray", …).
    pub(crate) fn kind(&self) -> &'static str {
        match self {
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
}

pub(crate) fn perr(msg: impl Into<String>) -> EvalError {
    EvalError::Pickle(msg.into())
}

/// How many times its own size a pickle may decode to (arrays widened to `f64`, strings), before
/// [`Node`] accessors fail: a legitimate file decodes to a few times its size; a memo bomb would
/// decode to without bound.
pub const EXPANSION_FACTOR: usize = 16;
/// Bytes every pickle may decode to whatever its size (small files with many tiny arrays).
pub(crate) const EXPANSION_FLOOR: usize = 64 << 20;

/// A parsed pickle: the objects its opcodes built, each once (see the module documentation).
pub struct Pickle {
    pub(crate) arena: Vec<Obj>,
    pub(crate) root: usize,
    /// Bytes still allowed to be decoded out of the arena.
    pub(crate) budget: std::sync::atomic::AtomicUsize,
    pub(crate) what: String,
}

/// Runs the pickle machine over `data`; `what` names the source in errors.
pub fn parse_pickle(data: &[u8], what: &str) -> Result<Pickle, EvalError> {
    parse(data, what, false)
}

/// Runs the pickle machine over `data`, whose top level must be a dict (a submission, a
/// tracker's output): any other top level is an error as soon as the opcode that makes it is
/// read, instead of after the whole file is decoded.
pub fn parse_pickle_dict(data: &[u8], what: &str) -> Result<Pickle, EvalError> {
    parse(data, what, true)
}

/// The ends of a pickle whose top level must be a dict, for
/// [`scenalog_input::read_file_checking_ends`]: it ends with STOP, and its first bytes do not
/// already make another top level (a 1 GB list is refused from its first 64 bytes, before it is
/// read).
pub fn dict_pickle_ends(head: &[u8], tail: &[u8]) -> Result<(), String> {
    scenalog_input::ends::pickle_ends(head, tail)?;
    let mut m = machine(head, true);
    if m.run().is_err() {
        if let Err(EvalError::Pickle(e)) = m.check_top(m.pos) {
            return Err(format!("is a pickle, but {e}"));
        }
    }
    Ok(())
}

/// The ends of a submission: an Arrow table's, else a dict pickle's ([`dict_pickle_ends`]).
pub fn submission_ends(head: &[u8], tail: &[u8]) -> Result<(), String> {
    if head.starts_with(b"ARROW1") {
        scenalog_input::ends::arrow_ends(head, tail)
    } else {
        dict_pickle_ends(head, tail)
    }
}

fn machine(data: &[u8], top_dict: bool) -> Machine<'_> {
    Machine {
        data,
        pos: 0,
        arena: Vec::new(),
        stack: Vec::new(),
        marks: Vec::new(),
        memo: Default::default(),
        top_dict,
    }
}

fn parse(data: &[u8], what: &str, top_dict: bool) -> Result<Pickle, EvalError> {
    let mut m = machine(data, top_dict);
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
    pub(crate) fn charge(&self, bytes: usize) -> Result<(), String> {
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

    pub(crate) fn raw(&self, i: usize) -> &[u8] {
        match &self.arena[i] {
            Obj::Bytes(b) => b,
            _ => &[],
        }
    }

    pub(crate) fn node(&self, index: usize) -> Node<'_> {
        Node {
            pickle: self,
            index,
        }
    }
}
