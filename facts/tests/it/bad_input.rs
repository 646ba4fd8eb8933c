//! Bad input: each error kind of `load_scene`, produced by corrupting a copy of a real log in a
//! temporary directory. Every error must name the offending file (and column/field) and none may
//! panic.
//!
//! Corrupted feather files are written with arrow-ipc's own writer (LZ4-compressed like the
//! originals) from the real file's record batches with one change each.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_array::{Array, ArrayRef, Float64Array, RecordBatch, StringArray};
use arrow_ipc::reader::FileReader;
use arrow_ipc::writer::{FileWriter, IpcWriteOptions};
use arrow_ipc::CompressionType;
use arrow_schema::{Field, Schema};
use scenalog_facts::read::{
    ADDED_EGO_UUID, ANNOTATIONS_FILE, ANNOTATIONS_WITH_EGO_FILE, EGO_POSES_FILE,
};
use scenalog_facts::{load_scene, LoadError, Scene};
use tempfile::TempDir;

const WITH_EGO: &str = "3b3570b4-7b0b-3268-a571-b0889dbf40b6";
const PLAIN: &str = "adcf7d18-0510-35b0-a2fa-b4cea13a6d76";

/// A writable copy of a real log in a temp dir; returns (guard, log dir).
fn copy_log(id: &str) -> (TempDir, PathBuf) {
    let tmp = tempfile::tempdir().expect("temp dir");
    let dst = tmp.path().join(id);
    copy_dir(&crate::log_dir(id), &dst);
    (tmp, dst)
}

fn copy_dir(src: &Path, dst: &Path) {
    std::fs::create_dir_all(dst).expect("mkdir");
    for entry in std::fs::read_dir(src).expect("read_dir") {
        let entry = entry.expect("entry");
        let to = dst.join(entry.file_name());
        if entry.path().is_dir() {
            copy_dir(&entry.path(), &to);
        } else {
            std::fs::copy(entry.path(), &to).expect("copy");
            let mut perm = std::fs::metadata(&to).expect("meta").permissions();
            #[allow(clippy::permissions_set_readonly_false)]
            perm.set_readonly(false);
            std::fs::set_permissions(&to, perm).expect("chmod");
        }
    }
}

fn read_batches(path: &Path) -> Vec<RecordBatch> {
    let file = std::fs::File::open(path).expect("open");
    let reader = FileReader::try_new(file, None).expect("arrow");
    reader.collect::<Result<Vec<_>, _>>().expect("batches")
}

fn write_feather(path: &Path, batches: &[RecordBatch]) {
    let schema = batches[0].schema();
    let file = std::fs::File::create(path).expect("create");
    let opts = IpcWriteOptions::default()
        .try_with_compression(Some(CompressionType::LZ4_FRAME))
        .expect("lz4");
    let mut w = FileWriter::try_new_with_options(file, &schema, opts).expect("writer");
    for b in batches {
        w.write(b).expect("write");
    }
    w.finish().expect("finish");
}

/// `batch` with column `name` replaced by `array` (the field takes the array's type).
fn replace_column(batch: &RecordBatch, name: &str, array: ArrayRef) -> RecordBatch {
    let schema = batch.schema();
    let (i, _) = schema.column_with_name(name).expect("column");
    let mut fields: Vec<Field> = schema.fields().iter().map(|f| f.as_ref().clone()).collect();
    fields[i] = Field::new(name, array.data_type().clone(), true);
    let mut cols = batch.columns().to_vec();
    cols[i] = array;
    RecordBatch::try_new(Arc::new(Schema::new(fields)), cols).expect("batch")
}

fn drop_column(batch: &RecordBatch, name: &str) -> RecordBatch {
    let mut b = batch.clone();
    let (i, _) = b.schema().column_with_name(name).expect("column");
    b.remove_column(i);
    b
}

fn f64_column(batch: &RecordBatch, name: &str) -> Vec<f64> {
    let col = batch.column_by_name(name).expect("column");
    let a = col.as_any().downcast_ref::<Float64Array>().expect("f64");
    a.values().to_vec()
}

fn str_column(batch: &RecordBatch, name: &str) -> Vec<String> {
    let col = batch.column_by_name(name).expect("column");
    let a = col.as_any().downcast_ref::<StringArray>().expect("utf8");
    (0..a.len()).map(|i| a.value(i).to_owned()).collect()
}

/// Rewrites the single-batch feather file `name` of `dir` through `f`.
fn rewrite(dir: &Path, name: &str, f: impl FnOnce(RecordBatch) -> Vec<RecordBatch>) {
    let path = dir.join(name);
    let batches = read_batches(&path);
    assert_eq!(batches.len(), 1, "the fixtures hold one batch");
    let out = f(batches.into_iter().next().expect("batch"));
    std::fs::remove_file(&path).expect("rm");
    write_feather(&path, &out);
}

fn load_err(dir: &Path) -> LoadError {
    match load_scene(dir) {
        Ok(_) => panic!("{}: loaded, but an error was expected", dir.display()),
        Err(e) => e,
    }
}

fn load_ok(dir: &Path) -> Scene {
    load_scene(dir).unwrap_or_else(|e| panic!("{e}"))
}

fn assert_names(err: &LoadError, file: &str, words: &[&str]) {
    let msg = err.to_string();
    assert!(
        err.path().ends_with(file),
        "error path {} should end with {file}: {msg}",
        err.path().display()
    );
    assert!(msg.contains(file), "message should name {file}: {msg}");
    for w in words {
        assert!(msg.contains(w), "message should contain {w:?}: {msg}");
    }
}

#[test]
fn rewritten_copy_in_several_batches_loads_the_same_scene() {
    // Guards the helpers: an unchanged rewrite (in 3 batches; poses out of order) is accepted.
    let (_tmp, dir) = copy_log(WITH_EGO);
    rewrite(&dir, ANNOTATIONS_WITH_EGO_FILE, |b| {
        vec![
            b.slice(0, 5000),
            b.slice(5000, 5000),
            b.slice(10000, b.num_rows() - 10000),
        ]
    });
    rewrite(&dir, EGO_POSES_FILE, |b| {
        let n = b.num_rows();
        vec![
            b.slice(2000, n - 2000),
            b.slice(1000, 1000),
            b.slice(0, 1000),
        ]
    });
    let a = load_ok(&dir);
    let b = load_ok(&crate::log_dir(WITH_EGO));
    assert_eq!(a.tracks, b.tracks);
    assert_eq!(a.timeline, b.timeline);
    assert_eq!(a.ego_poses, b.ego_poses);
    assert_eq!(a.map, b.map);
}

#[test]
fn missing_log_dir_annotations_and_pose_file() {
    let err = load_err(Path::new("/nonexistent/scenalog/log"));
    assert!(matches!(err, LoadError::MissingFile { .. }), "{err}");
    assert!(err.to_string().contains("/nonexistent/scenalog/log"));

    let (_tmp, dir) = copy_log(WITH_EGO);
    std::fs::remove_file(dir.join(ANNOTATIONS_WITH_EGO_FILE)).expect("rm");
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::MissingFile { .. }), "{err}");
    assert_names(&err, ANNOTATIONS_FILE, &["annotations_with_ego.feather"]);

    let (_tmp, dir) = copy_log(WITH_EGO);
    std::fs::remove_file(dir.join(EGO_POSES_FILE)).expect("rm");
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::MissingFile { .. }), "{err}");
    assert_names(&err, EGO_POSES_FILE, &["not found"]);
}

fn mkfifo(path: &Path) {
    let made = std::process::Command::new("mkfifo")
        .arg(path)
        .status()
        .expect("run mkfifo");
    assert!(made.success(), "mkfifo {}", path.display());
}

#[test]
fn paths_that_are_not_readable_regular_files_say_what_they_are() {
    // Before: each of these was "annotations.feather: not found", and a FIFO map would have
    // blocked the read forever.
    let (_tmp, dir) = copy_log(WITH_EGO);
    let ann = dir.join(ANNOTATIONS_WITH_EGO_FILE);
    std::fs::remove_file(&ann).expect("rm");
    mkfifo(&ann);
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::NotRegularFile { .. }), "{err}");
    assert_names(
        &err,
        ANNOTATIONS_WITH_EGO_FILE,
        &["FIFO", "not a regular file"],
    );

    std::fs::remove_file(&ann).expect("rm");
    std::os::unix::fs::symlink(&ann, &ann).expect("symlink");
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::Io { .. }), "{err}");
    assert_names(&err, ANNOTATIONS_WITH_EGO_FILE, &["symlink loop"]);

    // The map file a FIFO; the map directory a regular file.
    let (_tmp, dir) = copy_log(WITH_EGO);
    let map = map_path(&dir);
    std::fs::remove_file(&map).expect("rm");
    mkfifo(&map);
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::NotRegularFile { .. }), "{err}");
    let map_name = map
        .file_name()
        .expect("name")
        .to_string_lossy()
        .into_owned();
    assert_names(&err, &map_name, &["FIFO"]);
    std::fs::remove_dir_all(dir.join("map")).expect("rm map");
    std::fs::write(dir.join("map"), b"not a directory").expect("write");
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::Io { .. }), "{err}");
    assert_names(&err, "map", &["cannot read"]);

    // The log "directory" a regular file.
    let file = dir.join(EGO_POSES_FILE);
    let err = load_err(&file);
    assert!(matches!(err, LoadError::NotRegularFile { .. }), "{err}");
    assert_names(
        &err,
        EGO_POSES_FILE,
        &["is a regular file, not a directory"],
    );
}

#[test]
fn not_arrow_garbage_and_truncated() {
    let (_tmp, dir) = copy_log(WITH_EGO);
    let path = dir.join(ANNOTATIONS_WITH_EGO_FILE);
    std::fs::write(&path, b"timestamp_ns,track_uuid\n1,abc\n").expect("write");
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::NotArrow { .. }), "{err}");
    assert_names(&err, ANNOTATIONS_WITH_EGO_FILE, &["Arrow"]);

    // The real file cut in half: starts like Arrow, has no footer.
    let real =
        std::fs::read(crate::log_dir(WITH_EGO).join(ANNOTATIONS_WITH_EGO_FILE)).expect("read");
    std::fs::write(&path, &real[..real.len() / 2]).expect("write");
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::NotArrow { .. }), "{err}");
    assert_names(&err, ANNOTATIONS_WITH_EGO_FILE, &["Arrow"]);

    // An empty pose file.
    std::fs::write(&path, &real).expect("write");
    std::fs::write(dir.join(EGO_POSES_FILE), b"").expect("write");
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::NotArrow { .. }), "{err}");
    assert_names(&err, EGO_POSES_FILE, &[]);
}

#[test]
fn damaged_bytes_never_panic() {
    // Damage the real annotation and pose files at pseudo-random offsets (some also cut short);
    // each load is an error naming the damaged file or a scene, never a crash. (Before the reader
    // checked declared sizes, 3 of 800 such damages made arrow-ipc 60 panic; a one-off run of
    // 9,000 damages after the checks saw no panic and no abort.)
    let (_tmp, dir) = copy_log(WITH_EGO);
    let mut seed: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    let mut errors = 0;
    for file in [ANNOTATIONS_WITH_EGO_FILE, EGO_POSES_FILE] {
        let path = dir.join(file);
        let real = std::fs::read(&path).expect("read");
        for _ in 0..40 {
            let mut bytes = real.clone();
            for _ in 0..1 + rnd() % 4 {
                let at = (rnd() as usize) % bytes.len();
                bytes[at] = rnd() as u8;
            }
            if rnd() % 5 == 0 {
                bytes.truncate((rnd() as usize) % bytes.len());
            }
            std::fs::write(&path, &bytes).expect("write");
            if let Err(e) = load_scene(&dir) {
                assert!(e.to_string().contains(file), "{e}");
                errors += 1;
            }
        }
        std::fs::write(&path, &real).expect("restore");
    }
    assert!(errors > 0, "some damage must be detected");
    load_ok(&dir);
}

/// Offset in `bytes` (an LZ4 Arrow IPC file) of the uncompressed-length prefix of the first
/// compressed buffer of the first record batch.
fn first_compressed_length_prefix(bytes: &[u8]) -> usize {
    let n = bytes.len();
    let mut w = [0u8; 4];
    w.copy_from_slice(&bytes[n - 10..n - 6]);
    let footer_len = i32::from_le_bytes(w) as usize;
    let footer = arrow_ipc::root_as_footer(&bytes[n - 10 - footer_len..n - 10]).expect("footer");
    let block = footer.recordBatches().expect("blocks").get(0);
    let offset = block.offset() as usize;
    let meta_len = block.metaDataLength() as usize;
    let message = arrow_ipc::root_as_message(&bytes[offset + 8..offset + meta_len]).expect("msg");
    let batch = message.header_as_record_batch().expect("record batch");
    assert!(batch.compression().is_some(), "the fixture is compressed");
    let buf = batch
        .buffers()
        .expect("buffers")
        .iter()
        .find(|b| b.length() >= 8)
        .expect("a compressed buffer");
    offset + meta_len + buf.offset() as usize
}

#[test]
fn absurd_declared_sizes_are_errors_not_aborts() {
    // A compressed buffer claiming 2^50 uncompressed bytes would make the decoder allocate a
    // petabyte and abort the process; the reader must reject it first.
    let (_tmp, dir) = copy_log(WITH_EGO);
    let path = dir.join(ANNOTATIONS_WITH_EGO_FILE);
    let mut bytes = std::fs::read(&path).expect("read");
    let at = first_compressed_length_prefix(&bytes);
    let real_len = i64::from_le_bytes(bytes[at..at + 8].try_into().expect("8 bytes"));
    assert!(
        real_len > 0 && real_len < 1 << 20,
        "prefix found: {real_len}"
    );
    bytes[at..at + 8].copy_from_slice(&(1i64 << 50).to_le_bytes());
    std::fs::write(&path, &bytes).expect("write");
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::NotArrow { .. }), "{err}");
    assert_names(
        &err,
        ANNOTATIONS_WITH_EGO_FILE,
        &["1125899906842624 uncompressed bytes"],
    );
}

#[test]
fn missing_column() {
    let (_tmp, dir) = copy_log(WITH_EGO);
    rewrite(&dir, ANNOTATIONS_WITH_EGO_FILE, |b| {
        vec![drop_column(&b, "qw")]
    });
    let err = load_err(&dir);
    assert!(
        matches!(err, LoadError::MissingColumn { column: "qw", .. }),
        "{err}"
    );
    assert_names(&err, ANNOTATIONS_WITH_EGO_FILE, &["`qw`", "double"]);

    let (_tmp, dir) = copy_log(WITH_EGO);
    rewrite(&dir, EGO_POSES_FILE, |b| vec![drop_column(&b, "tz_m")]);
    let err = load_err(&dir);
    assert!(
        matches!(err, LoadError::MissingColumn { column: "tz_m", .. }),
        "{err}"
    );
    assert_names(&err, EGO_POSES_FILE, &["`tz_m`"]);
}

#[test]
fn wrongly_typed_column() {
    let (_tmp, dir) = copy_log(WITH_EGO);
    rewrite(&dir, ANNOTATIONS_WITH_EGO_FILE, |b| {
        let text: Vec<String> = f64_column(&b, "tx_m")
            .iter()
            .map(|v| v.to_string())
            .collect();
        let arr: ArrayRef = Arc::new(StringArray::from(text));
        vec![replace_column(&b, "tx_m", arr)]
    });
    let err = load_err(&dir);
    assert!(
        matches!(err, LoadError::ColumnType { column: "tx_m", .. }),
        "{err}"
    );
    assert_names(
        &err,
        ANNOTATIONS_WITH_EGO_FILE,
        &["`tx_m`", "Utf8", "double"],
    );

    let (_tmp, dir) = copy_log(WITH_EGO);
    rewrite(&dir, EGO_POSES_FILE, |b| {
        let col = b.column_by_name("timestamp_ns").expect("ts");
        let as_f64 = arrow_cast_i64_to_f64(col);
        vec![replace_column(&b, "timestamp_ns", as_f64)]
    });
    let err = load_err(&dir);
    assert!(
        matches!(
            err,
            LoadError::ColumnType {
                column: "timestamp_ns",
                ..
            }
        ),
        "{err}"
    );
    assert_names(
        &err,
        EGO_POSES_FILE,
        &["`timestamp_ns`", "Float64", "int64"],
    );
}

fn arrow_cast_i64_to_f64(col: &ArrayRef) -> ArrayRef {
    let a = col
        .as_any()
        .downcast_ref::<arrow_array::Int64Array>()
        .expect("i64");
    Arc::new(Float64Array::from_iter_values(
        a.values().iter().map(|&v| v as f64),
    ))
}

#[test]
fn nan_in_a_box_and_inf_in_a_pose() {
    let (_tmp, dir) = copy_log(WITH_EGO);
    rewrite(&dir, ANNOTATIONS_WITH_EGO_FILE, |b| {
        let mut v = f64_column(&b, "ty_m");
        v[5] = f64::NAN;
        vec![replace_column(&b, "ty_m", Arc::new(Float64Array::from(v)))]
    });
    let err = load_err(&dir);
    assert!(
        matches!(
            err,
            LoadError::NonFinite {
                column: "ty_m",
                row: 5,
                ..
            }
        ),
        "{err}"
    );
    assert_names(
        &err,
        ANNOTATIONS_WITH_EGO_FILE,
        &["`ty_m`", "row 5", "NaN", "finite"],
    );

    // Infinity in the pose row of the first annotation timestamp.
    let (_tmp, dir) = copy_log(WITH_EGO);
    let first_ns = load_ok(&crate::log_dir(WITH_EGO)).timeline.timestamps_ns()[0];
    let mut bad_row = None;
    rewrite(&dir, EGO_POSES_FILE, |b| {
        let ts = b
            .column_by_name("timestamp_ns")
            .and_then(|c| {
                c.as_any()
                    .downcast_ref::<arrow_array::Int64Array>()
                    .cloned()
            })
            .expect("ts");
        let row = ts
            .values()
            .iter()
            .position(|&t| t == first_ns)
            .expect("pose row");
        bad_row = Some(row);
        let mut v = f64_column(&b, "qz");
        v[row] = f64::INFINITY;
        vec![replace_column(&b, "qz", Arc::new(Float64Array::from(v)))]
    });
    let err = load_err(&dir);
    match &err {
        LoadError::NonFinite { column, row, .. } => {
            assert_eq!((*column, Some(*row)), ("qz", bad_row));
        }
        other => panic!("expected NonFinite, got {other}"),
    }
    assert_names(&err, EGO_POSES_FILE, &["`qz`", "inf"]);
}

#[test]
fn null_value() {
    let (_tmp, dir) = copy_log(WITH_EGO);
    rewrite(&dir, ANNOTATIONS_WITH_EGO_FILE, |b| {
        let v = f64_column(&b, "length_m");
        let with_null: Float64Array = v
            .iter()
            .enumerate()
            .map(|(i, &x)| if i == 42 { None } else { Some(x) })
            .collect();
        vec![replace_column(&b, "length_m", Arc::new(with_null))]
    });
    let err = load_err(&dir);
    assert!(
        matches!(
            err,
            LoadError::Null {
                column: "length_m",
                row: 42,
                ..
            }
        ),
        "{err}"
    );
    assert_names(
        &err,
        ANNOTATIONS_WITH_EGO_FILE,
        &["`length_m`", "row 42", "null"],
    );
}

#[test]
fn zero_quaternion() {
    let (_tmp, dir) = copy_log(WITH_EGO);
    rewrite(&dir, ANNOTATIONS_WITH_EGO_FILE, |b| {
        let n = b.num_rows();
        let mut out = b.clone();
        for q in ["qw", "qx", "qy", "qz"] {
            let mut v = f64_column(&out, q);
            v[7] = 0.0;
            out = replace_column(&out, q, Arc::new(Float64Array::from(v)));
        }
        assert_eq!(out.num_rows(), n);
        vec![out]
    });
    let err = load_err(&dir);
    assert!(
        matches!(err, LoadError::BadQuaternion { row: 7, .. }),
        "{err}"
    );
    assert_names(&err, ANNOTATIONS_WITH_EGO_FILE, &["row 7", "quaternion"]);
}

#[test]
fn duplicate_track_timestamp_rows() {
    let (_tmp, dir) = copy_log(WITH_EGO);
    let mut uuid = String::new();
    rewrite(&dir, ANNOTATIONS_WITH_EGO_FILE, |b| {
        uuid = str_column(&b, "track_uuid")[3].clone();
        vec![b.clone(), b.slice(3, 1)]
    });
    let err = load_err(&dir);
    match &err {
        LoadError::DuplicateRow {
            track,
            first_row,
            second_row,
            ..
        } => {
            assert_eq!(track, &uuid);
            assert_eq!((*first_row, *second_row), (3, 13_820));
        }
        other => panic!("expected DuplicateRow, got {other}"),
    }
    assert_names(
        &err,
        ANNOTATIONS_WITH_EGO_FILE,
        &[&uuid, "rows 3 and 13820"],
    );
}

#[test]
fn annotation_timestamp_without_ego_pose() {
    let (_tmp, dir) = copy_log(WITH_EGO);
    let ts = load_ok(&crate::log_dir(WITH_EGO)).timeline.timestamps_ns()[10];
    rewrite(&dir, EGO_POSES_FILE, |b| {
        let col = b.column_by_name("timestamp_ns").expect("ts");
        let a = col
            .as_any()
            .downcast_ref::<arrow_array::Int64Array>()
            .expect("i64");
        let row = a.values().iter().position(|&t| t == ts).expect("row");
        vec![b.slice(0, row), b.slice(row + 1, b.num_rows() - row - 1)]
    });
    let err = load_err(&dir);
    assert!(
        matches!(err, LoadError::NoEgoPose { timestamp_ns, .. } if timestamp_ns == ts),
        "{err}"
    );
    assert_names(
        &err,
        EGO_POSES_FILE,
        &[&ts.to_string(), ANNOTATIONS_WITH_EGO_FILE, "no ego pose"],
    );
}

#[test]
fn duplicate_pose_timestamp() {
    let (_tmp, dir) = copy_log(WITH_EGO);
    rewrite(&dir, EGO_POSES_FILE, |b| vec![b.clone(), b.slice(100, 1)]);
    let err = load_err(&dir);
    assert!(
        matches!(
            err,
            LoadError::DuplicatePoseTimestamp { first_row: 100, .. }
        ),
        "{err}"
    );
    assert_names(&err, EGO_POSES_FILE, &["`timestamp_ns`", "rows 100 and"]);
}

#[test]
fn mixed_category_several_egos_and_reserved_uuid() {
    // One row of a track relabelled.
    let (_tmp, dir) = copy_log(WITH_EGO);
    rewrite(&dir, ANNOTATIONS_WITH_EGO_FILE, |b| {
        let uuids = str_column(&b, "track_uuid");
        let mut cats = str_column(&b, "category");
        let last = uuids.iter().rposition(|u| *u == uuids[0]).expect("row");
        cats[last] = "ANIMAL".into();
        vec![replace_column(
            &b,
            "category",
            Arc::new(StringArray::from(cats)),
        )]
    });
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::MixedCategory { .. }), "{err}");
    assert_names(&err, ANNOTATIONS_WITH_EGO_FILE, &["`category`", "ANIMAL"]);

    // A whole non-ego track relabelled EGO_VEHICLE: two ego tracks.
    let (_tmp, dir) = copy_log(WITH_EGO);
    rewrite(&dir, ANNOTATIONS_WITH_EGO_FILE, |b| {
        let uuids = str_column(&b, "track_uuid");
        let mut cats = str_column(&b, "category");
        let other = uuids
            .iter()
            .zip(&cats)
            .find(|(_, c)| *c != "EGO_VEHICLE")
            .map(|(u, _)| u.clone())
            .expect("a non-ego track");
        for (u, c) in uuids.iter().zip(cats.iter_mut()) {
            if *u == other {
                *c = "EGO_VEHICLE".into();
            }
        }
        vec![replace_column(
            &b,
            "category",
            Arc::new(StringArray::from(cats)),
        )]
    });
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::SeveralEgoTracks { .. }), "{err}");
    assert_names(
        &err,
        ANNOTATIONS_WITH_EGO_FILE,
        &["EGO_VEHICLE", "at most one"],
    );

    // The plain log with a track named like the ego track the reader adds.
    let (_tmp, dir) = copy_log(PLAIN);
    rewrite(&dir, ANNOTATIONS_FILE, |b| {
        let mut uuids = str_column(&b, "track_uuid");
        let first = uuids[0].clone();
        for u in uuids.iter_mut().filter(|u| **u == first) {
            *u = ADDED_EGO_UUID.into();
        }
        vec![replace_column(
            &b,
            "track_uuid",
            Arc::new(StringArray::from(uuids)),
        )]
    });
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::ReservedUuid { .. }), "{err}");
    assert_names(&err, ANNOTATIONS_FILE, &["`track_uuid`", "reserved"]);
}

fn map_path(dir: &Path) -> PathBuf {
    let map = dir.join("map");
    std::fs::read_dir(&map)
        .expect("map dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("log_map_archive_"))
        })
        .expect("map file")
}

fn edit_map(dir: &Path, f: impl FnOnce(String) -> String) -> String {
    let path = map_path(dir);
    let text = std::fs::read_to_string(&path).expect("read map");
    std::fs::write(&path, f(text)).expect("write map");
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

#[test]
fn malformed_map_json() {
    // Not JSON at all: cut in the middle.
    let (_tmp, dir) = copy_log(WITH_EGO);
    let name = edit_map(&dir, |t| t[..t.len() / 2].to_owned());
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::MapJson { .. }), "{err}");
    assert_names(&err, &name, &["EOF"]);

    // A field of the wrong type: the message names its path.
    let (_tmp, dir) = copy_log(WITH_EGO);
    let name = edit_map(&dir, |t| {
        t.replacen(
            "\"is_intersection\": false",
            "\"is_intersection\": \"no\"",
            1,
        )
    });
    let err = load_err(&dir);
    match &err {
        LoadError::MapJson { field, .. } => {
            assert!(field.starts_with("lane_segments."), "{field}");
            assert!(field.ends_with(".is_intersection"), "{field}");
        }
        other => panic!("expected MapJson, got {other}"),
    }
    assert_names(&err, &name, &["is_intersection", "expected a boolean"]);

    // A missing field.
    let (_tmp, dir) = copy_log(WITH_EGO);
    let name = edit_map(&dir, |t| t.replacen("\"successors\"", "\"successorz\"", 1));
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::MapJson { .. }), "{err}");
    assert_names(
        &err,
        &name,
        &["lane_segments.", "missing field `successors`"],
    );

    // An unknown lane type.
    let (_tmp, dir) = copy_log(WITH_EGO);
    let name = edit_map(&dir, |t| {
        t.replacen("\"lane_type\": \"VEHICLE\"", "\"lane_type\": \"TRAM\"", 1)
    });
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::MapJson { .. }), "{err}");
    assert_names(&err, &name, &[".lane_type", "TRAM", "VEHICLE"]);

    // A point missing its z.
    let (_tmp, dir) = copy_log(WITH_EGO);
    let name = edit_map(&dir, |t| t.replacen(", \"z\": ", ", \"w\": ", 1));
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::MapJson { .. }), "{err}");
    assert_names(&err, &name, &["missing field `z`"]);
}

#[test]
fn no_map_file_and_two_map_files() {
    let (_tmp, dir) = copy_log(WITH_EGO);
    let path = map_path(&dir);
    std::fs::remove_file(&path).expect("rm");
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::NoMapFile { .. }), "{err}");
    assert!(err.path() == dir, "{err}");
    assert!(err.to_string().contains("log_map_archive_"), "{err}");

    let (_tmp, dir) = copy_log(WITH_EGO);
    let path = map_path(&dir);
    std::fs::copy(
        &path,
        dir.join("map/log_map_archive_copy____MIA_city_1.json"),
    )
    .expect("cp");
    let err = load_err(&dir);
    assert!(matches!(err, LoadError::SeveralMapFiles { .. }), "{err}");
    assert!(err.to_string().contains("expected one"), "{err}");
}
