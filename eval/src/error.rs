//! The error type of the crate.

/// Everything that can go wrong reading, writing or evaluating.
#[derive(Debug)]
pub enum EvalError {
    /// A file could not be read or written.
    Io(String, std::io::Error),
    /// An input path is not a readable regular file: missing, a directory, a FIFO, a symlink
    /// loop, permission denied (the problem says which).
    File(String, scenalog_input::FileProblem),
    /// The pickle stream is malformed or holds something unsupported.
    Pickle(String),
    /// The content has the wrong shape: the message names sequence, frame and field.
    Format(String),
}

impl std::fmt::Display for EvalError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EvalError::Io(p, e) => write!(f, "{p}: {e}"),
            EvalError::File(p, problem) => write!(f, "{p}: {problem}"),
            EvalError::Pickle(m) => write!(f, "pickle: {m}"),
            EvalError::Format(m) => write!(f, "{m}"),
        }
    }
}

impl std::error::Error for EvalError {}
