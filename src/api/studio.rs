//! What the studio (`scenalog studio`) asks while a rule is edited: the logs it has open, each
//! log's map and boxes to draw, a program's diagnostics, its matches on every open log, and why
//! a clicked track is or is not referred at a frame. The logs are loaded once when the studio
//! opens, and each keeps its [`Extractor`], so a relation extracted for one edit is not extracted
//! again for the next: a round of re-mining after an edit is the engine's work alone.
//!
//! Every answer is JSON for the page; every input the page sends (a program's text, a log id, a
//! track uuid, a frame, a library program's name) is checked against what the studio has open,
//! never used as a path.

use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;
use scenalog_extractors::Extractor;
use scenalog_facts::load_scene;
use scenalog_facts::map::LaneType;
use scenalog_facts::relation::Value;
use scenalog_facts::scene::{Scene, Track};
use serde_json::{json, Value as Json};

use crate::api::editor::{self, EditorDiagnostic, Level, Range};
use crate::api::error::{invalid, Error, Field};
use crate::api::explain::{explain_on, find_track};
use crate::api::inputs::{bundled, logs_or_samples, LIBRARY};
use crate::api::limits::Limits;
use crate::api::synth::{config, synthesizer, Outcome, SynthSettings, Synthesizer};
use crate::pipeline::explain::{explanation_text, Renderer};
use crate::pipeline::scenario::{evaluate_on, scenario_from_source, Scenario};

pub use crate::pipeline::studio_link::DEFAULT_PORT;

/// Most bytes of a program the studio evaluates (a rule is a few hundred).
pub const MAX_PROGRAM_BYTES: usize = 256 * 1024;

/// What the studio opens.
#[derive(Clone, Debug, Default)]
pub struct StudioRequest {
    /// Log directories, or directories of logs (default: the bundled sample logs).
    pub logs: Vec<PathBuf>,
    /// Program files or directories of them offered in the page (default: the bundled library).
    pub rules: Vec<PathBuf>,
    /// One evaluation's limits (a program deriving forever stops with an error).
    pub limits: Limits,
    /// Write programs from descriptions with this LLM server's settings (`None`: the page
    /// offers no synthesis).
    pub synth: Option<SynthSettings>,
}

/// One open log: its scene (loaded once, kept for the studio's life) and its extractor.
struct OpenLog {
    extractor: Extractor<'static>,
}

impl OpenLog {
    fn scene(&self) -> &'static Scene {
        self.extractor.scene()
    }
}

/// The studio's logs and programs, open for as long as it serves.
pub struct Studio {
    logs: Vec<OpenLog>,
    programs: Vec<(String, PathBuf)>,
    limits: scenalog_engine::Options,
    synthesizer: Option<Synthesizer>,
}

impl std::fmt::Debug for Studio {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Studio")
            .field("logs", &self.logs.len())
            .field("programs", &self.programs.len())
            .finish_non_exhaustive()
    }
}

/// Opens the request's logs (each loaded once; the scenes live as long as the process, which is
/// the studio's life) and lists its programs.
pub fn open(request: &StudioRequest) -> Result<Studio, Error> {
    request.limits.check()?;
    let inputs = logs_or_samples(
        &request.logs,
        "no logs given and the bundled sample logs are not found",
    )?;
    let mut logs = Vec::new();
    for input in inputs {
        let scene = load_scene(&input.dir).map_err(|e| {
            Error::about(
                Field::Logs,
                format!("cannot load log `{}`: {e}", input.dir.display()),
            )
        })?;
        let scene: &'static Scene = Box::leak(Box::new(scene));
        logs.push(OpenLog {
            extractor: Extractor::new(scene),
        });
    }
    let rule_paths = if request.rules.is_empty() {
        bundled(LIBRARY).into_iter().collect()
    } else {
        request.rules.clone()
    };
    let mut programs = Vec::new();
    if !rule_paths.is_empty() {
        for file in crate::api::inputs::rule_files(&rule_paths)? {
            programs.push((crate::pipeline::scenario::program_name(&file), file));
        }
    }
    programs.sort();
    programs.dedup_by(|a, b| a.0 == b.0);
    let synthesizer = match &request.synth {
        Some(settings) => Some(synthesizer(config(settings, None)?.config)?),
        None => None,
    };
    Ok(Studio {
        logs,
        programs,
        limits: request.limits.engine(1),
        synthesizer,
    })
}

/// A number rounded to centimetres (or hundredths), to keep the page's data small.
fn cm(x: f64) -> Json {
    json!((x * 100.0).round() / 100.0)
}

fn polygon(points: impl IntoIterator<Item = [f64; 2]>) -> Json {
    Json::Array(
        points
            .into_iter()
            .flat_map(|[x, y]| [cm(x), cm(y)])
            .collect(),
    )
}

fn range_json(r: &Range) -> Json {
    json!({
        "start": {"line": r.start.line, "character": r.start.character},
        "end": {"line": r.end.line, "character": r.end.character},
    })
}

/// The diagnostics of a program as the page shows them (placed in lines and UTF-16 columns).
pub fn diagnostics_json(diagnostics: &[EditorDiagnostic]) -> Json {
    Json::Array(
        diagnostics
            .iter()
            .map(|d| {
                json!({
                    "range": range_json(&d.range),
                    "level": match d.level { Level::Error => "error", Level::Warning => "warning" },
                    "code": d.code,
                    "message": d.message,
                })
            })
            .collect(),
    )
}

impl Studio {
    /// The open logs: id, city, frames, seconds and tracks of each.
    pub fn logs_json(&self) -> Json {
        Json::Array(
            self.logs
                .iter()
                .map(|l| {
                    let s = l.scene();
                    json!({
                        "id": s.log_id,
                        "city": s.city,
                        "frames": s.num_frames(),
                        "tracks": s.tracks.len(),
                    })
                })
                .collect(),
        )
    }

    /// Whether the studio writes programs from descriptions (an LLM server is configured).
    pub fn can_synthesize(&self) -> bool {
        self.synthesizer.is_some()
    }

    /// A program written from `description` by the configured LLM server, repaired on the
    /// checker's diagnostics as `scenalog synth` does: the program (absent when the server gave
    /// none), whether it checked clean, and what went wrong otherwise.
    pub fn synthesize_json(&self, description: &str) -> Json {
        let Some(synth) = &self.synthesizer else {
            return json!({"error": "no LLM server is configured (start the studio with --base-url, or set SCENALOG_LLM_BASE_URL)"});
        };
        if description.trim().is_empty() {
            return json!({"error": "the description is empty"});
        }
        if description.len() > MAX_PROGRAM_BYTES {
            return json!({"error": "the description is too long"});
        }
        let transcript = synth.synthesize(description.trim());
        let (clean, error) = match &transcript.outcome {
            Outcome::Clean { .. } => (true, None),
            Outcome::Failed => (false, Some("no round gave a program that checks clean: the last one is shown with its diagnostics".to_string())),
            Outcome::Unreachable { error } | Outcome::OverBudget { error } => (false, Some(error.clone())),
        };
        json!({
            "program": transcript.program(),
            "clean": clean,
            "rounds": transcript.rounds.len(),
            "error": error,
        })
    }

    /// The programs offered (their names, sorted).
    pub fn programs_json(&self) -> Json {
        Json::Array(self.programs.iter().map(|(n, _)| json!(n)).collect())
    }

    /// The text of the offered program named `name` (a name from [`Studio::programs_json`],
    /// never a path).
    pub fn program_text(&self, name: &str) -> Result<String, Error> {
        let Some((_, path)) = self.programs.iter().find(|(n, _)| n == name) else {
            return Err(invalid(
                Field::Rules,
                format!("no program named `{name}` in the studio"),
            ));
        };
        crate::input::read_text(path).map_err(|e| Error::about(Field::Rules, e))
    }

    fn log(&self, id: &str) -> Result<&OpenLog, Error> {
        self.logs
            .iter()
            .find(|l| l.scene().log_id == id)
            .ok_or_else(|| invalid(Field::Logs, format!("no log `{id}` open in the studio")))
    }

    /// What the page draws of log `id`: the drivable area, the lanes (type, in an intersection
    /// or not, polygon) and crossings as flat `[x0, y0, x1, y1, …]` city coordinates in metres,
    /// each frame's time in seconds from the start, and every track (the ego vehicle's too) as
    /// flat `[frame, x, y, yaw, length, width, …]` boxes.
    pub fn scene_json(&self, id: &str) -> Result<Json, Error> {
        let scene = self.log(id)?.scene();
        let map = &scene.map;
        let lanes: Vec<Json> = map
            .lanes
            .iter()
            .map(|l| {
                json!({
                    "type": match l.lane_type {
                        LaneType::Vehicle => "vehicle",
                        LaneType::Bike => "bike",
                        LaneType::Bus => "bus",
                    },
                    "intersection": l.is_intersection,
                    "polygon": polygon(l.polygon_xy()),
                })
            })
            .collect();
        let times: Vec<Json> = scene
            .timeline
            .frames()
            .iter()
            .map(|f| cm(scene.timeline.seconds(*f).unwrap_or(0.0)))
            .collect();
        let tracks: Vec<Json> = scene
            .tracks
            .iter()
            .map(|t| {
                let boxes: Vec<Json> = t
                    .boxes
                    .iter()
                    .flat_map(|b| {
                        let c = b.city_center();
                        [
                            json!(b.frame),
                            cm(c.x),
                            cm(c.y),
                            cm(b.city_yaw()),
                            cm(b.size[0]),
                            cm(b.size[1]),
                        ]
                    })
                    .collect();
                json!({"uuid": t.uuid, "category": t.category, "boxes": boxes})
            })
            .collect();
        Ok(json!({
            "id": scene.log_id,
            "drivable": map.drivable_areas.iter().map(|a| polygon(a.boundary.iter().map(|p| [p.x, p.y]))).collect::<Vec<_>>(),
            "lanes": lanes,
            "crossings": map.crossings.iter().map(|c| polygon(c.polygon_xy())).collect::<Vec<_>>(),
            "times": times,
            "tracks": tracks,
        }))
    }

    /// The program checked; `Ok` when it has no error.
    fn scenario(text: &str) -> Result<Scenario, Json> {
        if text.len() > MAX_PROGRAM_BYTES {
            return Err(json!({
                "diagnostics": [],
                "error": format!("the program is {} bytes; the studio takes at most {MAX_PROGRAM_BYTES}", text.len()),
            }));
        }
        let diagnostics = editor::diagnostics(text);
        if diagnostics.iter().any(|d| d.level == Level::Error) {
            return Err(json!({"diagnostics": diagnostics_json(&diagnostics)}));
        }
        scenario_from_source(Path::new("studio.dl"), text.to_string())
            .map_err(|e| json!({"diagnostics": diagnostics_json(&diagnostics), "error": e}))
    }

    /// The program's diagnostics and, when it has no error, its matches on every open log: per
    /// log, each referred track with the frames it is referred at and the tracks `related` names
    /// with it, how long the log took, or the error that stopped it; and the round's time.
    pub fn mine_json(&self, text: &str) -> Json {
        let started = Instant::now();
        let scenario = match Studio::scenario(text) {
            Ok(s) => s,
            Err(answer) => return answer,
        };
        let diagnostics = editor::diagnostics(text);
        let logs: Vec<Json> = self
            .logs
            .par_iter()
            .map(|l| self.matches_on(&scenario, l))
            .collect();
        json!({
            "diagnostics": diagnostics_json(&diagnostics),
            "logs": logs,
            "ms": started.elapsed().as_secs_f64() * 1000.0,
        })
    }

    fn matches_on(&self, scenario: &Scenario, log: &OpenLog) -> Json {
        let scene = log.scene();
        let started = Instant::now();
        let ev = match evaluate_on(&log.extractor, &scenario.program, &self.limits) {
            Ok(ev) => ev,
            Err(e) => {
                return json!({
                    "log": scene.log_id,
                    "error": e.message(&format!("on log {}: ", scene.log_id)).flags(),
                })
            }
        };
        let mut referred: std::collections::BTreeMap<usize, Vec<u32>> = Default::default();
        for t in ev.tuples("referred").unwrap_or_default() {
            if let [Value::Track(x), Value::Time(f)] = t.as_slice() {
                referred.entry(x.index()).or_default().push(*f);
            }
        }
        let mut related: std::collections::BTreeMap<usize, Vec<Json>> = Default::default();
        for t in ev.tuples("related").unwrap_or_default() {
            if let [Value::Track(x), Value::Track(o), Value::Time(f)] = t.as_slice() {
                if let Some(other) = scene.tracks.get(o.index()) {
                    related
                        .entry(x.index())
                        .or_default()
                        .push(json!([other.uuid, f]));
                }
            }
        }
        let tracks: Vec<Json> = referred
            .into_iter()
            .filter_map(|(i, mut frames)| {
                let t = scene.tracks.get(i)?;
                frames.sort_unstable();
                frames.dedup();
                Some(json!({
                    "uuid": t.uuid,
                    "category": t.category,
                    "frames": frames,
                    "related": related.remove(&i).unwrap_or_default(),
                }))
            })
            .collect();
        json!({
            "log": scene.log_id,
            "tracks": tracks,
            "ms": started.elapsed().as_secs_f64() * 1000.0,
        })
    }

    /// Why track `uuid` of log `log` is or is not referred by the program at `frame` (the
    /// `explain` proof or why-not report as text), with the frames it is referred at and the
    /// tracks related to it there.
    pub fn explain_json(&self, text: &str, log: &str, uuid: &str, frame: u32) -> Json {
        let scenario = match Studio::scenario(text) {
            Ok(s) => s,
            Err(answer) => return answer,
        };
        let open = match self.log(log) {
            Ok(l) => l,
            Err(e) => return json!({"error": e.flags()}),
        };
        let scene = open.scene();
        let track: &Track = match find_track(scene, uuid) {
            Ok(t) => t,
            Err(e) => return json!({ "error": e }),
        };
        // `Timeline::seconds` counts from the log's first timestamp.
        let Some(at) = scene.timeline.seconds(frame) else {
            return json!({"error": format!("no frame {frame} in log {log}")});
        };
        match explain_on(
            &scenario,
            &open.extractor,
            track,
            Some(at.max(0.0)),
            false,
            &self.limits,
        ) {
            Ok((explanation, related)) => {
                let renderer = Renderer {
                    scene,
                    scenario: &scenario,
                };
                json!({
                    "referred": explanation.referred(),
                    "frame": explanation.frame,
                    "frames": explanation.referred_frames,
                    "related": related.iter().filter_map(|r| scene.tracks.get(r.index()).map(|t| t.uuid.clone())).collect::<Vec<_>>(),
                    "text": explanation_text(&renderer, &explanation),
                })
            }
            Err(e) => json!({"error": e.error.flags()}),
        }
    }
}

/// The checker's diagnostics of a program as the page shows them; a program past
/// [`MAX_PROGRAM_BYTES`] is one error at its start.
pub fn check_json(text: &str) -> Json {
    if text.len() > MAX_PROGRAM_BYTES {
        return json!([{
            "range": {"start": {"line": 0, "character": 0}, "end": {"line": 0, "character": 0}},
            "level": "error",
            "code": "",
            "message": format!("the program is {} bytes; the studio takes at most {MAX_PROGRAM_BYTES}", text.len()),
        }]);
    }
    diagnostics_json(&editor::diagnostics(text))
}
