//! `scenalog mine`: run scenario programs over logs and write predictions.
//!
//! `scenalog mine --rules R.dl… --logs DIR… --out OUT` evaluates every program on every log and
//! writes, under OUT: `predictions.feather` (the long Arrow table, zstd-compressed),
//! `predictions.pkl` with `--pickle` (the official pickle, keyed `(log_id, description)`),
//! `matches.json` (one entry per referred track),
//! `summary.json`, `scored.pkl` with `--gt` (the scored sequences' predictions), and one pickle and record per (log, program) pair under `pairs/` (what
//! `--resume` skips). `--rules` takes files or directories of `.dl` files; `--logs` takes log
//! directories or directories of logs.
//!
//! With no `--rules`, `--logs` or `--descriptions`, it mines the scenario library over the
//! bundled sample logs and scores the two fixture prompts against the bundled ground truth.
//!
//! `--eval-timestamps FILE.json` gives the output timestamps per log as a JSON object
//! `{"<log_id>": [timestamp_ns, …], …}` (each an annotation timestamp of that log); logs not in
//! it get every 5th frame from the first, which are the benchmark's 2 Hz timestamps.
//!
//! `--gt G` scores the run at the end: only sequences in both the predictions and G are scored;
//! predictions for (log, description) pairs not in G are written but not scored, and G's
//! sequences the run did not mine are left out of the score.
//!
//! `--max-tuples N` is one pair's budget over all its relations, extracted ones included
//! (default: half the machine's memory shared by the threads); `--timeout-ms MS` one pair's time
//! limit (default 120 s). A pair past either fails, naming the relation, and the others run.
//! `--log-prompts log_prompt_pairs.json --dataset-dir SPLIT [--tracks TRACKER.pkl]` mines a
//! split's (log, prompt) pairs and only those (see [`crate::api::split`]), into
//! `OUT/submission.pkl`.
//! `--report` also writes `OUT/report/index.html` after the run: the table of programs × logs
//! and, for up to `--report-max-pictures` matches, pictures over the referred span with a frame
//! scrubber and the proof (see [`crate::pipeline::report`]).
//!
//! Exit code: 0 when everything ran; 1 when a log, program, synthesis or the scoring failed
//! (the rest ran and was written); 2 when the arguments or inputs are unusable.

use std::process::ExitCode;

use crate::api::mine::{Descriptions, MineRequest};
use crate::cli::mine_options::{fail, limits, synthesis};
pub use crate::cli::mine_options::{Format, Options};

/// Arguments of `scenalog mine` (boxed: they are many, and the command enum stays small).
#[derive(clap::Args)]
pub struct Args {
    /// The options.
    #[command(flatten)]
    pub options: Box<Options>,
}

/// The request of `scenalog mine` without `--log-prompts`; the flags of a split's run are an
/// error here.
fn request(args: &Options) -> Result<MineRequest, String> {
    for (set, flag) in [
        (args.dataset_dir.is_some(), "--dataset-dir"),
        (args.tracks.is_some(), "--tracks"),
        (args.programs.is_some(), "--programs"),
        (args.synthesize, "--synthesize"),
        (args.no_confidence_filter, "--no-confidence-filter"),
    ] {
        if set {
            return Err(format!("{flag} goes with --log-prompts"));
        }
    }
    let descriptions = match &args.descriptions {
        Some(file) => Some(Descriptions {
            file: file.clone(),
            synthesis: synthesis(args)?,
        }),
        None => None,
    };
    Ok(MineRequest {
        rules: args.rules.clone(),
        logs: args.logs.clone(),
        out: args.out.clone(),
        descriptions,
        resume: args.resume,
        threads: args.threads.map(|n| n as usize),
        pickle: args.pickle,
        gt: args.gt.clone(),
        eval_timestamps: args.eval_timestamps.clone(),
        limits: limits(args),
        report: args.report.then_some(args.report_max_pictures),
        rerun: args.rerun,
        progress: true,
        cancel: None,
    })
}

/// Runs the subcommand.
pub fn run(args: Args) -> ExitCode {
    let args = *args.options;
    if args.log_prompts.is_some() {
        return crate::cli::split::run(&args);
    }
    let request = match request(&args) {
        Ok(r) => r,
        Err(e) => return fail(e),
    };
    let plan = match crate::api::mine::plan(&request) {
        Ok(p) => p,
        Err(e) => return fail(e.flags()),
    };
    if let Some(summary) = &plan.synthesis_summary {
        eprintln!("scenalog mine: synthesis: {summary}");
    }
    for f in plan.failures.iter().chain(&plan.log_problems) {
        eprintln!("scenalog mine: {f}");
    }
    if let Some((what, causes)) = plan.nothing_to_mine() {
        eprintln!("scenalog mine: {what}");
        return ExitCode::from(if causes.is_empty() { 2 } else { 1 });
    }
    // The outputs, the scored pickle and the report are one generation, published together.
    let outcome = match crate::api::mine::run(&request, plan) {
        Ok(o) => o,
        Err(e) => return fail(e.flags()),
    };
    for e in &outcome.score_errors {
        eprintln!("scenalog mine: {e}");
    }
    let mut score_failed = !outcome.score_errors.is_empty();
    match &outcome.report_page {
        Some(Ok(page)) => eprintln!("scenalog mine: wrote the report {}", page.display()),
        Some(Err(e)) => {
            eprintln!("scenalog mine: the report: {e}");
            score_failed = true;
        }
        None => {}
    }
    match &outcome.recording {
        Some(Ok((path, notes))) => {
            eprintln!(
                "scenalog mine: wrote the Rerun recording {} (open it with `rerun {}`)",
                path.display(),
                path.display()
            );
            for n in notes {
                eprintln!("scenalog mine: the recording left out {n}");
            }
        }
        Some(Err(e)) => {
            eprintln!("scenalog mine: the Rerun recording: {e}");
            score_failed = true;
        }
        None => {}
    }
    if let Err(e) = &outcome.published {
        return fail(e);
    }
    let failures: Vec<String> = outcome.failures.iter().map(|f| f.flags()).collect();
    let outputs = &outcome.outputs;
    match args.format {
        Format::Json => {
            let value = serde_json::json!({
                "out": outputs.dir.display().to_string(),
                "matches": outcome.matches(),
                "failures": failures,
                "score": outcome.scored.as_ref().map(|s| s.report.to_json()),
            });
            match serde_json::to_string_pretty(&value) {
                Ok(text) => outln!("{text}"),
                Err(e) => return fail(format!("cannot encode the summary: {e}")),
            }
        }
        Format::Text => {
            out!("{}", outcome.table_text());
            if !failures.is_empty() {
                outln!("\nfailed ({}):", failures.len());
                for f in &failures {
                    let mut lines = f.trim_end().lines();
                    outln!("  {}", lines.next().unwrap_or_default());
                    for l in lines {
                        outln!("    {l}");
                    }
                }
            }
            let pickle = match &outputs.pickle {
                Some(p) => format!("{} (official pickle), ", p.name),
                None => String::new(),
            };
            outln!(
                "\nwrote {pickle}{} (Arrow table), {} (one entry per matched track) in {}",
                outputs.table.name,
                outputs.matches.name,
                outputs.dir.display()
            );
            if let Some(hint) = outcome.explain_hint() {
                outln!("\nwhy did a track match? for example:\n  {hint}");
            }
            if let Some((command, url)) = outcome.studio_hint() {
                outln!(
                    "or see it on the map, with the rule to edit:\n  {command}\n  then open {url}"
                );
            }
            match (&outcome.scored, outcome.score_text(), &outcome.gt) {
                (Some(s), Some(text), Some(p)) => {
                    outln!("\nscore against {}:", p.display());
                    out!("{text}");
                    let only = if s.not_mined.is_empty() {
                        ""
                    } else {
                        " --only-predicted"
                    };
                    if let Some(scored) = &outputs.scored {
                        outln!(
                            "score it again: scenalog eval --pred {} --gt {}{only}",
                            scored.path.display(),
                            p.display()
                        );
                    }
                }
                (None, _, Some(p)) if !score_failed => outln!(
                    "\nnot scored: no mined (log, description) pair is in {}",
                    p.display()
                ),
                _ => {}
            }
        }
    }
    if outcome.any_failed() || score_failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
