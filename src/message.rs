//! Messages that name the fields of a request: [`Field`] (one per field of the API's requests),
//! [`Message`] (text with fields in it) and [`Names`] (how a front end spells a field: the
//! command's flag `--max-tuples`, the Python package's keyword `max_tuples`).
//!
//! Everything below the front ends words its messages with fields, never with a front end's
//! spelling: the pipeline's failures ("… or raise " and [`Field::MaxTuples`]) and the API's
//! errors (`crate::api::Error`, a kind and a message) are [`Message`]s, and each front end
//! renders them with its own [`Names`] (`scenalog mine` with [`Names::Flags`],
//! `scenalog.mine` with [`Names::Keywords`]). Files a run writes (`summary.json`) are the
//! command's and name its flags.

use std::fmt::Display;

/// A field of a request, as a message names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    /// The rule programs (`--rules`, `rules`).
    Rules,
    /// The logs (`--logs`, `logs`).
    Logs,
    /// The ground truth (`--gt`, `gt`).
    Gt,
    /// The output timestamps (`--eval-timestamps`, `eval_timestamps`).
    EvalTimestamps,
    /// The worker threads (`--threads`, `threads`).
    Threads,
    /// The tuple budget of one pair or evaluation (`--max-tuples`, `max_tuples`).
    MaxTuples,
    /// The time limit of one pair or evaluation (`--timeout-ms`, `timeout_ms`).
    TimeoutMs,
    /// The descriptions to synthesize (`--descriptions`).
    Descriptions,
    /// A split's (log, prompt) pairs (`--log-prompts`, `log_prompts`).
    LogPrompts,
    /// The AV2 split directory (`--dataset-dir`, `dataset_dir`).
    DatasetDir,
    /// A tracker's output (`--tracks`, `tracks`).
    Tracks,
    /// Programs for a split's prompts (`--programs`, `programs`).
    Programs,
    /// The range filter of the evaluation (`--max-range-m`, `max_range_m`).
    MaxRangeM,
    /// The time explained (`--at`, `at`).
    At,
    /// The evaluation's rate (`--rate`, `rate`).
    Rate,
    /// The evaluation's timestamps (`--timestamps`, `timestamps`).
    Timestamps,
    /// Score only the sequences the predictions hold (`--only-predicted`, `only_predicted`).
    OnlyPredicted,
    /// The picture of an explanation (`--picture`, `picture`).
    Picture,
    /// The picture's size in pixels (`--picture-size`, `picture_size`).
    PictureSize,
    /// The frames a picture shows (`--frames`, `frames`).
    Frames,
    /// The Rerun recording of an explanation (`--rerun`, `rerun`).
    Rerun,
    /// Candidate programs per description (`--candidates`, `candidates`).
    Candidates,
    /// Evidence rounds after a synthesis search (`--evidence-rounds`, `evidence_rounds`).
    EvidenceRounds,
    /// The server whose grammar field synthesis fills (`--grammar`, `grammar`).
    Grammar,
}

impl Field {
    /// The command's flag.
    pub fn flag(self) -> &'static str {
        match self {
            Field::Rules => "--rules",
            Field::Logs => "--logs",
            Field::Gt => "--gt",
            Field::EvalTimestamps => "--eval-timestamps",
            Field::Threads => "--threads",
            Field::MaxTuples => "--max-tuples",
            Field::TimeoutMs => "--timeout-ms",
            Field::Descriptions => "--descriptions",
            Field::LogPrompts => "--log-prompts",
            Field::DatasetDir => "--dataset-dir",
            Field::Tracks => "--tracks",
            Field::Programs => "--programs",
            Field::MaxRangeM => "--max-range-m",
            Field::At => "--at",
            Field::Rate => "--rate",
            Field::Timestamps => "--timestamps",
            Field::OnlyPredicted => "--only-predicted",
            Field::Picture => "--picture",
            Field::PictureSize => "--picture-size",
            Field::Rerun => "--rerun",
            Field::Frames => "--frames",
            Field::Candidates => "--candidates",
            Field::EvidenceRounds => "--evidence-rounds",
            Field::Grammar => "--grammar",
        }
    }

    /// The Python package's keyword argument (without the `=`).
    pub fn keyword(self) -> &'static str {
        match self {
            Field::Rules => "rules",
            Field::Logs => "logs",
            Field::Gt => "gt",
            Field::EvalTimestamps => "eval_timestamps",
            Field::Threads => "threads",
            Field::MaxTuples => "max_tuples",
            Field::TimeoutMs => "timeout_ms",
            Field::Descriptions => "descriptions",
            Field::LogPrompts => "log_prompts",
            Field::DatasetDir => "dataset_dir",
            Field::Tracks => "tracks",
            Field::Programs => "programs",
            Field::MaxRangeM => "max_range_m",
            Field::At => "at",
            Field::Rate => "rate",
            Field::Timestamps => "timestamps",
            Field::OnlyPredicted => "only_predicted",
            Field::Picture => "picture",
            Field::PictureSize => "picture_size",
            Field::Rerun => "rerun",
            Field::Frames => "frames",
            Field::Candidates => "candidates",
            Field::EvidenceRounds => "evidence_rounds",
            Field::Grammar => "grammar",
        }
    }
}

/// How a front end spells the fields in the messages it shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Names {
    /// The command's flags: `--max-tuples: …`, "raise --max-tuples".
    Flags,
    /// The Python package's keywords: `max_tuples: …`, "raise max_tuples=".
    Keywords,
}

impl Names {
    /// `field` as a message's subject (before a colon): `--max-tuples` or `max_tuples`.
    pub fn subject(self, field: Field) -> &'static str {
        match self {
            Names::Flags => field.flag(),
            Names::Keywords => field.keyword(),
        }
    }

    /// `field` mentioned inside a sentence: `--max-tuples` or `max_tuples=`.
    pub fn mention(self, field: Field) -> String {
        match self {
            Names::Flags => field.flag().to_string(),
            Names::Keywords => format!("{}=", field.keyword()),
        }
    }
}

/// One piece of a message: text, or a field named as the caller names it.
#[derive(Clone, Debug, PartialEq)]
enum Piece {
    Text(String),
    Subject(Field),
    Mention(Field),
}

/// A message whose fields are named when it is rendered ([`Message::render`]), so the command
/// shows its flags and the Python package its keywords. Built from text and fields:
/// `Message::about(Field::Gt, "cannot read …")` renders `--gt: cannot read …` or
/// `gt: cannot read …`; `Message::text("… or raise ").mention(Field::MaxTuples)` renders
/// `… or raise --max-tuples` or `… or raise max_tuples=`.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Message {
    pieces: Vec<Piece>,
}

impl Message {
    /// A message naming no field.
    pub fn text(text: impl Display) -> Message {
        Message {
            pieces: vec![Piece::Text(text.to_string())],
        }
    }

    /// `FIELD: message` (the command's `--gt: …`).
    pub fn about(field: Field, message: impl Display) -> Message {
        Message {
            pieces: vec![Piece::Subject(field), Piece::Text(format!(": {message}"))],
        }
    }

    /// This message followed by `text`.
    pub fn then(mut self, text: impl Display) -> Message {
        self.pieces.push(Piece::Text(text.to_string()));
        self
    }

    /// This message followed by `field`, mentioned inside a sentence (`--max-tuples`,
    /// `max_tuples=`).
    pub fn mention(mut self, field: Field) -> Message {
        self.pieces.push(Piece::Mention(field));
        self
    }

    /// This message followed by `other`.
    pub fn append(mut self, other: &Message) -> Message {
        self.pieces.extend(other.pieces.iter().cloned());
        self
    }

    /// `FIELD: ` before this message (the command's `--programs: --rules: …`).
    pub fn within(self, field: Field) -> Message {
        let mut pieces = vec![Piece::Subject(field), Piece::Text(": ".to_string())];
        pieces.extend(self.pieces);
        Message { pieces }
    }

    /// `text` before this message (`program `p` failed on log L: ` before the engine's error).
    pub fn after(self, text: impl Display) -> Message {
        let mut pieces = vec![Piece::Text(text.to_string())];
        pieces.extend(self.pieces);
        Message { pieces }
    }

    /// The fields the message names, in order.
    pub fn fields(&self) -> Vec<Field> {
        self.pieces
            .iter()
            .filter_map(|p| match p {
                Piece::Subject(f) | Piece::Mention(f) => Some(*f),
                Piece::Text(_) => None,
            })
            .collect()
    }

    /// The message with these names.
    pub fn render(&self, names: Names) -> String {
        let mut out = String::new();
        for p in &self.pieces {
            match p {
                Piece::Text(t) => out.push_str(t),
                Piece::Subject(f) => out.push_str(names.subject(*f)),
                Piece::Mention(f) => out.push_str(&names.mention(*f)),
            }
        }
        out
    }

    /// The message with the command's flags.
    pub fn flags(&self) -> String {
        self.render(Names::Flags)
    }

    /// The message with the Python package's keyword arguments.
    pub fn keywords(&self) -> String {
        self.render(Names::Keywords)
    }
}

impl From<String> for Message {
    fn from(text: String) -> Message {
        Message::text(text)
    }
}

impl From<&str> for Message {
    fn from(text: &str) -> Message {
        Message::text(text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_message_names_flags_for_the_command_and_keywords_for_python() {
        let m = Message::about(Field::EvalTimestamps, "`t.json`: expected a JSON object");
        assert_eq!(
            m.flags(),
            "--eval-timestamps: `t.json`: expected a JSON object"
        );
        assert_eq!(
            m.keywords(),
            "eval_timestamps: `t.json`: expected a JSON object"
        );
        let m = Message::text("relation `near` would hold more than 9 tuples; raise ")
            .mention(Field::MaxTuples)
            .after("program `p` failed on log L: ");
        assert_eq!(
            m.flags(),
            "program `p` failed on log L: relation `near` would hold more than 9 tuples; raise \
             --max-tuples"
        );
        assert_eq!(
            m.keywords(),
            "program `p` failed on log L: relation `near` would hold more than 9 tuples; raise \
             max_tuples="
        );
        assert_eq!(m.fields(), vec![Field::MaxTuples]);
        let m = Message::about(Field::Rules, "no .dl file").within(Field::Programs);
        assert_eq!(m.flags(), "--programs: --rules: no .dl file");
        assert_eq!(m.keywords(), "programs: rules: no .dl file");
        // Text is never reworded: a flag written into text stays as written.
        assert_eq!(Message::text("--logs-dir x").keywords(), "--logs-dir x");
    }
}
