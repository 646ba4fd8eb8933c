//! Measuring synthesis over a set of descriptions (`scenalog synth --eval FILE`): each one is
//! synthesized (held-out prompts, so the model never sees the description's own library
//! program), and the report counts programs clean on the first round and within the rounds, the
//! mean number of rounds, and clean programs that match nothing on the sample logs.
//!
//! Whether a program matches anything is asked of a caller-supplied function (the command runs
//! the program on the sample logs with the engine), so this crate stays free of the pipeline.
//! Likewise the fixture score ([`FixtureScore`]: the synthesized programs of the descriptions
//! that are prompts of the official evaluation fixture, mined on its logs and scored as
//! `scenalog mine` scores them) is computed by the command and attached to the report.

use serde::Serialize;

use crate::repair::Outcome;
use crate::usage::{Price, Usage};
use crate::Synthesizer;

/// What became of one description.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EvalItem {
    /// The description.
    pub description: String,
    /// The round whose program checked clean (`None`: none did).
    pub clean_round: Option<usize>,
    /// Completions asked for (rounds used).
    pub rounds: usize,
    /// `referred` tuples of the clean program over the sample logs (`None`: no clean program, or
    /// the run failed, see `error`).
    pub matches: Option<usize>,
    /// The server's or the run's error, if any.
    pub error: Option<String>,
    /// The clean program (`None`: none checked clean).
    pub program: Option<String>,
    /// The tokens the server reported for this description's completions.
    pub usage: Usage,
    /// The server could not be reached (or refused) for this description: `error` says why.
    pub unreachable: bool,
    /// Candidates asked for in a search (`--candidates`; 1: no search, and the fields below
    /// are empty).
    pub candidates: usize,
    /// Of those, how many checked clean.
    pub clean_candidates: usize,
    /// The first candidate's clean program (the one a single synthesis would have kept;
    /// `None` without a search, or when it did not check clean).
    pub first_program: Option<String>,
    /// The kept candidate's mean Jaccard similarity to the others' matches (`None` without a
    /// search, or when none ran).
    pub agreement: Option<f64>,
}

impl EvalItem {
    /// Whether a search chose a program other than its first candidate's.
    pub fn selection_changed(&self) -> bool {
        self.candidates > 1 && self.program.is_some() && self.first_program != self.program
    }
}

/// One prompt's scores on the fixture.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PromptScore {
    /// The prompt (a description of the set).
    pub prompt: String,
    /// HOTA-Temporal over the prompt's sequences.
    pub hota_temporal: f64,
    /// HOTA-Track over the prompt's sequences.
    pub hota_track: f64,
    /// Timestamp-level balanced accuracy.
    pub timestamp_ba: f64,
    /// Log-level balanced accuracy.
    pub log_ba: f64,
}

/// The fixture score of the ground-truth prompts: the synthesized programs of the descriptions
/// that are prompts of the fixture's ground truth, mined on its logs and scored against it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FixtureScore {
    /// The ground truth scored against (a path).
    pub ground_truth: String,
    /// The descriptions of the set that are ground-truth prompts, in set order.
    pub prompts: Vec<String>,
    /// Of those, the ones without a clean program: scored as predicting nothing (not left out,
    /// so a failed synthesis lowers the score).
    pub without_program: Vec<String>,
    /// (log, prompt) pairs whose clean program failed on the log (past the time limit or the
    /// tuple budget), as "log: prompt: error": scored as predicting nothing there, like a
    /// program that did not check.
    pub failed_pairs: Vec<String>,
    /// Sequences scored ((log, prompt) pairs in both the predictions and the ground truth).
    pub sequences: usize,
    /// HOTA-Temporal over every scored sequence (the benchmark's main metric).
    pub hota_temporal: f64,
    /// HOTA-Track.
    pub hota_track: f64,
    /// Timestamp-level balanced accuracy.
    pub timestamp_ba: f64,
    /// Log-level balanced accuracy.
    pub log_ba: f64,
    /// Per prompt, in the ground truth's order.
    pub by_prompt: Vec<PromptScore>,
}

impl FixtureScore {
    /// The score as text: the metrics aligned with the report's lines, then one line a prompt.
    pub fn render(&self) -> String {
        let mut s = format!(
            "fixture prompts scored            {} ({} without a clean program)\n\
             fixture HOTA-Temporal             {:.4}\n\
             fixture HOTA-Track                {:.4}\n\
             fixture timestamp BA              {:.4}\n\
             fixture log BA                    {:.4}\n",
            self.prompts.len(),
            self.without_program.len(),
            self.hota_temporal,
            self.hota_track,
            self.timestamp_ba,
            self.log_ba,
        );
        for p in &self.by_prompt {
            s.push_str(&format!(
                "  {}: HOTA-Temporal {:.4}, HOTA-Track {:.4}, timestamp BA {:.4}, log BA {:.4}\n",
                p.prompt, p.hota_temporal, p.hota_track, p.timestamp_ba, p.log_ba
            ));
        }
        for d in &self.without_program {
            s.push_str(&format!("  no clean program (predicts nothing): {d}\n"));
        }
        for d in &self.failed_pairs {
            s.push_str(&format!("  failed (predicts nothing there): {d}\n"));
        }
        s
    }
}

/// The report over a description set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EvalReport {
    /// The rounds allowed per description.
    pub max_rounds: usize,
    /// One item per description, in order.
    pub items: Vec<EvalItem>,
    /// The fixture score of the descriptions that are ground-truth prompts (`None`: the set has
    /// none, or no ground truth was given).
    pub fixture: Option<FixtureScore>,
    /// Prices per million tokens the cost is computed at (`None`: no cost reported).
    pub price: Option<Price>,
    /// With candidates: the fixture score the first candidates would have had (each search's
    /// first program in place of the one it kept), to compare with [`EvalReport::fixture`].
    pub first_fixture: Option<FixtureScore>,
}

impl EvalReport {
    /// Descriptions whose first program checked clean.
    pub fn clean_first_round(&self) -> usize {
        self.items
            .iter()
            .filter(|i| i.clean_round == Some(1))
            .count()
    }

    /// Descriptions with a clean program within the allowed rounds.
    pub fn clean(&self) -> usize {
        self.items
            .iter()
            .filter(|i| i.clean_round.is_some())
            .count()
    }

    /// Mean rounds used per description (0 for an empty set).
    pub fn mean_rounds(&self) -> f64 {
        if self.items.is_empty() {
            return 0.0;
        }
        self.items.iter().map(|i| i.rounds as f64).sum::<f64>() / self.items.len() as f64
    }

    /// Clean programs that match nothing on the sample logs.
    pub fn match_nothing(&self) -> Vec<&str> {
        self.items
            .iter()
            .filter(|i| i.matches == Some(0))
            .map(|i| i.description.as_str())
            .collect()
    }

    /// The tokens over every description.
    pub fn usage(&self) -> Usage {
        self.items
            .iter()
            .fold(Usage::default(), |t, i| t.add(&i.usage))
    }

    /// Descriptions for which the server could not be reached (or refused).
    pub fn unreachable(&self) -> usize {
        self.items.iter().filter(|i| i.unreachable).count()
    }

    /// Descriptions synthesized by a search over candidates.
    pub fn searched(&self) -> usize {
        self.items.iter().filter(|i| i.candidates > 1).count()
    }

    /// The mean agreement of the kept programs over the searches where candidates ran
    /// (`None`: none did).
    pub fn mean_agreement(&self) -> Option<f64> {
        let a: Vec<f64> = self.items.iter().filter_map(|i| i.agreement).collect();
        (!a.is_empty()).then(|| a.iter().sum::<f64>() / a.len() as f64)
    }

    /// Searches that kept another program than their first candidate's.
    pub fn selection_changed(&self) -> usize {
        self.items.iter().filter(|i| i.selection_changed()).count()
    }

    /// Descriptions whose synthesis or run ended in an error.
    pub fn errors(&self) -> usize {
        self.items.iter().filter(|i| i.error.is_some()).count()
    }

    /// The report as one JSON object: the counts of [`EvalReport::render`] (`descriptions`,
    /// `clean_first_round`, `clean`, `max_rounds`, `mean_rounds`, `match_nothing`, `errors`), the
    /// `items` (with each clean program and its `usage`, with `cost` when priced), the total
    /// `usage` (likewise), `price` (null without one) and `fixture` (null without one); with
    /// candidates also `searched`, `selection_changed`, `mean_agreement` and `first_fixture`
    /// (each item with its `candidates`, `clean_candidates`, `first_program` and `agreement`).
    pub fn to_json(&self) -> serde_json::Value {
        let price = self.price.as_ref();
        let mut items = serde_json::to_value(&self.items).unwrap_or_default();
        if let Some(list) = items.as_array_mut() {
            for (v, i) in list.iter_mut().zip(&self.items) {
                v["usage"] = i.usage.to_json(price);
            }
        }
        serde_json::json!({
            "descriptions": self.items.len(),
            "clean_first_round": self.clean_first_round(),
            "clean": self.clean(),
            "max_rounds": self.max_rounds,
            "mean_rounds": self.mean_rounds(),
            "match_nothing": self.match_nothing(),
            "errors": self.errors(),
            "items": items,
            "usage": self.usage().to_json(price),
            "price": self.price,
            "fixture": self.fixture,
            "searched": self.searched(),
            "selection_changed": self.selection_changed(),
            "mean_agreement": self.mean_agreement(),
            "first_fixture": self.first_fixture,
        })
    }

    /// The report as text (the format README.md shows).
    pub fn render(&self) -> String {
        let n = self.items.len();
        let pct = |k: usize| {
            if n == 0 {
                0.0
            } else {
                100.0 * k as f64 / n as f64
            }
        };
        let nothing = self.match_nothing();
        let errors = self.errors();
        let mut s = format!(
            "descriptions                      {n}\n\
             clean on round 1                  {} ({:.0} %)\n\
             clean within {} rounds             {} ({:.0} %)\n\
             mean rounds                       {:.2}\n\
             clean but match nothing on logs   {}\n\
             errors (server or run)            {errors}\n",
            self.clean_first_round(),
            pct(self.clean_first_round()),
            self.max_rounds,
            self.clean(),
            pct(self.clean()),
            self.mean_rounds(),
            nothing.len(),
        );
        s.push_str(&self.render_usage());
        if let Some(f) = &self.fixture {
            s.push_str(&f.render());
        }
        s.push_str(&self.render_search());
        for d in nothing {
            s.push_str(&format!("  matches nothing: {d}\n"));
        }
        for i in self.items.iter().filter(|i| i.clean_round.is_none()) {
            s.push_str(&format!(
                "  not clean: {}{}\n",
                i.description,
                i.error
                    .as_deref()
                    .map(|e| format!(" ({e})"))
                    .unwrap_or_default()
            ));
        }
        s
    }
}

impl EvalReport {
    /// The search lines of [`EvalReport::render`] (nothing without candidates): how many
    /// searches kept another program than their first candidate, the mean agreement, and the
    /// fixture score of the first candidates against the kept programs', in all and per prompt.
    pub fn render_search(&self) -> String {
        let searched = self.searched();
        if searched == 0 {
            return String::new();
        }
        let mut s = format!(
            "searches over candidates          {searched} ({} kept another program than the first)\n",
            self.selection_changed()
        );
        if let Some(a) = self.mean_agreement() {
            s.push_str(&format!("mean agreement of kept programs   {a:.3}\n"));
        }
        if let (Some(first), Some(kept)) = (&self.first_fixture, &self.fixture) {
            s.push_str(&format!(
                "fixture HOTA-Temporal: first      {:.4}\n\
                 fixture HOTA-Temporal: kept       {:.4}\n",
                first.hota_temporal, kept.hota_temporal
            ));
            for p in &kept.by_prompt {
                let before = first
                    .by_prompt
                    .iter()
                    .find(|f| f.prompt == p.prompt)
                    .map_or(f64::NAN, |f| f.hota_temporal);
                let agreement = self
                    .items
                    .iter()
                    .find(|i| i.description == p.prompt)
                    .and_then(|i| i.agreement)
                    .map(|a| format!(", agreement {a:.3}"))
                    .unwrap_or_default();
                s.push_str(&format!(
                    "  {}: first {before:.4}, kept {:.4}{agreement}\n",
                    p.prompt, p.hota_temporal
                ));
            }
        }
        s
    }

    /// The token lines of [`EvalReport::render`]: the totals, then one line a description, with
    /// the cost when priced.
    pub fn render_usage(&self) -> String {
        let u = self.usage();
        let cost = |u: &Usage| {
            self.price
                .map(|p| format!(", cost {:.4}", p.cost(u)))
                .unwrap_or_default()
        };
        let mut s = format!(
            "tokens: uncached input            {}\n\
             tokens: cached input              {}\n\
             tokens: output                    {}\n",
            u.uncached_tokens(),
            u.cached_tokens,
            u.completion_tokens,
        );
        if let Some(p) = &self.price {
            s.push_str(&format!(
                "cost at {}, {}, {} per million     {:.4}\n",
                p.input,
                p.cached,
                p.output,
                p.cost(&u)
            ));
        }
        if u.without_usage > 0 {
            s.push_str(&format!(
                "  {} of {} server answers reported no usage (not counted)\n",
                u.without_usage, u.completions
            ));
        }
        for i in &self.items {
            s.push_str(&format!(
                "  tokens {}: {} uncached, {} cached, {} output{}\n",
                i.description,
                i.usage.uncached_tokens(),
                i.usage.cached_tokens,
                i.usage.completion_tokens,
                cost(&i.usage)
            ));
        }
        s
    }
}

/// Synthesizes every description with `synth` (whose configuration should have `held_out`
/// set) and runs each clean program through `matches`, which returns its `referred` tuples over
/// the sample logs.
pub fn evaluate(
    synth: &Synthesizer,
    descriptions: &[String],
    mut matches: impl FnMut(&str) -> Result<usize, String>,
) -> EvalReport {
    let mut items = Vec::new();
    for d in descriptions {
        let t = synth.synthesize(d);
        let mut item = EvalItem {
            description: t.description.clone(),
            clean_round: None,
            rounds: t.rounds.len(),
            matches: None,
            error: None,
            program: None,
            usage: t.usage(),
            unreachable: false,
            candidates: 1,
            clean_candidates: 0,
            first_program: None,
            agreement: None,
        };
        if let Some(search) = &t.search {
            item.candidates = search.candidates.len();
            item.clean_candidates = search
                .candidates
                .iter()
                .filter(|c| c.transcript.is_clean())
                .count();
            item.first_program = search
                .candidates
                .first()
                .filter(|c| c.transcript.is_clean())
                .and_then(|c| c.transcript.program())
                .map(str::to_string);
            item.agreement = search
                .chosen
                .and_then(|c| search.candidates.get(c))
                .and_then(|c| c.agreement);
        }
        match &t.outcome {
            Outcome::Clean { round } => {
                item.clean_round = Some(*round);
                if let Some(p) = t.program() {
                    item.program = Some(p.to_string());
                    match matches(p) {
                        Ok(n) => item.matches = Some(n),
                        Err(e) => item.error = Some(e),
                    }
                }
            }
            Outcome::Failed => {}
            Outcome::Unreachable { error } => {
                item.error = Some(error.clone());
                item.unreachable = true;
            }
            Outcome::OverBudget { error } => item.error = Some(error.clone()),
        }
        items.push(item);
    }
    EvalReport {
        max_rounds: synth.config().rounds.max(1),
        items,
        fixture: None,
        price: None,
        first_fixture: None,
    }
}
