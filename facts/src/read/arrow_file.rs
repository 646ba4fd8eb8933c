//! Reading selected, typed columns of an Arrow IPC file (feather v2, LZ4 or uncompressed).

use std::path::Path;

use arrow_array::{
    Array, ArrayRef, Float32Array, Float64Array, Int64Array, LargeStringArray, RecordBatch,
    StringArray, StringViewArray,
};
use arrow_schema::DataType;
use scenalog_input::FileProblem;

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
    /// 32- or 64-bit floats (a tracker's scores are often float32).
    AnyFloat,
}

impl Kind {
    fn describe(self) -> &'static str {
        match self {
            Kind::Int64 => "int64",
            Kind::Float64 => "double (float64)",
            Kind::Str => "string (utf8)",
            Kind::AnyFloat => "float or double",
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
            Kind::AnyFloat => matches!(ty, DataType::Float32 | DataType::Float64),
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
///
/// The file must be a regular file; its framing and declared sizes are checked by
/// [`scenalog_input::arrow`] before anything is decoded.
pub(crate) fn read_table(path: &Path, wanted: &[ColumnWant]) -> Result<Table, LoadError> {
    let bytes = scenalog_input::read_file_checking_ends(
        path,
        scenalog_input::LOG_TABLE_LIMIT,
        &scenalog_input::ends::arrow_ends,
    )
    .map_err(|problem| match problem {
        FileProblem::NotFormat(reason) => LoadError::NotArrow {
            path: path.to_path_buf(),
            reason,
        },
        problem => file_error(path, problem),
    })?;
    let not_arrow = |e: scenalog_input::Corrupt| LoadError::NotArrow {
        path: path.to_path_buf(),
        reason: e.reason,
    };
    let schema = scenalog_input::read_schema(&bytes).map_err(not_arrow)?;
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
    let batches = scenalog_input::read_batches(&bytes, Some(projection)).map_err(not_arrow)?;
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

/// The error for a path that is not a readable regular file: missing, something else (a
/// directory, a FIFO), or unreadable (permission denied, a symlink loop).
pub(crate) fn file_error(path: &Path, problem: FileProblem) -> LoadError {
    match problem {
        FileProblem::NotFound => LoadError::MissingFile {
            path: path.to_path_buf(),
            expected: "the file to exist",
        },
        wrong @ (FileProblem::WrongKind { .. }
        | FileProblem::TooLarge { .. }
        | FileProblem::NotUtf8(_)
        | FileProblem::NotFormat(_)) => LoadError::NotRegularFile {
            path: path.to_path_buf(),
            what: wrong.to_string(),
        },
        FileProblem::Io(source) => LoadError::Io {
            path: path.to_path_buf(),
            source,
        },
    }
}

/// The error for an I/O failure on `path` other than reading a file (listing a directory).
pub(crate) fn io_error(path: &Path, source: std::io::Error) -> LoadError {
    if source.kind() == std::io::ErrorKind::NotFound {
        file_error(path, FileProblem::NotFound)
    } else {
        file_error(path, FileProblem::Io(source))
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

/// The values of a float32 or float64 column as `f64` (type checked by [`read_table`]).
pub(crate) fn any_floats(col: &ArrayRef) -> Vec<f64> {
    if let Some(a) = col.as_any().downcast_ref::<Float32Array>() {
        a.values().iter().map(|&v| f64::from(v)).collect()
    } else {
        f64s(col).to_vec()
    }
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
