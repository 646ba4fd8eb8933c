//! Bad input beyond the pickle reader's own checks (tests/pickle_io.rs): ground truth out of order,
//! truncated Arrow tables, and everything the drivable-area ROI filter reads (maps, dataset directories,
//! box fields). Every case is an error naming the place, never a panic.

use scenalog_eval::{
    evaluate, read_pickle, read_table, EvalOptions, RoiMaps, RoiRaster, Submission,
};
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

const LOG_A: &str = "3b3570b4-7b0b-3268-a571-b0889dbf40b6";
const LOG_B: &str = "3bffdcff-c3a7-38b6-a0f2-64196d130958";

fn data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/av2")
        .join(rel)
}

fn load() -> (Submission, Submission) {
    let pred = read_pickle(&data("eval/combined_predictions_dev.pkl")).expect("predictions");
    let gt = read_pickle(&data("eval/combined_gt_dev.pkl")).expect("ground truth");
    (pred, gt)
}

fn key(log: &str) -> (String, String) {
    let prompt = if log == LOG_B {
        "stopped car"
    } else {
        "vehicle with a bicycle to its right"
    };
    (log.to_string(), prompt.to_string())
}

#[test]
fn ground_truth_out_of_time_order() {
    let (pred, mut gt) = load();
    gt.sequences.get_mut(&key(LOG_A)).expect("seq").swap(10, 11);
    let e = evaluate(&pred, &gt, &EvalOptions::default())
        .expect_err("out of order")
        .to_string();
    assert!(
        e.contains("ground truth") && e.contains("frame 11") && e.contains("timestamp_ns"),
        "{e}"
    );
}

#[test]
fn truncated_arrow_table() {
    let bytes = std::fs::read(data("eval/combined_gt_dev.feather")).expect("read");
    let dir = tempfile::tempdir().expect("tempdir");
    for cut in [0, 8, 100, bytes.len() / 2, bytes.len() - 10] {
        let p = dir.path().join(format!("cut{cut}.feather"));
        std::fs::write(&p, &bytes[..cut]).expect("write");
        let e = read_table(&p).expect_err("truncated").to_string();
        assert!(e.contains(&format!("cut{cut}.feather")), "{e}");
    }
}

/// A map directory holding only `files` (name, content).
fn map_dir(root: &Path, log: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = root.join(log).join("map");
    std::fs::create_dir_all(&dir).expect("mkdir");
    for (name, content) in files {
        std::fs::write(dir.join(name), content).expect("write");
    }
    dir
}

#[test]
fn malformed_maps_name_the_file_and_field() {
    let root = tempfile::tempdir().expect("tempdir");
    let archive = "log_map_archive_x.json";
    let cases: [(&str, &[&str]); 6] = [
        ("{not json", &["not JSON"]),
        (r#"{"lane_segments": {}}"#, &["drivable_areas"]),
        (
            r#"{"drivable_areas": {"7": {"id": 7}}}"#,
            &["drivable area 7", "area_boundary"],
        ),
        (
            r#"{"drivable_areas": {"7": {"area_boundary": [{"x": 1.0, "z": 0.0}]}}}"#,
            &["drivable area 7", "area_boundary[0]", "\"y\""],
        ),
        (r#"{"drivable_areas": {}}"#, &["no drivable-area vertices"]),
        (
            r#"{"drivable_areas": {"1": {"area_boundary": [{"x": 0, "y": 0}, {"x": 1e7, "y": 1e7}]}}}"#,
            &["too large"],
        ),
    ];
    for (i, (content, wants)) in cases.iter().enumerate() {
        let log = format!("log{i}");
        let dir = map_dir(root.path(), &log, &[(archive, content)]);
        let e = RoiRaster::from_map_dir(&dir)
            .expect_err("malformed map")
            .to_string();
        assert!(e.contains(archive), "case {i}: {e}");
        for w in *wants {
            assert!(e.contains(w), "case {i}: {e} lacks {w}");
        }
    }
    // no archive, or two
    let dir = map_dir(root.path(), "none", &[("other.json", "{}")]);
    let e = RoiRaster::from_map_dir(&dir)
        .expect_err("no map")
        .to_string();
    assert!(e.contains("log_map_archive_") && e.contains("none"), "{e}");
    let dir = map_dir(
        root.path(),
        "two",
        &[
            ("log_map_archive_a.json", "{}"),
            ("log_map_archive_b.json", "{}"),
        ],
    );
    let e = RoiRaster::from_map_dir(&dir)
        .expect_err("two maps")
        .to_string();
    assert!(e.contains("2 log_map_archive_"), "{e}");
    // not a directory at all
    let e = RoiRaster::from_map_dir(&root.path().join("absent"))
        .expect_err("absent")
        .to_string();
    assert!(e.contains("absent"), "{e}");
}

#[test]
fn dataset_dir_without_a_log_names_it() {
    let root = tempfile::tempdir().expect("tempdir");
    let e = RoiMaps::load(root.path(), [LOG_A])
        .expect_err("missing log")
        .to_string();
    assert!(e.contains(LOG_A) && e.contains("dataset directory"), "{e}");
}

/// The rasters of the given fixture logs (built once per test binary, then shared).
fn maps_of(logs: &[&str]) -> Arc<RoiMaps> {
    static ALL: OnceLock<RoiMaps> = OnceLock::new();
    let all = ALL.get_or_init(|| RoiMaps::load(&data("logs"), [LOG_A, LOG_B]).expect("maps"));
    let mut maps = RoiMaps::default();
    for log in logs {
        maps.insert(*log, all.shared(log).expect("raster"));
    }
    Arc::new(maps)
}

#[test]
fn roi_filter_needs_every_log_and_box_field() {
    let (pred, gt) = load();
    // a raster for one log only: the other log's sequences are an error naming it
    let opts = EvalOptions {
        roi: Some(maps_of(&[LOG_A])),
        ..EvalOptions::default()
    };
    let e = evaluate(&pred, &gt, &opts)
        .expect_err("missing raster")
        .to_string();
    assert!(e.contains(LOG_B) && e.contains("drivable-area map"), "{e}");

    let opts = EvalOptions {
        roi: Some(maps_of(&[LOG_A, LOG_B])),
        ..EvalOptions::default()
    };
    for field in ["yaw", "size"] {
        let mut p = pred.clone();
        let f = &mut p.sequences.get_mut(&key(LOG_B)).expect("seq")[4];
        if field == "yaw" {
            f.yaw.clear();
        } else {
            f.size.pop();
        }
        let e = evaluate(&p, &gt, &opts).expect_err(field).to_string();
        assert!(
            e.contains("predictions") && e.contains("frame 4") && e.contains(field),
            "{e}"
        );
        let mut sub = p.clone();
        let e = scenalog_eval::mining::filter_roi(&mut sub, &opts.roi.clone().expect("roi"))
            .expect_err(field)
            .to_string();
        assert!(e.contains(field), "{e}");
    }
    // without the ROI the same boxes need no size or yaw
    let mut p = pred.clone();
    p.sequences.get_mut(&key(LOG_B)).expect("seq")[4]
        .yaw
        .clear();
    assert!(evaluate(&p, &gt, &EvalOptions::default()).is_ok());
}

/// Boxes on the far side of the grid or with non-finite coordinates are outside the ROI, not a panic.
#[test]
fn boxes_off_the_grid_are_outside() {
    let maps = maps_of(&[LOG_A]);
    let r = maps.get(LOG_A).expect("raster");
    let b = r.bounds();
    for (x, y) in [
        (b[0] as f64 - 100.0, b[1] as f64),
        (b[2] as f64 + 100.0, b[3] as f64),
        (f64::NAN, b[1] as f64 + 10.0),
        (f64::INFINITY, f64::NEG_INFINITY),
        (1e300, -1e300),
    ] {
        assert!(!r.contains(x, y), "{x},{y}");
        assert!(!r.box_in_roi([x, y, 0.0], [4.0, 2.0, 1.5], 0.3));
    }
    assert!(!r.box_in_roi([f64::NAN; 3], [f32::NAN; 3], f32::NAN));
}

/// NaN or infinite numbers in a box of predictions or ground truth, in the pickle and the Arrow
/// table, are errors naming the sequence, the frame and the field.
#[test]
fn non_finite_boxes_name_sequence_frame_and_field() {
    let (pred, gt) = load();
    let dir = tempfile::tempdir().expect("tempdir");
    let k = key(LOG_A);
    type Spoil = fn(&mut scenalog_eval::FrameData);
    let cases: [(&str, Spoil); 5] = [
        ("translation_m", |f| f.translation_m[1][0] = f64::NAN),
        ("size", |f| f.size[0][2] = f32::INFINITY),
        ("yaw", |f| f.yaw[0] = f32::NEG_INFINITY),
        ("score", |f| {
            if let Some(s) = f.score.as_mut() {
                s[0] = f32::NAN
            }
        }),
        ("ego_translation_m", |f| f.ego_translation_m[2] = f64::NAN),
    ];
    for (which, sub) in [("predictions", &pred), ("ground truth", &gt)] {
        for (field, spoil) in cases {
            if field == "score" && which == "ground truth" {
                continue;
            }
            let mut bad = sub.clone();
            let frames = bad.sequences.get_mut(&k).expect("the sequence");
            let frame = frames
                .iter()
                .position(|f| f.len() > 1)
                .expect("a frame with two boxes");
            spoil(&mut frames[frame]);
            let path = dir.path().join("bad.pkl");
            scenalog_eval::write_pickle(&bad, &path).expect("write");
            let table = dir.path().join("bad.feather");
            scenalog_eval::write_table(&bad, &table).expect("write");
            for file in [&path, &table] {
                let e = scenalog_eval::read_any(file)
                    .expect_err("a NaN box must be refused")
                    .to_string();
                for part in [LOG_A, &format!("frame {frame} "), &format!("{field:?}")] {
                    assert!(e.contains(part), "{which} {field}: {e} lacks {part}");
                }
            }
        }
    }
}

/// A log id that would climb out of the dataset directory, in a prediction or ground-truth key,
/// is refused with the id named, before anything is joined to `--dataset-dir`.
#[test]
fn climbing_and_absolute_log_ids_are_refused() {
    let (pred, _) = load();
    let dir = tempfile::tempdir().expect("tempdir");
    for id in ["../../elsewhere/log", "/etc", "a/b", ".."] {
        let mut bad = pred.clone();
        let frames = bad.sequences.remove(&key(LOG_A)).expect("the sequence");
        bad.sequences
            .insert((id.to_string(), "a prompt".to_string()), frames);
        let path = dir.path().join("ids.pkl");
        scenalog_eval::write_pickle(&bad, &path).expect("write");
        let e = scenalog_eval::read_any(&path)
            .expect_err("refused")
            .to_string();
        assert!(e.contains(&format!("log id {id:?}")), "{e}");
        let e = RoiMaps::load(&data("logs"), [id])
            .expect_err("refused")
            .to_string();
        assert!(e.contains(&format!("log id {id:?}")), "{e}");
    }
}
