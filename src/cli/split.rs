//! `scenalog mine --log-prompts FILE --dataset-dir SPLIT [--tracks TRACKER.pkl] --out DIR`: a
//! split's (log, prompt) pairs, and only those, mined into one submission (see
//! [`crate::api::split`], which does the work; this module turns the flags into its request and
//! prints the run).

use std::process::ExitCode;

use crate::api::split::{prepare, run as run_split, SplitRequest};
use crate::cli::mine_options::{fail, limits, synthesis, Format, Options};

/// The request of `mine --log-prompts`: the flags of a programs-on-logs run are an error here
/// (not silently ignored), and `--dataset-dir` is required.
fn request(args: &Options) -> Result<SplitRequest, String> {
    let Some(pairs_path) = &args.log_prompts else {
        return Err("--log-prompts is required here".to_string());
    };
    if !args.rules.is_empty() || !args.logs.is_empty() || args.descriptions.is_some() {
        return Err("--log-prompts takes its programs from --programs and the library, and its logs from --dataset-dir; leave out --rules, --logs and --descriptions".to_string());
    }
    // Flags of the programs-on-logs run that a split's run has no use for: an error, not a flag
    // silently ignored.
    for (set, flag, instead) in [
        (
            args.gt.is_some(),
            "--gt",
            "score the submission afterwards with `scenalog eval OUT/submission.pkl G`",
        ),
        (
            args.eval_timestamps.is_some(),
            "--eval-timestamps",
            "a split's logs are mined at their own timestamps",
        ),
        (
            args.report,
            "--report",
            "picture matches with `scenalog mine --rules … --logs … --report` or `scenalog explain … --picture`",
        ),
        (
            args.format == Format::Json,
            "--format json",
            "OUT/summary.json holds every pair's record",
        ),
    ] {
        if set {
            return Err(format!("{flag} does not go with --log-prompts: {instead}"));
        }
    }
    let Some(split) = &args.dataset_dir else {
        return Err("--log-prompts needs --dataset-dir SPLIT (the AV2 split with each log's ego poses and map)".to_string());
    };
    Ok(SplitRequest {
        out: args.out.clone(),
        tracks: args.tracks.clone(),
        confidence_filter: !args.no_confidence_filter,
        programs: args.programs.clone(),
        synthesis: if args.synthesize {
            Some(synthesis(args)?)
        } else {
            None
        },
        resume: args.resume,
        threads: args.threads.map(|n| n as usize),
        limits: limits(args),
        progress: true,
        cancel: None,
        ..SplitRequest::new(pairs_path.clone(), split.clone())
    })
}

/// Runs `mine --log-prompts`.
pub fn run(args: &Options) -> ExitCode {
    let request = match request(args) {
        Ok(r) => r,
        Err(e) => return fail(e),
    };
    let plan = match prepare(&request) {
        Ok(p) => p,
        Err(e) => return fail(e.flags()),
    };
    if let Some(summary) = &plan.synthesis_summary {
        eprintln!("scenalog mine: synthesis: {summary}");
    }
    for p in plan.problems.iter().chain(&plan.log_problems) {
        eprintln!("scenalog mine: {p}");
    }
    for p in &plan.without_program {
        eprintln!("scenalog mine: no program for the prompt {p:?}: its predictions are empty");
    }
    if plan.logs.is_empty() {
        eprintln!("scenalog mine: no log to mine");
        return ExitCode::from(if plan.log_problems.is_empty() { 2 } else { 1 });
    }
    let outcome = match run_split(&request, plan) {
        Ok(o) => o,
        Err(e) => return fail(e.flags()),
    };
    outln!("{}", outcome.counts_text());
    let failures: Vec<String> = outcome.failures.iter().map(|f| f.flags()).collect();
    if !failures.is_empty() {
        outln!("\nfailed ({}):", failures.len());
        for f in &failures {
            outln!("  {}", f.trim_end().replace('\n', "\n    "));
        }
    }
    if !outcome.without_program.is_empty() {
        outln!("\nno program ({}):", outcome.without_program.len());
        for p in &outcome.without_program {
            outln!("  {p}");
        }
    }
    let outputs = &outcome.outputs;
    let pickle = outputs.pickle.as_ref().map_or("", |p| p.name);
    outln!(
        "\nwrote {pickle} (the submission: official pickle, one sequence per written pair) and {} \
         in {}",
        outputs.table.name,
        outputs.dir.display()
    );
    if failures.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
