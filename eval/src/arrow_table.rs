//! The long Arrow table form of a submission (`combined_*_dev.feather`): one row per (sequence, frame,
//! object). A frame without objects is one row whose object columns are null.

use crate::error::EvalError;
use crate::model::{FrameData, Submission};
use arrow_array::cast::AsArray;
use arrow_array::types::Int32Type;
use arrow_array::{
    Array, ArrayRef, DictionaryArray, Float32Array, Float64Array, Int32Array, Int64Array,
    RecordBatch, StringArray,
};
use arrow_ipc::writer::{FileWriter, IpcWriteOptions};
use arrow_ipc::CompressionType;
use arrow_schema::{DataType, Field, Schema};
use std::path::Path;
use std::sync::Arc;

fn col<'a, T: 'static>(b: &'a RecordBatch, name: &str, what: &str) -> Result<&'a T, EvalError> {
    b.column_by_name(name)
        .ok_or_else(|| EvalError::Format(format!("{what}: column {name:?} missing")))?
        .as_any()
        .downcast_ref::<T>()
        .ok_or_else(|| {
            EvalError::Format(format!(
                "{what}: column {name:?} has type {:?}",
                b.column_by_name(name).map(|c| c.data_type().clone())
            ))
        })
}

/// A string column read either way it may be stored: plain `Utf8`, or dictionary-encoded
/// (any integer keys, `Utf8` values), as our own tables store `log_id`, `prompt` and `name`.
enum Strings<'a> {
    /// Plain strings.
    Plain(&'a StringArray),
    /// Keys into a dictionary: a row is null when its key is.
    Dict {
        keys: &'a dyn Array,
        index: Vec<usize>,
        values: &'a StringArray,
    },
}

impl<'a> Strings<'a> {
    /// The column `name` of `b` as strings; an error naming the column when it is missing or of
    /// another type.
    fn of(b: &'a RecordBatch, name: &str, what: &str) -> Result<Strings<'a>, EvalError> {
        let column = b
            .column_by_name(name)
            .ok_or_else(|| EvalError::Format(format!("{what}: column {name:?} missing")))?;
        let wrong = || {
            EvalError::Format(format!(
                "{what}: column {name:?} has type {:?}",
                column.data_type()
            ))
        };
        if let Some(plain) = column.as_string_opt::<i32>() {
            return Ok(Strings::Plain(plain));
        }
        let dict = column.as_any_dictionary_opt().ok_or_else(wrong)?;
        let values = dict.values().as_string_opt::<i32>().ok_or_else(wrong)?;
        // The decoder has checked every non-null key against the dictionary's length; an empty
        // dictionary (no key to normalise) leaves every row null.
        let index = if values.is_empty() {
            vec![0; dict.keys().len()]
        } else {
            dict.normalized_keys()
        };
        Ok(Strings::Dict {
            keys: dict.keys(),
            index,
            values,
        })
    }

    /// Whether row `r` is null.
    fn is_null(&self, r: usize) -> bool {
        match self {
            Strings::Plain(a) => a.is_null(r),
            Strings::Dict {
                keys,
                index,
                values,
            } => keys.is_null(r) || values.is_empty() || values.is_null(index[r]),
        }
    }

    /// Row `r`'s string (empty for a null row; check [`Strings::is_null`] first).
    fn value(&self, r: usize) -> &'a str {
        match self {
            Strings::Plain(a) => a.value(r),
            Strings::Dict { index, values, .. } => {
                if values.is_empty() {
                    ""
                } else {
                    values.value(index[r])
                }
            }
        }
    }
}

/// Reads the long Arrow table (IPC file, uncompressed or LZ4- or zstd-compressed; its string
/// columns plain or dictionary-encoded).
///
/// The path must be a regular file; the file's framing and declared sizes are checked
/// ([`scenalog_input::arrow`]) before anything is decoded, so a corrupt table is an error naming
/// the file, never a panic or an allocation the bytes cannot back.
pub fn read_table(path: &Path) -> Result<Submission, EvalError> {
    let what = path.display().to_string();
    let bytes = scenalog_input::read_file_checking_ends(
        path,
        scenalog_input::DATA_LIMIT,
        &scenalog_input::ends::arrow_ends,
    )
    .map_err(|p| EvalError::File(what.clone(), p))?;
    table_from_bytes(&bytes, &what)
}

/// Reads the long Arrow table from the bytes of an IPC file; `what` names it in errors.
pub fn table_from_bytes(bytes: &[u8], what: &str) -> Result<Submission, EvalError> {
    let not_arrow = |e: scenalog_input::Corrupt| {
        EvalError::Format(format!("{what}: not a readable Arrow IPC file: {e}"))
    };
    let batches = scenalog_input::read_batches(bytes, None).map_err(not_arrow)?;
    let what = what.to_string();
    let mut sub = Submission::default();
    let mut last: Option<(String, String, i32)> = None;
    let mut row_no = 0usize;
    for b in batches {
        let log = Strings::of(&b, "log_id", &what)?;
        let prompt = Strings::of(&b, "prompt", &what)?;
        let fi = col::<Int32Array>(&b, "frame_index", &what)?;
        let ts = col::<Int64Array>(&b, "timestamp_ns", &what)?;
        let ego: Vec<&Float64Array> = ["ego_tx_m", "ego_ty_m", "ego_tz_m"]
            .iter()
            .map(|n| col::<Float64Array>(&b, n, &what))
            .collect::<Result<_, _>>()?;
        let oi = col::<Int32Array>(&b, "object_index", &what)?;
        let tid = col::<Int32Array>(&b, "track_id", &what)?;
        let label = col::<Int32Array>(&b, "label", &what)?;
        let name = Strings::of(&b, "name", &what)?;
        let t: Vec<&Float64Array> = ["tx_m", "ty_m", "tz_m"]
            .iter()
            .map(|n| col::<Float64Array>(&b, n, &what))
            .collect::<Result<_, _>>()?;
        let s: Vec<&Float32Array> = ["length_m", "width_m", "height_m"]
            .iter()
            .map(|n| col::<Float32Array>(&b, n, &what))
            .collect::<Result<_, _>>()?;
        let yaw = col::<Float32Array>(&b, "yaw", &what)?;
        let v: Vec<&Float64Array> = ["vx_m_per_s", "vy_m_per_s", "vz_m_per_s"]
            .iter()
            .map(|n| col::<Float64Array>(&b, n, &what))
            .collect::<Result<_, _>>()?;
        let score = if b.column_by_name("score").is_some() {
            Some(col::<Float32Array>(&b, "score", &what)?)
        } else {
            None
        };
        for r in 0..b.num_rows() {
            let place = format!("{what}: row {row_no}");
            row_no += 1;
            if log.is_null(r) || prompt.is_null(r) || fi.is_null(r) || ts.is_null(r) {
                return Err(EvalError::Format(format!(
                    "{place}: null log_id, prompt, frame_index or timestamp_ns"
                )));
            }
            let key = (log.value(r).to_string(), prompt.value(r).to_string());
            let frames = sub.sequences.entry(key.clone()).or_default();
            let this = (key.0.clone(), key.1.clone(), fi.value(r));
            if last.as_ref() != Some(&this) {
                if fi.value(r) as usize != frames.len() {
                    return Err(EvalError::Format(format!(
                        "{place}: sequence {key:?} frame_index {} out of order (expected {})",
                        fi.value(r),
                        frames.len()
                    )));
                }
                frames.push(FrameData {
                    timestamp_ns: ts.value(r),
                    ego_translation_m: [ego[0].value(r), ego[1].value(r), ego[2].value(r)],
                    description: Some(key.1.clone()),
                    score: score.map(|_| Vec::new()),
                    ..Default::default()
                });
                last = Some(this);
            }
            if oi.is_null(r) {
                continue;
            }
            let Some(f) = frames.last_mut() else { continue };
            if oi.value(r) as usize != f.len() {
                return Err(EvalError::Format(format!(
                    "{place}: sequence {key:?} object_index {} out of order",
                    oi.value(r)
                )));
            }
            f.translation_m
                .push([t[0].value(r), t[1].value(r), t[2].value(r)]);
            f.size.push([s[0].value(r), s[1].value(r), s[2].value(r)]);
            f.yaw.push(yaw.value(r));
            f.velocity_m_per_s
                .push([v[0].value(r), v[1].value(r), v[2].value(r)]);
            f.label.push(label.value(r));
            f.name.push(name.value(r).to_string());
            f.track_id.push(tid.value(r));
            if let (Some(sc), Some(out)) = (score, f.score.as_mut()) {
                out.push(sc.value(r));
            }
        }
    }
    sub.validate(&what)?;
    Ok(sub)
}

/// The compression of the long tables we write: zstd, per buffer, as the Arrow IPC format
/// allows (pyarrow, polars and our readers decode it).
pub const TABLE_COMPRESSION: CompressionType = CompressionType::ZSTD;

/// The values of the long table's dictionary-encoded columns (`log_id`, `prompt`, `name`): each
/// column's dictionary, one string a value, sorted. A table written in several record batches
/// (one a log, [`table_bytes`]) uses the same dictionaries in every batch, as an Arrow IPC file
/// must (a file cannot replace a dictionary between batches).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct TableDictionaries {
    /// The `log_id` column's values.
    pub log_ids: Vec<String>,
    /// The `prompt` column's values.
    pub prompts: Vec<String>,
    /// The `name` column's values (object categories or labels).
    pub names: Vec<String>,
}

impl TableDictionaries {
    /// The dictionaries of one submission: every value it holds, sorted.
    pub fn of(sub: &Submission) -> TableDictionaries {
        let mut d = TableDictionaries::default();
        let mut names = std::collections::BTreeSet::new();
        for ((l, p), frames) in &sub.sequences {
            d.log_ids.push(l.clone());
            d.prompts.push(p.clone());
            names.extend(
                frames
                    .iter()
                    .flat_map(|f| f.name.iter().map(String::as_str)),
            );
        }
        d.names = names.into_iter().map(str::to_string).collect();
        d.normalise();
        d
    }

    /// Sorts each dictionary and removes repeated values.
    pub fn normalise(&mut self) {
        for v in [&mut self.log_ids, &mut self.prompts, &mut self.names] {
            v.sort_unstable();
            v.dedup();
        }
    }
}

/// A dictionary-encoded string column: `values` (the dictionary) and one key a row.
fn dictionary_column(
    column: &str,
    values: &[String],
    rows: Vec<Option<&str>>,
) -> Result<ArrayRef, EvalError> {
    let keys: Int32Array = rows
        .into_iter()
        .map(|v| match v {
            None => Ok(None),
            Some(v) => values
                .binary_search_by(|x| x.as_str().cmp(v))
                .map(|i| Some(i as i32))
                .map_err(|_| {
                    EvalError::Format(format!(
                        "column {column:?}: {v:?} is not in the table's dictionary"
                    ))
                }),
        })
        .collect::<Result<_, _>>()?;
    let dictionary = Arc::new(StringArray::from_iter_values(values));
    let array = DictionaryArray::<Int32Type>::try_new(keys, dictionary)
        .map_err(|e| EvalError::Format(format!("column {column:?}: {e}")))?;
    Ok(Arc::new(array))
}

/// Record batches of the long table (every one written with the same [`TableDictionaries`],
/// as a run's parts are) as one batch: their rows in order, the dictionary columns' keys joined
/// over the first batch's dictionary (so the result still shares the run's dictionaries, as one
/// Arrow IPC file needs).
///
/// # Errors
/// The batches' schemas differ, or their dictionaries do (a part of another run).
pub fn concat_sharing_dictionaries(batches: &[RecordBatch]) -> Result<RecordBatch, EvalError> {
    let err = |e: arrow_schema::ArrowError| EvalError::Format(format!("joining parts: {e}"));
    let Some(first) = batches.first() else {
        return Err(EvalError::Format("joining parts: no batch".into()));
    };
    let schema = first.schema();
    let mut columns: Vec<ArrayRef> = Vec::with_capacity(schema.fields().len());
    for (c, field) in schema.fields().iter().enumerate() {
        let parts: Vec<&ArrayRef> = batches.iter().map(|b| b.column(c)).collect();
        if field.data_type() == &dictionary_type() {
            let dicts = parts
                .iter()
                .map(|a| {
                    a.as_any()
                        .downcast_ref::<DictionaryArray<Int32Type>>()
                        .ok_or_else(|| {
                            EvalError::Format(format!(
                                "joining parts: column {:?} is not a dictionary",
                                field.name()
                            ))
                        })
                })
                .collect::<Result<Vec<_>, _>>()?;
            let values = dicts[0].values();
            if dicts.iter().any(|d| d.values().as_ref() != values.as_ref()) {
                return Err(EvalError::Format(format!(
                    "joining parts: column {:?} has different dictionaries",
                    field.name()
                )));
            }
            let keys: Vec<&dyn Array> = dicts.iter().map(|d| d.keys() as &dyn Array).collect();
            let keys = arrow_select::concat::concat(&keys).map_err(err)?;
            let keys = keys
                .as_any()
                .downcast_ref::<Int32Array>()
                .cloned()
                .ok_or_else(|| EvalError::Format("joining parts: keys are not Int32".into()))?;
            let array = DictionaryArray::<Int32Type>::try_new(keys, values.clone()).map_err(err)?;
            columns.push(Arc::new(array));
        } else {
            let arrays: Vec<&dyn Array> = parts.iter().map(|a| a.as_ref()).collect();
            columns.push(arrow_select::concat::concat(&arrays).map_err(err)?);
        }
    }
    RecordBatch::try_new(schema, columns).map_err(err)
}

/// The type of the dictionary-encoded string columns.
fn dictionary_type() -> DataType {
    DataType::Dictionary(Box::new(DataType::Int32), Box::new(DataType::Utf8))
}

/// The submission as one record batch of the long table, its string columns encoded with
/// `dicts` (every value must be in them).
pub fn table_batch(sub: &Submission, dicts: &TableDictionaries) -> Result<RecordBatch, EvalError> {
    let with_score = sub.sequences.values().flatten().all(|f| f.score.is_some());
    let mut log: Vec<Option<&str>> = Vec::new();
    let mut prompt: Vec<Option<&str>> = Vec::new();
    let mut fi = Vec::new();
    let mut ts = Vec::new();
    let mut ego: [Vec<f64>; 3] = Default::default();
    let mut oi: Vec<Option<i32>> = Vec::new();
    let mut tid = Vec::new();
    let mut label = Vec::new();
    let mut name: Vec<Option<&str>> = Vec::new();
    let mut t: [Vec<Option<f64>>; 3] = Default::default();
    let mut s: [Vec<Option<f32>>; 3] = Default::default();
    let mut yaw = Vec::new();
    let mut v: [Vec<Option<f64>>; 3] = Default::default();
    let mut score = Vec::new();
    for ((l, p), frames) in &sub.sequences {
        for (i, f) in frames.iter().enumerate() {
            let n = f.len().max(1);
            for j in 0..n {
                log.push(Some(l));
                prompt.push(Some(p));
                fi.push(i as i32);
                ts.push(f.timestamp_ns);
                for (e, x) in ego.iter_mut().zip(f.ego_translation_m) {
                    e.push(x);
                }
                let has = j < f.len();
                oi.push(has.then_some(j as i32));
                tid.push(has.then(|| f.track_id[j]));
                label.push(has.then(|| f.label[j]));
                name.push(has.then(|| f.name[j].as_str()));
                for k in 0..3 {
                    t[k].push(has.then(|| f.translation_m[j][k]));
                    s[k].push(has.then(|| f.size[j][k]));
                    v[k].push(has.then(|| f.velocity_m_per_s.get(j).map_or(f64::NAN, |x| x[k])));
                }
                yaw.push(has.then(|| f.yaw[j]));
                score.push(has.then(|| f.score.as_ref().map_or(f32::NAN, |x| x[j])));
            }
        }
    }
    let mut fields = Vec::new();
    let mut cols: Vec<ArrayRef> = Vec::new();
    let mut add = |n: &str, dt: DataType, nullable: bool, a: ArrayRef| {
        fields.push(Field::new(n, dt, nullable));
        cols.push(a);
    };
    add(
        "log_id",
        dictionary_type(),
        false,
        dictionary_column("log_id", &dicts.log_ids, log)?,
    );
    add(
        "prompt",
        dictionary_type(),
        false,
        dictionary_column("prompt", &dicts.prompts, prompt)?,
    );
    add(
        "frame_index",
        DataType::Int32,
        false,
        Arc::new(Int32Array::from(fi)),
    );
    add(
        "timestamp_ns",
        DataType::Int64,
        false,
        Arc::new(Int64Array::from(ts)),
    );
    for (k, n) in ["ego_tx_m", "ego_ty_m", "ego_tz_m"].iter().enumerate() {
        add(
            n,
            DataType::Float64,
            false,
            Arc::new(Float64Array::from(std::mem::take(&mut ego[k]))),
        );
    }
    add(
        "object_index",
        DataType::Int32,
        true,
        Arc::new(Int32Array::from(oi)),
    );
    add(
        "track_id",
        DataType::Int32,
        true,
        Arc::new(Int32Array::from(tid)),
    );
    add(
        "label",
        DataType::Int32,
        true,
        Arc::new(Int32Array::from(label)),
    );
    add(
        "name",
        dictionary_type(),
        true,
        dictionary_column("name", &dicts.names, name)?,
    );
    for (k, n) in ["tx_m", "ty_m", "tz_m"].iter().enumerate() {
        add(
            n,
            DataType::Float64,
            true,
            Arc::new(Float64Array::from(std::mem::take(&mut t[k]))),
        );
    }
    for (k, n) in ["length_m", "width_m", "height_m"].iter().enumerate() {
        add(
            n,
            DataType::Float32,
            true,
            Arc::new(Float32Array::from(std::mem::take(&mut s[k]))),
        );
    }
    add(
        "yaw",
        DataType::Float32,
        true,
        Arc::new(Float32Array::from(yaw)),
    );
    for (k, n) in ["vx_m_per_s", "vy_m_per_s", "vz_m_per_s"]
        .iter()
        .enumerate()
    {
        add(
            n,
            DataType::Float64,
            true,
            Arc::new(Float64Array::from(std::mem::take(&mut v[k]))),
        );
    }
    if with_score {
        add(
            "score",
            DataType::Float32,
            true,
            Arc::new(Float32Array::from(score)),
        );
    }
    let schema = Arc::new(Schema::new(fields));
    RecordBatch::try_new(schema, cols).map_err(|e| EvalError::Format(e.to_string()))
}

/// The IPC write options of our tables: `codec` per buffer (`None`: uncompressed).
pub fn table_write_options(codec: Option<CompressionType>) -> Result<IpcWriteOptions, EvalError> {
    IpcWriteOptions::default()
        .try_with_compression(codec)
        .map_err(|e| EvalError::Format(format!("Arrow write options: {e}")))
}

/// The long Arrow table of `sub` as the bytes of an IPC file (one record batch), its `log_id`,
/// `prompt` and `name` columns dictionary-encoded with `dicts`, every buffer compressed with
/// `codec`.
pub fn table_bytes(
    sub: &Submission,
    dicts: &TableDictionaries,
    codec: Option<CompressionType>,
) -> Result<Vec<u8>, EvalError> {
    let batch = table_batch(sub, dicts)?;
    let ferr = |e: arrow_schema::ArrowError| EvalError::Format(e.to_string());
    let mut buf = Vec::new();
    {
        let mut w = FileWriter::try_new_with_options(
            &mut buf,
            &batch.schema(),
            table_write_options(codec)?,
        )
        .map_err(ferr)?;
        w.write(&batch).map_err(ferr)?;
        w.finish().map_err(ferr)?;
    }
    Ok(buf)
}

/// Writes the long Arrow table atomically (a temporary file, synced, then renamed): one record
/// batch, `log_id`, `prompt` and `name` dictionary-encoded, zstd-compressed
/// ([`TABLE_COMPRESSION`]); `score` only when every frame has scores.
pub fn write_table(sub: &Submission, path: &Path) -> Result<(), EvalError> {
    write_table_with(
        sub,
        path,
        &TableDictionaries::of(sub),
        Some(TABLE_COMPRESSION),
    )
}

/// [`write_table`] with given dictionaries (which must hold every value of `sub`) and codec.
pub fn write_table_with(
    sub: &Submission,
    path: &Path,
    dicts: &TableDictionaries,
    codec: Option<CompressionType>,
) -> Result<(), EvalError> {
    let what = path.display().to_string();
    let buf = table_bytes(sub, dicts, codec).map_err(|e| match e {
        EvalError::Format(m) => EvalError::Format(format!("{what}: {m}")),
        e => e,
    })?;
    scenalog_input::out_dir::write_atomic(path, &buf, true).map_err(|e| EvalError::Io(what, e))
}

/// Reads a submission from a pickle or an Arrow table, by content (Arrow files start with `ARROW1`).
///
/// The path must be a regular file: a FIFO, a directory, a symlink loop or a permission problem
/// is an [`EvalError::File`] saying which.
pub fn read_any(path: &Path) -> Result<Submission, EvalError> {
    let what = path.display().to_string();
    let bytes = scenalog_input::read_file_checking_ends(
        path,
        scenalog_input::DATA_LIMIT,
        &crate::pickle::submission_ends,
    )
    .map_err(|p| EvalError::File(what.clone(), p))?;
    if bytes.starts_with(b"ARROW1") {
        table_from_bytes(&bytes, &what)
    } else {
        crate::pickle::read_pickle_bytes(&bytes, &what)
    }
}
