//! Writes scaled copies of real Argoverse 2 logs for the scale benchmark (README.md, "At scale"):
//!
//! - `--dense N`: every non-ego track N times (the original and N−1 copies) in the same frames and
//!   the same area: copy c of a track is moved by a fixed offset drawn uniformly in ±`SPREAD_M`
//!   metres in x and y (seeded by the track's position and the copy), so the log holds N times
//!   the objects packed around the same ego.
//! - `--longer N`: the log's timeline N times in a row: copy c's annotation and pose timestamps
//!   are shifted by c times the log's span (plus one frame), its non-ego tracks take new ids (the
//!   ego keeps its own), so the log is N times longer with N times the tracks, spread over time.
//!
//! Run from the workspace: `cargo run --release --example scale_logs -- --dense 10
//! tests/data/av2/logs /tmp/dense10` writes `/tmp/dense10/<log id>/` for every log directory in
//! the input (its map linked, annotations and poses rewritten). The 150-log split is written by
//! `scenalog-tracker`'s `make_tracker_pickles --scaled` (README.md).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_array::{Array, ArrayRef, Float64Array, Int64Array, RecordBatch, StringArray};
use arrow_ipc::reader::FileReader;
use arrow_ipc::writer::FileWriter;

/// Half the side of the square a dense copy is moved within, metres.
const SPREAD_M: f64 = 15.0;
/// The annotation and pose files rewritten (whichever the log has).
const FEATHERS: &[&str] = &[
    "annotations_with_ego.feather",
    "annotations.feather",
    "city_SE3_egovehicle.feather",
];
/// The ego's category: its track is never copied in `--dense`, and keeps its id in `--longer`.
const EGO: &str = "EGO_VEHICLE";
/// One frame at 10 Hz, nanoseconds.
const FRAME_NS: i64 = 100_000_000;

#[derive(Clone, Copy)]
enum Mode {
    Dense(usize),
    Longer(usize),
}

fn main() {
    if let Err(e) = run() {
        eprintln!("scale_logs: {e}");
        std::process::exit(2);
    }
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: scale_logs (--dense N | --longer N) LOGS_DIR OUT_DIR";
    let [flag, n, logs, out] = args.as_slice() else {
        return Err(usage.to_string());
    };
    let n: usize = n
        .parse()
        .map_err(|_| format!("{n}: not a count; {usage}"))?;
    if n == 0 {
        return Err("the factor must be at least 1".to_string());
    }
    let mode = match flag.as_str() {
        "--dense" => Mode::Dense(n),
        "--longer" => Mode::Longer(n),
        _ => return Err(usage.to_string()),
    };
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(logs)
        .map_err(|e| format!("{logs}: {e}"))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.join("map").is_dir())
        .collect();
    dirs.sort();
    if dirs.is_empty() {
        return Err(format!("{logs}: no log directories"));
    }
    for dir in dirs {
        let name = dir.file_name().ok_or("a log directory without a name")?;
        let to = Path::new(out).join(name);
        scale_log(&dir, &to, mode)?;
        eprintln!("wrote {}", to.display());
    }
    Ok(())
}

fn scale_log(from: &Path, to: &Path, mode: Mode) -> Result<(), String> {
    std::fs::create_dir_all(to).map_err(|e| format!("{}: {e}", to.display()))?;
    let map = std::fs::canonicalize(from.join("map")).map_err(|e| e.to_string())?;
    let link = to.join("map");
    if std::fs::symlink_metadata(&link).is_err() {
        symlink_dir(&map, &link)?;
    }
    // The span of the timeline (annotations and poses).
    let mut span: Option<(i64, i64)> = None;
    for f in FEATHERS.iter().filter(|f| from.join(f).is_file()) {
        let batch = read(&from.join(f))?;
        let ts = int_column(&batch, "timestamp_ns")?;
        for &t in ts.values().iter() {
            span = Some(span.map_or((t, t), |(lo, hi)| (lo.min(t), hi.max(t))));
        }
    }
    let (lo, hi) = span.ok_or("the log has no timestamps")?;
    let period = hi - lo + FRAME_NS;
    for f in FEATHERS.iter().filter(|f| from.join(f).is_file()) {
        let batch = read(&from.join(f))?;
        let poses = f.starts_with("city_");
        let copies: Vec<RecordBatch> = match mode {
            Mode::Dense(_) if poses => vec![batch],
            Mode::Dense(n) => (0..n)
                .map(|c| transform(&batch, c, |_| 0, Some(Box::new(offsets(c)))))
                .collect::<Result<_, _>>()?,
            Mode::Longer(n) => (0..n)
                .map(|c| transform(&batch, c, |_| c as i64 * period, None))
                .collect::<Result<_, _>>()?,
        };
        let schema = copies[0].schema();
        let all =
            arrow_select::concat::concat_batches(&schema, &copies).map_err(|e| e.to_string())?;
        write(&to.join(f), &all)?;
    }
    Ok(())
}

/// Where a dense copy moves a track's boxes, by track uuid.
type Offset = Box<dyn FnMut(&str) -> [f64; 2]>;

/// A deterministic offset per (track, copy): copy 0 stays put.
fn offsets(copy: usize) -> impl FnMut(&str) -> [f64; 2] + 'static {
    let mut memo: HashMap<String, [f64; 2]> = HashMap::new();
    move |uuid: &str| {
        if copy == 0 {
            return [0.0, 0.0];
        }
        *memo.entry(uuid.to_string()).or_insert_with(|| {
            let seed = uuid
                .bytes()
                .fold(copy as u64, |h, b| h.wrapping_mul(1_000_003) ^ u64::from(b));
            let mut rng = fastrand::Rng::with_seed(seed);
            [
                (rng.f64() * 2.0 - 1.0) * SPREAD_M,
                (rng.f64() * 2.0 - 1.0) * SPREAD_M,
            ]
        })
    }
}

/// Copy `copy` of `batch`: timestamps shifted, non-ego track ids suffixed with the copy (when
/// `copy > 0`) and non-ego boxes moved by `offset(track)` when given. A pose table (no
/// `track_uuid`) only has its timestamps shifted. Dense copies (`offset` given) of the ego are
/// left out: there is one ego.
fn transform(
    batch: &RecordBatch,
    copy: usize,
    shift: impl Fn(usize) -> i64,
    mut offset: Option<Offset>,
) -> Result<RecordBatch, String> {
    let schema = batch.schema();
    let uuids = match batch.column_by_name("track_uuid") {
        Some(c) => Some(
            c.as_any()
                .downcast_ref::<StringArray>()
                .ok_or("track_uuid is not a string column")?
                .clone(),
        ),
        None => None,
    };
    let category = match batch.column_by_name("category") {
        Some(c) => Some(
            c.as_any()
                .downcast_ref::<StringArray>()
                .ok_or("category is not a string column")?
                .clone(),
        ),
        None => None,
    };
    let rows = batch.num_rows();
    let is_ego = |i: usize| category.as_ref().is_some_and(|c| c.value(i) == EGO);
    // The rows kept: every row, except the ego's in dense copies past the first.
    let keep: Vec<u32> = (0..rows)
        .filter(|&i| !(offset.is_some() && copy > 0 && is_ego(i)))
        .map(|i| i as u32)
        .collect();
    let moved: Vec<[f64; 2]> = keep
        .iter()
        .map(|&i| {
            let i = i as usize;
            match (&mut offset, &uuids) {
                (Some(f), Some(u)) if !is_ego(i) => f(u.value(i)),
                _ => [0.0, 0.0],
            }
        })
        .collect();
    let take = arrow_array::UInt32Array::from(keep.clone());
    let mut columns: Vec<ArrayRef> = Vec::with_capacity(schema.fields().len());
    for field in schema.fields() {
        let col = batch
            .column_by_name(field.name())
            .ok_or("a column of the schema is missing")?;
        let col = arrow_select::take::take(col.as_ref(), &take, None).map_err(|e| e.to_string())?;
        let new: ArrayRef = match field.name().as_str() {
            "timestamp_ns" => {
                let c = col
                    .as_any()
                    .downcast_ref::<Int64Array>()
                    .ok_or("timestamp_ns is not an int64 column")?;
                let d = shift(copy);
                Arc::new(c.unary::<_, arrow_array::types::Int64Type>(|t| t + d))
            }
            "track_uuid" if copy > 0 => {
                let c = col
                    .as_any()
                    .downcast_ref::<StringArray>()
                    .ok_or("track_uuid is not a string column")?;
                Arc::new(
                    (0..c.len())
                        .map(|i| {
                            if is_ego(keep[i] as usize) {
                                c.value(i).to_string()
                            } else {
                                format!("{}-{copy}", c.value(i))
                            }
                        })
                        .map(Some)
                        .collect::<StringArray>(),
                )
            }
            name @ ("tx_m" | "ty_m") if offset.is_some() && uuids.is_some() => {
                let axis = usize::from(name == "ty_m");
                let c = col
                    .as_any()
                    .downcast_ref::<Float64Array>()
                    .ok_or("tx_m/ty_m is not a float64 column")?;
                Arc::new(
                    (0..c.len())
                        .map(|i| Some(c.value(i) + moved[i][axis]))
                        .collect::<Float64Array>(),
                )
            }
            _ => col,
        };
        columns.push(new);
    }
    RecordBatch::try_new(schema.clone(), columns).map_err(|e| e.to_string())
}

fn read(path: &Path) -> Result<RecordBatch, String> {
    let file = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let reader = FileReader::try_new(file, None).map_err(|e| format!("{}: {e}", path.display()))?;
    let schema = reader.schema();
    let batches: Vec<RecordBatch> = reader
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    arrow_select::concat::concat_batches(&schema, &batches).map_err(|e| e.to_string())
}

fn write(path: &Path, batch: &RecordBatch) -> Result<(), String> {
    let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut w = FileWriter::try_new(file, &batch.schema()).map_err(|e| e.to_string())?;
    w.write(batch).map_err(|e| e.to_string())?;
    w.finish().map_err(|e| e.to_string())
}

fn int_column<'b>(batch: &'b RecordBatch, name: &str) -> Result<&'b Int64Array, String> {
    batch
        .column_by_name(name)
        .and_then(|c| c.as_any().downcast_ref::<Int64Array>())
        .ok_or_else(|| format!("no int64 column {name}"))
}

#[cfg(unix)]
fn symlink_dir(from: &Path, to: &Path) -> Result<(), String> {
    std::os::unix::fs::symlink(from, to).map_err(|e| format!("{}: {e}", to.display()))
}

#[cfg(not(unix))]
fn symlink_dir(_from: &Path, to: &Path) -> Result<(), String> {
    Err(format!(
        "{}: linking the map needs a Unix system",
        to.display()
    ))
}
