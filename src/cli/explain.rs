//! `scenalog explain --rules R.dl --log DIR --track UUID [--at SECONDS] [--json] [--why-not]`:
//! why a track matched a scenario program at one frame (the proof of `referred(track, frame)`,
//! each rule with its source and each body fact with its values), or why it did not (the rule
//! that came closest, the literal that failed and the values that failed it).
//!
//! The frame is the one nearest to `--at` seconds from the log's start; without `--at`, the
//! first frame where the track is referred, or, for a track never referred, the middle of its
//! annotated frames. The why-not report comes with `--why-not`, or by itself when the track is
//! not referred at that frame. `--json` prints one object (keys documented in
//! [`crate::pipeline::explain`]). [`crate::api::explain`] does the work and the drawing.
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

use crate::api::explain::{
    explain, ExplainError, ExplainRequest, FrameSpan, PictureRequest, ViewFrom as Reference,
};
use crate::api::Limits;

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
    /// Also write the track explained at every frame as a Rerun recording (OUT.rrd): boxes,
    /// map, referred and related marked, the proof at each frame (needs a build with
    /// `--features rerun`).
    #[arg(long, value_name = "OUT.rrd")]
    pub rerun: Option<PathBuf>,
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
fn parse_frames(text: &str) -> Result<FrameSpan, String> {
    if text == "referred" {
        return Ok(FrameSpan::Referred);
    }
    let bad = || format!("--frames `{text}`: expected A..B (frame indices, A <= B) or `referred`");
    let (a, b) = text.split_once("..").ok_or_else(bad)?;
    let a: u32 = a.trim().parse().map_err(|_| bad())?;
    let b: u32 = b
        .trim()
        .trim_start_matches('=')
        .parse()
        .map_err(|_| bad())?;
    if a > b {
        return Err(bad());
    }
    Ok(FrameSpan::Range(a, b))
}

fn fail(code: u8, msg: &str) -> ExitCode {
    eprintln!("scenalog explain: {msg}");
    ExitCode::from(code)
}

fn failed(e: ExplainError) -> ExitCode {
    fail(e.code, &e.error.flags())
}

/// Runs the subcommand.
pub fn run(args: Args) -> ExitCode {
    let request = ExplainRequest {
        rules: args.rules.clone(),
        log: args.log.clone(),
        track: args.track.clone(),
        at: args.at,
        why_not: args.why_not,
        limits: Limits {
            max_tuples: args.max_tuples,
            timeout_ms: args.timeout_ms,
        },
    };
    let explained = match explain(&request) {
        Ok(x) => x,
        Err(e) => return failed(e),
    };
    if let Some(out) = &args.picture {
        let frames = match args.frames.as_deref().map(parse_frames).transpose() {
            Ok(f) => f,
            Err(e) => return fail(2, &e),
        };
        let picture = PictureRequest {
            out: out.clone(),
            size: args.picture_size,
            view: match args.view {
                ViewFrom::Ego => Reference::Ego,
                ViewFrom::Object => Reference::Referred,
            },
            frames,
        };
        if let Err(e) = explained.draw(&picture) {
            return failed(e);
        }
    }
    if let Some(out) = &args.rerun {
        if let Err(e) = explained.record(out) {
            return failed(e);
        }
    }
    let text = if args.json {
        format!("{:#}\n", explained.json())
    } else {
        explained.text()
    };
    crate::cli::stdout::write_str(&text);
    ExitCode::SUCCESS
}
