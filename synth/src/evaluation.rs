//! Measuring synthesis over a set of descriptions (`scenalog synth --eval FILE`): each one is
//! synthesized (held-out prompts, so the model never sees the description's own library
//! program), and the report counts programs clean on the first round and within the rounds, the
//! mean number of rounds, and clean programs that match nothing on the sample logs.
//!
//! Whether a program matches anything is asked of a caller-supplied function (the command runs
//! the program on the sample logs with the engine), so this crate stays free of the pipeline.

use serde::Serialize;

use crate::repair::Outcome;
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
}

/// The report over a description set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EvalReport {
    /// The rounds allowed per description.
    pub max_rounds: usize,
    /// One item per description, in order.
    pub items: Vec<EvalItem>,
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
        let errors = self.items.iter().filter(|i| i.error.is_some()).count();
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
        };
        match &t.outcome {
            Outcome::Clean { round } => {
                item.clean_round = Some(*round);
                if let Some(p) = t.program() {
                    match matches(p) {
                        Ok(n) => item.matches = Some(n),
                        Err(e) => item.error = Some(e),
                    }
                }
            }
            Outcome::Failed => {}
            Outcome::Unreachable { error } => item.error = Some(error.clone()),
        }
        items.push(item);
    }
    EvalReport {
        max_rounds: synth.config().rounds.max(1),
        items,
    }
}
