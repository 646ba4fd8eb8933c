//! Reading selected, typed columns of an Arrow IPC file (feather v2, LZ4 or uncompressed).

use std::io::Cursor;
use std::path::Path;

use arrow_array::{
    Array, ArrayRef, Float64Array, Int64Array, LargeStringArray, RecordBatch, StringArray,
    StringViewArray,
};
use arrow_ipc::reader::FileReader;
use arrow_schema::DataType;

use crate::error::LoadError;

/// The type a column must have.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// 64-bit signed integers.
    Int64,
    /// 64-bit floats.
    Float64,
    /// UTF-8 strings (`utf8`, `large_utf8` or `utf8_view`).
    Str,
}

impl Kind {
    fn describe(self) -> &'static str {
        match self {
            Kind::Int64 => "int64",
            Kind::Float64 => "double (float64)",
            Kind::Str => "string (utf8)",
        }
    }

    fn accepts(self, ty: &DataType) -> bool {
        match self {
            Kind::Int64 => *ty == DataType::Int64,
            Kind::Float64 => *ty == DataType::Float64,
            Kind::Str => matches!(
                ty,
                DataType::Utf8 | DataType::LargeUtf8 | DataType::Utf8View
            ),
        }
    }
}

/// A column the caller needs: its name and type.
pub(crate) type ColumnWant = (&'static str, Kind);

/// The record batches of a file, projected to the wanted columns in the wanted order, with every
/// column checked for type and nulls.
pub(crate) struct Table {
    /// The batches; column `i` of each is the `i`-th wanted column.
    pub batches: Vec<RecordBatch>,
}

impl Table {
    /// Total number of rows.
    pub fn num_rows(&self) -> usize {
        self.batches.iter().map(|b| b.num_rows()).sum()
    }
}

/// Reads `path`, an Arrow IPC file, keeping only the `wanted` columns (in that order).
pub(crate) fn read_table(path: &Path, wanted: &[ColumnWant]) -> Result<Table, LoadError> {
    let bytes = std::fs::read(path).map_err(|source| io_error(path, source))?;
    let not_arrow = |e: arrow_schema::ArrowError| LoadError::NotArrow {
        path: path.to_path_buf(),
        reason: e.to_string(),
    };
    if bytes.len() < 12 || &bytes[..6] != b"ARROW1" {
        return Err(LoadError::NotArrow {
            path: path.to_path_buf(),
            reason: "the file does not start with the Arrow magic bytes `ARROW1`".into(),
        });
    }
    let footer_fits = read_i32(&bytes, bytes.len() - 10)
        .and_then(|l| usize::try_from(l).ok())
        .is_some_and(|l| l + 10 + 8 <= bytes.len());
    if &bytes[bytes.len() - 6..] != b"ARROW1" || !footer_fits {
        return Err(LoadError::NotArrow {
            path: path.to_path_buf(),
            reason: "the file does not end with an Arrow IPC footer (cut short?)".into(),
        });
    }
    // The footer is small: read it once for the schema, then again with the projection.
    let schema = guard(path, || {
        FileReader::try_new(Cursor::new(&bytes[..]), None).map(|r| r.schema())
    })?
    .map_err(not_arrow)?;
    let mut projection = Vec::with_capacity(wanted.len());
    for &(name, kind) in wanted {
        let (index, field) = schema
            .column_with_name(name)
            .ok_or(LoadError::MissingColumn {
                path: path.to_path_buf(),
                column: name,
                expected: kind.describe(),
            })?;
        if !kind.accepts(field.data_type()) {
            return Err(LoadError::ColumnType {
                path: path.to_path_buf(),
                column: name,
                expected: kind.describe(),
                found: field.data_type().to_string(),
            });
        }
        projection.push(index);
    }
    check_declared_sizes(path, &bytes)?;
    let batches = guard(path, || {
        let reader = FileReader::try_new(Cursor::new(&bytes[..]), Some(projection))?;
        reader.collect::<Result<Vec<RecordBatch>, _>>()
    })?
    .map_err(not_arrow)?;
    let mut first_row = 0;
    for batch in &batches {
        for (i, &(name, _)) in wanted.iter().enumerate() {
            let col = batch.column(i);
            if col.null_count() > 0 {
                let row = (0..col.len()).find(|&r| col.is_null(r)).unwrap_or(0);
                return Err(LoadError::Null {
                    path: path.to_path_buf(),
                    column: name,
                    row: first_row + row,
                });
            }
        }
        first_row += batch.num_rows();
    }
    Ok(Table { batches })
}

/// LZ4 cannot expand data more than about 255-fold; a buffer declaring more is corrupt.
const MAX_EXPANSION: u64 = 256;

/// Checks the sizes a file declares before the Arrow decoder trusts them: every record batch
/// block lies inside the file, every buffer inside its block, no batch declares more rows, and no
/// compressed buffer more uncompressed bytes, than its compressed size allows. Without this a
/// corrupt length makes the decoder try to allocate terabytes and abort the process.
fn check_declared_sizes(path: &Path, bytes: &[u8]) -> Result<(), LoadError> {
    let corrupt = |reason: String| LoadError::NotArrow {
        path: path.to_path_buf(),
        reason,
    };
    let n = bytes.len();
    let footer_len = read_i32(bytes, n.wrapping_sub(10)).unwrap_or(-1);
    let footer_start = usize::try_from(footer_len)
        .ok()
        .and_then(|l| n.checked_sub(10 + l))
        .ok_or_else(|| corrupt("bad footer length".into()))?;
    let footer = arrow_ipc::root_as_footer(&bytes[footer_start..n - 10])
        .map_err(|e| corrupt(format!("bad footer: {e}")))?;
    let blocks = footer.recordBatches().into_iter().flatten();
    let dictionaries = footer.dictionaries().into_iter().flatten();
    for (i, block) in blocks.chain(dictionaries).enumerate() {
        let range = |what: &str| corrupt(format!("block {i}: {what} lies outside the file"));
        let offset = usize::try_from(block.offset()).map_err(|_| range("offset"))?;
        let meta_len = usize::try_from(block.metaDataLength()).map_err(|_| range("metadata"))?;
        let body_len = usize::try_from(block.bodyLength()).map_err(|_| range("body"))?;
        let body_start = offset
            .checked_add(meta_len)
            .ok_or_else(|| range("metadata"))?;
        let body_end = body_start
            .checked_add(body_len)
            .filter(|&e| e <= n)
            .ok_or_else(|| range("body"))?;
        let meta = &bytes[offset..body_start];
        // Metadata: [0xFFFFFFFF continuation] i32 length, then the flatbuffer message.
        let skip = if meta.get(..4) == Some(&[0xFF; 4]) {
            8
        } else {
            4
        };
        let message = meta
            .get(skip..)
            .and_then(|m| arrow_ipc::root_as_message(m).ok())
            .ok_or_else(|| corrupt(format!("block {i}: unreadable message header")))?;
        let Some(batch) = message
            .header_as_record_batch()
            .or_else(|| message.header_as_dictionary_batch().and_then(|d| d.data()))
        else {
            continue;
        };
        let max_len = (body_len as u64).saturating_mul(MAX_EXPANSION) + 1024;
        let lengths = std::iter::once(batch.length()).chain(
            batch
                .nodes()
                .into_iter()
                .flatten()
                .map(|node| node.length()),
        );
        for len in lengths {
            if u64::try_from(len).map_or(true, |l| l > max_len) {
                return Err(corrupt(format!(
                    "block {i} declares {len} rows in a body of {body_len} bytes"
                )));
            }
        }
        // ZSTD can expand further, but this build decodes LZ4 only (ZSTD files fail later).
        let compressed = batch
            .compression()
            .is_some_and(|c| c.codec() == arrow_ipc::CompressionType::LZ4_FRAME);
        for buf in batch.buffers().into_iter().flatten() {
            let start = usize::try_from(buf.offset())
                .ok()
                .and_then(|o| o.checked_add(body_start));
            let len = usize::try_from(buf.length()).ok();
            let (Some(start), Some(len)) = (start, len) else {
                return Err(corrupt(format!(
                    "block {i}: negative buffer offset or length"
                )));
            };
            if start.checked_add(len).is_none_or(|e| e > body_end) {
                return Err(corrupt(format!(
                    "block {i}: a buffer lies outside its body"
                )));
            }
            if compressed && len >= 8 {
                let declared = read_i64(bytes, start).unwrap_or(-1);
                let limit = (len as u64).saturating_mul(MAX_EXPANSION) + 1024;
                if declared != -1 && u64::try_from(declared).map_or(true, |d| d > limit) {
                    return Err(corrupt(format!(
                        "block {i}: a compressed buffer of {len} bytes declares {declared} uncompressed bytes"
                    )));
                }
            }
        }
    }
    Ok(())
}

fn read_i32(bytes: &[u8], at: usize) -> Option<i32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(i32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

fn read_i64(bytes: &[u8], at: usize) -> Option<i64> {
    let b = bytes.get(at..at.checked_add(8)?)?;
    let mut w = [0u8; 8];
    w.copy_from_slice(b);
    Some(i64::from_le_bytes(w))
}

/// Runs the Arrow decoder, turning a panic inside it (possible on corrupt input in some arrow
/// versions) into a [`LoadError::NotArrow`] so that no input can crash the program.
fn guard<T>(path: &Path, f: impl FnOnce() -> T) -> Result<T, LoadError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).map_err(|_| LoadError::NotArrow {
        path: path.to_path_buf(),
        reason: "the Arrow decoder rejected the file's contents".into(),
    })
}

pub(crate) fn io_error(path: &Path, source: std::io::Error) -> LoadError {
    if source.kind() == std::io::ErrorKind::NotFound {
        LoadError::MissingFile {
            path: path.to_path_buf(),
            expected: "the file to exist",
        }
    } else {
        LoadError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// The values of an int64 column (type checked by [`read_table`], so the downcast holds).
pub(crate) fn i64s(col: &ArrayRef) -> &[i64] {
    col.as_any()
        .downcast_ref::<Int64Array>()
        .map(|a| a.values().as_ref())
        .unwrap_or(&[])
}

/// The values of a float64 column (type checked by [`read_table`], so the downcast holds).
pub(crate) fn f64s(col: &ArrayRef) -> &[f64] {
    col.as_any()
        .downcast_ref::<Float64Array>()
        .map(|a| a.values().as_ref())
        .unwrap_or(&[])
}

/// A string column of any of the accepted string layouts.
pub(crate) enum Strs<'a> {
    Utf8(&'a StringArray),
    Large(&'a LargeStringArray),
    View(&'a StringViewArray),
    /// Not a string column (cannot happen after [`read_table`]'s checks).
    None,
}

impl<'a> Strs<'a> {
    /// Views a column as strings.
    pub fn of(col: &'a ArrayRef) -> Strs<'a> {
        let any = col.as_any();
        if let Some(a) = any.downcast_ref::<StringArray>() {
            Strs::Utf8(a)
        } else if let Some(a) = any.downcast_ref::<LargeStringArray>() {
            Strs::Large(a)
        } else if let Some(a) = any.downcast_ref::<StringViewArray>() {
            Strs::View(a)
        } else {
            Strs::None
        }
    }

    /// The string at row `i` (of this batch).
    pub fn get(&self, i: usize) -> &'a str {
        match self {
            Strs::Utf8(a) => a.value(i),
            Strs::Large(a) => a.value(i),
            Strs::View(a) => a.value(i),
            Strs::None => "",
        }
    }
}
