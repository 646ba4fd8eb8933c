//! The API's errors: a message that names the request's fields, rendered either with the
//! command's flags (`--max-tuples`) or with the Python package's keyword arguments
//! (`max_tuples=`), so each caller's user reads the names they typed.

use std::fmt::Display;

/// A field of a request, as an error message names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arg {
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
    /// One pair's tuple budget (`--max-tuples`, `max_tuples`).
    MaxTuples,
    /// One pair's time limit (`--timeout-ms`, `timeout_ms`).
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
}

impl Arg {
    /// The command's flag.
    pub fn flag(self) -> &'static str {
        match self {
            Arg::Rules => "--rules",
            Arg::Logs => "--logs",
            Arg::Gt => "--gt",
            Arg::EvalTimestamps => "--eval-timestamps",
            Arg::Threads => "--threads",
            Arg::MaxTuples => "--max-tuples",
            Arg::TimeoutMs => "--timeout-ms",
            Arg::Descriptions => "--descriptions",
            Arg::LogPrompts => "--log-prompts",
            Arg::DatasetDir => "--dataset-dir",
            Arg::Tracks => "--tracks",
            Arg::Programs => "--programs",
            Arg::MaxRangeM => "--max-range-m",
            Arg::At => "--at",
            Arg::Rate => "--rate",
            Arg::Timestamps => "--timestamps",
        }
    }

    /// The Python package's keyword argument (without the `=`).
    pub fn keyword(self) -> &'static str {
        match self {
            Arg::Rules => "rules",
            Arg::Logs => "logs",
            Arg::Gt => "gt",
            Arg::EvalTimestamps => "eval_timestamps",
            Arg::Threads => "threads",
            Arg::MaxTuples => "max_tuples",
            Arg::TimeoutMs => "timeout_ms",
            Arg::Descriptions => "descriptions",
            Arg::LogPrompts => "log_prompts",
            Arg::DatasetDir => "dataset_dir",
            Arg::Tracks => "tracks",
            Arg::Programs => "programs",
            Arg::MaxRangeM => "max_range_m",
            Arg::At => "at",
            Arg::Rate => "rate",
            Arg::Timestamps => "timestamps",
        }
    }

    /// Every field, for rewording messages of the layers below the API.
    const ALL: [Arg; 16] = [
        Arg::Rules,
        Arg::Logs,
        Arg::Gt,
        Arg::EvalTimestamps,
        Arg::Threads,
        Arg::MaxTuples,
        Arg::TimeoutMs,
        Arg::Descriptions,
        Arg::LogPrompts,
        Arg::DatasetDir,
        Arg::Tracks,
        Arg::Programs,
        Arg::MaxRangeM,
        Arg::At,
        Arg::Rate,
        Arg::Timestamps,
    ];
}

/// Whose names an error is rendered with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Names {
    /// The command's flags: `--max-tuples: …`, "raise --max-tuples".
    Flags,
    /// The Python package's keywords: `max_tuples: …`, "raise max_tuples=".
    Keywords,
}

impl Names {
    /// `arg` as a message's subject (before a colon): `--max-tuples` or `max_tuples`.
    fn subject(self, arg: Arg) -> &'static str {
        match self {
            Names::Flags => arg.flag(),
            Names::Keywords => arg.keyword(),
        }
    }

    /// `arg` mentioned inside a sentence: `--max-tuples` or `max_tuples=`.
    fn mention(self, arg: Arg) -> String {
        match self {
            Names::Flags => arg.flag().to_string(),
            Names::Keywords => format!("{}=", arg.keyword()),
        }
    }

    /// A message of a layer below the API (a pair's failure, the extractor's "raise
    /// --max-tuples"), its flags named as these names mention them. Only whole flags are
    /// replaced: `--max-tuples` followed by a letter, a digit or `-` is left alone.
    pub fn reword(self, message: &str) -> String {
        if self == Names::Flags {
            return message.to_string();
        }
        let mut out = message.to_string();
        for arg in Arg::ALL {
            out = replace_word(&out, arg.flag(), &self.mention(arg));
        }
        out
    }
}

/// `text` with every `word` not followed by a word character or `-` replaced by `with`.
fn replace_word(text: &str, word: &str, with: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find(word) {
        let after = &rest[at + word.len()..];
        let whole = !after
            .chars()
            .next()
            .is_some_and(|c| c.is_alphanumeric() || c == '-' || c == '_');
        out.push_str(&rest[..at]);
        out.push_str(if whole { with } else { word });
        rest = after;
    }
    out.push_str(rest);
    out
}

/// What went wrong, for a caller that maps errors onto its own kinds (Python's `ValueError`,
/// `FileNotFoundError`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// A field's value is out of its range (the command's parser refuses it before the API).
    Invalid,
    /// A file the request names does not exist.
    NotFound,
    /// Anything else: an unreadable or malformed input, a failed run.
    Failed,
}

/// One piece of a message: text, or a field named as the caller names it.
#[derive(Clone, Debug, PartialEq)]
enum Piece {
    Text(String),
    Subject(Arg),
    Mention(Arg),
}

/// An error of the API: its kind and a message naming the request's fields.
#[derive(Clone, Debug, PartialEq)]
pub struct Error {
    /// What went wrong.
    pub kind: ErrorKind,
    pieces: Vec<Piece>,
}

impl Error {
    /// A message naming no field (text from below the API is reworded when rendered).
    pub fn plain(message: impl Display) -> Error {
        Error {
            kind: ErrorKind::Failed,
            pieces: vec![Piece::Text(message.to_string())],
        }
    }

    /// `ARG: message` (the command's `--gt: …`).
    pub fn about(arg: Arg, message: impl Display) -> Error {
        Error {
            kind: ErrorKind::Failed,
            pieces: vec![Piece::Subject(arg), Piece::Text(format!(": {message}"))],
        }
    }

    /// `before ARG after`, the field mentioned inside a sentence.
    pub fn mentioning(before: &str, arg: Arg, after: impl Display) -> Error {
        Error {
            kind: ErrorKind::Failed,
            pieces: vec![
                Piece::Text(before.to_string()),
                Piece::Mention(arg),
                Piece::Text(after.to_string()),
            ],
        }
    }

    /// `ARG: ` before this error (the command's `--programs: --rules: …`).
    pub fn within(self, arg: Arg) -> Error {
        let mut pieces = vec![Piece::Subject(arg), Piece::Text(": ".to_string())];
        pieces.extend(self.pieces);
        Error { pieces, ..self }
    }

    /// The same error, of this kind.
    pub fn of_kind(self, kind: ErrorKind) -> Error {
        Error { kind, ..self }
    }

    /// The message with the command's flags.
    pub fn flags(&self) -> String {
        self.render(Names::Flags)
    }

    /// The message with the Python package's keyword arguments.
    pub fn keywords(&self) -> String {
        self.render(Names::Keywords)
    }

    /// The message with these names.
    pub fn render(&self, names: Names) -> String {
        let mut out = String::new();
        for p in &self.pieces {
            match p {
                Piece::Text(t) => out.push_str(&names.reword(t)),
                Piece::Subject(a) => out.push_str(names.subject(*a)),
                Piece::Mention(a) => out.push_str(&names.mention(*a)),
            }
        }
        out
    }
}

impl From<String> for Error {
    fn from(message: String) -> Error {
        Error::plain(message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_error_names_flags_for_the_command_and_keywords_for_python() {
        let e = Error::about(Arg::EvalTimestamps, "`t.json`: expected a JSON object");
        assert_eq!(
            e.flags(),
            "--eval-timestamps: `t.json`: expected a JSON object"
        );
        assert_eq!(
            e.keywords(),
            "eval_timestamps: `t.json`: expected a JSON object"
        );
        let e = Error::mentioning("no ", Arg::Rules, " given");
        assert_eq!(e.flags(), "no --rules given");
        assert_eq!(e.keywords(), "no rules= given");
    }

    #[test]
    fn messages_from_below_are_reworded_whole_flags_only() {
        let m = "relation `near` would hold more than 9 tuples; raise --max-tuples";
        assert_eq!(
            Names::Keywords.reword(m),
            "relation `near` would hold more than 9 tuples; raise max_tuples="
        );
        assert_eq!(Names::Flags.reword(m), m);
        // A longer flag that starts like one of ours is not ours.
        assert_eq!(Names::Keywords.reword("--logs-dir x"), "--logs-dir x");
        assert_eq!(Names::Keywords.reword("(--logs)"), "(logs=)");
    }
}
