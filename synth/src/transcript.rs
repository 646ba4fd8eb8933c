//! What a synthesis records, as plain data: each round of the check-and-repair loop
//! ([`Round`]), how it ended ([`Outcome`]), the whole [`Transcript`], and with candidates the
//! [`Search`] over them and the [`EvidenceRound`]s after it. The loops that make them live in
//! [`crate::repair`], [`crate::search`] and [`crate::evidence`]; these types are below all three,
//! since a transcript holds a search whose candidates hold transcripts.

use serde::{Deserialize, Serialize};

use crate::usage::Usage;

/// The word the model answers to keep its program.
pub const KEEP: &str = "KEEP";

/// What one round produced.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RoundResult {
    /// The program checked with no error (warnings may remain).
    Clean,
    /// The program has errors.
    Errors,
    /// The answer held no program.
    NoCode,
    /// The program checked with no error but with warnings that usually change its meaning
    /// (`scenalog_rules::diagnostics::MEANING_WARNINGS`); they were sent back once.
    Warnings,
}

/// One completion and what the checker made of it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Round {
    /// 1-based round number.
    pub round: usize,
    /// Whether the completion came from the cache.
    pub cached: bool,
    /// The tokens the server reported for it (zero from the cache).
    pub usage: Usage,
    /// The model's whole answer.
    pub completion: String,
    /// The program taken from it, with the description comment first (`None`: no code).
    pub program: Option<String>,
    /// The checker's diagnostics on `program`, as JSON (see [`diagnostics::to_json`]).
    pub diagnostics: serde_json::Value,
    /// How many of them are errors.
    pub errors: usize,
    /// What the round amounted to.
    pub result: RoundResult,
    /// The message sent back to the model after this round (`None` after the last one or a
    /// clean one).
    pub feedback: Option<String>,
}

/// How synthesis of one description ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Outcome {
    /// A program checked clean in this round.
    Clean {
        /// The round (1-based).
        round: usize,
    },
    /// Every round ended with errors or without code.
    Failed,
    /// The server could not be reached or did not answer properly.
    Unreachable {
        /// The client's error.
        error: String,
    },
    /// The token budget (`max_tokens`) was spent before a program checked clean.
    OverBudget {
        /// What was spent, in words.
        error: String,
    },
}

impl Outcome {
    /// Whether nothing more may be asked of the server: it could not be reached, or the
    /// token budget is spent.
    pub fn stops_asking(&self) -> bool {
        matches!(
            self,
            Outcome::Unreachable { .. } | Outcome::OverBudget { .. }
        )
    }
}

/// Everything that happened while synthesizing one description.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Transcript {
    /// The description (on one line).
    pub description: String,
    /// The model asked.
    pub model: String,
    /// The rounds, in order.
    pub rounds: Vec<Round>,
    /// How it ended.
    pub outcome: Outcome,
    /// With several candidates: every candidate, what it matched, and why this one was kept
    /// (absent with one candidate, so such a transcript reads as before searches existed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub search: Option<Search>,
    /// The evidence rounds after the search: what the kept program matched, shown to the model,
    /// and its answer (absent when there were none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub evidence: Vec<EvidenceRound>,
}

impl Transcript {
    /// Whether a program checked clean.
    pub fn is_clean(&self) -> bool {
        matches!(self.outcome, Outcome::Clean { .. })
    }

    /// The last program any round produced (the clean one when there is one).
    pub fn program(&self) -> Option<&str> {
        self.rounds.iter().rev().find_map(|r| r.program.as_deref())
    }

    /// The diagnostics of [`Transcript::program`] as JSON (an empty array when there is none).
    pub fn diagnostics(&self) -> serde_json::Value {
        self.rounds
            .iter()
            .rev()
            .find(|r| r.program.is_some())
            .map_or_else(|| serde_json::json!([]), |r| r.diagnostics.clone())
    }

    /// The tokens the server reported over every round (of every candidate, after a search,
    /// and of the evidence rounds).
    pub fn usage(&self) -> Usage {
        let evidence = self
            .evidence
            .iter()
            .fold(Usage::default(), |t, e| t.add(&e.usage));
        let rounds = match &self.search {
            Some(search) => search
                .candidates
                .iter()
                .fold(Usage::default(), |t, c| t.add(&c.transcript.usage())),
            None => self
                .rounds
                .iter()
                .fold(Usage::default(), |t, r| t.add(&r.usage)),
        };
        rounds.add(&evidence)
    }

    /// The transcript as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }
}

/// One candidate of a search as the transcript records it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Candidate {
    /// Its number (0: asked as a single synthesis asks; others sampled).
    pub sample: usize,
    /// Its own check-and-repair transcript.
    pub transcript: Transcript,
    /// How many (log, track, frame) boxes it matched (`None`: not clean, or not run).
    pub matched: Option<usize>,
    /// Why it could not be run, when it could not.
    pub match_error: Option<String>,
    /// Its mean Jaccard similarity to the other clean candidates that ran (`None`: it did not
    /// run).
    pub agreement: Option<f64>,
    /// The candidates that matched exactly the same boxes as it (itself included).
    pub group: Vec<usize>,
}

/// Every candidate of a search, and which was kept and why.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Search {
    /// The candidates, in sample order.
    pub candidates: Vec<Candidate>,
    /// The candidate kept (`None`: none checked clean).
    pub chosen: Option<usize>,
    /// Why it was kept, in words.
    pub reason: String,
}

impl Search {
    /// The programs of the candidates that checked clean, in sample order.
    pub fn clean_programs(&self) -> Vec<String> {
        self.candidates
            .iter()
            .filter(|c| c.transcript.is_clean())
            .filter_map(|c| c.transcript.program().map(str::to_string))
            .collect()
    }
}

/// What came of one evidence round.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "verdict", rename_all = "snake_case")]
pub enum Verdict {
    /// The model kept the program (answered `KEEP`, or the same program again).
    Keep,
    /// The model revised the program; the revision checked clean, ran, and is kept.
    Revised,
    /// The model's revision never checked clean: the program shown stays.
    RevisionNotClean,
    /// The revision checked clean but could not be run on the logs: the program shown stays.
    RevisionFailed {
        /// Why it could not be run.
        error: String,
    },
    /// The answer held neither `KEEP` nor a program: the program shown stays.
    Unclear,
    /// The program shown could not be run for its evidence: no question was asked.
    NoEvidence {
        /// Why.
        error: String,
    },
    /// The server could not be reached: the program stays.
    Unreachable {
        /// The client's error.
        error: String,
    },
    /// The token budget was spent: nothing was asked, the program stays.
    OverBudget {
        /// What was spent.
        error: String,
    },
}

/// One evidence round as the transcript records it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EvidenceRound {
    /// 1-based round number.
    pub round: usize,
    /// The program shown.
    pub program: String,
    /// What the model was told about it (the evidence, or why there is none).
    pub evidence: String,
    /// The model's answer (`None`: none was asked for, or none came).
    pub answer: Option<String>,
    /// Whether the answer came from the cache.
    pub cached: bool,
    /// The tokens the server reported for the answer (a revision's later repair rounds are
    /// counted in its candidate's transcript).
    pub usage: Usage,
    /// What came of it.
    #[serde(flatten)]
    pub verdict: Verdict,
    /// The candidate of the search that holds the revision, with its check-and-repair rounds
    /// (whose round 1 is `answer`); `None` when there was no revision.
    pub candidate: Option<usize>,
}

impl EvidenceRound {
    /// One line saying what came of the round ("evidence round 1: the model kept the program").
    pub fn summary(&self) -> String {
        let what = match &self.verdict {
            Verdict::Keep => "the model kept the program".to_string(),
            Verdict::Revised => format!(
                "the model revised the program; the revision (candidate {}) checked clean, ran \
                 and is kept",
                self.candidate.unwrap_or_default()
            ),
            Verdict::RevisionNotClean => {
                "the model's revision never checked clean; the program stays".to_string()
            }
            Verdict::RevisionFailed { error } => {
                format!("the model's revision could not be run ({error}); the program stays")
            }
            Verdict::Unclear => {
                format!("the answer held neither {KEEP} nor a program; the program stays")
            }
            Verdict::NoEvidence { error } => {
                format!("the program could not be run for its evidence ({error})")
            }
            Verdict::Unreachable { error } | Verdict::OverBudget { error } => {
                format!("no answer ({error}); the program stays")
            }
        };
        format!("evidence round {}: {what}", self.round)
    }
}
