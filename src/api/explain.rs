//! Explaining a track (`scenalog explain`, `scenalog.explain`): why a track is referred by a
//! program at one frame (the proof of `referred(track, frame)`), or why not (the rule that came
//! closest, the literal that failed and the values that failed it).
//!
//! The frame is the one nearest to `at` seconds from the log's start; without it, the first
//! frame where the track is referred, or, for a track never referred, the middle of its
//! annotated frames. The why-not report comes when asked for, or by itself when the track is
//! not referred at that frame. Rendering (text, JSON, pictures) is the caller's, with
//! [`crate::pipeline::explain`] and [`crate::pipeline::picture`].

use std::path::{Path, PathBuf};

use scenalog_engine::{explain, why_not};
use scenalog_extractors::cache::Extractor;
use scenalog_facts::load_scene;
use scenalog_facts::relation::Value;
use scenalog_facts::scene::{Frame, Scene, Track, TrackId};

use crate::api::error::{Arg, Error, ErrorKind};
use crate::api::mine::Limits;
use crate::pipeline::explain::{evaluate_for_explain, referred_frames, Explanation};
use crate::pipeline::picture::related_at;
use crate::pipeline::scenario::{scenario_from_source, Scenario};

/// A track to explain.
#[derive(Clone, Debug, Default)]
pub struct ExplainRequest {
    /// The scenario program (defines `referred(Track, T)`).
    pub rules: PathBuf,
    /// The log directory.
    pub log: PathBuf,
    /// The track's uuid (a unique prefix is enough).
    pub track: String,
    /// The frame nearest to this many seconds from the log's start (finite, 0 or more).
    pub at: Option<f64>,
    /// Also say why the track is not referred (automatic when it is not referred).
    pub why_not: bool,
    /// The evaluation's limits (as one pair's of `mine`).
    pub limits: Limits,
}

/// Why a track could not be explained.
#[derive(Clone, Debug, PartialEq)]
pub struct ExplainError {
    /// The command's exit code: 1 the rules do not check or evaluation failed, 2 an unusable
    /// input (unreadable rules or log, unknown track, bad `at`).
    pub code: u8,
    /// The message.
    pub error: Error,
}

/// Explains the request's track (see [`explain_track`]).
pub fn explain_request(request: &ExplainRequest) -> Result<Explained, ExplainError> {
    let unusable = |error: Error| ExplainError { code: 2, error };
    if let Some(a) = request.at {
        if !a.is_finite() || a < 0.0 {
            return Err(unusable(
                Error::about(
                    Arg::At,
                    format!("expected a finite number of seconds >= 0, got {a}"),
                )
                .of_kind(ErrorKind::Invalid),
            ));
        }
    }
    request.limits.check().map_err(unusable)?;
    let limits = crate::pipeline::limits::pair_limits(
        request.limits.max_tuples,
        request.limits.timeout_ms,
        1,
    );
    explain_track(
        &request.rules,
        &request.log,
        &request.track,
        request.at,
        request.why_not,
        &limits,
    )
    .map_err(|(code, message)| ExplainError {
        code,
        error: Error::plain(message),
    })
}

/// The track with this uuid, or the only one whose uuid starts with it.
fn find_track<'s>(scene: &'s Scene, uuid: &str) -> Result<&'s Track, String> {
    if let Some(t) = scene.track_by_uuid(uuid) {
        return Ok(t);
    }
    let matches: Vec<&Track> = if uuid.is_empty() {
        Vec::new()
    } else {
        scene
            .tracks
            .iter()
            .filter(|t| t.uuid.starts_with(uuid))
            .collect()
    };
    match matches.as_slice() {
        [t] => Ok(t),
        [] => Err(format!(
            "no track `{uuid}` in log {} ({} tracks; `scenalog facts LOG_DIR --relation category \
             --json` lists each track's uuid with its categories)",
            scene.log_id,
            scene.tracks.len()
        )),
        many => Err(format!(
            "`{uuid}` is the start of {} track uuids in log {} (e.g. {}, {}); give more of it",
            many.len(),
            scene.log_id,
            many[0].uuid,
            many[1].uuid
        )),
    }
}

/// A track explained at one frame: what `scenalog explain` prints and pictures.
pub struct Explained {
    /// The log's scene.
    pub scene: Scene,
    /// The checked program.
    pub scenario: Scenario,
    /// The proof of `referred(track, frame)` and/or the why-not report.
    pub explanation: Explanation,
    /// The objects related to the track at the frame.
    pub related: Vec<TrackId>,
}

/// Explains why `track_uuid` (a uuid or an unambiguous prefix) is or is not referred by the
/// program `rules` on `log` at the frame nearest `at` seconds (see the module's doc for the
/// frame chosen without it); `why_not_wanted` adds the why-not report to a proof. The program is
/// evaluated within `limits` (tuple budget, time limit). Errors are the exit code and the message
/// `scenalog explain` prints.
pub fn explain_track(
    rules: &Path,
    log: &Path,
    track_uuid: &str,
    at: Option<f64>,
    why_not_wanted: bool,
    limits: &scenalog_engine::Options,
) -> Result<Explained, (u8, String)> {
    let display = rules.display().to_string();
    let source = match crate::input::read_text(rules) {
        Ok(s) => s,
        Err(e) => return Err((2, e)),
    };
    let scenario = match scenario_from_source(rules, source) {
        Ok(s) => s,
        Err(e) => return Err((1, e)),
    };
    let scene = match load_scene(log) {
        Ok(s) => s,
        Err(e) => return Err((2, e.to_string())),
    };
    let track = match find_track(&scene, track_uuid) {
        Ok(t) => t,
        Err(e) => return Err((2, e)),
    };
    let extractor = Extractor::new(&scene);
    let ev = match evaluate_for_explain(&extractor, &scenario.program, false, limits) {
        Ok(ev) => ev,
        Err(e) => {
            return Err((
                1,
                format!("evaluating {display} on log {}: {e}", scene.log_id),
            ))
        }
    };
    let frames = referred_frames(&ev, track.id);
    let frame: Frame = match at {
        Some(at) => match crate::pipeline::explain::frame_at(&scene, at) {
            Ok(f) => f,
            Err(e) => return Err((2, e)),
        },
        None => match frames.first() {
            Some(f) => *f,
            None => match track.frame_span() {
                Some((a, b)) => a + (b - a) / 2,
                None => 0,
            },
        },
    };
    let tuple = [Value::Track(track.id), Value::Time(frame)];
    let proof = match explain(&scenario.program, &ev, "referred", &tuple) {
        Ok(p) => p,
        Err(e) => return Err((1, format!("{display}: {e}"))),
    };
    let want_why_not = why_not_wanted || proof.is_none();
    let why = if want_why_not {
        let whole = match evaluate_for_explain(&extractor, &scenario.program, true, limits) {
            Ok(ev) => ev,
            Err(e) => {
                return Err((
                    1,
                    format!("evaluating {display} on log {}: {e}", scene.log_id),
                ))
            }
        };
        match why_not(&scenario.program, &whole, "referred", &tuple) {
            Ok(w) => Some(w),
            Err(e) => return Err((1, format!("{display}: {e}"))),
        }
    } else {
        None
    };
    let explanation = Explanation {
        track: track.id,
        frame,
        referred_frames: frames,
        proof,
        why_not: why,
    };
    let related = related_at(&ev, track.id, frame);
    drop(ev);
    drop(extractor);
    Ok(Explained {
        scene,
        scenario,
        explanation,
        related,
    })
}
