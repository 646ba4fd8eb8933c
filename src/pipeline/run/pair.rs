//! One (log, program) pair mined: the program evaluated on the log, its referred and related
//! tuples turned into labelled frames and matches, and the pair's record written.

use super::*;
use crate::message::Field;
use crate::pipeline::tracks::{Label, LabelledFrame};

/// What every pair of one log shares.
pub(crate) struct PairContext<'a> {
    pub(crate) log: &'a LogInput,
    pub(crate) scene: &'a Scene,
    /// Each box's tracker score (`None`: ground truth).
    pub(crate) scores: BoxScores<'a>,
    /// The output frames.
    pub(crate) frames: &'a [Frame],
    pub(crate) options: &'a RunOptions,
}

/// The prediction frames and matches of a pair from its tuples; a program kept from a search
/// has its referred boxes' scores scaled by its candidates' agreement ([`agreement`]).
pub(crate) fn build_pair(
    ctx: &PairContext<'_>,
    extractor: &Extractor<'_>,
    scenario: &Scenario,
    referred: &[(TrackId, Frame)],
    related: &[(TrackId, TrackId, Frame)],
) -> (Vec<FrameData>, Vec<Match>) {
    let labelled = label_frames(ctx.scene, referred, related, ctx.frames);
    let agreement = agreement(ctx, extractor, scenario, &labelled);
    let out = to_frames(
        ctx.scene,
        &scenario.description,
        &labelled,
        ctx.scores,
        agreement.as_ref(),
    );
    (out, matches_of(ctx.scene, scenario, referred, related))
}

/// For a program kept from a synthesis search: per (track, output frame), the fraction of the
/// search's clean candidates that label that box referred (each candidate evaluated on the log
/// and labelled as the program is; the kept program's own `labelled` frames are used as they
/// are, not evaluated again). `None` without candidates. A candidate that fails on the log
/// counts as referring to nothing.
pub(crate) fn agreement(
    ctx: &PairContext<'_>,
    extractor: &Extractor<'_>,
    scenario: &Scenario,
    labelled: &[LabelledFrame],
) -> Option<Agreement> {
    if scenario.candidates.is_empty() {
        return None;
    }
    let n = scenario.candidates.len() as f32;
    let mut counts: Agreement = Agreement::new();
    let mut count = |frames: &[LabelledFrame]| {
        for lf in frames {
            for &(track, label) in &lf.objects {
                if label == Label::Referred {
                    *counts.entry((track, lf.frame)).or_insert(0.0) += 1.0;
                }
            }
        }
    };
    for program in &scenario.candidates {
        if *program == scenario.program {
            count(labelled);
            continue;
        }
        let Ok(evaluation) = evaluate_on(extractor, program, &ctx.options.engine) else {
            continue;
        };
        let referred = referred_tuples(&evaluation);
        let related = related_tuples(&evaluation);
        count(&label_frames(ctx.scene, &referred, &related, ctx.frames));
    }
    for v in counts.values_mut() {
        *v /= n;
    }
    Some(counts)
}

/// The first 8 characters of a log id, for messages and tables.
pub fn short_id(log_id: &str) -> &str {
    log_id.get(..8).unwrap_or(log_id)
}

/// The frames predictions are emitted at: the given timestamps (each must be a frame of the
/// log), or every 5th frame from the first.
pub(crate) fn output_frames(
    scene: &Scene,
    given: Option<&Vec<i64>>,
) -> Result<Vec<Frame>, Message> {
    let Some(given) = given else {
        return Ok(eval_frames(scene));
    };
    let mut frames = Vec::with_capacity(given.len());
    for &ns in given {
        let f = scene.timeline.frame_of(ns).ok_or_else(|| {
            Message::about(
                Field::EvalTimestamps,
                format!(
                    "{ns} is not an annotation timestamp of log {}",
                    scene.log_id
                ),
            )
        })?;
        frames.push(f);
    }
    frames.sort_unstable();
    frames.dedup();
    Ok(frames)
}

/// Evaluates one program on one log and writes the pair's files.
pub(crate) fn mine_pair(
    ctx: &PairContext<'_>,
    extractor: &Extractor<'_>,
    scenario: &Scenario,
    index: usize,
    fingerprint: &str,
) -> PairResult {
    let (log, options) = (ctx.log, ctx.options);
    let t0 = Instant::now();
    let engine = match limits_after_check(&options.engine, scenario) {
        Ok(o) => o,
        Err(e) => return failed(log, index, format!("{e} (log {})", log.log_id)),
    };
    let evaluation = match evaluate_on(extractor, &scenario.program, &engine) {
        Ok(e) => e,
        Err(e) => {
            let context = format!("program `{}` failed on log {}: ", scenario.name, log.log_id);
            return failed(log, index, e.message(&context));
        }
    };
    let evaluate = t0.elapsed();
    let t1 = Instant::now();
    let referred = referred_tuples(&evaluation);
    let related = related_tuples(&evaluation);
    let (frames, matches) = build_pair(ctx, extractor, scenario, &referred, &related);
    let tracks = t1.elapsed();
    let t2 = Instant::now();
    let written = write_pair(ctx, scenario, &referred, &related, fingerprint);
    let write = t2.elapsed();
    let status = match written {
        Ok(()) => PairStatus::Done,
        Err(e) => PairStatus::Failed(Message::text(e)),
    };
    PairResult {
        log_id: log.log_id.clone(),
        scenario: index,
        status,
        frames,
        matches,
        evaluate,
        tracks,
        write,
    }
}

/// Writes the pair's record (its tuples, from which `--resume` rebuilds it).
pub(crate) fn write_pair(
    ctx: &PairContext<'_>,
    scenario: &Scenario,
    referred: &[(TrackId, Frame)],
    related: &[(TrackId, TrackId, Frame)],
    fingerprint: &str,
) -> Result<(), String> {
    let (log, scene, options) = (ctx.log, ctx.scene, ctx.options);
    let record = PairRecord {
        fingerprint: fingerprint.to_string(),
        log_id: log.log_id.clone(),
        description: scenario.description.clone(),
        program: scenario.name.clone(),
        source: scenario.source.clone(),
        timestamps: options.timestamps.get(&log.log_id).cloned(),
        tracks: scene.tracks.len(),
        referred: referred.iter().map(|&(v, f)| (v.0, f)).collect(),
        related: related.iter().map(|&(v, o, f)| (v.0, o.0, f)).collect(),
    };
    let path = output::pair_path(&options.out, &log.log_id, &scenario.name);
    output::write_json(&path, &record, false)
}

/// `referred(Track, Time)` tuples.
pub(crate) fn referred_tuples(e: &scenalog_engine::Evaluation) -> Vec<(TrackId, Frame)> {
    e.tuples("referred")
        .unwrap_or_default()
        .iter()
        .filter_map(|t| match t.as_slice() {
            [Value::Track(v), Value::Time(f)] => Some((*v, *f)),
            _ => None,
        })
        .collect()
}

/// `related(Track, Other, Time)` tuples.
pub(crate) fn related_tuples(e: &scenalog_engine::Evaluation) -> Vec<(TrackId, TrackId, Frame)> {
    e.tuples("related")
        .unwrap_or_default()
        .iter()
        .filter_map(|t| match t.as_slice() {
            [Value::Track(v), Value::Track(o), Value::Time(f)] => Some((*v, *o, *f)),
            _ => None,
        })
        .collect()
}

/// One [`Match`] per referred track, in track order (tracks are sorted by uuid).
pub(crate) fn matches_of(
    scene: &Scene,
    scenario: &Scenario,
    referred: &[(TrackId, Frame)],
    related: &[(TrackId, TrackId, Frame)],
) -> Vec<Match> {
    let mut frames: BTreeMap<TrackId, BTreeSet<Frame>> = BTreeMap::new();
    for &(t, f) in referred {
        frames.entry(t).or_default().insert(f);
    }
    let mut rel: BTreeMap<TrackId, BTreeSet<&str>> = BTreeMap::new();
    for &(t, o, _) in related {
        rel.entry(t)
            .or_default()
            .insert(scene.track(o).uuid.as_str());
    }
    frames
        .into_iter()
        .filter_map(|(t, fs)| {
            let first = *fs.first()?;
            let last = *fs.last()?;
            let track = scene.track(t);
            Some(Match {
                log_id: scene.log_id.clone(),
                description: scenario.description.clone(),
                program: scenario.name.clone(),
                track_uuid: track.uuid.clone(),
                category: track.category.clone(),
                first_s: round_ms(scene.timeline.seconds(first).unwrap_or(0.0)),
                last_s: round_ms(scene.timeline.seconds(last).unwrap_or(0.0)),
                frames: fs.len(),
                related: rel
                    .get(&t)
                    .map(|s| s.iter().map(|u| u.to_string()).collect())
                    .unwrap_or_default(),
            })
        })
        .collect()
}

/// Seconds rounded to the millisecond (frames are 0.1 s apart; the rest is clock noise).
pub(crate) fn round_ms(s: f64) -> f64 {
    (s * 1000.0).round() / 1000.0
}
