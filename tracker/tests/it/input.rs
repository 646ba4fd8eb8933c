//! The tracker file reader and the confidence filter on the committed noisy test file.

use std::path::PathBuf;

use scenalog_tracker::filter::{kept_tracks, SINGLE_FRAME_MIN_SCORE, TRACK_MIN_SCORE};
use scenalog_tracker::{tracked_log, Filter, TrackerPickle};

fn data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/av2")
        .join(rel)
}

/// The filter drops exactly the tracks its rule names (the noisy file's low-scoring one-frame
/// false positives), and the scene keeps the others with their scores.
#[test]
fn the_confidence_filter_drops_low_scoring_short_tracks_of_the_noisy_file() {
    let pickle = TrackerPickle::open(&data("tracker/noisy.pkl")).expect("noisy.pkl");
    let log = "3b3570b4-7b0b-3268-a571-b0889dbf40b6";
    let frames = pickle.frames(log).expect("frames");
    let all = kept_tracks(&frames, Filter::None);
    let kept = kept_tracks(&frames, Filter::RefAv);
    let mut dropped = 0;
    for id in &all {
        let scores: Vec<f32> = frames
            .iter()
            .flat_map(|f| f.track_id.iter().zip(&f.score))
            .filter(|(t, _)| *t == id)
            .map(|(_, s)| *s)
            .collect();
        let low = scores.iter().copied().fold(f32::INFINITY, f32::min);
        let should_drop = if scores.len() == 1 {
            low <= SINGLE_FRAME_MIN_SCORE
        } else {
            low <= TRACK_MIN_SCORE
        };
        assert_eq!(kept.contains(id), !should_drop, "track {id}: {scores:?}");
        dropped += usize::from(should_drop);
    }
    assert!(dropped > 0, "the noisy file has filtered false positives");
    let dir = data("logs").join(log);
    let filtered = tracked_log(log, &frames, &dir, Filter::RefAv, pickle.file()).expect("scene");
    let unfiltered = tracked_log(log, &frames, &dir, Filter::None, pickle.file()).expect("scene");
    assert_eq!(
        unfiltered.scene.tracks.len() - filtered.scene.tracks.len(),
        dropped
    );
    // Scores line up with boxes, the ego's are 1.0, the rest are the tracker's.
    for (t, s) in filtered.scene.tracks.iter().zip(&filtered.scores) {
        assert_eq!(t.boxes.len(), s.len());
        if t.id == filtered.scene.ego {
            assert!(s.iter().all(|&x| x == 1.0));
        } else {
            assert!(s.iter().all(|&x| x < 1.0));
        }
    }
}

#[test]
fn a_log_not_in_the_file_is_an_error_naming_it() {
    let pickle = TrackerPickle::open(&data("tracker/exact.pkl")).expect("exact.pkl");
    let e = pickle.frames("no-such-log").expect_err("missing log");
    assert_eq!(e.log.as_deref(), Some("no-such-log"));
    assert!(e.to_string().contains("not in the tracker file"), "{e}");
}

/// Mutated tracker files never panic: each byte flip either reads or is an error.
#[test]
fn byte_mutants_of_a_tracker_file_never_panic() {
    let bytes = std::fs::read(data("tracker/exact.pkl")).expect("exact.pkl");
    // The first 40 KB: the structure of the first log's first frames, where flips bite.
    let head = &bytes[..bytes.len().min(40_000)];
    let mut rng = fastrand::Rng::with_seed(7);
    for _ in 0..80 {
        let mut m = bytes.clone();
        let i = rng.usize(..head.len());
        m[i] = rng.u8(..);
        if let Ok(p) = TrackerPickle::from_bytes(&m, "mutant") {
            let logs: Vec<String> = p.log_ids().map(String::from).collect();
            for l in logs.iter().take(1) {
                let _ = p.frames(l);
            }
        }
    }
}
