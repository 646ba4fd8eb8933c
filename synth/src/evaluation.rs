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

    /// Descriptions whose synthesis or run ended in an error.
    pub fn errors(&self) -> usize {
        self.items.iter().filter(|i| i.error.is_some()).count()
    }

    /// The report as one JSON object: the counts of [`EvalReport::render`] (`descriptions`,
    /// `clean_first_round`, `clean`, `max_rounds`, `mean_rounds`, `match_nothing`, `errors`), the
    /// `items` (with each clean program and its `usage`, with `cost` when priced), the total
    /// `usage` (likewise), `price` (null without one) and `fixture` (null without one).
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
        };
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
        }
        items.push(item);
    }
    EvalReport {
        max_rounds: synth.config().rounds.max(1),
        items,
        fixture: None,
        price: None,
    }
}
