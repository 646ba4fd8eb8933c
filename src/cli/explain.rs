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
//! `--picture OUT.png|OUT.svg|OUT.gif` also draws the scene at that frame from above (see
//! `scenalog-view`): the track highlighted, its related objects linked to it, the proof's
//! geometric facts (or the why-not report's failing literal) drawn and listed; `--view object`
//! puts the track at the centre, heading up, instead of the ego. With `--frames A..B` (frame
//! indices, inclusive) or `--frames referred` (the span the track is referred in), the picture
//! shows the track's path over those frames with the referred frames marked, and a `.gif` is
//! an animation of them.
//!
//! Exit codes: 0 explained; 1 the rules do not check (diagnostics on stderr) or evaluation
//! failed; 2 unreadable rules file or log, unknown track, bad `--at` or `--frames`, a frame
//! outside the log, a track absent at the pictured frame, an unwritable picture path.

use std::path::PathBuf;
use std::process::ExitCode;

use scenalog_facts::scene::Frame;

use crate::api::explain::{explain_track, Explained};
use crate::pipeline::explain::{explanation_json, explanation_text, Explanation, Renderer};
use crate::pipeline::picture::{explanation_picture, frame_pictures};
use scenalog_view::track_path::animation_frames;
use scenalog_view::{
    path_svg, scene_svg, write_animation, write_picture, Format, PathPicture, Reference, ViewError,
};

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
    /// Also draw the scene from above into this file (.png, .svg, or .gif for an animation).
    #[arg(long, value_name = "OUT")]
    pub picture: Option<PathBuf>,
    /// The picture's width and height in pixels.
    #[arg(long, default_value_t = 800, value_name = "PX", value_parser = clap::value_parser!(u32).range(200..=4000))]
    pub picture_size: u32,
    /// Whose frame the picture is drawn in (that object at the centre, heading up).
    #[arg(long, value_enum, default_value_t = ViewFrom::Ego)]
    pub view: ViewFrom,
    /// Draw the track's path over frames `A..B` (inclusive), or `referred` for the span it is
    /// referred in, instead of one frame.
    #[arg(long, value_name = "A..B|referred")]
    pub frames: Option<String>,
    /// Most tuples the evaluation may hold, across all its relations, as `mine --max-tuples`
    /// [default: sized to the machine, as `mine`'s].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_tuples: Option<u64>,
    /// Longest the evaluation may take, in milliseconds, as `mine --timeout-ms` [default:
    /// 120000].
    #[arg(long, value_name = "MS", value_parser = clap::value_parser!(u64).range(1..))]
    pub timeout_ms: Option<u64>,
}

/// Whose frame `--picture` is drawn in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ViewFrom {
    /// The ego vehicle's.
    Ego,
    /// The explained track's.
    Object,
}

/// Parses `--frames`: `A..B` (inclusive) or `referred` (the first to the last referred frame).
fn parse_frames(text: &str, referred: &[Frame]) -> Result<(Frame, Frame), String> {
    if text == "referred" {
        return match (referred.first(), referred.last()) {
            (Some(a), Some(b)) => Ok((*a, *b)),
            _ => Err("--frames referred: the track is never referred".to_string()),
        };
    }
    let bad = || format!("--frames `{text}`: expected A..B (frame indices, A <= B) or `referred`");
    let (a, b) = text.split_once("..").ok_or_else(bad)?;
    let a: Frame = a.trim().parse().map_err(|_| bad())?;
    let b: Frame = b
        .trim()
        .trim_start_matches('=')
        .parse()
        .map_err(|_| bad())?;
    if a > b {
        return Err(bad());
    }
    Ok((a, b))
}

/// Draws `--picture`: one frame, or the path over `--frames`.
fn draw(
    args: &Args,
    out: &std::path::Path,
    renderer: &Renderer<'_>,
    explanation: &Explanation,
    related: Vec<scenalog_facts::scene::TrackId>,
    limits: &scenalog_engine::Options,
) -> Result<(), (u8, String)> {
    let reference = match args.view {
        ViewFrom::Ego => Reference::Ego,
        ViewFrom::Object => Reference::Referred,
    };
    let mut picture = explanation_picture(renderer, explanation, related, reference);
    picture.width = args.picture_size;
    picture.height = args.picture_size;
    if reference == Reference::Referred {
        // Centred on the object: closer in (it grows to show the related objects).
        picture.half_extent = 18.0;
    }
    let view_err = |e: ViewError| {
        let code = if matches!(e, ViewError::Render(_)) {
            1
        } else {
            2
        };
        (code, format!("--picture: {e}"))
    };
    let Some(frames) = &args.frames else {
        let svg = scene_svg(&picture).map_err(view_err)?;
        return write_picture(out, &svg).map_err(view_err);
    };
    let (first, last) = parse_frames(frames, &explanation.referred_frames).map_err(|e| (2, e))?;
    let mut path = PathPicture {
        picture,
        track: explanation.track,
        first,
        last,
        referred_frames: explanation.referred_frames.clone(),
        frames: Vec::new(),
    };
    match Format::of(out).map_err(view_err)? {
        Format::Gif => {
            // Each frame with its own proof and related objects.
            path.frames =
                frame_pictures(renderer, &path.picture, first, last, limits).map_err(|e| (1, e))?;
            let frames = animation_frames(&path).map_err(view_err)?;
            write_animation(out, &frames, 10).map_err(view_err)
        }
        Format::Png | Format::Svg => {
            let svg = path_svg(&path).map_err(view_err)?;
            write_picture(out, &svg).map_err(view_err)
        }
    }
}

fn fail(code: u8, msg: &str) -> ExitCode {
    eprintln!("scenalog explain: {msg}");
    ExitCode::from(code)
}

/// Runs the subcommand.
pub fn run(args: Args) -> ExitCode {
    let limits = crate::pipeline::limits::pair_limits(args.max_tuples, args.timeout_ms, 1);
    let explained = match explain_track(
        &args.rules,
        &args.log,
        &args.track,
        args.at,
        args.why_not,
        &limits,
    ) {
        Ok(x) => x,
        Err((code, e)) => return fail(code, &e),
    };
    let Explained {
        scene,
        scenario,
        explanation,
        related,
    } = explained;
    let renderer = Renderer {
        scene: &scene,
        scenario: &scenario,
    };
    if let Some(out) = &args.picture {
        if let Err((code, e)) = draw(&args, out, &renderer, &explanation, related, &limits) {
            return fail(code, &e);
        }
    }
    let text = if args.json {
        format!("{:#}\n", explanation_json(&renderer, &explanation))
    } else {
        explanation_text(&renderer, &explanation)
    };
    crate::cli::stdout::write_str(&text);
    ExitCode::SUCCESS
}
