//! A tracker file written from a log's own annotations (`tests/data/av2/tracker/exact.pkl`, see
//! `examples/make_tracker_pickles.rs`) gives the same facts as the annotations: every relation
//! of the catalog, tuple for tuple (tracks compared by the annotation uuid they stand for; floats to
//! 1e-4, relative above 1: the city-frame round trip differs by 1e-12 m, which columns computed
//! or stored in `f32` turn into a few `f32` steps, 1e-6 at most on these logs).

use std::path::PathBuf;

use scenalog_extractors::{extract_all_with, Extractor};
use scenalog_facts::relation::Value;
use scenalog_facts::scene::EGO_CATEGORY;
use scenalog_facts::Scene;
use scenalog_tracker::{tracked_log, Filter, TrackerPickle};

fn data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/av2")
        .join(rel)
}

/// A relation's rows as comparable tuples: discrete values as text, floats kept apart.
type Row = (Vec<String>, Vec<f64>);

fn rows(scene: &Scene, uuid_of: &dyn Fn(usize) -> String) -> Vec<(String, Vec<Row>)> {
    let ex = Extractor::new(scene);
    let mut out: Vec<(String, Vec<Row>)> = extract_all_with(&ex)
        .into_iter()
        .map(|r| {
            let mut rows: Vec<Row> = (0..r.len())
                .filter_map(|i| r.row(i))
                .map(|row| {
                    let mut keys = Vec::new();
                    let mut floats = Vec::new();
                    for v in row {
                        match v {
                            Value::Track(t) => keys.push(uuid_of(t.index())),
                            Value::Time(f) => keys.push(format!("t{f}")),
                            Value::Lane(l) => keys.push(format!("{l:?}")),
                            Value::Str(s) => keys.push(s.to_string()),
                            Value::Int(i) => keys.push(i.to_string()),
                            Value::Float(x) => floats.push(x),
                        }
                    }
                    (keys, floats)
                })
                .collect();
            rows.sort_by(|a, b| {
                a.0.cmp(&b.0).then_with(|| {
                    a.1.iter()
                        .zip(&b.1)
                        .map(|(x, y)| x.total_cmp(y))
                        .find(|o| o.is_ne())
                        .unwrap_or(std::cmp::Ordering::Equal)
                })
            });
            (r.name.to_string(), rows)
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

#[test]
fn exact_tracker_file_gives_the_annotations_facts() {
    let pickle = TrackerPickle::open(&data("tracker/exact.pkl")).expect("exact.pkl reads");
    let logs: Vec<String> = pickle.log_ids().map(String::from).collect();
    assert_eq!(logs.len(), 3);
    for log in logs {
        let dir = data("logs").join(&log);
        let truth = scenalog_facts::load_scene(&dir).expect("annotations");
        let frames = pickle.frames(&log).expect("frames");
        let tracked =
            tracked_log(&log, &frames, &dir, Filter::None, pickle.file()).expect("tracker scene");
        let scene = &tracked.scene;
        assert_eq!(scene.tracks.len(), truth.tracks.len(), "{log}: track count");
        assert_eq!(scene.num_boxes(), truth.num_boxes(), "{log}: box count");
        let others: Vec<&str> = truth
            .tracks
            .iter()
            .filter(|t| t.category != EGO_CATEGORY)
            .map(|t| t.uuid.as_str())
            .collect();
        let truth_ego = truth.track(truth.ego).uuid.clone();
        let mapped = |t: usize| match tracked.tracker_ids[t] {
            Some(id) => others[id as usize].to_string(),
            None => truth_ego.clone(),
        };
        // RefAV's order of objects is the input file's: a tracker file has no annotation rows
        // to order by (its tracks go by first frame), so `refav_order` is not compared.
        let a = without_order(rows(&truth, &|t| truth.tracks[t].uuid.clone()));
        let b = without_order(rows(scene, &mapped));
        assert_eq!(a.len(), b.len());
        let mut compared = 0usize;
        for ((name_a, ra), (name_b, rb)) in a.iter().zip(&b) {
            assert_eq!(name_a, name_b);
            assert_eq!(ra.len(), rb.len(), "{log}: relation {name_a}: tuple count");
            for (x, y) in ra.iter().zip(rb) {
                assert_eq!(x.0, y.0, "{log}: relation {name_a}");
                for (u, v) in x.1.iter().zip(&y.1) {
                    assert!(
                        (u - v).abs() <= 1e-4 * u.abs().max(1.0),
                        "{log}: {name_a}: {u} vs {v}"
                    );
                }
            }
            compared += ra.len();
        }
        assert!(compared > 100_000, "{log}: only {compared} tuples compared");
    }
}

/// The relations but `refav_order`.
fn without_order(rel: Vec<(String, Vec<Row>)>) -> Vec<(String, Vec<Row>)> {
    rel.into_iter()
        .filter(|(n, _)| n != "refav_order")
        .collect()
}
