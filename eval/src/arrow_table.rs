//! The long Arrow table form of a submission (`combined_*_dev.feather`): one row per (sequence, frame,
//! object). A frame without objects is one row whose object columns are null.

use crate::error::EvalError;
use crate::model::{FrameData, Submission};
use arrow_array::{
    Array, ArrayRef, Float32Array, Float64Array, Int32Array, Int64Array, RecordBatch, StringArray,
};
use arrow_ipc::writer::FileWriter;
use arrow_schema::{DataType, Field, Schema};
use std::io::Write;
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

/// Reads the long Arrow table (IPC file, optionally LZ4-compressed).
///
/// The path must be a regular file; the file's framing and declared sizes are checked
/// ([`scenalog_input::arrow`]) before anything is decoded, so a corrupt table is an error naming
/// the file, never a panic or an allocation the bytes cannot back.
pub fn read_table(path: &Path) -> Result<Submission, EvalError> {
    let what = path.display().to_string();
    let bytes = scenalog_input::read_regular_file(path, scenalog_input::DATA_LIMIT)
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
        let log = col::<StringArray>(&b, "log_id", &what)?;
        let prompt = col::<StringArray>(&b, "prompt", &what)?;
        let fi = col::<Int32Array>(&b, "frame_index", &what)?;
        let ts = col::<Int64Array>(&b, "timestamp_ns", &what)?;
        let ego: Vec<&Float64Array> = ["ego_tx_m", "ego_ty_m", "ego_tz_m"]
            .iter()
            .map(|n| col::<Float64Array>(&b, n, &what))
            .collect::<Result<_, _>>()?;
        let oi = col::<Int32Array>(&b, "object_index", &what)?;
        let tid = col::<Int32Array>(&b, "track_id", &what)?;
        let label = col::<Int32Array>(&b, "label", &what)?;
        let name = col::<StringArray>(&b, "name", &what)?;
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

/// Writes the long Arrow table atomically (uncompressed IPC file; `score` only when every frame has scores).
pub fn write_table(sub: &Submission, path: &Path) -> Result<(), EvalError> {
    let with_score = sub.sequences.values().flatten().all(|f| f.score.is_some());
    let mut log = Vec::new();
    let mut prompt = Vec::new();
    let mut fi = Vec::new();
    let mut ts = Vec::new();
    let mut ego: [Vec<f64>; 3] = Default::default();
    let mut oi: Vec<Option<i32>> = Vec::new();
    let mut tid = Vec::new();
    let mut label = Vec::new();
    let mut name: Vec<Option<String>> = Vec::new();
    let mut t: [Vec<Option<f64>>; 3] = Default::default();
    let mut s: [Vec<Option<f32>>; 3] = Default::default();
    let mut yaw = Vec::new();
    let mut v: [Vec<Option<f64>>; 3] = Default::default();
    let mut score = Vec::new();
    for ((l, p), frames) in &sub.sequences {
        for (i, f) in frames.iter().enumerate() {
            let n = f.len().max(1);
            for j in 0..n {
                log.push(l.clone());
                prompt.push(p.clone());
                fi.push(i as i32);
                ts.push(f.timestamp_ns);
                for (e, x) in ego.iter_mut().zip(f.ego_translation_m) {
                    e.push(x);
                }
                let has = j < f.len();
                oi.push(has.then_some(j as i32));
                tid.push(has.then(|| f.track_id[j]));
                label.push(has.then(|| f.label[j]));
                name.push(has.then(|| f.name[j].clone()));
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
        DataType::Utf8,
        false,
        Arc::new(StringArray::from(log)),
    );
    add(
        "prompt",
        DataType::Utf8,
        false,
        Arc::new(StringArray::from(prompt)),
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
        DataType::Utf8,
        true,
        Arc::new(StringArray::from(name)),
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
    let what = path.display().to_string();
    let ferr = |e: arrow_schema::ArrowError| EvalError::Format(format!("{what}: {e}"));
    let schema = Arc::new(Schema::new(fields));
    let batch = RecordBatch::try_new(schema.clone(), cols).map_err(ferr)?;
    let mut buf = Vec::new();
    {
        let mut w = FileWriter::try_new(&mut buf, &schema).map_err(ferr)?;
        w.write(&batch).map_err(ferr)?;
        w.finish().map_err(ferr)?;
    }
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{file_name}.tmp{}", std::process::id()));
    let io = |e| EvalError::Io(what.clone(), e);
    let mut f = std::fs::File::create(&tmp).map_err(io)?;
    f.write_all(&buf).map_err(io)?;
    f.sync_all().map_err(io)?;
    drop(f);
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io(e)
    })
}

/// Reads a submission from a pickle or an Arrow table, by content (Arrow files start with `ARROW1`).
///
/// The path must be a regular file: a FIFO, a directory, a symlink loop or a permission problem
/// is an [`EvalError::File`] saying which.
pub fn read_any(path: &Path) -> Result<Submission, EvalError> {
    let what = path.display().to_string();
    let bytes = scenalog_input::read_regular_file(path, scenalog_input::DATA_LIMIT)
        .map_err(|p| EvalError::File(what.clone(), p))?;
    if bytes.starts_with(b"ARROW1") {
        table_from_bytes(&bytes, &what)
    } else {
        crate::pickle::read_pickle_bytes(&bytes, &what)
    }
}
