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

use crate::api::mine::{Descriptions, MineOutcome, MinePlan, MineRequest};
use crate::cli::mine_options::{fail, limits, synthesis};
pub use crate::cli::mine_options::{Format, Options};
use crate::pipeline::output::{MATCHES_JSON, PREDICTIONS_PICKLE, PREDICTIONS_TABLE, SCORED_PICKLE};
use crate::pipeline::run::{LogInput, RunReport};
use crate::pipeline::scenario::Scenario;
use crate::pipeline::summary::{render_score, render_table};

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
    for f in &plan.failures {
        eprintln!("scenalog mine: {f}");
    }
    for f in &plan.log_problems {
        eprintln!("scenalog mine: {f}");
    }
    if plan.scenarios.is_empty() {
        eprintln!("scenalog mine: no program to mine");
        return ExitCode::from(if plan.failures.is_empty() { 2 } else { 1 });
    }
    if plan.logs.is_empty() {
        eprintln!("scenalog mine: no log to mine");
        return ExitCode::from(if plan.log_problems.is_empty() { 2 } else { 1 });
    }
    // The outputs, the scored pickle and the report are one generation, published together.
    let outcome = match crate::api::mine::run(&request, &plan) {
        Ok(o) => o,
        Err(e) => return fail(e.flags()),
    };
    let MineOutcome {
        report,
        pair_failures,
        scored,
        score_errors,
        report_page,
        published,
    } = outcome;
    let MinePlan {
        scenarios,
        logs,
        failures,
        mut log_problems,
        gt,
        out,
        ..
    } = plan;
    let gt_path = gt.map(|(p, _)| p);
    for (_, e) in &report.log_failures {
        log_problems.push(e.clone());
    }
    for e in &score_errors {
        eprintln!("scenalog mine: {e}");
    }
    let mut score_failed = !score_errors.is_empty();
    let any_failed = report.any_failed() || !failures.is_empty() || !log_problems.is_empty();
    match report_page {
        Some(Ok(page)) => eprintln!("scenalog mine: wrote the report {}", page.display()),
        Some(Err(e)) => {
            eprintln!("scenalog mine: the report: {e}");
            score_failed = true;
        }
        None => {}
    }
    if let Err(e) = published {
        return fail(e);
    }

    match args.format {
        Format::Json => {
            let all_failures: Vec<&String> = failures
                .iter()
                .chain(&log_problems)
                .chain(&pair_failures)
                .collect();
            let value = serde_json::json!({
                "out": out.display().to_string(),
                "matches": report.matches(),
                "failures": all_failures,
                "score": scored.as_ref().map(|s| s.report.to_json()),
            });
            match serde_json::to_string_pretty(&value) {
                Ok(text) => outln!("{text}"),
                Err(e) => return fail(format!("cannot encode the summary: {e}")),
            }
        }
        Format::Text => {
            out!("{}", render_table(&report, &scenarios, &logs));
            let all = failures.len() + log_problems.len() + pair_failures.len();
            if all > 0 {
                outln!("\nfailed ({all}):");
                for f in failures.iter().chain(&log_problems).chain(&pair_failures) {
                    let mut lines = f.trim_end().lines();
                    outln!("  {}", lines.next().unwrap_or_default());
                    for l in lines {
                        outln!("    {l}");
                    }
                }
            }
            let pickle = if args.pickle {
                format!("{PREDICTIONS_PICKLE} (official pickle), ")
            } else {
                String::new()
            };
            outln!(
                "\nwrote {pickle}{} (Arrow table), {} (one entry per matched track) in {}",
                PREDICTIONS_TABLE,
                MATCHES_JSON,
                out.display()
            );
            if let Some(hint) = explain_hint(&report, &scenarios, &logs) {
                outln!("\nwhy did a track match? for example:\n  {hint}");
            }
            match (&scored, &gt_path) {
                (Some(s), Some(p)) => {
                    outln!("\nscore against {}:", p.display());
                    out!("{}", render_score(s));
                    let only = if s.not_mined.is_empty() {
                        ""
                    } else {
                        " --only-predicted"
                    };
                    outln!(
                        "score it again: scenalog eval --pred {} --gt {}{only}",
                        out.join(SCORED_PICKLE).display(),
                        p.display()
                    );
                }
                (None, Some(p)) if !score_failed => outln!(
                    "\nnot scored: no mined (log, description) pair is in {}",
                    p.display()
                ),
                _ => {}
            }
        }
    }
    if any_failed || score_failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// A `scenalog explain` command for the first match of the run (by program, then log).
fn explain_hint(report: &RunReport, scenarios: &[Scenario], logs: &[LogInput]) -> Option<String> {
    let pair = report
        .pairs
        .iter()
        .filter(|p| !p.matches.is_empty())
        .min_by_key(|p| (p.scenario, logs.iter().position(|l| l.log_id == p.log_id)))?;
    let m = pair.matches.first()?;
    let log = logs.iter().find(|l| l.log_id == pair.log_id)?;
    Some(format!(
        "scenalog explain --rules {} --log {} --track {} --at {}",
        scenarios[pair.scenario].path.display(),
        log.dir.display(),
        m.track_uuid,
        m.first_s
    ))
}
