//! `scenalog explain --rules R.dl --log DIR --track UUID [--at SECONDS] [--json] [--why-not]`:
//! why a track matched a scenario program at one frame (the proof of `referred(track, frame)`,
//! each rule with its source and each body fact with its values), or why it did not (the rule
//! that came closest, the literal that failed and the values that failed it).
//!
//! The frame is the one nearest to `--at` seconds from the log's start; without `--at`, the
//! first frame where the track is referred, or, for a track never referred, the middle of its
//! annotated frames. The why-not report comes with `--why-not`, or by itself when the track is
//! not referred at that frame. `--json` prints one object (keys documented in
//! [`crate::pipeline::explain`]).
//!
//! Exit codes: 0 explained; 1 the rules do not check (diagnostics on stderr) or evaluation
//! failed; 2 unreadable rules file or log, unknown track, bad `--at`.

use std::path::PathBuf;
use std::process::ExitCode;

use scenalog_engine::{explain, why_not};
use scenalog_extractors::cache::Extractor;
use scenalog_facts::load_scene;
use scenalog_facts::relation::Value;
use scenalog_facts::scene::{Frame, Scene, Track};

use crate::pipeline::explain::{
    evaluate_for_explain, explanation_json, explanation_text, frame_nearest, referred_frames,
    Explanation, Renderer,
};
use crate::pipeline::scenario::scenario_from_source;

/// Arguments of `scenalog explain`.
#[derive(clap::Args)]
pub struct Args {
    /// The scenario program (defines `referred(Track, T)`).
    #[arg(long, value_name = "R.dl")]
    pub rules: PathBuf,
    /// The log directory.
    #[arg(long, value_name = "DIR")]
    pub log: PathBuf,
    /// The track's uuid (a unique prefix is enough).
    #[arg(long, value_name = "UUID")]
    pub track: String,
    /// Explain the frame nearest to this many seconds from the log's start (a finite number, 0
    /// or more).
    #[arg(long, value_name = "SECONDS", value_parser = crate::cli::flags::non_negative_finite)]
    pub at: Option<f64>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Also say why the track is not referred (automatic when it is not referred at the frame).
    #[arg(long)]
    pub why_not: bool,
}

fn fail(code: u8, msg: &str) -> ExitCode {
    eprintln!("scenalog explain: {msg}");
    ExitCode::from(code)
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
            "no track `{uuid}` in log {} ({} tracks; `scenalog facts {}` lists them by category)",
            scene.log_id,
            scene.tracks.len(),
            scene.log_id
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

/// Runs the subcommand.
pub fn run(args: Args) -> ExitCode {
    let display = args.rules.display().to_string();
    let source = match std::fs::read_to_string(&args.rules) {
        Ok(s) => s,
        Err(e) => return fail(2, &format!("cannot read `{display}`: {e}")),
    };
    let scenario = match scenario_from_source(&args.rules, source) {
        Ok(s) => s,
        Err(e) => return fail(1, &e),
    };
    let scene = match load_scene(&args.log) {
        Ok(s) => s,
        Err(e) => return fail(2, &e.to_string()),
    };
    let track = match find_track(&scene, &args.track) {
        Ok(t) => t,
        Err(e) => return fail(2, &e),
    };
    let extractor = Extractor::new(&scene);
    let ev = match evaluate_for_explain(&extractor, &scenario.program, false) {
        Ok(ev) => ev,
        Err(e) => {
            return fail(
                1,
                &format!("evaluating {display} on log {}: {e}", scene.log_id),
            )
        }
    };
    let frames = referred_frames(&ev, track.id);
    let frame: Frame = match args.at {
        Some(at) => match frame_nearest(&scene, at) {
            Some(f) => f,
            None => return fail(2, &format!("log {} has no frames", scene.log_id)),
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
        Err(e) => return fail(1, &format!("{display}: {e}")),
    };
    let want_why_not = args.why_not || proof.is_none();
    let why = if want_why_not {
        let whole = match evaluate_for_explain(&extractor, &scenario.program, true) {
            Ok(ev) => ev,
            Err(e) => {
                return fail(
                    1,
                    &format!("evaluating {display} on log {}: {e}", scene.log_id),
                )
            }
        };
        match why_not(&scenario.program, &whole, "referred", &tuple) {
            Ok(w) => Some(w),
            Err(e) => return fail(1, &format!("{display}: {e}")),
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
    let renderer = Renderer {
        scene: &scene,
        scenario: &scenario,
    };
    let text = if args.json {
        format!("{:#}\n", explanation_json(&renderer, &explanation))
    } else {
        explanation_text(&renderer, &explanation)
    };
    crate::cli::stdout::write_str(&text);
    ExitCode::SUCCESS
}
