//! Explanations of a scenario on one log, for `scenalog explain`: the evaluation they need,
//! the grounded proof of `referred(track, frame)` and the why-not report, rendered for people
//! (values in readable form: tracks as uuid prefix and category, frames as seconds from the
//! log's start, lanes with their type, numbers with their unit) and as JSON for tools.
//!
//! # JSON
//!
//! [`explanation_json`] returns one object with these keys (stable; new keys may be added):
//!
//! - `log_id`, `rules` (the program file), `description`
//! - `track`: `{uuid, category}`; `frame` (frame index), `seconds` (from the log's start)
//! - `referred` (bool: is `referred(track, frame)` derived), `referred_frames` (how many frames
//!   the track is referred in), `referred_seconds` (`[first, last]` or `null`)
//! - `proof`: a derivation or `null`; a derivation is `{relation, tuple, text, clause, binding,
//!   body}` where `clause` is `null` for a catalog fact, else `{index, line, text}` (the rule's
//!   source); `binding` maps variable names to values; `body` lists one entry per body literal in
//!   source order: `{literal, source, kind, text, …}` with `kind` one of `"atom"` (`relation`,
//!   `tuple`, `derivation`: a nested derivation or `null`), `"absent"` (`relation`, `pattern`),
//!   `"comparison"` (`lhs`, `op`, `rhs`, `binds`), `"aggregate"` (`func`, `result`,
//!   `group_size`)
//! - `why_not`: a report or `null` (present with `--why-not` or when the track is not referred
//!   there): `{relation, pattern, holds, input, relation_size, closest_input, closest_clause,
//!   attempts}`; each attempt is `{clause: {index, line, text}, outcome, …}` with `outcome`
//!   `"derives"` (`binding`, `bindings`), `"head_mismatch"` (`column`, `expected`, `found`) or
//!   `"fails"` (`failure`: `{step: {"body": i} | {"head": i}, literal, held, bindings,
//!   binding_count, truncated, reason}`); `reason` is `{kind, text, …}` with `kind` one of
//!   `"missing"` (`relation`, `relation_size`, `wanted`, `closest`: `[{tuple, differs}]`,
//!   `nested`: a report or `null`), `"comparison"` (`op`, `values`: `[{binding, lhs, rhs}]`),
//!   `"present"` (`relation`, `found`: `[{binding, tuple}]`), `"aggregate"` (`func`, `values`:
//!   `[{binding, result, required, group_size}]`), `"head_value"` (`column`, `wanted`,
//!   `values`: `[{binding, value}]`), `"unevaluable"`
//!
//! Values are as in `scenalog facts --json`: tracks as uuids, lanes as map ids, times as frame
//! indices, strings and numbers as themselves; every entry with a `text` key also has the
//! human rendering.

use scenalog_engine::{
    BodyFact, ClauseAttempt, Derivation, Evaluation, Failure, NearMiss, Options, Outcome, Reason,
    Step, WhyNot,
};
use scenalog_extractors::cache::Extractor;
use scenalog_facts::catalog::ColType;
use scenalog_facts::relation::Value;
use scenalog_facts::scene::{Frame, TrackId};
use scenalog_facts::Scene;
use scenalog_rules::ast::{CmpOp, Literal};
use scenalog_rules::printer::print_literal;
use scenalog_rules::CheckedProgram;
use serde_json::{json, Value as Json};

use super::scenario::{EvaluationError, Scenario};
use crate::message::{Field, Message};

mod json;
mod text;
mod values;

/// How many characters of a track's uuid the text shows.
pub const UUID_PREFIX: usize = 8;

/// Evaluates a program on a scene for explaining. For a proof (`whole` false): provenance on,
/// catalog relations asked with the constraints the program implies, as `mine` does. For a
/// why-not report (`whole` true): provenance off, and catalog relations asked whole, without
/// the constants, categories and bounds, so the report sees the values that failed a
/// comparison or a constant (the speed that was not `< 0.5`, the direction that was not
/// `"right"`). Derived relations are the same either way: the engine filters again. Either runs
/// within `limits`' tuple budget and time limit (callers pass `mine`'s, from
/// [`super::limits::pair_limits`]), so a runaway program is an error here too, never a hang.
pub fn evaluate_for_explain(
    extractor: &Extractor<'_>,
    program: &CheckedProgram,
    whole: bool,
    limits: &Options,
) -> Result<Evaluation, EvaluationError> {
    let options = Options {
        provenance: !whole,
        ..limits.clone()
    };
    if whole {
        super::scenario::evaluate_on_whole(extractor, program, &options)
    } else {
        super::scenario::evaluate_on(extractor, program, &options)
    }
}

/// The frames at which `referred(track, frame)` is derived, ascending.
pub fn referred_frames(ev: &Evaluation, track: TrackId) -> Vec<Frame> {
    let mut frames: Vec<Frame> = ev
        .tuples("referred")
        .unwrap_or_default()
        .iter()
        .filter_map(|t| match t.as_slice() {
            [Value::Track(x), Value::Time(f)] if *x == track => Some(*f),
            _ => None,
        })
        .collect();
    frames.sort_unstable();
    frames.dedup();
    frames
}

/// The frame whose time is nearest to `seconds` from the log's start (the earlier on a tie).
pub fn frame_nearest(scene: &Scene, seconds: f64) -> Option<Frame> {
    scene
        .timeline
        .frames()
        .iter()
        .copied()
        .filter_map(|f| scene.timeline.seconds(f).map(|s| (f, (s - seconds).abs())))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(f, _)| f)
}

/// The log's frame nearest `seconds` from its start, when `seconds` lies within the log's time
/// range (to half a 0.1 s step past either end); otherwise an error naming the range (and the
/// request's field [`Field::At`]), so `--at 999` on a 15 s log is refused rather than explaining
/// the last frame.
pub fn frame_at(scene: &Scene, seconds: f64) -> Result<Frame, Message> {
    let frames = scene.timeline.frames();
    let span = frames
        .first()
        .zip(frames.last())
        .and_then(|(a, b)| Some((scene.timeline.seconds(*a)?, scene.timeline.seconds(*b)?)));
    let Some((first, last)) = span else {
        return Err(Message::text(format!("log {} has no frames", scene.log_id)));
    };
    const HALF_STEP: f64 = 0.05;
    if seconds < first - HALF_STEP || seconds > last + HALF_STEP {
        return Err(Message::text("").mention(Field::At).then(format!(
            " {seconds}: outside log {}, which runs from {first:.1} s to {last:.1} s",
            scene.log_id
        )));
    }
    frame_nearest(scene, seconds)
        .ok_or_else(|| Message::text(format!("log {} has no frames", scene.log_id)))
}

/// Renders values for a person, with the scene for names and times.
pub struct Renderer<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The scenario (its source gives rule text and lines).
    pub scenario: &'a Scenario,
}

/// Everything `scenalog explain` reports for one track and frame.
pub struct Explanation {
    /// The track.
    pub track: TrackId,
    /// The frame explained.
    pub frame: Frame,
    /// Frames at which the track is referred.
    pub referred_frames: Vec<Frame>,
    /// The grounded proof of `referred(track, frame)`, when it is derived.
    pub proof: Option<Derivation>,
    /// The why-not report, when asked for or when the track is not referred at the frame.
    pub why_not: Option<WhyNot>,
}

impl Explanation {
    /// Whether `referred(track, frame)` is derived.
    pub fn referred(&self) -> bool {
        self.referred_frames.binary_search(&self.frame).is_ok()
    }
}

/// The text `scenalog explain` prints.
pub fn explanation_text(r: &Renderer<'_>, e: &Explanation) -> String {
    let mut out = String::new();
    let n = e.referred_frames.len();
    let span = match (e.referred_frames.first(), e.referred_frames.last()) {
        (Some(a), Some(b)) => format!(" (from {} to {})", r.frame(*a), r.frame(*b)),
        _ => String::new(),
    };
    let uuid = r
        .scene
        .tracks
        .get(e.track.index())
        .map_or(String::new(), |t| t.uuid.clone());
    out.push_str(&format!(
        "{}: \"{}\" on log {}\n",
        r.file(),
        r.scenario.description,
        r.scene.log_id
    ));
    out.push_str(&format!(
        "track {uuid} ({}) is referred in {n} frame{}{span}\n",
        r.scene
            .tracks
            .get(e.track.index())
            .map_or("?", |t| t.category.as_str()),
        if n == 1 { "" } else { "s" }
    ));
    out.push_str(&format!(
        "at {} (frame {}): {}\n\n",
        r.frame(e.frame),
        e.frame,
        if e.referred() {
            "referred"
        } else {
            "NOT referred"
        }
    ));
    if let Some(p) = &e.proof {
        out.push_str("Proof:\n");
        r.derivation_text(p, 2, true, &mut out);
    }
    if let Some(w) = &e.why_not {
        if e.proof.is_some() {
            out.push('\n');
        }
        out.push_str("Why not:\n");
        r.why_not_text(w, &mut out);
    }
    out
}

/// The JSON `scenalog explain --json` prints (keys in the module documentation).
pub fn explanation_json(r: &Renderer<'_>, e: &Explanation) -> Json {
    let track = r.scene.tracks.get(e.track.index());
    let secs = |f: &Frame| r.scene.timeline.seconds(*f);
    json!({
        "log_id": r.scene.log_id,
        "rules": r.file(),
        "description": r.scenario.description,
        "track": {
            "uuid": track.map(|t| t.uuid.clone()),
            "category": track.map(|t| t.category.clone()),
        },
        "frame": e.frame,
        "seconds": secs(&e.frame),
        "referred": e.referred(),
        "referred_frames": e.referred_frames.len(),
        "referred_seconds": match (e.referred_frames.first(), e.referred_frames.last()) {
            (Some(a), Some(b)) => json!([secs(a), secs(b)]),
            _ => Json::Null,
        },
        "proof": e.proof.as_ref().map_or(Json::Null, |p| r.derivation_json(p)),
        "why_not": e.why_not.as_ref().map_or(Json::Null, |w| r.why_not_json(w)),
    })
}
