//! Small real inputs to mutate, cut from the bundled Argoverse 2 data (tests/data/av2, CC BY-NC-SA
//! 4.0): a log of one frame (annotations, ego poses, a map of three lanes, a crossing and a drivable area), and a submission of
//! a few frames as an LZ4 Arrow table, an uncompressed one and a pickle. Small, so that each
//! mutant is read in well under a millisecond in a debug build.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use arrow_array::{Array, Int64Array, RecordBatch, UInt32Array};
use arrow_ipc::reader::FileReader;
use arrow_ipc::writer::{FileWriter, IpcWriteOptions};
use arrow_ipc::CompressionType;

/// The log the small log is cut from (annotations with ego rows, rows not sorted by time).
pub const LOG: &str = "3b3570b4-7b0b-3268-a571-b0889dbf40b6";
/// Its map file's name.
pub const MAP_FILE: &str =
    "log_map_archive_3b3570b4-7b0b-3268-a571-b0889dbf40b6____MIA_city_47894.json";
/// Distinct annotation timestamps kept.
const FRAMES: usize = 1;

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/av2")
        .join(rel)
}

fn read_feather(path: &Path) -> Vec<RecordBatch> {
    let file = std::fs::File::open(path).expect("open a bundled feather");
    FileReader::try_new(file, None)
        .expect("a bundled feather")
        .collect::<Result<_, _>>()
        .expect("its batches")
}

/// An Arrow IPC file of `batches`, LZ4-compressed (as AV2 writes them) or not.
pub fn feather(batches: &[RecordBatch], lz4: bool) -> Vec<u8> {
    let schema = batches[0].schema();
    let codec = lz4.then_some(CompressionType::LZ4_FRAME);
    let options = IpcWriteOptions::default()
        .try_with_compression(codec)
        .expect("options");
    let mut out = Vec::new();
    let mut w = FileWriter::try_new_with_options(&mut out, &schema, options).expect("writer");
    for b in batches {
        w.write(b).expect("write");
    }
    w.finish().expect("finish");
    drop(w);
    out
}

/// The rows of `batch` where `keep` holds for the int64 `timestamp_ns`.
fn rows_at(batch: &RecordBatch, keep: impl Fn(i64) -> bool) -> RecordBatch {
    let ts = batch
        .column_by_name("timestamp_ns")
        .and_then(|c| c.as_any().downcast_ref::<Int64Array>())
        .expect("timestamp_ns int64");
    let rows: Vec<u32> = (0..ts.len())
        .filter(|&r| keep(ts.value(r)))
        .map(|r| r as u32)
        .collect();
    arrow_select::take::take_record_batch(batch, &UInt32Array::from(rows)).expect("take")
}

/// The three files of a small log, each a valid input of its reader. The feathers come LZ4
/// compressed, as AV2 writes them (what is fuzzed), and uncompressed (the files around a fuzzed
/// one: a debug build of lz4_flex zero-fills a 4 MiB block per buffer, byte by byte, which would
/// be most of the run time).
pub struct SmallLog {
    /// `annotations_with_ego.feather`, LZ4.
    pub annotations: Vec<u8>,
    /// The same, uncompressed.
    pub annotations_plain: Vec<u8>,
    /// `city_SE3_egovehicle.feather`, LZ4.
    pub poses: Vec<u8>,
    /// The same, uncompressed.
    pub poses_plain: Vec<u8>,
    /// `map/<MAP_FILE>`.
    pub map: Vec<u8>,
}

/// The first [`FRAMES`] timestamps of [`LOG`] and a few of its lanes, crossings and areas.
pub fn small_log() -> SmallLog {
    let dir = data(&format!("logs/{LOG}"));
    let ann = read_feather(&dir.join("annotations_with_ego.feather"));
    let mut stamps = BTreeSet::new();
    for b in &ann {
        let ts = b
            .column_by_name("timestamp_ns")
            .and_then(|c| c.as_any().downcast_ref::<Int64Array>())
            .expect("timestamp_ns int64");
        stamps.extend(ts.values().iter().copied());
    }
    let kept: BTreeSet<i64> = stamps.into_iter().take(FRAMES).collect();
    let ann: Vec<RecordBatch> = ann
        .iter()
        .map(|b| rows_at(b, |t| kept.contains(&t)))
        .collect();
    let poses: Vec<RecordBatch> = read_feather(&dir.join("city_SE3_egovehicle.feather"))
        .iter()
        .map(|b| rows_at(b, |t| kept.contains(&t)))
        .collect();

    let map_text = std::fs::read_to_string(dir.join("map").join(MAP_FILE)).expect("map");
    let mut map: serde_json::Value = serde_json::from_str(&map_text).expect("map JSON");
    for (key, keep) in [
        ("lane_segments", 3),
        ("pedestrian_crossings", 1),
        ("drivable_areas", 1),
    ] {
        let all = map[key].as_object().expect("an object of features");
        let some: serde_json::Map<String, serde_json::Value> = all
            .iter()
            .take(keep)
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect();
        map[key] = serde_json::Value::Object(some);
    }
    let map = serde_json::to_vec_pretty(&map).expect("JSON");
    SmallLog {
        annotations: feather(&ann, true),
        annotations_plain: feather(&ann, false),
        poses: feather(&poses, true),
        poses_plain: feather(&poses, false),
        map,
    }
}

/// A small prediction table (the first `rows` rows of the official sample submission, with
/// its own schema), LZ4-compressed or not.
pub fn small_prediction_table(rows: usize, lz4: bool) -> Vec<u8> {
    let batches = read_feather(&data("eval/combined_predictions_dev.feather"));
    let first = batches[0].slice(0, rows.min(batches[0].num_rows()));
    feather(&[first], lz4)
}

/// The same sequences as `table` as an official-format pickle.
pub fn pickle_of_table(table: &[u8]) -> Vec<u8> {
    let sub = scenalog_eval::table_from_bytes(table, "small table").expect("a valid table");
    scenalog_eval::pickle_bytes(&sub)
}
