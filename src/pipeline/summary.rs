//! What a mining run prints for a person: the matches per program and log, the time per stage,
//! the failures; and scoring a run's predictions against ground truth.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use scenalog_eval::{evaluate, EvalOptions, Report, SeqKey, Submission};

use super::run::{short_id, LogInput, PairStatus, RunReport};
use super::scenario::Scenario;

/// The table of matched (referred) tracks: one row per program, one column per log, a total
/// column; `ERR` where the pair failed. Then a line of totals and the time per stage.
pub fn render_table(report: &RunReport, scenarios: &[Scenario], logs: &[LogInput]) -> String {
    let mut cells: BTreeMap<(usize, &str), String> = BTreeMap::new();
    let mut totals = vec![0usize; scenarios.len()];
    for p in &report.pairs {
        let cell = match p.status {
            PairStatus::Failed(_) => "ERR".to_string(),
            _ => {
                totals[p.scenario] += p.matches.len();
                p.matches.len().to_string()
            }
        };
        cells.insert((p.scenario, p.log_id.as_str()), cell);
    }
    let name_w = scenarios
        .iter()
        .map(|s| s.name.chars().count())
        .max()
        .unwrap_or(0)
        .max("program".len());
    let col_w = 8;
    let mut out = String::new();
    let _ = write!(out, "{:<name_w$}", "program");
    for l in logs {
        let _ = write!(out, "  {:>col_w$}", short_id(&l.log_id));
    }
    let _ = writeln!(out, "  {:>col_w$}", "total");
    for (i, s) in scenarios.iter().enumerate() {
        let _ = write!(out, "{:<name_w$}", s.name);
        for l in logs {
            let cell = cells
                .get(&(i, l.log_id.as_str()))
                .map(String::as_str)
                .unwrap_or("-");
            let _ = write!(out, "  {cell:>col_w$}");
        }
        let _ = writeln!(out, "  {:>col_w$}", totals[i]);
    }
    let pairs = report.pairs.len();
    let failed = report
        .pairs
        .iter()
        .filter(|p| matches!(p.status, PairStatus::Failed(_)))
        .count();
    let resumed = report.resumed();
    let with_matches = report.with_matches();
    let total: usize = totals.iter().sum();
    let _ = writeln!(
        out,
        "\n{} programs x {} logs: {pairs} pairs ({resumed} resumed, {failed} failed), \
         {with_matches} with matches, {total} matched tracks",
        scenarios.len(),
        logs.len()
    );
    let t = &report.timings;
    let _ = writeln!(
        out,
        "time: load {:.2} s, extract+evaluate {:.2} s, tracks {:.2} s, write {:.2} s \
         (summed over threads); wall {:.2} s on {} thread{}",
        t.load.as_secs_f64(),
        t.evaluate.as_secs_f64(),
        t.tracks.as_secs_f64(),
        t.write.as_secs_f64(),
        t.wall.as_secs_f64(),
        report.threads,
        if report.threads == 1 { "" } else { "s" }
    );
    out
}

/// A run scored against ground truth.
#[derive(Debug, Clone)]
pub struct Scored {
    /// The evaluation's report over the scored sequences.
    pub report: Report,
    /// The predictions of the scored sequences (what `scenalog eval` scores the same).
    pub predictions: Submission,
    /// The sequences scored: in both the predictions and the ground truth.
    pub scored: Vec<SeqKey>,
    /// Predicted sequences not in the ground truth (not scored).
    pub not_in_gt: usize,
    /// Ground-truth sequences the run did not predict (left out of the score).
    pub not_mined: Vec<SeqKey>,
}

/// Scores the predictions of the sequences present in both `pred` and `gt`. Predictions for
/// (log, description) pairs the ground truth does not hold are not scored; ground-truth
/// sequences the run did not mine are left out (so each prompt is scored over the logs it was
/// mined on). `Ok(None)` when no sequence is in both.
pub fn score(pred: &Submission, gt: &Submission) -> Result<Option<Scored>, String> {
    let mut p = Submission::default();
    let mut g = Submission::default();
    let mut not_in_gt = 0;
    for (key, frames) in &pred.sequences {
        match gt.sequences.get(key) {
            Some(gframes) => {
                p.sequences.insert(key.clone(), frames.clone());
                g.sequences.insert(key.clone(), gframes.clone());
            }
            None => not_in_gt += 1,
        }
    }
    let not_mined: Vec<SeqKey> = gt
        .sequences
        .keys()
        .filter(|k| !pred.sequences.contains_key(*k))
        .cloned()
        .collect();
    if p.sequences.is_empty() {
        return Ok(None);
    }
    let report = evaluate(&p, &g, &EvalOptions::default()).map_err(|e| e.to_string())?;
    Ok(Some(Scored {
        report,
        scored: p.sequences.keys().cloned().collect(),
        predictions: p,
        not_in_gt,
        not_mined,
    }))
}

/// The four headline numbers and the per-prompt values, as `scenalog eval` prints them.
pub fn render_score(s: &Scored) -> String {
    let r = &s.report;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "scored {} sequence{} against the ground truth ({} predicted sequences not in it, {} of \
         its sequences not mined)",
        s.scored.len(),
        if s.scored.len() == 1 { "" } else { "s" },
        s.not_in_gt,
        s.not_mined.len()
    );
    let _ = writeln!(out, "HOTA-Temporal: {}", r.hota_temporal);
    let _ = writeln!(out, "HOTA-Track: {}", r.hota_track);
    let _ = writeln!(out, "Timestamp-level Balanced Accuracy: {}", r.timestamp_ba);
    let _ = writeln!(out, "Log-level Balanced Accuracy: {}", r.log_ba);
    for (prompt, ts) in &r.timestamp_ba_by_prompt {
        let ht = r
            .hota_temporal_by_prompt
            .get(prompt)
            .map_or(0.0, |h| h.value);
        let hk = r.hota_track_by_prompt.get(prompt).map_or(0.0, |h| h.value);
        let lb = r.log_ba_by_prompt.get(prompt).copied().unwrap_or(f64::NAN);
        let _ = writeln!(
            out,
            "  {prompt}: HOTA-Temporal {ht:.4}, HOTA-Track {hk:.4}, timestamp BA {ts:.4}, log BA {lb:.4}"
        );
    }
    out
}
