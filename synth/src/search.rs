//! Synthesis as a search over candidates: several programs for one description (the first asked
//! as a single synthesis asks, the others sampled), each through the check-and-repair loop, each
//! clean one run on logs by a [`Matcher`], and the one kept that agrees most with the others on
//! what they match (the medoid under Jaccard similarity of their matched (log, track, frame)
//! sets). Programs that mean the same thing match the same boxes however they are written, so
//! the majority's meaning wins over a minority's and over one that does not parse.
//!
//! Ties are broken by fewer rounds, then a shorter program, then the earlier candidate. Without a
//! matcher, nothing is run and the first clean candidate is kept.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

use crate::evidence::Verdict;
use crate::extract::one_line;
use crate::repair::{self, Transcript};
pub use crate::transcript::{Candidate, Search};
use crate::Synthesizer;

/// The temperature candidates after the first are sampled at, unless configured otherwise.
pub const SAMPLE_TEMPERATURE: f64 = 0.7;

/// One matched box: (log, track, frame), numbered by the matcher (the same numbering for every
/// candidate of a search).
pub type MatchKey = (u32, u32, u32);

/// What a program matches on the logs of a search: its `referred` (log, track, frame) tuples,
/// or why it could not be run. Made by the caller that has the logs (the command's library).
#[derive(Clone)]
pub struct Matcher(pub Arc<MatchFn>);

/// The function inside a [`Matcher`]: a program's text to its matched boxes, or why it could not
/// be run.
pub type MatchFn = dyn Fn(&str) -> Result<BTreeSet<MatchKey>, String> + Send + Sync;

impl std::fmt::Debug for Matcher {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Matcher(..)")
    }
}

/// The Jaccard similarity of two sets (1 for two empty sets: both match nothing).
pub fn jaccard(a: &BTreeSet<MatchKey>, b: &BTreeSet<MatchKey>) -> f64 {
    let union = a.union(b).count();
    if union == 0 {
        return 1.0;
    }
    a.intersection(b).count() as f64 / union as f64
}

/// What [`select`] decided.
#[derive(Debug, Clone, PartialEq)]
pub struct Selection {
    /// The index kept (`None`: no candidate has a match set).
    pub chosen: Option<usize>,
    /// Each candidate's mean similarity to the others with a match set (`None` for those
    /// without; 1 for a lone candidate).
    pub agreement: Vec<Option<f64>>,
    /// Each candidate's group: the candidates with exactly its match set.
    pub groups: Vec<Vec<usize>>,
    /// Why the chosen one won.
    pub reason: String,
}

/// Picks the medoid of the candidates that have match sets (`None`: not clean or not run):
/// the one with the highest mean Jaccard similarity to the others; ties go to fewer `rounds`,
/// then a shorter program (`lengths`), then the lower index.
pub fn select(
    sets: &[Option<BTreeSet<MatchKey>>],
    rounds: &[usize],
    lengths: &[usize],
) -> Selection {
    let ran: Vec<usize> = (0..sets.len()).filter(|&i| sets[i].is_some()).collect();
    let mut agreement = vec![None; sets.len()];
    let mut groups = vec![Vec::new(); sets.len()];
    for &i in &ran {
        let Some(a) = &sets[i] else { continue };
        let others: Vec<f64> = ran
            .iter()
            .filter(|&&j| j != i)
            .filter_map(|&j| sets[j].as_ref().map(|b| jaccard(a, b)))
            .collect();
        agreement[i] = Some(if others.is_empty() {
            1.0
        } else {
            others.iter().sum::<f64>() / others.len() as f64
        });
        groups[i] = ran
            .iter()
            .copied()
            .filter(|&j| sets[j].as_ref() == Some(a))
            .collect();
    }
    let key = |i: usize| {
        (
            agreement[i].unwrap_or(0.0),
            std::cmp::Reverse(rounds.get(i).copied().unwrap_or(usize::MAX)),
            std::cmp::Reverse(lengths.get(i).copied().unwrap_or(usize::MAX)),
            std::cmp::Reverse(i),
        )
    };
    let chosen = ran.iter().copied().max_by(|&a, &b| {
        key(a)
            .partial_cmp(&key(b))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let reason = match chosen {
        None => "no candidate checked clean and ran on the logs".to_string(),
        Some(c) => {
            let tied: Vec<usize> = ran
                .iter()
                .copied()
                .filter(|&j| j != c && agreement[j] == agreement[c])
                .collect();
            let mut r = format!(
                "candidate {c} agrees most with the others (mean Jaccard similarity {:.3} over {} \
                 candidate{} that ran); {} of them matched exactly what it matched",
                agreement[c].unwrap_or(0.0),
                ran.len(),
                if ran.len() == 1 { "" } else { "s" },
                groups[c].len(),
            );
            if !tied.is_empty() {
                r.push_str(&format!(
                    "; tied with {tied:?}, kept for fewer rounds, then a shorter program, then \
                     the earlier sample"
                ));
            }
            r
        }
    };
    Selection {
        chosen,
        agreement,
        groups,
        reason,
    }
}

/// Synthesizes [`crate::SynthConfig::candidates`] candidates for `description` and keeps one
/// (see the module's documentation), then shows the kept one its matches in
/// [`crate::SynthConfig::evidence_rounds`] evidence rounds ([`crate::evidence`]): a revision
/// that checks clean and runs is added to the candidates and kept. The transcript is the kept
/// candidate's, with the whole search in [`Transcript::search`] and the evidence rounds in
/// [`Transcript::evidence`]; when none checked clean, the first candidate's. A server that
/// cannot be reached stops the search at that candidate.
pub fn run(synth: &Synthesizer, description: &str) -> Transcript {
    let description = one_line(description);
    let k = synth.config().candidates.max(1);
    let mut transcripts: Vec<Transcript> = Vec::with_capacity(k);
    for sample in 0..k {
        let t = repair::run_sample(synth, &description, sample);
        let stop = t.outcome.stops_asking();
        transcripts.push(t);
        if stop {
            break;
        }
    }
    // Candidates with the same text (sampling often repeats itself) are run once.
    let mut runs = Runs::default();
    let (mut sets, mut errors): (Vec<_>, Vec<_>) =
        transcripts.iter().map(|t| runs.run(synth, t)).unzip();
    let mut selection = select(&sets, &rounds_of(&transcripts), &lengths_of(&transcripts));
    if selection.chosen.is_none() && synth.config().matcher.is_none() {
        selection.chosen = transcripts.iter().position(Transcript::is_clean);
        selection.reason = match selection.chosen {
            Some(c) => format!("no logs to run candidates on: candidate {c}, the first clean one"),
            None => "no candidate checked clean".to_string(),
        };
    }
    let (mut chosen, mut reason) = (selection.chosen, selection.reason);
    let mut evidence_rounds = Vec::new();
    if let Some(evidence) = synth.config().evidence.as_ref() {
        for round in 1..=synth.evidence_rounds() {
            let Some(c) = chosen else { break };
            let Some(shown) = transcripts[c]
                .program()
                .filter(|_| transcripts[c].is_clean())
            else {
                break;
            };
            let shown = shown.to_string();
            let (mut record, revision) =
                crate::evidence::ask(synth, evidence, &description, &shown, round);
            if let Some(revised) = revision {
                let index = transcripts.len();
                record.candidate = Some(index);
                let (set, error) = runs.run(synth, &revised);
                if let (Verdict::Revised, Some(e)) = (&record.verdict, &error) {
                    record.verdict = Verdict::RevisionFailed { error: e.clone() };
                }
                if record.verdict == Verdict::Revised {
                    chosen = Some(index);
                    reason = format!(
                        "candidate {index}: candidate {c} as the model revised it after seeing \
                         what it matches on the logs (evidence round {round}); before that, {reason}"
                    );
                }
                transcripts.push(revised);
                sets.push(set);
                errors.push(error);
            }
            let revised = record.verdict == Verdict::Revised;
            evidence_rounds.push(record);
            if !revised {
                break;
            }
        }
    }
    // Agreement and groups over every candidate, revisions included.
    let selection = select(&sets, &rounds_of(&transcripts), &lengths_of(&transcripts));
    let candidates: Vec<Candidate> = transcripts
        .iter()
        .enumerate()
        .map(|(i, t)| Candidate {
            sample: i,
            transcript: t.clone(),
            matched: sets[i].as_ref().map(BTreeSet::len),
            match_error: errors[i].clone(),
            agreement: selection.agreement[i],
            group: selection.groups[i].clone(),
        })
        .collect();
    // At least one candidate was asked for, so there is a transcript to keep.
    let kept = chosen.unwrap_or(0).min(transcripts.len() - 1);
    let mut transcript = transcripts[kept].clone();
    transcript.search = Some(Search {
        candidates,
        chosen,
        reason,
    });
    transcript.evidence = evidence_rounds;
    transcript
}

fn rounds_of(transcripts: &[Transcript]) -> Vec<usize> {
    transcripts.iter().map(|t| t.rounds.len()).collect()
}

fn lengths_of(transcripts: &[Transcript]) -> Vec<usize> {
    transcripts
        .iter()
        .map(|t| t.program().map_or(usize::MAX, str::len))
        .collect()
}

/// The matcher's results by program text, so a program is run once however often it recurs.
#[derive(Default)]
struct Runs(BTreeMap<String, Result<BTreeSet<MatchKey>, String>>);

impl Runs {
    /// A candidate's match set (`None`: not clean, no matcher, or it failed) and why it failed.
    fn run(
        &mut self,
        synth: &Synthesizer,
        t: &Transcript,
    ) -> (Option<BTreeSet<MatchKey>>, Option<String>) {
        let Some(program) = t.program().filter(|_| t.is_clean()) else {
            return (None, None);
        };
        let Some(matcher) = synth.config().matcher.as_ref() else {
            return (None, None);
        };
        let result = self
            .0
            .entry(program.to_string())
            .or_insert_with(|| (matcher.0)(program));
        match result {
            Ok(set) => (Some(set.clone()), None),
            Err(e) => (None, Some(e.clone())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(keys: &[u32]) -> Option<BTreeSet<MatchKey>> {
        Some(keys.iter().map(|&k| (0, k, 0)).collect())
    }

    #[test]
    fn the_majority_meaning_is_chosen_and_ties_go_to_fewer_rounds_then_shorter() {
        // Three candidates match {1,2,3}, one {7}, one did not check.
        let sets = vec![
            set(&[7]),
            set(&[1, 2, 3]),
            None,
            set(&[1, 2, 3]),
            set(&[1, 2, 3]),
        ];
        let s = select(&sets, &[1, 2, 1, 1, 1], &[10, 10, 10, 30, 20]);
        // 1, 3 and 4 agree equally; 1 took two rounds; 4 is shorter than 3.
        assert_eq!(s.chosen, Some(4), "{}", s.reason);
        assert_eq!(s.groups[4], vec![1, 3, 4]);
        assert_eq!(s.agreement[2], None);
        assert!(s.agreement[0] < s.agreement[4]);
        assert!(s.reason.contains("tied with"), "{}", s.reason);
    }

    /// A transcript with a search, as written beside a program, reads back with the same clean
    /// candidates (how `--resume` gets them).
    #[test]
    fn a_search_reads_back_from_its_transcript_json() {
        let round = |program: &str, result: repair::RoundResult| repair::Round {
            round: 1,
            cached: false,
            usage: crate::Usage::default(),
            completion: format!("```\n{program}\n```"),
            program: Some(program.to_string()),
            diagnostics: serde_json::json!([]),
            errors: 0,
            result,
            feedback: None,
        };
        let transcript = |program: &str, clean: bool| Transcript {
            description: "d".into(),
            model: "m".into(),
            rounds: vec![round(
                program,
                if clean {
                    repair::RoundResult::Clean
                } else {
                    repair::RoundResult::Errors
                },
            )],
            outcome: if clean {
                repair::Outcome::Clean { round: 1 }
            } else {
                repair::Outcome::Failed
            },
            search: None,
            evidence: Vec::new(),
        };
        let candidate = |sample: usize, t: Transcript| Candidate {
            sample,
            transcript: t,
            matched: None,
            match_error: None,
            agreement: None,
            group: Vec::new(),
        };
        let mut kept = transcript("a.", true);
        kept.search = Some(Search {
            candidates: vec![
                candidate(0, transcript("a.", true)),
                candidate(1, transcript("b(", false)),
                candidate(2, transcript("c.", true)),
            ],
            chosen: Some(0),
            reason: "r".into(),
        });
        let back: Transcript = serde_json::from_str(&kept.to_json()).expect("reads back");
        assert_eq!(back, kept);
        let search = back.search.expect("search");
        assert_eq!(search.clean_programs(), vec!["a.", "c."]);
    }

    #[test]
    fn near_agreement_counts_and_nothing_clean_chooses_nothing() {
        // 0 and 1 overlap mostly; 2 is apart: 0 or 1 wins, never 2.
        let sets = vec![set(&[1, 2, 3, 4]), set(&[1, 2, 3]), set(&[9])];
        let s = select(&sets, &[1, 1, 1], &[5, 5, 5]);
        assert!(matches!(s.chosen, Some(0) | Some(1)), "{s:?}");
        assert_eq!(select(&[None, None], &[1, 1], &[1, 1]).chosen, None);
        // A lone candidate that ran is kept.
        assert_eq!(select(&[None, set(&[])], &[1, 1], &[1, 1]).chosen, Some(1));
        assert_eq!(jaccard(&BTreeSet::new(), &BTreeSet::new()), 1.0);
    }
}
