//! The fixture score of `scenalog synth --eval`: the synthesized programs of the descriptions
//! that are prompts of the evaluation fixture's ground truth, mined on its logs and scored as
//! `scenalog mine` scores them (the same run, the same scoring).
//!
//! A ground-truth prompt of the set whose synthesis gave no clean program is mined as a program
//! that predicts nothing, so a failed synthesis lowers the score instead of leaving the prompt
//! out of it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use scenalog_synth::evaluation::{EvalReport, FixtureScore, PromptScore};

use crate::api::error::{Field, Message, Names};
use crate::api::inputs::log_dirs;
use crate::pipeline::run::{run as run_mining, PairStatus, RunOptions};
use crate::pipeline::scenario::scenario_from_source;
use crate::pipeline::summary::score;

/// The program a ground-truth prompt without a clean program is mined with: it matches nothing.
fn predicts_nothing(description: &str) -> String {
    format!(
        "// description: {}\n// No clean program was synthesized: this one predicts nothing.\n\
         referred(X, T) :- ego(X), present(X, T), T < 0.\n",
        scenalog_synth::extract::one_line(description)
    )
}

/// Mines the report's programs for the ground truth's prompts on `logs` (a directory of logs)
/// and scores them against `gt_path`; `Ok(None)` when no description of the set is one of its
/// prompts. Each pair runs within `limits` (a pair past them is mined as no match; its failure
/// in the score rendered with `names`). Scratch
/// output goes to a fresh directory under `scratch`, removed afterwards.
pub(crate) fn fixture_score(
    report: &EvalReport,
    gt_path: &Path,
    logs: &Path,
    scratch: &Path,
    limits: &scenalog_engine::Options,
    names: Names,
) -> Result<Option<FixtureScore>, Message> {
    let gt = scenalog_eval::read_any(gt_path).map_err(|e| Message::about(Field::Gt, e))?;
    let gt_prompts: BTreeSet<&str> = gt.sequences.keys().map(|(_, p)| p.as_str()).collect();
    let (mut prompts, mut without_program, mut scenarios) = (Vec::new(), Vec::new(), Vec::new());
    for item in &report.items {
        let d = item.description.as_str();
        if !gt_prompts.contains(d) || prompts.iter().any(|p| p == d) {
            continue;
        }
        let source = match &item.program {
            Some(p) => p.clone(),
            None => {
                without_program.push(d.to_string());
                predicts_nothing(d)
            }
        };
        let path = PathBuf::from(format!("{}.dl", scenalog_synth::slug::slug(d)));
        let scenario = scenario_from_source(&path, source)?;
        if scenario.description != d {
            return Err(Message::text(format!(
                "the program for `{d}` is described as `{}`",
                scenario.description
            )));
        }
        prompts.push(d.to_string());
        scenarios.push(scenario);
    }
    if prompts.is_empty() {
        return Ok(None);
    }
    let (log_inputs, problems) = log_dirs(&[logs.to_path_buf()]).map_err(|e| e.message)?;
    if let Some(p) = problems.first() {
        return Err(Message::text(p));
    }
    let out = scratch.join(format!("scenalog-synth-fixture-{}", std::process::id()));
    let options = RunOptions {
        out: out.clone(),
        resume: false,
        timestamps: BTreeMap::new(),
        threads: None,
        engine: limits.clone(),
        progress: false,
        names: Default::default(),
        keep_submission: true,
        cancel: None,
    };
    let run = run_mining(&scenarios, &log_inputs, &options);
    let _ = std::fs::remove_dir_all(&out);
    let mut run = run?;
    if let Some((log, e)) = run.log_failures.first() {
        return Err(e.clone().after(format!("{log}: ")));
    }
    // A pair past the limits has no prediction: mine it again with a program that predicts
    // nothing, so the prompt is scored there (as zero) rather than left out of the score.
    let mut failed_pairs = Vec::new();
    let mut redo: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for p in &run.pairs {
        if let PairStatus::Failed(e) = &p.status {
            let d = &scenarios[p.scenario].description;
            failed_pairs.push(format!("{}: {d}: {}", p.log_id, e.render(names)));
            redo.entry(p.log_id.clone()).or_default().push(p.scenario);
        }
    }
    for (log_id, indices) in redo {
        let log = log_inputs.iter().filter(|l| l.log_id == log_id).cloned();
        let nothing = indices
            .iter()
            .map(|&i| {
                let d = &scenarios[i].description;
                let path = PathBuf::from(format!("{}.dl", scenalog_synth::slug::slug(d)));
                scenario_from_source(&path, predicts_nothing(d))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let again = run_mining(&nothing, &log.collect::<Vec<_>>(), &options);
        let _ = std::fs::remove_dir_all(&out);
        run.submission.sequences.extend(again?.submission.sequences);
    }
    let scored = score(&run.submission, &gt)?
        .ok_or_else(|| "no (log, prompt) pair of the ground truth was mined".to_string())?;
    let r = &scored.report;
    let by_prompt = r
        .timestamp_ba_by_prompt
        .iter()
        .map(|(prompt, ts)| PromptScore {
            prompt: prompt.clone(),
            hota_temporal: r
                .hota_temporal_by_prompt
                .get(prompt)
                .map_or(0.0, |h| h.value),
            hota_track: r.hota_track_by_prompt.get(prompt).map_or(0.0, |h| h.value),
            timestamp_ba: *ts,
            log_ba: r.log_ba_by_prompt.get(prompt).copied().unwrap_or(f64::NAN),
        })
        .collect();
    Ok(Some(FixtureScore {
        ground_truth: gt_path.display().to_string(),
        prompts,
        without_program,
        failed_pairs,
        sequences: scored.scored.len(),
        hota_temporal: r.hota_temporal,
        hota_track: r.hota_track,
        timestamp_ba: r.timestamp_ba,
        log_ba: r.log_ba,
        by_prompt,
    }))
}
