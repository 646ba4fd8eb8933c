//! The evidence round of a search: the kept program is run on the logs, what it matches is told
//! to the model in words (an [`Evidence`] function the caller with the logs supplies: counts
//! per category, the longest match's proof, or the nearest misses of a program that matches
//! nothing), and the model answers `KEEP` or a revised program. A revision goes through the
//! check-and-repair loop (continuing the same conversation) and is run on the logs; when it
//! checks clean and runs, it is kept, and the next round (up to the configured number) shows it
//! its own matches. Every round is recorded in the transcript ([`EvidenceRound`]).

use std::sync::Arc;

use crate::client::Message;
use crate::extract::{extract, with_description, Extracted};
use crate::repair::{self, Transcript};
pub use crate::transcript::{EvidenceRound, Verdict, KEEP};
use crate::usage::Usage;
use crate::Synthesizer;
use scenalog_rules::grammar::Answer;

/// What a program matches on the logs of a search, in words for the model, or why it could not
/// be run. Made by the caller that has the logs (the command's library).
#[derive(Clone)]
pub struct Evidence(pub Arc<EvidenceFn>);

/// The function inside an [`Evidence`].
pub type EvidenceFn = dyn Fn(&str) -> Result<String, String> + Send + Sync;

impl std::fmt::Debug for Evidence {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Evidence(..)")
    }
}

/// The message that shows the model what its program matched.
pub fn evidence_message(description: &str, evidence: &str) -> String {
    format!(
        "Your program was run on real driving logs. {evidence}\n\
         Does it find what the description \"{description}\" means, and only that? If it does, \
         answer with the single word {KEEP}. If it does not, reply with the complete corrected \
         program in one fenced code block (```scenalog ... ```)."
    )
}

/// The verdict on an answer, before any revision is checked: keep (`KEEP` and no program, or
/// the same program), a revision (its program), or unclear.
pub(crate) enum Reading {
    Keep,
    Revision,
    Unclear,
}

/// Reads the model's answer to the evidence about `shown` (for `description`).
pub(crate) fn read_answer(answer: &str, shown: &str, description: &str) -> Reading {
    match extract(answer) {
        Extracted::Program(code) => {
            if with_description(&code, description).trim() == shown.trim() {
                Reading::Keep
            } else {
                Reading::Revision
            }
        }
        Extracted::NoCode => {
            // `KEEP` as a word anywhere, or an answer that is only "keep" in any case.
            let bare = answer.trim_matches(|c: char| !c.is_alphanumeric());
            let keep = bare.eq_ignore_ascii_case(KEEP)
                || answer
                    .split(|c: char| !c.is_ascii_alphabetic())
                    .any(|w| w == KEEP);
            if keep {
                Reading::Keep
            } else {
                Reading::Unclear
            }
        }
    }
}

/// Asks one evidence round about `shown` (a clean program of `description`): runs the
/// evidence, asks the model, and on a revision runs its check-and-repair loop. The verdict is
/// [`Verdict::Revised`] when a clean revision came back (the caller runs it on the logs and may
/// turn it into [`Verdict::RevisionFailed`]); the revision's transcript is returned beside the
/// round, for the caller to add to the search's candidates.
pub(crate) fn ask(
    synth: &Synthesizer,
    evidence: &Evidence,
    description: &str,
    shown: &str,
    round: usize,
) -> (EvidenceRound, Option<Transcript>) {
    let mut record = EvidenceRound {
        round,
        program: shown.to_string(),
        evidence: String::new(),
        answer: None,
        cached: false,
        usage: Usage::default(),
        verdict: Verdict::Keep,
        candidate: None,
    };
    let told = match (evidence.0)(shown) {
        Ok(text) => text,
        Err(error) => {
            record.evidence = format!("could not be run: {error}");
            record.verdict = Verdict::NoEvidence { error };
            return (record, None);
        }
    };
    record.evidence = told.clone();
    let mut messages = synth.prompt(description);
    messages.push(Message::assistant(format!(
        "```scenalog\n{}\n```",
        shown.trim()
    )));
    messages.push(Message::user(evidence_message(description, &told)));
    let (answer, cached, usage) = match synth.complete_answer(&messages, 0, Answer::ProgramOrKeep) {
        Ok(a) => a,
        Err(e) => {
            let error = e.to_string();
            record.verdict = match e {
                crate::ClientError::Budget { .. } => Verdict::OverBudget { error },
                _ => Verdict::Unreachable { error },
            };
            return (record, None);
        }
    };
    record.answer = Some(answer.clone());
    record.cached = cached;
    record.usage = usage;
    match read_answer(&answer, shown, description) {
        Reading::Keep => (record, None),
        Reading::Unclear => {
            record.verdict = Verdict::Unclear;
            (record, None)
        }
        Reading::Revision => {
            // Round 1 of the revision is this answer; its tokens are counted in this round.
            let first = Some((answer, cached, Usage::default()));
            let revision = repair::converse(synth, description, messages, 0, first);
            record.verdict = if revision.is_clean() {
                Verdict::Revised
            } else {
                Verdict::RevisionNotClean
            };
            (record, Some(revision))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn answers_are_read_as_keep_revision_or_unclear() {
        let shown = "// description: d\nreferred(V, T) :- present(V, T).\n";
        let keep = |a: &str| matches!(read_answer(a, shown, "d"), Reading::Keep);
        assert!(keep("KEEP"));
        assert!(keep("  Keep. "));
        assert!(keep("The matches look right. KEEP"));
        assert!(
            keep("```scenalog\nreferred(V, T) :- present(V, T).\n```"),
            "the same program"
        );
        assert!(matches!(
            read_answer(
                "```\nreferred(V, T) :- ego(V), present(V, T).\n```",
                shown,
                "d"
            ),
            Reading::Revision
        ));
        assert!(matches!(
            read_answer("I would not keep it as is", shown, "d"),
            Reading::Unclear
        ));
        assert!(matches!(read_answer("", shown, "d"), Reading::Unclear));
    }
}
