//! A track explained over its log, written as a Rerun recording (`scenalog explain --rerun
//! OUT.rrd`) for the viewer AV teams already use: the map (drivable area, lanes, crossings) once,
//! then at every frame of the log every object's box — the program's referred objects, the
//! objects related to the explained track, the ego vehicle and the others each an entity of its
//! own, coloured as in the pictures — and the explained track's proof (or why-not report) at that
//! frame as text. Two timelines: `frame` (the 10 Hz frame) and `time` (seconds from the log's
//! start). [`write_run_recording`] writes a whole run's matches: each log with matches under
//! `logs/<log id>/`, its map and every box, and per program that matched there its referred and
//! related objects per frame. Built only with the `rerun` feature.

use std::collections::BTreeSet;
use std::path::Path;

use scenalog_facts::scene::EGO_CATEGORY;
use scenalog_facts::scene::{Frame, TrackBox, TrackId};

use super::explain::{explanation_text, Renderer};
use super::picture::frame_explanations;

/// The colours of the pictures (`scenalog_view::style`), as RGB.
const REFERRED: [u8; 3] = [0xe6, 0x00, 0x7e];
const RELATED: [u8; 3] = [0x00, 0xb3, 0xc7];
const EGO: [u8; 3] = [0x22, 0x22, 0x22];
const OTHER: [u8; 3] = [0x9e, 0x9e, 0x9e];
const LANE: [u8; 3] = [0xbc, 0xbc, 0xbc];
const DRIVABLE: [u8; 3] = [0x80, 0x80, 0x80];
const CROSSING: [u8; 3] = [0xff, 0xff, 0xff];

/// Writes the recording of `track` explained at every frame of the log to `out` (through a
/// temporary file beside it, renamed into place when complete). The program is evaluated again
/// within `limits`.
pub fn write_recording(
    r: &Renderer<'_>,
    track: TrackId,
    limits: &scenalog_engine::Options,
    out: &Path,
) -> Result<(), String> {
    let scene = r.scene;
    let (Some(&first), Some(&last)) = (
        scene.timeline.frames().first(),
        scene.timeline.frames().last(),
    ) else {
        return Err(format!("log {} has no frames", scene.log_id));
    };
    let explained = frame_explanations(r, track, first, last, limits)
        .map_err(|m| m.render(crate::message::Names::Flags))?;
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    let tmp = out.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let written = record(r, track, &explained, &tmp);
    match written {
        Ok(()) => {
            std::fs::rename(&tmp, out).map_err(|e| format!("cannot write `{}`: {e}", out.display()))
        }
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(format!("cannot write `{}`: {e}", out.display()))
        }
    }
}

fn strip(points: &[nalgebra::Point3<f64>]) -> Vec<[f32; 3]> {
    points
        .iter()
        .map(|p| [p.x as f32, p.y as f32, p.z as f32])
        .collect()
}

fn closed(mut points: Vec<[f32; 3]>) -> Vec<[f32; 3]> {
    if let Some(&p) = points.first() {
        points.push(p);
    }
    points
}

/// A line through points in the city frame, metres.
type Strip = Vec<[f32; 3]>;

/// The closed outline of a shape between two edges (a lane's boundaries, a crossing's edges).
fn ring(one: &[nalgebra::Point3<f64>], other: &[nalgebra::Point3<f64>]) -> Vec<[f32; 3]> {
    let mut points = strip(one);
    points.extend(strip(other).into_iter().rev());
    closed(points)
}

/// The boxes of `boxes` (with their labels) as one Boxes3D.
fn boxes(of: &[(&TrackBox, String)], colour: [u8; 3]) -> rerun::Boxes3D {
    let centres = of.iter().map(|(b, _)| {
        let c = b.city_center();
        [c.x as f32, c.y as f32, c.z as f32]
    });
    let halves = of.iter().map(|(b, _)| {
        [
            b.size[0] as f32 / 2.0,
            b.size[1] as f32 / 2.0,
            b.size[2] as f32 / 2.0,
        ]
    });
    let turns = of.iter().map(|(b, _)| {
        let half = b.city_yaw() as f32 / 2.0;
        rerun::Quaternion::from_xyzw([0.0, 0.0, half.sin(), half.cos()])
    });
    rerun::Boxes3D::from_centers_and_half_sizes(centres, halves)
        .with_quaternions(turns)
        .with_colors(
            of.iter()
                .map(|_| rerun::Color::from_rgb(colour[0], colour[1], colour[2])),
        )
        .with_labels(of.iter().map(|(_, l)| l.clone()))
}

fn record(
    r: &Renderer<'_>,
    track: TrackId,
    explained: &super::picture::FrameExplanations,
    path: &Path,
) -> Result<(), String> {
    let failed = |e: rerun::RecordingStreamError| e.to_string();
    let scene = r.scene;
    let rec = rerun::RecordingStreamBuilder::new("scenalog")
        .recording_id(format!("{}-{}", scene.log_id, r.scenario.name))
        .save(path)
        .map_err(failed)?;
    let map = &scene.map;
    let colour = |c: [u8; 3]| rerun::Color::from_rgb(c[0], c[1], c[2]);
    let rings: [(&str, Vec<Strip>, [u8; 3]); 3] = [
        (
            "map/drivable",
            map.drivable_areas
                .iter()
                .map(|a| closed(strip(&a.boundary)))
                .collect(),
            DRIVABLE,
        ),
        (
            "map/lanes",
            map.lanes
                .iter()
                .map(|l| ring(&l.right_boundary, &l.left_boundary))
                .collect(),
            LANE,
        ),
        (
            "map/crossings",
            map.crossings
                .iter()
                .map(|c| ring(&c.edge1, &c.edge2))
                .collect(),
            CROSSING,
        ),
    ];
    for (entity, strips, c) in rings {
        rec.log_static(
            entity,
            &rerun::LineStrips3D::new(strips).with_colors([colour(c)]),
        )
        .map_err(failed)?;
    }
    rec.log_static(
        "program",
        &rerun::TextDocument::new(r.scenario.source.clone()),
    )
    .map_err(failed)?;
    for (explanation, related) in &explained.frames {
        let frame: Frame = explanation.frame;
        rec.set_time_sequence("frame", i64::from(frame));
        rec.set_duration_secs("time", scene.timeline.seconds(frame).unwrap_or(0.0));
        let referred: BTreeSet<TrackId> = explained
            .referred
            .iter()
            .filter(|(_, f)| *f == frame)
            .map(|(x, _)| *x)
            .collect();
        let related: BTreeSet<TrackId> = related.iter().copied().collect();
        let mut groups: [Vec<(&TrackBox, String)>; 4] = Default::default();
        for t in &scene.tracks {
            let Some(b) = t.box_at(frame) else {
                continue;
            };
            let label = format!("{} ({})", &t.uuid[..t.uuid.len().min(8)], t.category);
            let group = if referred.contains(&t.id) {
                0
            } else if related.contains(&t.id) {
                1
            } else if t.category == EGO_CATEGORY {
                2
            } else {
                3
            };
            groups[group].push((b, label));
        }
        for ((entity, colour), group) in [
            ("objects/referred", REFERRED),
            ("objects/related", RELATED),
            ("objects/ego", EGO),
            ("objects/other", OTHER),
        ]
        .into_iter()
        .zip(&groups)
        {
            rec.log(entity, &boxes(group, colour)).map_err(failed)?;
        }
        let explained_box: Vec<(&TrackBox, String)> = scene
            .tracks
            .get(track.index())
            .and_then(|t| t.box_at(frame).map(|b| (b, t.uuid.clone())))
            .into_iter()
            .collect();
        rec.log("explained", &boxes(&explained_box, [0, 0, 0]))
            .map_err(failed)?;
        let mut text = explanation_text(r, explanation);
        if explained_box.is_empty() {
            text.push_str("The track has no box at this frame.\n");
        }
        rec.log("proof", &rerun::TextDocument::new(text))
            .map_err(failed)?;
    }
    rec.flush_blocking().map_err(|e| e.to_string())
}

/// An entity path from parts taken as they are (names may hold `/` or spaces).
fn entity(parts: &[&str]) -> rerun::EntityPath {
    rerun::EntityPath::new(
        parts
            .iter()
            .map(|p| rerun::EntityPathPart::new(*p))
            .collect(),
    )
}

/// The (track, frame) pairs a program marks on a log, as referred or as related.
type Marks = BTreeSet<(TrackId, Frame)>;

/// The matches of a run as one Rerun recording at `path`: per log with matches, under
/// `logs/<log id>/`, the map once, every object's box per frame (`objects`), and per program
/// that matched there `programs/<name>/referred` and `programs/<name>/related` per frame, the
/// programs evaluated again on the log within `limits`. Logs that cannot be read or programs
/// that fail are skipped and named in the returned notes.
pub fn write_run_recording(
    path: &Path,
    scenarios: &[super::scenario::Scenario],
    logs: &[super::run::LogInput],
    pairs: &[super::run::PairResult],
    limits: &scenalog_engine::Options,
) -> Result<Vec<String>, String> {
    let failed = |e: rerun::RecordingStreamError| format!("cannot write `{}`: {e}", path.display());
    let rec = rerun::RecordingStreamBuilder::new("scenalog")
        .recording_id("scenalog-mine")
        .save(path)
        .map_err(failed)?;
    let colour = |c: [u8; 3]| rerun::Color::from_rgb(c[0], c[1], c[2]);
    let mut notes = Vec::new();
    for log in logs {
        let matched: Vec<usize> = pairs
            .iter()
            .filter(|p| p.log_id == log.log_id && !p.matches.is_empty())
            .map(|p| p.scenario)
            .collect();
        if matched.is_empty() {
            continue;
        }
        let scene = match scenalog_facts::load_scene(&log.dir) {
            Ok(s) => s,
            Err(e) => {
                notes.push(format!("log {}: {e}", log.log_id));
                continue;
            }
        };
        let extractor = scenalog_extractors::cache::Extractor::new(&scene);
        let id = scene.log_id.as_str();
        let map = &scene.map;
        for (name, strips, c) in [
            (
                "lanes",
                map.lanes
                    .iter()
                    .map(|l| ring(&l.right_boundary, &l.left_boundary))
                    .collect::<Vec<Strip>>(),
                LANE,
            ),
            (
                "crossings",
                map.crossings
                    .iter()
                    .map(|c| ring(&c.edge1, &c.edge2))
                    .collect(),
                CROSSING,
            ),
        ] {
            rec.log_static(
                entity(&["logs", id, "map", name]),
                &rerun::LineStrips3D::new(strips).with_colors([colour(c)]),
            )
            .map_err(failed)?;
        }
        // Per program: its referred and related (track, frame) on this log.
        let mut programs: Vec<(&str, Marks, Marks)> = Vec::new();
        for s in matched {
            let Some(scenario) = scenarios.get(s) else {
                continue;
            };
            let ev = match super::scenario::evaluate_on(&extractor, &scenario.program, limits) {
                Ok(ev) => ev,
                Err(e) => {
                    notes.push(
                        e.message(&format!("{} on log {id}: ", scenario.name))
                            .render(crate::message::Names::Flags),
                    );
                    continue;
                }
            };
            let referred = super::scenario::referred_pairs(&ev).into_iter().collect();
            let related = super::scenario::related_triples(&ev)
                .into_iter()
                .map(|(_, o, f)| (o, f))
                .collect();
            programs.push((scenario.name.as_str(), referred, related));
        }
        for &frame in scene.timeline.frames() {
            rec.set_time_sequence("frame", i64::from(frame));
            rec.set_duration_secs("time", scene.timeline.seconds(frame).unwrap_or(0.0));
            let present: Vec<(TrackId, &TrackBox, String)> = scene
                .tracks
                .iter()
                .filter_map(|t| {
                    let b = t.box_at(frame)?;
                    Some((
                        t.id,
                        b,
                        format!("{} ({})", &t.uuid[..t.uuid.len().min(8)], t.category),
                    ))
                })
                .collect();
            let all: Vec<(&TrackBox, String)> =
                present.iter().map(|(_, b, l)| (*b, l.clone())).collect();
            rec.log(entity(&["logs", id, "objects"]), &boxes(&all, OTHER))
                .map_err(failed)?;
            for (name, referred, related) in &programs {
                for (kind, set, c) in [
                    ("referred", referred, REFERRED),
                    ("related", related, RELATED),
                ] {
                    let these: Vec<(&TrackBox, String)> = present
                        .iter()
                        .filter(|(t, _, _)| set.contains(&(*t, frame)))
                        .map(|(_, b, l)| (*b, l.clone()))
                        .collect();
                    rec.log(
                        entity(&["logs", id, "programs", name, kind]),
                        &boxes(&these, c),
                    )
                    .map_err(failed)?;
                }
            }
        }
    }
    rec.flush_blocking()
        .map_err(|e| format!("cannot write `{}`: {e}", path.display()))?;
    Ok(notes)
}
