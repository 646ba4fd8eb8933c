//! What the picture of an explanation shows: the proof's geometric facts (the distance of a
//! `near`, the sector of a `direction`, the lane of `in_lane`, the half-plane of a `crossing`…)
//! as [`scenalog_view::Annotation`]s, the proof's lines as the picture's notes, the objects
//! related to the track at the frame; for a why-not report, the literals that held and the one
//! that failed, drawn in the failure colour; for an animation, each frame's own picture. The
//! drawing itself is `scenalog-view`'s.

use scenalog_engine::{
    explain, why_not, BodyFact, Derivation, Evaluation, Options, Outcome, Reason, Step, WhyNot,
};
use scenalog_extractors::cache::Extractor;
use scenalog_facts::relation::Value;
use scenalog_facts::scene::{Frame, TrackId};
use scenalog_rules::ast::{ExprKind, Literal};
use scenalog_view::{Annotation, Mark, Picture, Reference, Side};

use super::explain::{evaluate_for_explain, referred_frames, Explanation, Renderer};
use super::scenario::EvaluationError;
use crate::message::Message;

/// Most proof lines a picture lists.
const MAX_NOTES: usize = 9;

/// The objects `related(track, other, frame)` names, sorted.
pub fn related_at(ev: &Evaluation, track: TrackId, frame: Frame) -> Vec<TrackId> {
    let mut out: Vec<TrackId> = ev
        .tuples("related")
        .unwrap_or_default()
        .iter()
        .filter_map(|t| match t.as_slice() {
            [Value::Track(x), Value::Track(o), Value::Time(f)] if *x == track && *f == frame => {
                Some(*o)
            }
            _ => None,
        })
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

fn short(r: &Renderer<'_>, t: TrackId) -> String {
    r.scene
        .tracks
        .get(t.index())
        .map_or(format!("#{}", t.0), |tr| tr.uuid.chars().take(8).collect())
}

fn track(v: Option<&Option<Value>>) -> Option<TrackId> {
    match v {
        Some(Some(Value::Track(t))) => Some(*t),
        _ => None,
    }
}

fn float(v: Option<&Option<Value>>) -> Option<f64> {
    match v {
        Some(Some(Value::Float(x))) => Some(*x),
        _ => None,
    }
}

fn string(v: Option<&Option<Value>>) -> Option<&str> {
    match v {
        Some(Some(Value::Str(s))) => Some(s),
        _ => None,
    }
}

/// The mark a catalog fact draws, if it has a geometric meaning; columns may be unknown
/// (`None`) in a why-not pattern.
pub fn mark_of(
    r: &Renderer<'_>,
    relation: &str,
    t: &[Option<Value>],
    holds: bool,
) -> Option<Annotation> {
    let (mark, label) = match relation {
        "near" => {
            let (a, b) = (track(t.first())?, track(t.get(1))?);
            let label = match float(t.get(3)) {
                Some(d) => format!("near {d:.1} m"),
                None => "near".to_string(),
            };
            (
                Mark::Distance {
                    a,
                    b,
                    metres: float(t.get(3)).unwrap_or(f64::NAN),
                },
                label,
            )
        }
        "direction" => {
            let (from, to) = (track(t.first())?, track(t.get(1))?);
            let name = string(t.get(3))?;
            let side = Side::parse(name)?;
            let dist = float(t.get(4)).map_or(String::new(), |d| format!(", {d:.1} m"));
            (
                Mark::Sector { from, to, side },
                format!("{} {name} of {}{dist}", short(r, to), short(r, from)),
            )
        }
        "crossing" => {
            let (from, by) = (track(t.first())?, track(t.get(1))?);
            let name = string(t.get(3))?;
            let side = Side::parse(name)?;
            (
                Mark::Crossing { from, by, side },
                format!("{} crosses {}'s {name}", short(r, by), short(r, from)),
            )
        }
        "in_lane" => {
            let tr = track(t.first())?;
            let Some(Some(Value::Lane(lane))) = t.get(2) else {
                return None;
            };
            (
                Mark::Lane {
                    track: tr,
                    lane: *lane,
                },
                r.value(&Value::Lane(*lane), None),
            )
        }
        "at_crosswalk" => {
            let tr = track(t.first())?;
            let label = match float(t.get(2)) {
                Some(d) => format!("crosswalk {d:.1} m"),
                None => "crosswalk".to_string(),
            };
            (Mark::Crosswalk { track: tr }, label)
        }
        "at_stop_sign" => (
            Mark::Link {
                a: track(t.first())?,
                b: track(t.get(1))?,
            },
            "at stop sign".to_string(),
        ),
        "following" | "same_lane" | "facing" | "heading_toward" | "heading_relative"
        | "road_side" => {
            let (a, b) = (track(t.first())?, track(t.get(1))?);
            let extra = string(t.get(3)).map_or(String::new(), |s| format!(" {s}"));
            (
                Mark::Link { a, b },
                format!("{}{extra}", relation.replace('_', " ")),
            )
        }
        _ => return None,
    };
    Some(Annotation { mark, label, holds })
}

fn some(tuple: &[Value]) -> Vec<Option<Value>> {
    tuple.iter().cloned().map(Some).collect()
}

/// The geometric facts anywhere in a proof, each once.
pub fn proof_annotations(r: &Renderer<'_>, d: &Derivation, out: &mut Vec<Annotation>) {
    for f in &d.body {
        if let BodyFact::Atom {
            relation,
            tuple,
            derivation,
            ..
        } = f
        {
            if let Some(a) = mark_of(r, relation, &some(tuple), true) {
                if !out.contains(&a) {
                    out.push(a);
                }
            }
            if let Some(child) = derivation {
                proof_annotations(r, child, out);
            }
        }
    }
}

/// The proof's facts as lines (`literal   fact`), depth first, derived atoms replaced by their
/// own rule's facts.
pub fn proof_notes(r: &Renderer<'_>, d: &Derivation, out: &mut Vec<(String, bool)>) {
    for f in &d.body {
        if out.len() >= MAX_NOTES {
            return;
        }
        if let BodyFact::Atom {
            derivation: Some(child),
            ..
        } = f
        {
            if child.clause.is_some() {
                proof_notes(r, child, out);
                continue;
            }
        }
        let text = r.body_fact_text(d.clause, f);
        if !out.iter().any(|(t, _)| *t == text) {
            out.push((text, true));
        }
    }
}

/// A body atom's tuple under a binding (`None` where an argument is unbound or an expression).
fn ground(atom: &scenalog_rules::ast::Atom, binding: &[(String, Value)]) -> Vec<Option<Value>> {
    atom.args
        .iter()
        .map(|e| match &e.kind {
            ExprKind::Var(v) => binding.iter().find(|(k, _)| k == v).map(|(_, x)| x.clone()),
            ExprKind::Str(s) => Some(Value::Str(s.as_str().into())),
            ExprKind::Int(i) => Some(Value::Int(*i)),
            ExprKind::Float(x) => Some(Value::Float(*x)),
            ExprKind::Quantity(q) => Some(Value::Float(q.number().as_f64())),
            _ => None,
        })
        .collect()
}

/// The marks and lines of a why-not report: the closest rule's literals that held (drawn as
/// holding, for the first binding that reached the failure) and the failing literal (drawn in
/// the failure colour: the closest tuple of a missing atom, or the atoms whose values failed a
/// comparison).
pub fn why_not_content(r: &Renderer<'_>, w: &WhyNot) -> (Vec<Annotation>, Vec<(String, bool)>) {
    let mut marks = Vec::new();
    let mut notes = Vec::new();
    let Some(attempt) = w.closest() else {
        notes.push((format!("no rule derives {}", w.relation), false));
        return (marks, notes);
    };
    let Outcome::Fails(f) = &attempt.outcome else {
        return (marks, notes);
    };
    let clause = attempt.clause;
    let binding = f.bindings.first().cloned().unwrap_or_default();
    // The variables the failing literal compares, if it is a comparison.
    let failing_vars: Vec<String> = match f.step {
        Step::Body(i) => match r.literal(Some(clause), i) {
            Some(Literal::Cmp(c)) => [c.lhs.as_var(), c.rhs.as_var()]
                .into_iter()
                .flatten()
                .map(str::to_string)
                .collect(),
            _ => Vec::new(),
        },
        Step::Head(_) => Vec::new(),
    };
    let reason = r.reason_text(clause, f);
    let first_reason = reason.first().cloned().unwrap_or_default();
    for s in &f.held {
        notes.push((r.step_text(clause, *s), true));
        let Step::Body(i) = s else { continue };
        let Some(Literal::Pos(atom)) = r.literal(Some(clause), *i) else {
            continue;
        };
        let fails = atom.args.iter().any(|e| {
            e.as_var()
                .is_some_and(|v| failing_vars.iter().any(|x| x == v))
        });
        if let Some(mut a) = mark_of(r, &atom.pred, &ground(atom, &binding), !fails) {
            if fails {
                a.label = format!("{}: {first_reason}", a.label);
            }
            marks.push(a);
        }
    }
    notes.push((format!("{}   {first_reason}", f.text), false));
    if let Reason::Missing {
        relation, closest, ..
    } = &f.reason
    {
        if let Some(m) = closest.first() {
            if let Some(mut a) = mark_of(r, relation, &some(&m.tuple), false) {
                a.label = format!("closest: {}", a.label);
                marks.push(a);
            }
        }
    }
    (marks, notes)
}

/// The picture of an explanation: the track highlighted, its related objects, the proof's (or
/// why-not report's) facts drawn and listed.
pub fn explanation_picture<'a>(
    r: &Renderer<'a>,
    e: &Explanation,
    related: Vec<TrackId>,
    reference: Reference,
) -> Picture<'a> {
    let mut p = Picture::new(r.scene, e.frame);
    p.reference = reference;
    p.referred = Some(e.track);
    p.related = related;
    p.title = r.scenario.description.clone();
    let who = r.track(e.track);
    p.referred_here = e.proof.is_some();
    if let Some(proof) = &e.proof {
        p.status = format!("{who}: referred — why:");
        proof_annotations(r, proof, &mut p.annotations);
        proof_notes(r, proof, &mut p.notes);
    } else if e.why_not.is_some() {
        p.status = format!("{who}: NOT referred — why not:");
    } else {
        p.status = format!("{who}: NOT referred at this frame");
    }
    if let Some(w) = &e.why_not {
        let (marks, notes) = why_not_content(r, w);
        if e.proof.is_none() {
            p.annotations = marks;
            p.notes = notes;
        }
    }
    p
}

/// A track explained at every frame of a span, and what the evaluation derived at each: what an
/// animation and a Rerun recording show.
pub struct FrameExplanations {
    /// Per frame from the first to the last: the track's proof (or why-not report where it is
    /// present and not referred) and the objects related to it there.
    pub frames: Vec<(Explanation, Vec<TrackId>)>,
    /// Every `referred(X, T)` the program derives, sorted.
    pub referred: Vec<(TrackId, Frame)>,
    /// Every `related(X, Y, T)` it derives, sorted.
    pub related: Vec<(TrackId, TrackId, Frame)>,
}

/// Explains `track` at each frame from `first` to `last` (inclusive), the program evaluated
/// again within `limits` (once, and once whole when some frame needs a why-not report).
pub fn frame_explanations(
    r: &Renderer<'_>,
    track: TrackId,
    first: Frame,
    last: Frame,
    limits: &Options,
) -> Result<FrameExplanations, Message> {
    let failed = |e: EvaluationError| {
        e.message(&format!(
            "evaluating {} on log {}: ",
            r.scenario.path.display(),
            r.scene.log_id
        ))
    };
    let text = |e: scenalog_engine::WhyNotError| Message::text(e);
    let extractor = Extractor::new(r.scene);
    let ev =
        evaluate_for_explain(&extractor, &r.scenario.program, false, limits).map_err(failed)?;
    let referred = referred_frames(&ev, track);
    let present = |f: Frame| {
        r.scene
            .tracks
            .get(track.index())
            .is_some_and(|t| t.box_at(f).is_some())
    };
    // The whole evaluation (for why-not reports) only when some frame needs one.
    let needs_why_not = (first..=last).any(|f| present(f) && referred.binary_search(&f).is_err());
    let whole = if needs_why_not {
        Some(evaluate_for_explain(&extractor, &r.scenario.program, true, limits).map_err(failed)?)
    } else {
        None
    };
    let mut frames = Vec::new();
    for frame in first..=last {
        let tuple = [Value::Track(track), Value::Time(frame)];
        let proof = explain(&r.scenario.program, &ev, "referred", &tuple).map_err(text)?;
        let why_not = match (&proof, &whole) {
            (None, Some(w)) if present(frame) => {
                Some(why_not(&r.scenario.program, w, "referred", &tuple).map_err(text)?)
            }
            _ => None,
        };
        let e = Explanation {
            track,
            frame,
            referred_frames: referred.clone(),
            proof,
            why_not,
        };
        frames.push((e, related_at(&ev, track, frame)));
    }
    let all_referred = super::scenario::referred_pairs(&ev);
    let all_related = super::scenario::related_triples(&ev);
    Ok(FrameExplanations {
        frames,
        referred: all_referred,
        related: all_related,
    })
}

/// The picture of each frame from `first` to `last` (inclusive) of `like.referred`'s track,
/// each with its own proof (or, where the track is not referred, its own why-not report) and
/// related objects, drawn as `like` is (point of view, size, extent): an animation's frames.
/// The program is evaluated again within `limits`.
pub fn frame_pictures<'a>(
    r: &Renderer<'a>,
    like: &Picture<'a>,
    first: Frame,
    last: Frame,
    limits: &Options,
) -> Result<Vec<Picture<'a>>, Message> {
    let Some(track) = like.referred else {
        return Ok(Vec::new());
    };
    let explained = frame_explanations(r, track, first, last, limits)?;
    let mut out = Vec::new();
    for (e, related) in &explained.frames {
        let mut p = explanation_picture(r, e, related.clone(), like.reference);
        p.width = like.width;
        p.height = like.height;
        p.half_extent = like.half_extent;
        out.push(p);
    }
    Ok(out)
}
