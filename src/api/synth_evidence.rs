//! The evidence a synthesis search shows the model about its chosen program (`synth
//! --candidates K`, the evidence round): what the program matches on the search's logs, in
//! words. How many tracks and frames it matches per category and on how many of the logs; the
//! longest match (the track referred in the longest run of frames) with the proof `scenalog
//! explain` gives at its middle frame; and for a program that matches nothing, its nearest misses: the tracks whose why-not
//! report holds the most literals before one fails, with the literal that fails and the values
//! that failed it (as `scenalog explain --why-not` prints them).
//!
//! The proof and the reports are `explain`'s own text, so the model reads what a person reads.

use std::collections::BTreeMap;
use std::path::Path;

use rayon::prelude::*;

use scenalog_engine::{
    explain as prove, why_not_each, Options, Outcome as Attempt, Reason, WhyNot,
};
use scenalog_extractors::Extractor;
use scenalog_facts::relation::Value;
use scenalog_facts::scene::{Frame, Scene, Track, TrackId};

use crate::pipeline::explain::{
    evaluate_for_explain, explanation_text, referred_frames, Explanation, Renderer,
};
use crate::pipeline::run::referred_tuples;
use crate::pipeline::scenario::{scenario_from_source, Scenario};

/// Lines of a proof or a why-not report shown at most (the rest is cut, saying so).
const MAX_PROOF_LINES: usize = 30;
/// Tracks per log whose why-not report is asked for when a program matches nothing.
const MISS_TRACKS_PER_LOG: usize = 24;
/// Nearest misses shown.
const NEAREST_MISSES: usize = 2;

/// What `program` matches on `scenes`, in words for the model (see the module's doc); each
/// evaluation within `options`. An error says why the program could not be run.
pub fn evidence(scenes: &[Scene], program: &str, options: &Options) -> Result<String, String> {
    let scenario = scenario_from_source(Path::new("program.dl"), program.to_string())?;
    let mut per_category: BTreeMap<String, (usize, usize)> = BTreeMap::new();
    // (frames in the longest run, log index, track, the run's middle frame)
    let mut longest: Option<(usize, usize, TrackId, Frame)> = None;
    let mut total_frames = 0;
    let mut logs_matched = 0;
    // Each log's referred frames by track, the logs in parallel as `mine` runs them.
    let per_log: Vec<Result<BTreeMap<TrackId, Vec<Frame>>, String>> = scenes
        .par_iter()
        .map(|scene| {
            let extractor = Extractor::new(scene);
            // As `mine` evaluates it: no provenance, only what it matches is wanted here.
            let ev = crate::pipeline::scenario::evaluate_on(&extractor, &scenario.program, options)
                .map_err(|e| format!("on log {}: {e}", scene.log_id))?;
            let mut by_track: BTreeMap<TrackId, Vec<Frame>> = BTreeMap::new();
            for (track, frame) in referred_tuples(&ev) {
                by_track.entry(track).or_default().push(frame);
            }
            Ok(by_track)
        })
        .collect();
    for (l, (scene, by_track)) in scenes.iter().zip(per_log).enumerate() {
        let by_track = by_track?;
        logs_matched += usize::from(!by_track.is_empty());
        for (track, mut frames) in by_track {
            frames.sort_unstable();
            frames.dedup();
            total_frames += frames.len();
            let category = category(scene, track);
            let entry = per_category.entry(category.to_string()).or_default();
            entry.0 += 1;
            entry.1 += frames.len();
            let (run, middle) = longest_run(scene, &frames);
            if longest.is_none_or(|(n, ..)| run > n) {
                longest = Some((run, l, track, middle));
            }
        }
    }
    let logs = plural(scenes.len(), "log");
    let Some((run, l, track, frame)) = longest else {
        return Ok(nearest_misses(scenes, &scenario, options, &logs));
    };
    let tracks: usize = per_category.values().map(|c| c.0).sum();
    let mut text = format!(
        "On the {logs} your program matches {} over {} in all, on {} of the {}:\n",
        plural(tracks, "track"),
        plural(total_frames, "frame"),
        logs_matched,
        plural(scenes.len(), "log"),
    );
    for (category, (t, f)) in &per_category {
        text.push_str(&format!(
            "- {category}: {}, {}\n",
            plural(*t, "track"),
            plural(*f, "frame")
        ));
    }
    let scene = &scenes[l];
    let extractor = Extractor::new(scene);
    let ev = evaluate_for_explain(&extractor, &scenario.program, false, options)
        .map_err(|e| format!("on log {}: {e}", scene.log_id))?;
    let tuple = [Value::Track(track), Value::Time(frame)];
    let proof = prove(&scenario.program, &ev, "referred", &tuple).map_err(|e| e.to_string())?;
    let explanation = Explanation {
        track,
        frame,
        referred_frames: referred_frames(&ev, track),
        proof,
        why_not: None,
    };
    let renderer = Renderer {
        scene,
        scenario: &scenario,
    };
    text.push_str(&format!(
        "\nThe longest match: track {} on log {}, {} in a row; why it matches at {}:\n{}",
        renderer.track(track),
        scene.log_id,
        plural(run, "frame"),
        renderer.frame(frame),
        body(&explanation_text(&renderer, &explanation)),
    ));
    Ok(text)
}

/// The text for a program that matches nothing: its nearest misses over `scenes`.
fn nearest_misses(scenes: &[Scene], scenario: &Scenario, options: &Options, logs: &str) -> String {
    let mut text = format!("On the {logs} your program matches nothing.");
    let mentioned: Vec<&str> = quoted(&scenario.source);
    // (closeness, log, track, frame, report), the logs in parallel as `mine` runs them.
    let mut misses: Vec<(usize, usize, TrackId, Frame, WhyNot)> = scenes
        .par_iter()
        .enumerate()
        .flat_map_iter(|(l, scene)| log_misses(l, scene, scenario, options, &mentioned))
        .collect();
    misses.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    if misses.is_empty() {
        return text;
    }
    text.push_str(" The nearest misses (the literal that fails, and the values that failed it):\n");
    for (_, l, track, frame, report) in misses.into_iter().take(NEAREST_MISSES) {
        let scene = &scenes[l];
        let renderer = Renderer { scene, scenario };
        let explanation = Explanation {
            track,
            frame,
            referred_frames: Vec::new(),
            proof: None,
            why_not: Some(report),
        };
        text.push_str(&format!(
            "\nTrack {} on log {} at {}:\n{}",
            renderer.track(track),
            scene.log_id,
            renderer.frame(frame),
            body(&explanation_text(&renderer, &explanation)),
        ));
    }
    text
}

/// The why-not reports of up to [`MISS_TRACKS_PER_LOG`] tracks of log `l` (of the categories
/// the program names, when it names any present), each at its middle frame, with their
/// closeness; none when the program cannot be evaluated whole there.
fn log_misses(
    l: usize,
    scene: &Scene,
    scenario: &Scenario,
    options: &Options,
    mentioned: &[&str],
) -> Vec<(usize, usize, TrackId, Frame, WhyNot)> {
    let extractor = Extractor::new(scene);
    let Ok(whole) = evaluate_for_explain(&extractor, &scenario.program, true, options) else {
        return Vec::new();
    };
    let named: Vec<&Track> = scene
        .tracks
        .iter()
        .filter(|t| mentioned.contains(&t.category.as_str()))
        .collect();
    let pool: Vec<&Track> = if named.is_empty() {
        scene.tracks.iter().collect()
    } else {
        named
    };
    let step = pool.len().div_ceil(MISS_TRACKS_PER_LOG).max(1);
    let asked: Vec<(TrackId, Frame)> = pool
        .iter()
        .step_by(step)
        .filter_map(|t| t.frame_span().map(|(a, b)| (t.id, a + (b - a) / 2)))
        .collect();
    let tuples: Vec<Vec<Value>> = asked
        .iter()
        .map(|&(t, f)| vec![Value::Track(t), Value::Time(f)])
        .collect();
    let reports = why_not_each(&scenario.program, &whole, "referred", &tuples);
    asked
        .into_iter()
        .zip(reports)
        .filter_map(|((track, frame), report)| {
            report.ok().map(|r| (closeness(&r), l, track, frame, r))
        })
        .collect()
}

/// How close a why-not report came: the literals its closest clause held, and in turn those of
/// the derived relation it missed.
fn closeness(report: &WhyNot) -> usize {
    let Some(attempt) = report.closest() else {
        return 0;
    };
    match &attempt.outcome {
        Attempt::Derives { .. } => usize::MAX / 2,
        Attempt::HeadMismatch { .. } => 0,
        Attempt::Fails(f) => {
            let nested = match &f.reason {
                Reason::Missing {
                    nested: Some(n), ..
                } => closeness(n),
                _ => 0,
            };
            1 + f.held.len() + nested
        }
    }
}

/// The longest run of consecutive log frames in `frames` (ascending): its length and middle.
fn longest_run(scene: &Scene, frames: &[Frame]) -> (usize, Frame) {
    let timeline = scene.timeline.frames();
    let index = |f: &Frame| timeline.binary_search(f).ok();
    let (mut best, mut best_start, mut start) = (0, 0, 0);
    for i in 0..frames.len() {
        let follows = i > 0
            && matches!((index(&frames[i - 1]), index(&frames[i])), (Some(a), Some(b)) if b == a + 1);
        if !follows {
            start = i;
        }
        if i + 1 - start > best {
            best = i + 1 - start;
            best_start = start;
        }
    }
    (best, frames[best_start + best / 2])
}

/// An explanation's text without its three header lines (the file, the track, the frame),
/// at most [`MAX_PROOF_LINES`] lines.
fn body(text: &str) -> String {
    let lines: Vec<&str> = text
        .lines()
        .skip(3)
        .skip_while(|l| l.trim().is_empty())
        .collect();
    let mut out: String = lines
        .iter()
        .take(MAX_PROOF_LINES)
        .map(|l| format!("{l}\n"))
        .collect();
    if lines.len() > MAX_PROOF_LINES {
        out.push_str(&format!(
            "  … ({} more lines)\n",
            lines.len() - MAX_PROOF_LINES
        ));
    }
    out
}

/// The quoted strings of a program (the categories and directions it names).
fn quoted(source: &str) -> Vec<&str> {
    source.split('"').skip(1).step_by(2).collect()
}

fn category(scene: &Scene, track: TrackId) -> &str {
    scene
        .tracks
        .get(track.index())
        .map_or("?", |t| t.category.as_str())
}

fn plural(n: usize, word: &str) -> String {
    format!("{n} {word}{}", if n == 1 { "" } else { "s" })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_scenes() -> Vec<Scene> {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join(crate::api::inputs::SAMPLE_LOGS);
        let mut dirs: Vec<_> = std::fs::read_dir(&dir)
            .expect("the sample logs")
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_dir())
            .collect();
        dirs.sort();
        dirs.iter()
            .map(|d| scenalog_facts::load_scene(d).expect("a sample log"))
            .collect()
    }

    /// A program that matches: the counts per category, and the proof of its longest match
    /// with the values that made it hold.
    #[test]
    fn a_match_is_counted_per_category_and_its_longest_run_proved() {
        let scenes = sample_scenes();
        let program = "// description: stopped car\nreferred(V, T) :- category(V, \"REGULAR_VEHICLE\"), stopped(V, T).\n";
        let text = evidence(&scenes, program, &Options::default()).expect("runs");
        assert!(
            text.starts_with("On the 3 logs your program matches "),
            "{text}"
        );
        assert!(text.contains(", on 3 of the 3 logs:\n"), "{text}");
        assert!(text.contains("\n- REGULAR_VEHICLE: "), "{text}");
        assert_eq!(text.matches("\n- ").count(), 1, "one category: {text}");
        assert!(text.contains("The longest match: track "), "{text}");
        assert!(text.contains("✓ stopped(V, T)"), "{text}");
        assert!(
            text.contains("m/s < 0.5"),
            "the speed that made it hold: {text}"
        );
    }

    /// A program that matches nothing: its nearest misses say which literal fails and with what
    /// values, among the tracks of the category it names.
    #[test]
    fn nothing_matched_shows_the_nearest_misses() {
        let scenes = sample_scenes();
        let program = "// description: fast bus\nreferred(V, T) :- category(V, \"BUS\"), speed(V, T, S), S > 60.0.\n";
        let text = evidence(&scenes, program, &Options::default()).expect("runs");
        assert!(
            text.starts_with("On the 3 logs your program matches nothing. The nearest misses"),
            "{text}"
        );
        assert!(text.contains("(BUS) on log"), "{text}");
        assert!(text.contains("✗ S > 60.0"), "the failing literal: {text}");
    }

    /// A program that does not check is an error, not evidence.
    #[test]
    fn a_program_that_does_not_check_is_an_error() {
        let scenes = sample_scenes();
        assert!(evidence(
            &scenes,
            "referred(V, T) :- nothing(V, T).",
            &Options::default()
        )
        .is_err());
    }
}
