//! [`Node`], a lazy generic view of one object of a parsed [`Pickle`], decoding strings, numbers
//! and numpy arrays on demand against the pickle's expansion budget.

use super::*;

/// A lazy view of one object of a [`Pickle`].
#[derive(Clone, Copy)]
pub struct Node<'a> {
    pub(crate) pickle: &'a Pickle,
    pub(crate) index: usize,
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

impl<'a> Node<'a> {
    pub(crate) fn obj(&self) -> &'a Obj {
        &self.pickle.arena[self.index]
    }

    /// A short name of the object's type, for error messages ("dict", "list", "ndarray", …).
    pub fn kind(&self) -> &'static str {
        self.obj().kind()
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
