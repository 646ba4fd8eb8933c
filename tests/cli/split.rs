//! `scenalog mine --log-prompts`: a split's pairs from annotations or a tracker's output, on the
//! real sample logs and the tracker files made from them (`tests/data/av2/tracker/`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Output;

use scenalog_eval::{evaluate, read_pickle, EvalOptions, PyValue as P, Submission};

fn data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/av2")
        .join(rel)
}

const LOG_A: &str = "3b3570b4-7b0b-3268-a571-b0889dbf40b6";
const LOG_B: &str = "3bffdcff-c3a7-38b6-a0f2-64196d130958";

/// `scenalog mine --log-prompts PAIRS --dataset-dir logs --out OUT [--tracks T] [extra…]`.
fn mine(pairs: &Path, tracks: Option<&Path>, out: &Path, extra: &[&str]) -> Output {
    let mut c = crate::util::scenalog();
    c.arg("mine")
        .arg("--log-prompts")
        .arg(pairs)
        .arg("--dataset-dir")
        .arg(data("logs"))
        .arg("--out")
        .arg(out)
        .args(["--threads", "2"])
        .args(extra);
    if let Some(t) = tracks {
        c.arg("--tracks").arg(t);
    }
    c.output().expect("scenalog runs")
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn submission(out: &Path) -> Submission {
    read_pickle(&out.join("submission.pkl")).expect("submission.pkl reads")
}

fn hota_temporal(sub: &Submission) -> f64 {
    let gt = read_pickle(&data("eval/combined_gt_dev.pkl")).expect("ground truth");
    evaluate(sub, &gt, &EvalOptions::default())
        .expect("evaluates")
        .hota_temporal
}

/// No leftovers of the run beside its outputs (the published generation and its link).
fn no_temporary_files(out: &Path) {
    let current = std::fs::read_link(out.join(".current")).ok();
    for e in std::fs::read_dir(out).expect("out").flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let published = name == ".current" || current.as_deref() == Some(Path::new(&name));
        // The folder's lock file stays, released (naming no holder).
        let released_lock =
            name == ".lock" && std::fs::read_to_string(e.path()).is_ok_and(|t| t.is_empty());
        assert!(
            published || released_lock || !name.starts_with('.'),
            "left behind: {name}"
        );
    }
}

#[test]
fn exact_tracker_scores_as_annotations_and_noisy_lower() {
    let dir = tempfile::tempdir().expect("tempdir");
    let pairs = data("tracker/log_prompt_pairs_fixture.json");
    let mut scores = BTreeMap::new();
    for (name, tracks) in [
        ("annotations", None),
        ("exact", Some(data("tracker/exact.pkl"))),
        ("noisy", Some(data("tracker/noisy.pkl"))),
    ] {
        let out = dir.path().join(name);
        let o = mine(&pairs, tracks.as_deref(), &out, &[]);
        assert!(o.status.success(), "{name}: {}", text(&o));
        let sub = submission(&out);
        let keys: Vec<_> = sub.sequences.keys().cloned().collect();
        assert_eq!(
            keys,
            vec![
                (
                    LOG_A.to_string(),
                    "vehicle with a bicycle to its right".to_string()
                ),
                (LOG_B.to_string(), "stopped car".to_string()),
            ]
        );
        no_temporary_files(&out);
        // Joined from per-log parts, the file is byte for byte the whole submission's pickle.
        let bytes = std::fs::read(out.join("submission.pkl")).expect("read");
        assert!(bytes == scenalog_eval::pickle_bytes(&sub), "{name}");
        scores.insert(name, hota_temporal(&sub));
    }
    assert_eq!(scores["exact"], scores["annotations"], "{scores:?}");
    assert!(scores["annotations"] > 0.5, "{scores:?}");
    assert!(scores["noisy"] < scores["annotations"] - 0.02, "{scores:?}");
}

/// Every predicted box of the noisy run carries the tracker's score of that box (found by its
/// timestamp and city centre); ground truth carries 1.0.
#[test]
fn tracker_scores_are_carried_into_the_predictions() {
    let dir = tempfile::tempdir().expect("tempdir");
    let pairs = data("tracker/log_prompt_pairs_sample.json");
    let out = dir.path().join("noisy");
    let o = mine(&pairs, Some(&data("tracker/noisy.pkl")), &out, &[]);
    assert!(o.status.success(), "{}", text(&o));
    let tracker = scenalog_tracker::TrackerPickle::open(&data("tracker/noisy.pkl")).expect("pkl");
    let sub = submission(&out);
    let (mut checked, mut below_one) = (0usize, 0usize);
    for ((log, _), frames) in &sub.sequences {
        let dets = tracker.frames(log).expect("frames");
        for f in frames {
            let d = dets
                .iter()
                .find(|d| d.timestamp_ns == f.timestamp_ns)
                .expect("a tracker frame at every output timestamp");
            let scores = f.score.as_ref().expect("scores");
            for (i, t) in f.translation_m.iter().enumerate() {
                if scores[i] == 1.0 {
                    // The ego (scored 1.0; referred by programs about any vehicle, or related)
                    // is in no tracker frame; every tracker score is below one (asserted below).
                    continue;
                }
                let j = (0..d.len())
                    .find(|&j| (0..3).all(|k| (d.translation_m[j][k] - t[k]).abs() < 1e-6))
                    .unwrap_or_else(|| panic!("{log}: box {t:?} is not a tracker box"));
                assert_eq!(scores[i], d.score[j], "{log} at {}", f.timestamp_ns);
                checked += 1;
                below_one += usize::from(scores[i] < 1.0);
            }
        }
    }
    assert!(
        checked > 1000 && below_one == checked,
        "{checked} {below_one}"
    );

    let gt_out = dir.path().join("gt");
    let o = mine(&pairs, None, &gt_out, &[]);
    assert!(o.status.success(), "{}", text(&o));
    let all_one = submission(&gt_out).sequences.values().flatten().all(|f| {
        f.score
            .as_ref()
            .is_some_and(|s| s.iter().all(|&x| x == 1.0))
    });
    assert!(all_one);
}

#[test]
fn listed_pairs_only_and_prompts_without_program_get_empty_predictions() {
    let dir = tempfile::tempdir().expect("tempdir");
    let pairs_path = data("tracker/log_prompt_pairs_sample.json");
    let out = dir.path().join("o");
    let o = mine(&pairs_path, Some(&data("tracker/exact.pkl")), &out, &[]);
    assert!(o.status.success(), "{}", text(&o));
    let listed: BTreeMap<String, Vec<String>> =
        serde_json::from_str(&std::fs::read_to_string(&pairs_path).expect("pairs")).expect("json");
    let want: Vec<(String, String)> = listed
        .iter()
        .flat_map(|(l, ps)| ps.iter().map(move |p| (l.clone(), p.clone())))
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    let sub = submission(&out);
    assert_eq!(sub.sequences.keys().cloned().collect::<Vec<_>>(), want);
    let empty = &sub.sequences[&(
        "adcf7d18-0510-35b0-a2fa-b4cea13a6d76".to_string(),
        "a prompt no program describes".to_string(),
    )];
    assert!(!empty.is_empty(), "frames at the output timestamps");
    assert!(empty
        .iter()
        .all(|f| f.name.iter().all(|n| n == "OTHER_OBJECT")));
    assert!(
        text(&o).contains("a prompt no program describes"),
        "{}",
        text(&o)
    );
}

#[test]
fn a_log_missing_from_the_tracker_file_is_named_and_the_rest_mined() {
    let dir = tempfile::tempdir().expect("tempdir");
    let pairs = dir.path().join("pairs.json");
    std::fs::write(
        &pairs,
        format!(
            r#"{{"{LOG_A}": ["stopped car"], "00000000-0000-0000-0000-000000000000": ["stopped car"]}}"#
        ),
    )
    .expect("write");
    let out = dir.path().join("o");
    let o = mine(&pairs, Some(&data("tracker/exact.pkl")), &out, &[]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains("log 00000000-0000-0000-0000-000000000000: not in the tracker file"),
        "{}",
        text(&o)
    );
    let sub = submission(&out);
    assert_eq!(sub.sequences.len(), 1);
    assert!(sub
        .sequences
        .contains_key(&(LOG_A.to_string(), "stopped car".to_string())));
}

/// A tracker pickle of two logs: `bad` gets one broken frame (by `breakage`), LOG_B stays good.
fn broken_pickle(dir: &Path, breakage: &str) -> PathBuf {
    let s = |x: &str| P::Str(x.to_string());
    let frame = |ts: i64, t: [f64; 3], name: &str| {
        P::Dict(vec![
            (s("timestamp_ns"), P::I64(ts)),
            (s("translation_m"), P::F64Array(vec![1, 3], t.to_vec())),
            (s("size"), P::F64Array(vec![1, 3], vec![4.0, 2.0, 1.5])),
            (s("yaw"), P::F64Array(vec![1], vec![0.0])),
            (s("name"), P::StrArray(vec![name.to_string()])),
            (s("score"), P::F32Array(vec![1], vec![0.9])),
            (s("track_id"), P::I64Array(vec![1])),
        ])
    };
    let good = |log: &str| {
        let scene = scenalog_facts::load_scene(&data("logs").join(log)).expect("log");
        let frames: Vec<P> = scene
            .timeline
            .timestamps_ns()
            .iter()
            .enumerate()
            .map(|(f, &ts)| {
                let p = scene.ego_poses[f].translation.vector;
                frame(ts, [p.x + 10.0, p.y, p.z], "REGULAR_VEHICLE")
            })
            .collect();
        frames
    };
    let mut a = good(LOG_A);
    let P::Dict(items) = &mut a[3] else {
        unreachable!()
    };
    match breakage {
        "nan" => items[1].1 = P::F64Array(vec![1, 3], vec![f64::NAN, 0.0, 0.0]),
        "lengths" => items[3].1 = P::F64Array(vec![2], vec![0.0, 0.1]),
        "category" => items[4].1 = P::StrArray(vec!["SPACESHIP".into()]),
        _ => unreachable!(),
    }
    let value = P::Dict(vec![
        (s(LOG_A), P::List(a)),
        (s(LOG_B), P::List(good(LOG_B))),
    ]);
    let path = dir.join(format!("{breakage}.pkl"));
    std::fs::write(&path, scenalog_eval::encode_value(&value)).expect("write");
    path
}

#[test]
fn bad_tracker_boxes_are_named_by_log_frame_and_field_and_good_logs_mined() {
    let dir = tempfile::tempdir().expect("tempdir");
    let pairs = dir.path().join("pairs.json");
    std::fs::write(
        &pairs,
        format!(r#"{{"{LOG_A}": ["stopped car"], "{LOG_B}": ["stopped car"]}}"#),
    )
    .expect("write");
    for (breakage, field, what) in [
        ("nan", "translation_m", "not finite"),
        ("lengths", "yaw", "2 values but \"track_id\" has 1"),
        ("category", "name", "unknown AV2 category \"SPACESHIP\""),
    ] {
        let tracks = broken_pickle(dir.path(), breakage);
        let out = dir.path().join(breakage);
        let o = mine(&pairs, Some(&tracks), &out, &[]);
        let t = text(&o);
        assert_eq!(o.status.code(), Some(1), "{breakage}: {t}");
        let expected = format!("log {LOG_A}: frame 3: field \"{field}\": ");
        assert!(t.contains(&expected) && t.contains(what), "{breakage}: {t}");
        let sub = submission(&out);
        let keys: Vec<_> = sub.sequences.keys().map(|k| k.0.as_str()).collect();
        assert_eq!(keys, vec![LOG_B], "{breakage}");
        no_temporary_files(&out);
    }
}

#[test]
fn a_file_that_is_not_the_tracking_format_is_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    let pairs = data("tracker/log_prompt_pairs_fixture.json");
    // The official scenario-mining ground truth is a pickle, but not a tracker's output.
    let o = mine(
        &pairs,
        Some(&data("eval/combined_gt_dev.pkl")),
        dir.path(),
        &[],
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("not the AV2 3D-tracking format"),
        "{}",
        text(&o)
    );
    // And a file that is no pickle at all.
    let o = mine(
        &pairs,
        Some(&data("logs").join(LOG_A).join("city_SE3_egovehicle.feather")),
        dir.path(),
        &[],
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("not a readable pickle"), "{}", text(&o));
    assert!(!dir.path().join("submission.pkl").exists());
}

#[test]
fn flags_of_the_programs_on_logs_run_are_refused_not_ignored() {
    // --gt, --eval-timestamps, --report and --format json mean nothing for a split's pairs:
    // each is an error naming what to do instead, and nothing is written.
    let dir = tempfile::tempdir().expect("tempdir");
    let pairs = data("tracker/log_prompt_pairs_fixture.json");
    let gt = data("eval/combined_gt_dev.pkl");
    let gt = gt.to_str().expect("utf-8 path");
    for (extra, says) in [
        (vec!["--gt", gt], "scenalog eval"),
        (vec!["--eval-timestamps", gt], "own timestamps"),
        (vec!["--report"], "--picture"),
        (vec!["--format", "json"], "summary.json"),
    ] {
        let o = mine(&pairs, None, dir.path(), &extra);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", text(&o));
        assert!(
            text(&o).contains("does not go with --log-prompts") && text(&o).contains(says),
            "{extra:?}: {}",
            text(&o)
        );
        assert!(!dir.path().join("submission.pkl").exists());
    }
}

/// `--resume` redoes a pair whose log changed (here: its map file, byte for byte) and reuses
/// the others.
#[test]
fn resume_redoes_pairs_whose_log_files_changed() {
    let dir = tempfile::tempdir().expect("tempdir");
    let split = dir.path().join("split");
    for log in [LOG_A, LOG_B] {
        let from = data("logs").join(log);
        let to = split.join(log);
        std::fs::create_dir_all(to.join("map")).expect("mkdir");
        for e in std::fs::read_dir(&from).expect("log").flatten() {
            if e.path().is_file() {
                std::fs::copy(e.path(), to.join(e.file_name())).expect("copy");
            }
        }
        for e in std::fs::read_dir(from.join("map")).expect("map").flatten() {
            std::fs::copy(e.path(), to.join("map").join(e.file_name())).expect("copy");
        }
    }
    let pairs = data("tracker/log_prompt_pairs_fixture.json");
    let out = dir.path().join("o");
    let run = |resume: bool| {
        let mut c = crate::util::scenalog();
        c.arg("mine")
            .arg("--log-prompts")
            .arg(&pairs)
            .arg("--dataset-dir")
            .arg(&split)
            .arg("--out")
            .arg(&out);
        if resume {
            c.arg("--resume");
        }
        let o = c.output().expect("runs");
        assert!(o.status.success(), "{}", text(&o));
        let summary: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(out.join("summary.json")).expect("summary"),
        )
        .expect("json");
        summary["pairs"]
            .as_array()
            .expect("pairs")
            .iter()
            .map(|p| {
                (
                    p["log_id"].as_str().unwrap_or("").to_string(),
                    p["status"].as_str().unwrap_or("").to_string(),
                )
            })
            .collect::<BTreeMap<String, String>>()
    };
    let first = run(false);
    assert!(first.values().all(|s| s == "done"), "{first:?}");
    let again = run(true);
    assert!(again.values().all(|s| s == "resumed"), "{again:?}");
    let map = std::fs::read_dir(split.join(LOG_A).join("map"))
        .expect("map")
        .flatten()
        .find(|e| {
            e.file_name()
                .to_string_lossy()
                .starts_with("log_map_archive_")
        })
        .expect("map file")
        .path();
    let mut bytes = std::fs::read(&map).expect("read");
    bytes.push(b'\n');
    std::fs::write(&map, bytes).expect("write");
    let changed = run(true);
    assert_eq!(changed[LOG_A], "done", "{changed:?}");
    assert_eq!(changed[LOG_B], "resumed", "{changed:?}");
}

/// RefAV's per-log form of a tracker's output (`sm_annotations.feather`: the annotation columns
/// plus `score`, the ego as a track) works as a split directory as it is: its scores reach the
/// predictions as a tracker pickle's do.
#[test]
fn refav_per_log_feather_with_scores_is_read_and_its_scores_carried() {
    use std::sync::Arc;

    use arrow_array::{Array, Float32Array, RecordBatch, StringArray};
    use arrow_schema::{DataType, Field, Schema};

    let dir = tempfile::tempdir().expect("tempdir");
    let from = data("logs").join(LOG_B);
    let to = dir.path().join("split").join(LOG_B);
    std::fs::create_dir_all(to.join("map")).expect("mkdir");
    let poses = "city_SE3_egovehicle.feather";
    std::fs::copy(from.join(poses), to.join(poses)).expect("copy");
    for e in std::fs::read_dir(from.join("map")).expect("map").flatten() {
        std::fs::copy(e.path(), to.join("map").join(e.file_name())).expect("copy");
    }
    // The annotations with a float32 `score` column: 0.25 for every object, 1 for the ego.
    let file = std::fs::File::open(from.join("annotations_with_ego.feather")).expect("open");
    let reader = arrow_ipc::reader::FileReader::try_new(file, None).expect("arrow");
    let mut fields: Vec<Field> = reader
        .schema()
        .fields()
        .iter()
        .map(|f| f.as_ref().clone())
        .collect();
    fields.push(Field::new("score", DataType::Float32, false));
    let schema = Arc::new(Schema::new(fields));
    let out_file = std::fs::File::create(to.join("sm_annotations.feather")).expect("create");
    let mut writer = arrow_ipc::writer::FileWriter::try_new(out_file, &schema).expect("writer");
    for batch in reader {
        let batch = batch.expect("batch");
        let category = batch
            .column_by_name("category")
            .and_then(|c| c.as_any().downcast_ref::<StringArray>().cloned())
            .expect("category column");
        let score: Float32Array = (0..category.len())
            .map(|i| {
                Some(if category.value(i) == "EGO_VEHICLE" {
                    1.0
                } else {
                    0.25
                })
            })
            .collect();
        let mut columns = batch.columns().to_vec();
        columns.push(Arc::new(score));
        let batch = RecordBatch::try_new(schema.clone(), columns).expect("batch with score");
        writer.write(&batch).expect("write");
    }
    writer.finish().expect("finish");

    let pairs = dir.path().join("pairs.json");
    std::fs::write(&pairs, format!("{{\"{LOG_B}\": [\"stopped car\"]}}")).expect("pairs");
    let out = dir.path().join("out");
    let o = crate::util::scenalog()
        .arg("mine")
        .arg("--log-prompts")
        .arg(&pairs)
        .arg("--dataset-dir")
        .arg(dir.path().join("split"))
        .arg("--out")
        .arg(&out)
        .output()
        .expect("scenalog runs");
    assert!(o.status.success(), "{}", text(&o));
    let sub = submission(&out);
    let frames = &sub.sequences[&(LOG_B.to_string(), "stopped car".to_string())];
    let (mut quarter, mut other) = (0usize, 0usize);
    for f in frames {
        let scores = f.score.as_ref().expect("scores");
        for (i, &s) in scores.iter().enumerate() {
            if s == 0.25 {
                quarter += 1;
            } else if !(s == 1.0 && f.name[i] == "OTHER_OBJECT") {
                other += 1;
            }
        }
    }
    assert!(
        quarter > 100 && other == 0,
        "{quarter} scored 0.25, {other} other"
    );
}

/// Log ids that would climb out of `--dataset-dir` or name an absolute path, in `--log-prompts`
/// and in a tracker pickle, are refused with the id named; nothing outside the split is read.
#[test]
fn climbing_and_absolute_log_ids_are_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    // A log outside the split, which a joined path would reach.
    let outside = dir.path().join("elsewhere");
    std::fs::create_dir_all(&outside).expect("mkdir");
    for id in [
        "../../elsewhere/log",
        "..",
        "/etc",
        outside.to_str().expect("utf8"),
    ] {
        let pairs = dir.path().join("pairs.json");
        let json = serde_json::json!({ id: ["stopped car"] });
        std::fs::write(&pairs, json.to_string()).expect("write");
        let o = mine(&pairs, None, &dir.path().join("out"), &[]);
        assert_eq!(o.status.code(), Some(2), "{id}: {}", text(&o));
        assert!(
            text(&o).contains(&format!("log id {id:?}")),
            "{id}: {}",
            text(&o)
        );

        let s = |x: &str| P::Str(x.to_string());
        let tracks = dir.path().join("tracks.pkl");
        let value = P::Dict(vec![(s(id), P::List(Vec::new()))]);
        std::fs::write(&tracks, scenalog_eval::encode_value(&value)).expect("write");
        let o = mine(
            &data("tracker/log_prompt_pairs_fixture.json"),
            Some(&tracks),
            &dir.path().join("out"),
            &[],
        );
        assert_eq!(o.status.code(), Some(2), "{id}: {}", text(&o));
        assert!(
            text(&o).contains(&format!("log id {id:?}")),
            "{id}: {}",
            text(&o)
        );
    }
}
