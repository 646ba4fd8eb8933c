//! numpy's raw array bytes as numbers: every integer and float width a tracker writes (`i1`–`i8`,
//! `u1`–`u8`, `f2`, `f4`, `f8`, `b1`), either byte order, and Fortran-order data put back in
//! row-major (C) order.

/// A numpy dtype as far as the pickle reader needs it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Dtype {
    /// e.g. "f8", "i4", "U31", "b1", "O8".
    pub(crate) code: String,
    /// '<', '>', '|' or '='.
    pub(crate) endian: char,
}

impl Dtype {
    /// The type code without a byte-order prefix.
    pub(crate) fn bare(&self) -> &str {
        self.code.trim_start_matches(['<', '>', '=', '|'])
    }

    /// Whether multi-byte values are big-endian ('>' in the dtype's state or code).
    fn big_endian(&self) -> bool {
        self.endian == '>' || self.code.starts_with('>')
    }

    /// Whether it is numpy's object dtype (the array's data is a list of Python objects).
    pub(crate) fn is_object(&self) -> bool {
        self.bare().starts_with('O')
    }
}

/// Bytes per value of a numeric dtype, `None` for any other.
pub(crate) fn width(d: &Dtype) -> Option<usize> {
    match d.bare() {
        "f8" | "i8" | "u8" => Some(8),
        "f4" | "i4" | "u4" => Some(4),
        "f2" | "i2" | "u2" => Some(2),
        "i1" | "u1" | "b1" | "?" => Some(1),
        _ => None,
    }
}

/// What to do about a dtype this reader does not decode, for error messages.
pub(crate) fn unsupported(d: &Dtype) -> String {
    let code = d.bare();
    let hint = match code.chars().next() {
        Some('M' | 'm') => "store times as int64 nanoseconds (`.astype(\"int64\")`)",
        Some('c') => "complex numbers have no meaning here",
        Some('V') => "structured arrays are not read: store one plain array per field",
        _ => "convert it with `.astype(\"float64\")` or `.astype(\"int64\")`",
    };
    format!("unsupported numpy dtype {code:?}: {hint}")
}

/// An IEEE half-precision float.
fn half_to_f64(bits: u16) -> f64 {
    let sign = if bits & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = i32::from((bits >> 10) & 0x1f);
    let frac = f64::from(bits & 0x3ff);
    match exp {
        0 => sign * frac * 2f64.powi(-24),
        0x1f if frac == 0.0 => sign * f64::INFINITY,
        0x1f => f64::NAN,
        e => sign * (1.0 + frac / 1024.0) * 2f64.powi(e - 15),
    }
}

/// Decodes raw numeric numpy bytes to `f64`, in the order they are stored.
#[allow(clippy::modulo_one)]
pub(crate) fn decode(d: &Dtype, raw: &[u8]) -> Result<Vec<f64>, String> {
    let be = d.big_endian();
    let code = d.bare();
    macro_rules! dec {
        ($t:ty, $n:expr, $conv:expr) => {{
            if raw.len() % $n != 0 {
                return Err(format!(
                    "{} bytes is not a whole number of {} values",
                    raw.len(),
                    code
                ));
            }
            raw.chunks_exact($n)
                .map(|c| {
                    let mut a = [0u8; $n];
                    a.copy_from_slice(c);
                    let v = if be {
                        <$t>::from_be_bytes(a)
                    } else {
                        <$t>::from_le_bytes(a)
                    };
                    $conv(v)
                })
                .collect()
        }};
    }
    Ok(match code {
        "f8" => dec!(f64, 8, |v: f64| v),
        "f4" => dec!(f32, 4, f64::from),
        "f2" => dec!(u16, 2, half_to_f64),
        "i8" => dec!(i64, 8, |v: i64| v as f64),
        "i4" => dec!(i32, 4, f64::from),
        "i2" => dec!(i16, 2, f64::from),
        "i1" => dec!(i8, 1, f64::from),
        "u8" => dec!(u64, 8, |v: u64| v as f64),
        "u4" => dec!(u32, 4, f64::from),
        "u2" => dec!(u16, 2, f64::from),
        "u1" | "b1" | "?" => dec!(u8, 1, f64::from),
        _ => return Err(unsupported(d)),
    })
}

/// An integer numpy scalar, exactly (timestamps exceed `f64` precision).
pub(crate) fn scalar_i64(d: &Dtype, b: &[u8]) -> Option<i64> {
    let code = d.bare();
    let be = d.big_endian();
    match (code, <[u8; 8]>::try_from(b)) {
        ("i8" | "u8", Ok(a)) => {
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

/// Reorders values stored in Fortran (column-major) order for `shape` into C (row-major) order.
pub(crate) fn fortran_to_c<T: Copy>(values: &[T], shape: &[usize]) -> Vec<T> {
    if shape.len() < 2 {
        return values.to_vec();
    }
    // Fortran strides: the first axis varies fastest.
    let mut strides = vec![1usize; shape.len()];
    for k in 1..shape.len() {
        strides[k] = strides[k - 1] * shape[k - 1];
    }
    let mut out = Vec::with_capacity(values.len());
    let mut index = vec![0usize; shape.len()];
    for _ in 0..values.len() {
        let at: usize = index.iter().zip(&strides).map(|(i, s)| i * s).sum();
        out.push(values[at]);
        // The next C-order index: the last axis varies fastest.
        for k in (0..shape.len()).rev() {
            index[k] += 1;
            if index[k] < shape[k] {
                break;
            }
            index[k] = 0;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dt(code: &str, endian: char) -> Dtype {
        Dtype {
            code: code.into(),
            endian,
        }
    }

    #[test]
    fn widths_orders_and_halves() {
        assert_eq!(decode(&dt("i2", '>'), &[0xff, 0xfe]).unwrap(), [-2.0]);
        assert_eq!(decode(&dt("i2", '<'), &[0xfe, 0xff]).unwrap(), [-2.0]);
        assert_eq!(decode(&dt("u2", '>'), &[0x01, 0x00]).unwrap(), [256.0]);
        assert_eq!(decode(&dt("f2", '<'), &[0x00, 0x3c]).unwrap(), [1.0]);
        assert_eq!(decode(&dt("f2", '<'), &[0x00, 0xc1]).unwrap(), [-2.5]);
        assert_eq!(
            decode(&dt("f2", '<'), &[0x01, 0x00]).unwrap(),
            [2f64.powi(-24)]
        );
        assert!(decode(&dt("f2", '<'), &[0x00, 0x7c]).unwrap()[0].is_infinite());
        assert_eq!(
            decode(&dt("f8", '>'), &1.5f64.to_be_bytes()).unwrap(),
            [1.5]
        );
        assert!(decode(&dt("M8", '<'), &[0; 8])
            .unwrap_err()
            .contains("int64 nanoseconds"));
        let big = dt("i8", '>');
        assert_eq!(
            scalar_i64(&big, &1_700_000_000_123_456_789i64.to_be_bytes()),
            Some(1_700_000_000_123_456_789)
        );
    }

    #[test]
    fn fortran_order_becomes_row_major() {
        // [[1, 2, 3], [4, 5, 6]] stored column by column.
        assert_eq!(
            fortran_to_c(&[1, 4, 2, 5, 3, 6], &[2, 3]),
            vec![1, 2, 3, 4, 5, 6]
        );
        // A 2x2x2 array: element (i, j, k) = 100i + 10j + k.
        let mut f = Vec::new();
        for k in 0..2 {
            for j in 0..2 {
                for i in 0..2 {
                    f.push(100 * i + 10 * j + k);
                }
            }
        }
        assert_eq!(
            fortran_to_c(&f, &[2, 2, 2]),
            vec![0, 1, 10, 11, 100, 101, 110, 111]
        );
        assert_eq!(fortran_to_c(&[7, 8], &[2]), vec![7, 8]);
    }
}
