//! The API's errors: a kind (for a caller that maps errors onto its own, Python's `ValueError`
//! and `FileNotFoundError`) and a [`Message`] naming the request's [`Field`]s, which each front
//! end renders with its own [`Names`]: the command's flags (`--max-tuples: …`) or the Python
//! package's keyword arguments (`max_tuples: …`). Nothing below the API words a message with a
//! front end's spelling, so there is nothing to translate back.

use std::fmt::Display;

pub use crate::message::{Field, Message, Names};

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

/// An error of the API: its kind, a message naming the request's fields, and a hint a front end
/// may add (what to set instead).
#[derive(Clone, Debug, PartialEq)]
pub struct Error {
    /// What went wrong.
    pub kind: ErrorKind,
    /// The message.
    pub message: Message,
    /// What the caller could do about it, naming a field (`scenalog eval` shows it on its own
    /// line: "add --only-predicted"); `None` when there is nothing to add.
    pub hint: Option<Message>,
}

impl Error {
    /// A message naming no field.
    pub fn plain(message: impl Display) -> Error {
        Error::from(Message::text(message))
    }

    /// `FIELD: message` (the command's `--gt: …`).
    pub fn about(field: Field, message: impl Display) -> Error {
        Error::from(Message::about(field, message))
    }

    /// `before FIELD after`, the field mentioned inside a sentence.
    pub fn mentioning(before: &str, field: Field, after: impl Display) -> Error {
        Error::from(Message::text(before).mention(field).then(after))
    }

    /// `FIELD: ` before this error (the command's `--programs: --rules: …`).
    pub fn within(self, field: Field) -> Error {
        Error {
            message: self.message.within(field),
            ..self
        }
    }

    /// The same error, of this kind.
    pub fn of_kind(self, kind: ErrorKind) -> Error {
        Error { kind, ..self }
    }

    /// The same error, with this hint.
    pub fn with_hint(self, hint: Message) -> Error {
        Error {
            hint: Some(hint),
            ..self
        }
    }

    /// The message with the command's flags.
    pub fn flags(&self) -> String {
        self.message.flags()
    }

    /// The message with the Python package's keyword arguments.
    pub fn keywords(&self) -> String {
        self.message.keywords()
    }

    /// The message with these names.
    pub fn render(&self, names: Names) -> String {
        self.message.render(names)
    }
}

impl From<Message> for Error {
    fn from(message: Message) -> Error {
        Error {
            kind: ErrorKind::Failed,
            message,
            hint: None,
        }
    }
}

impl From<String> for Error {
    fn from(message: String) -> Error {
        Error::plain(message)
    }
}

/// An out-of-range value of a field.
pub(crate) fn invalid(field: Field, message: impl Display) -> Error {
    Error::about(field, message).of_kind(ErrorKind::Invalid)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_error_names_flags_for_the_command_and_keywords_for_python() {
        let e = Error::about(Field::EvalTimestamps, "`t.json`: expected a JSON object");
        assert_eq!(
            e.flags(),
            "--eval-timestamps: `t.json`: expected a JSON object"
        );
        assert_eq!(
            e.keywords(),
            "eval_timestamps: `t.json`: expected a JSON object"
        );
        let e = Error::mentioning("no ", Field::Rules, " given");
        assert_eq!(e.flags(), "no --rules given");
        assert_eq!(e.keywords(), "no rules= given");
        assert_eq!(e.kind, ErrorKind::Failed);
        assert_eq!(invalid(Field::Threads, "x").kind, ErrorKind::Invalid);
    }
}
