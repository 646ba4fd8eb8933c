//! Explaining a track (`scenalog explain`, `scenalog.explain`): why a track is referred by a
//! program at one frame (the proof of `referred(track, frame)`), or why not (the rule that came
//! closest, the literal that failed and the values that failed it). One entry, [`explain`],
//! which both front ends call; the result renders itself as text ([`Explained::text`]) and JSON
//! ([`Explained::json`], keys in [`crate::pipeline::explain`]) and draws itself
//! ([`Explained::draw`]: the scene from above, or the track's path over frames).
//!
//! The frame is the one nearest to `at` seconds from the log's start; without it, the first
//! frame where the track is referred, or, for a track never referred, the middle of its
//! annotated frames. The why-not report comes when asked for, or by itself when the track is
//! not referred at that frame. The program is evaluated within one pair's [`Limits`] (`mine`'s
//! defaults), so a runaway program is an error naming the limit, never a hang.

use std::path::{Path, PathBuf};

use scenalog_engine::{explain as prove, why_not};
use scenalog_extractors::Extractor;
use scenalog_facts::load_scene;
use scenalog_facts::relation::Value;
use scenalog_facts::scene::{Frame, Scene, Track, TrackId};
use scenalog_view::track_path::animation_frames;
use scenalog_view::{
    path_svg, scene_svg, write_animation, write_picture, Format, PathPicture, Reference, ViewError,
};

use crate::api::error::{invalid, Error, Field, Message};
use crate::api::limits::Limits;
use crate::pipeline::explain::{
    evaluate_for_explain, explanation_json, explanation_text, frame_at, referred_frames,
    Explanation, Renderer,
};
use crate::pipeline::picture::{explanation_picture, frame_pictures, related_at};
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

/// Why a track could not be explained (or pictured).
#[derive(Clone, Debug, PartialEq)]
pub struct ExplainError {
    /// The command's exit code: 1 the rules do not check, evaluation failed or a picture could
    /// not be drawn; 2 an unusable input (unreadable rules or log, unknown track, bad `at`, a
    /// frame outside the log, an unwritable picture path).
    pub code: u8,
    /// The message.
    pub error: Error,
}

impl ExplainError {
    fn new(code: u8, error: impl Into<Error>) -> ExplainError {
        ExplainError {
            code,
            error: error.into(),
        }
    }
}

/// Explains why the request's track (a uuid or an unambiguous prefix) is or is not referred by
/// its program on its log at the frame nearest `at` seconds (see the module's doc for the frame
/// chosen without it); `why_not` adds the why-not report to a proof.
pub fn explain(request: &ExplainRequest) -> Result<Explained, ExplainError> {
    let unusable = |error: Error| ExplainError { code: 2, error };
    if let Some(a) = request.at {
        if !a.is_finite() || a < 0.0 {
            return Err(unusable(invalid(
                Field::At,
                format!("expected a finite number of seconds >= 0, got {a}"),
            )));
        }
    }
    request.limits.check().map_err(unusable)?;
    let limits = request.limits.engine(1);
    let rules = &request.rules;
    let source = crate::input::read_text(rules).map_err(|e| ExplainError::new(2, e))?;
    let scenario = scenario_from_source(rules, source).map_err(|e| ExplainError::new(1, e))?;
    let scene = load_scene(&request.log).map_err(|e| ExplainError::new(2, e.to_string()))?;
    let track = find_track(&scene, &request.track).map_err(|e| ExplainError::new(2, e))?;
    let extractor = Extractor::new(&scene);
    let (explanation, related) = explain_on(
        &scenario,
        &extractor,
        track,
        request.at,
        request.why_not,
        &limits,
    )?;
    drop(extractor);
    Ok(Explained {
        scene,
        scenario,
        explanation,
        related,
        limits,
    })
}

/// Explains `track` of the extractor's scene as [`explain`] does (the frame nearest `at`, the
/// why-not report when asked or not referred), with the scene already loaded: the explanation
/// and the objects `related` names at its frame. The studio calls it for every click.
pub(crate) fn explain_on(
    scenario: &Scenario,
    extractor: &Extractor<'_>,
    track: &Track,
    at: Option<f64>,
    why_not_too: bool,
    limits: &scenalog_engine::Options,
) -> Result<(Explanation, Vec<TrackId>), ExplainError> {
    let scene = extractor.scene();
    let display = scenario.path.display().to_string();
    let failed = |e: crate::pipeline::scenario::EvaluationError| {
        ExplainError::new(
            1,
            e.message(&format!("evaluating {display} on log {}: ", scene.log_id)),
        )
    };
    let ev = evaluate_for_explain(extractor, &scenario.program, false, limits).map_err(failed)?;
    let frames = referred_frames(&ev, track.id);
    let frame: Frame = match at {
        Some(at) => frame_at(scene, at).map_err(|e| ExplainError::new(2, e))?,
        None => match frames.first() {
            Some(f) => *f,
            None => match track.frame_span() {
                Some((a, b)) => a + (b - a) / 2,
                None => 0,
            },
        },
    };
    let tuple = [Value::Track(track.id), Value::Time(frame)];
    let proof = prove(&scenario.program, &ev, "referred", &tuple)
        .map_err(|e| ExplainError::new(1, format!("{display}: {e}")))?;
    let why = if why_not_too || proof.is_none() {
        let whole =
            evaluate_for_explain(extractor, &scenario.program, true, limits).map_err(failed)?;
        let report = why_not(&scenario.program, &whole, "referred", &tuple)
            .map_err(|e| ExplainError::new(1, format!("{display}: {e}")))?;
        Some(report)
    } else {
        None
    };
    let related = related_at(&ev, track.id, frame);
    let explanation = Explanation {
        track: track.id,
        frame,
        referred_frames: frames,
        proof,
        why_not: why,
    };
    Ok((explanation, related))
}

/// The track with this uuid, or the only one whose uuid starts with it.
pub(crate) fn find_track<'s>(scene: &'s Scene, uuid: &str) -> Result<&'s Track, String> {
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
    scene: Scene,
    scenario: Scenario,
    explanation: Explanation,
    related: Vec<TrackId>,
    /// The limits the program was evaluated within (again so for an animation's frames).
    limits: scenalog_engine::Options,
}

impl Explained {
    fn renderer(&self) -> Renderer<'_> {
        Renderer {
            scene: &self.scene,
            scenario: &self.scenario,
        }
    }

    /// Whether the track is referred at the frame explained.
    pub fn referred(&self) -> bool {
        self.explanation.referred()
    }

    /// The frame explained.
    pub fn frame(&self) -> Frame {
        self.explanation.frame
    }

    /// The frames at which the track is referred, ascending.
    pub fn referred_frames(&self) -> &[Frame] {
        &self.explanation.referred_frames
    }

    /// The text `scenalog explain` prints: the track, the frame, the proof and/or the why-not
    /// report, values in readable form.
    pub fn text(&self) -> String {
        explanation_text(&self.renderer(), &self.explanation)
    }

    /// The JSON `scenalog explain --json` prints (keys in [`crate::pipeline::explain`]).
    pub fn json(&self) -> serde_json::Value {
        explanation_json(&self.renderer(), &self.explanation)
    }

    /// Writes the track explained at every frame of its log as a Rerun recording (`.rrd`): the
    /// map, every object's box per frame (referred, related, ego, other), the proof or why-not
    /// report per frame (see `pipeline::recording`). Needs the `rerun` feature; without it, an
    /// error saying so.
    pub fn record(&self, out: &Path) -> Result<(), ExplainError> {
        if out.extension().is_none_or(|e| e != "rrd") {
            return Err(ExplainError::new(
                2,
                invalid(
                    Field::Rerun,
                    format!("expected a `.rrd` file, got `{}`", out.display()),
                ),
            ));
        }
        #[cfg(feature = "rerun")]
        {
            crate::pipeline::recording::write_recording(
                &self.renderer(),
                self.explanation.track,
                &self.limits,
                out,
            )
            .map_err(|e| ExplainError::new(2, Error::about(Field::Rerun, e)))
        }
        #[cfg(not(feature = "rerun"))]
        {
            Err(ExplainError::new(
                2,
                Error::about(Field::Rerun, crate::api::mine::WITHOUT_RERUN),
            ))
        }
    }

    /// Draws the picture the request asks for (see [`PictureRequest`]): the scene at the frame
    /// explained, or the track's path over frames (a `.gif`: an animation, each frame with its
    /// own proof, the program evaluated again within the explanation's limits).
    pub fn draw(&self, request: &PictureRequest) -> Result<(), ExplainError> {
        let size = request.size;
        if !(200..=4000).contains(&size) {
            return Err(ExplainError::new(
                2,
                invalid(
                    Field::PictureSize,
                    format!("expected 200 to 4000 pixels, got {size}"),
                ),
            ));
        }
        let renderer = self.renderer();
        let mut picture = explanation_picture(
            &renderer,
            &self.explanation,
            self.related.clone(),
            request.view,
        );
        picture.width = size;
        picture.height = size;
        if request.view == Reference::Referred {
            // Centred on the object: closer in (it grows to show the related objects).
            picture.half_extent = 18.0;
        }
        let out = &request.out;
        let view_err = |e: ViewError| {
            let code = if matches!(e, ViewError::Render(_)) {
                1
            } else {
                2
            };
            ExplainError::new(code, Error::about(Field::Picture, e))
        };
        let Some(frames) = &request.frames else {
            let svg = scene_svg(&picture).map_err(view_err)?;
            return write_picture(out, &svg).map_err(view_err);
        };
        let (first, last) = match *frames {
            FrameSpan::Range(a, b) => (a, b),
            FrameSpan::Referred => {
                let referred = &self.explanation.referred_frames;
                match (referred.first(), referred.last()) {
                    (Some(a), Some(b)) => (*a, *b),
                    _ => {
                        let never = Message::text("")
                            .mention(Field::Frames)
                            .then(" referred: the track is never referred");
                        return Err(ExplainError::new(2, never));
                    }
                }
            }
        };
        let mut path = PathPicture {
            picture,
            track: self.explanation.track,
            first,
            last,
            referred_frames: self.explanation.referred_frames.clone(),
            frames: Vec::new(),
        };
        match Format::of(out).map_err(view_err)? {
            Format::Gif => {
                // Each frame with its own proof and related objects.
                path.frames = frame_pictures(&renderer, &path.picture, first, last, &self.limits)
                    .map_err(|e| ExplainError::new(1, e))?;
                let frames = animation_frames(&path).map_err(view_err)?;
                write_animation(out, &frames, 10).map_err(view_err)
            }
            Format::Png | Format::Svg => {
                let svg = path_svg(&path).map_err(view_err)?;
                write_picture(out, &svg).map_err(view_err)
            }
        }
    }
}

/// Whose frame a picture is drawn in.
pub use scenalog_view::Reference as ViewFrom;

/// The frames a path picture shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameSpan {
    /// Frames `A..=B` (frame indices).
    Range(Frame, Frame),
    /// The first to the last frame the track is referred in.
    Referred,
}

/// A picture of an explanation to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct PictureRequest {
    /// The file: `.png`, `.svg`, or `.gif` (an animation of the path's frames).
    pub out: PathBuf,
    /// Width and height in pixels (200 to 4000).
    pub size: u32,
    /// Whose frame it is drawn in: the ego's ([`ViewFrom::Ego`]) or the track's
    /// ([`ViewFrom::Referred`], closer in, heading up).
    pub view: ViewFrom,
    /// The track's path over these frames instead of the one frame explained.
    pub frames: Option<FrameSpan>,
}

impl PictureRequest {
    /// A picture of the frame explained into `out`, 800 px, in the ego's frame.
    pub fn new(out: impl AsRef<Path>) -> PictureRequest {
        PictureRequest {
            out: out.as_ref().to_path_buf(),
            size: 800,
            view: ViewFrom::Ego,
            frames: None,
        }
    }
}
