//! Labelled frames of one (log, description) pair as a prediction sequence in the evaluation's
//! data model (the official pickle's fields).

use scenalog_eval::FrameData;
use scenalog_facts::{Frame, Scene, TrackId};

use super::tracks::{Label, LabelledFrame};

/// The name the benchmark gives each label.
pub fn label_name(label: Label) -> &'static str {
    match label {
        Label::Referred => "REFERRED_OBJECT",
        Label::Related => "RELATED_OBJECT",
        Label::Other => "OTHER_OBJECT",
    }
}

/// Each box's score: `scores[track][i]` for `scene.tracks[track].boxes[i]` (a tracker's
/// confidence), or `None` for ground truth, whose boxes all score 1.0.
pub type BoxScores<'a> = Option<&'a [Vec<f32>]>;

/// Per (track, frame), the fraction of a synthesis search's candidates that refer to that box
/// (see `Scenario::candidates`).
pub type Agreement = std::collections::HashMap<(TrackId, Frame), f32>;

/// One prediction frame per labelled frame: every annotated object with its city-frame box,
/// label, track id (the scene's track index) and score: the tracker's score of that box at that
/// frame when `scores` is given (whatever its label), else 1.0 (ground truth; rules give no
/// confidence of their own).
pub fn to_frames(
    scene: &Scene,
    description: &str,
    frames: &[LabelledFrame],
    scores: BoxScores<'_>,
    agreement: Option<&Agreement>,
) -> Vec<FrameData> {
    frames
        .iter()
        .filter_map(|lf| {
            let timestamp_ns = scene.timeline.ns(lf.frame)?;
            let ego = scene.ego_poses.get(lf.frame as usize)?.translation.vector;
            let mut out = FrameData {
                timestamp_ns,
                ego_translation_m: [ego.x, ego.y, ego.z],
                description: Some(description.to_string()),
                score: Some(Vec::with_capacity(lf.objects.len())),
                ..FrameData::default()
            };
            for &(track, label) in &lf.objects {
                let t = scene.track(track);
                let Ok(i) = t.boxes.binary_search_by_key(&lf.frame, |b| b.frame) else {
                    continue;
                };
                let b = &t.boxes[i];
                let mut score = scores
                    .and_then(|s| s.get(track.index())?.get(i).copied())
                    .unwrap_or(1.0);
                if let (Some(a), Label::Referred) = (agreement, label) {
                    // The kept program is one of the candidates: a box it refers to has at
                    // least its vote.
                    score *= a.get(&(track, lf.frame)).copied().unwrap_or(1.0);
                }
                let c = b.city_center();
                out.translation_m.push([c.x, c.y, c.z]);
                out.size
                    .push([b.size[0] as f32, b.size[1] as f32, b.size[2] as f32]);
                out.yaw.push(b.city_yaw() as f32);
                out.velocity_m_per_s.push([0.0; 3]);
                out.label.push(label as i32);
                out.name.push(label_name(label).to_string());
                out.track_id.push(track.0 as i32);
                if let Some(s) = &mut out.score {
                    s.push(score);
                }
            }
            Some(out)
        })
        .collect()
}
