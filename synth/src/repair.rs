//! The repair loop: ask for a program, check it, send the diagnostics back, and ask again, up to
//! the configured number of rounds; every round is recorded in a [`Transcript`].

use scenalog_rules::diagnostics::MEANING_WARNINGS;
use scenalog_rules::{check, CheckOptions};

use crate::client::Message;
use crate::diagnostics;
use crate::extract::{extract, one_line, with_description, Extracted};
pub use crate::transcript::{Outcome, Round, RoundResult, Transcript};
use crate::usage::Usage;
use crate::Synthesizer;

/// What the model is told when its answer held no program.
pub const NO_CODE_FEEDBACK: &str = "Your answer contained no program: no fenced code block and no clause (`head :- body.`). Reply with the complete Scenalog program for the description in one fenced code block (```scenalog ... ```), and nothing else.";

/// The feedback for a program with errors: the diagnostics as JSON and the offending lines.
pub fn error_feedback(program: &str, diags: &[scenalog_rules::Diagnostic]) -> String {
    let n = diagnostics::error_count(diags);
    // One diagnostic a line: compact for the model, still easy to read.
    let items: Vec<String> = match diagnostics::to_json(diags, program) {
        serde_json::Value::Array(a) => a.iter().map(|d| d.to_string()).collect(),
        other => vec![other.to_string()],
    };
    let json = format!("[\n{}\n]", items.join(",\n"));
    format!(
        "The checker rejected the program with {n} error{}. Its diagnostics as JSON (lines and columns count from 1 at the `// description:` line):\n\n```json\n{json}\n```\n\nThe offending lines:\n\n```\n{}```\n\nFix every error and reply with the complete corrected program in one fenced code block (```scenalog ... ```).",
        if n == 1 { "" } else { "s" },
        diagnostics::render(diags, program),
    )
}

/// The feedback for a program that checks but has warnings that usually change its meaning.
pub fn warning_feedback(program: &str, diags: &[scenalog_rules::Diagnostic]) -> String {
    let meaning: Vec<scenalog_rules::Diagnostic> = diags
        .iter()
        .filter(|d| MEANING_WARNINGS.contains(&d.code))
        .cloned()
        .collect();
    let items: Vec<String> = match diagnostics::to_json(&meaning, program) {
        serde_json::Value::Array(a) => a.iter().map(|d| d.to_string()).collect(),
        other => vec![other.to_string()],
    };
    format!(
        "The program checks, but the checker warns about {} place{} where it probably does not say what the description means. Its warnings as JSON (lines and columns count from 1 at the `// description:` line):\n\n```json\n[\n{}\n]\n```\n\nThe lines:\n\n```\n{}```\n\nFix each one, or keep it and say why in a `//` comment, and reply with the complete program in one fenced code block (```scenalog ... ```).",
        meaning.len(),
        if meaning.len() == 1 { "" } else { "s" },
        items.join(",\n"),
        diagnostics::render(&meaning, program),
    )
}

/// Runs the loop for one description with `synth`'s client, cache and configuration.
pub fn run(synth: &Synthesizer, description: &str) -> Transcript {
    run_sample(synth, description, 0)
}

/// [`run`] for candidate `sample` of a search (0: the same as [`run`]; others sampled, see
/// [`Synthesizer::complete_sample`]).
pub fn run_sample(synth: &Synthesizer, description: &str, sample: usize) -> Transcript {
    let description = one_line(description);
    let messages = synth.prompt(&description);
    converse(synth, &description, messages, sample, None)
}

/// The loop from `messages` on (the conversation so far, ending with the user's request): up
/// to the configured rounds of completions, each checked and repaired. `first`, when given, is
/// the answer to `messages` already received (the completion, whether cached, its tokens),
/// used as round 1 instead of asking again.
pub fn converse(
    synth: &Synthesizer,
    description: &str,
    mut messages: Vec<Message>,
    sample: usize,
    mut first: Option<(String, bool, Usage)>,
) -> Transcript {
    let description = description.to_string();
    let config = synth.config();
    let mut transcript = Transcript {
        description: description.clone(),
        model: config.llm.model.clone(),
        rounds: Vec::new(),
        outcome: Outcome::Failed,
        search: None,
        evidence: Vec::new(),
    };
    let rounds = config.rounds.max(1);
    // Meaning-changing warnings are sent back once; a program that keeps them is then clean.
    let mut warned = false;
    for round in 1..=rounds {
        let answer = match first.take() {
            Some(answer) => Ok(answer),
            None => synth.complete_sample(&messages, sample),
        };
        let (completion, cached, usage) = match answer {
            Ok(c) => c,
            Err(e) => {
                let error = e.to_string();
                transcript.outcome = match e {
                    crate::ClientError::Budget { .. } => Outcome::OverBudget { error },
                    _ => Outcome::Unreachable { error },
                };
                return transcript;
            }
        };
        let mut r = Round {
            round,
            cached,
            usage,
            completion: completion.clone(),
            program: None,
            diagnostics: serde_json::json!([]),
            errors: 0,
            result: RoundResult::NoCode,
            feedback: None,
        };
        let feedback = match extract(&completion) {
            Extracted::NoCode => NO_CODE_FEEDBACK.to_string(),
            Extracted::Program(code) => {
                let program = with_description(&code, &description);
                let outcome = check(
                    &program,
                    &CheckOptions {
                        require_referred: true,
                    },
                );
                r.diagnostics = diagnostics::to_json(&outcome.diagnostics, &program);
                r.errors = diagnostics::error_count(&outcome.diagnostics);
                let feedback = error_feedback(&program, &outcome.diagnostics);
                let warns = outcome
                    .diagnostics
                    .iter()
                    .any(|d| MEANING_WARNINGS.contains(&d.code));
                if outcome.program.is_some() && warns && !warned && round < rounds {
                    warned = true;
                    r.result = RoundResult::Warnings;
                    let feedback = warning_feedback(&program, &outcome.diagnostics);
                    r.program = Some(program);
                    r.feedback = Some(feedback.clone());
                    messages.push(Message::assistant(completion));
                    messages.push(Message::user(feedback));
                    transcript.rounds.push(r);
                    continue;
                }
                r.program = Some(program);
                if outcome.program.is_some() {
                    r.result = RoundResult::Clean;
                    transcript.rounds.push(r);
                    transcript.outcome = Outcome::Clean { round };
                    return transcript;
                }
                r.result = RoundResult::Errors;
                feedback
            }
        };
        if round < rounds {
            r.feedback = Some(feedback.clone());
            messages.push(Message::assistant(completion));
            messages.push(Message::user(feedback));
        }
        transcript.rounds.push(r);
    }
    transcript
}
