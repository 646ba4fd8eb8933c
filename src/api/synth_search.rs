//! What a synthesis search runs its candidates on (`--candidates K`): the logs loaded once, a
//! [`Matcher`] that checks a candidate program and evaluates it on every one of them, as
//! `mine` does, returning its `referred` (log, track, frame) tuples, and the [`Evidence`] the
//! evidence round shows the model ([`crate::api::synth_evidence`]). The search itself (the
//! candidates, the medoid, the evidence rounds) is the synthesis crate's
//! (`scenalog_synth::search`).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use rayon::prelude::*;
use scenalog_extractors::cache::Extractor;
use scenalog_synth::{Evidence, MatchKey, Matcher};

use crate::api::error::{Error, Field};
use crate::api::inputs::logs_or_samples;
use crate::api::limits::Limits;
use crate::pipeline::run::referred_tuples;
use crate::pipeline::scenario::{evaluate_on, scenario_from_source};

/// The matcher of a search over `logs` (log directories or directories of logs; none: the
/// bundled sample logs), each candidate evaluated within `limits` on each log, and the evidence
/// of a program on the same logs, the logs loaded once for both.
///
/// # Errors
/// No logs are given and the sample logs are not bundled, or a log cannot be found or read.
pub fn search_logs(logs: &[PathBuf], limits: &Limits) -> Result<(Matcher, Evidence), Error> {
    let inputs = logs_or_samples(
        logs,
        "a search runs its candidates on logs: give some (the sample logs are not here)",
    )?;
    let mut scenes = Vec::with_capacity(inputs.len());
    for log in &inputs {
        let scene = scenalog_facts::load_scene(&log.dir).map_err(|e| {
            Error::about(
                Field::Logs,
                format!("cannot read log `{}`: {e}", log.dir.display()),
            )
        })?;
        scenes.push(scene);
    }
    let scenes = Arc::new(scenes);
    // The logs run at once share the machine's memory, as `mine`'s pairs do.
    let options = limits.engine(rayon::current_num_threads());
    let evidence = {
        let (scenes, options) = (Arc::clone(&scenes), options.clone());
        Evidence(Arc::new(move |program: &str| {
            crate::api::synth_evidence::evidence(&scenes, program, &options)
        }))
    };
    let matcher = Matcher(Arc::new(move |program: &str| {
        let scenario = scenario_from_source(Path::new("candidate.dl"), program.to_string())?;
        // The logs in parallel, as `mine` runs them.
        let per_log: Vec<Result<Vec<MatchKey>, String>> = scenes
            .par_iter()
            .enumerate()
            .map(|(l, scene)| {
                let extractor = Extractor::new(scene);
                let evaluation = evaluate_on(&extractor, &scenario.program, &options)
                    .map_err(|e| format!("on log {}: {e}", scene.log_id))?;
                Ok(referred_tuples(&evaluation)
                    .into_iter()
                    .map(|(track, frame)| (l as u32, track.0, frame))
                    .collect())
            })
            .collect();
        let mut matched: BTreeSet<MatchKey> = BTreeSet::new();
        for keys in per_log {
            matched.extend(keys?);
        }
        Ok(matched)
    }));
    Ok((matcher, evidence))
}
