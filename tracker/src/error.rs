//! The crate's error: what was wrong, and where (file, log, frame, field).

/// A problem with tracker input, naming the file and, when known, the log, frame and field.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackerError {
    /// The file read.
    pub file: String,
    /// The log id.
    pub log: Option<String>,
    /// The frame's index in the log's list.
    pub frame: Option<usize>,
    /// The field.
    pub field: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl TrackerError {
    /// An error about the whole file.
    pub fn file(file: &str, message: impl Into<String>) -> TrackerError {
        TrackerError {
            file: file.to_string(),
            log: None,
            frame: None,
            field: None,
            message: message.into(),
        }
    }

    /// An error about one log.
    pub fn log(file: &str, log: &str, message: impl Into<String>) -> TrackerError {
        TrackerError {
            log: Some(log.to_string()),
            ..TrackerError::file(file, message)
        }
    }

    /// An error about one field of one frame of a log.
    pub fn field(
        file: &str,
        log: &str,
        frame: usize,
        field: &str,
        message: impl Into<String>,
    ) -> TrackerError {
        TrackerError {
            log: Some(log.to_string()),
            frame: Some(frame),
            field: Some(field.to_string()),
            ..TrackerError::file(file, message)
        }
    }
}

impl std::fmt::Display for TrackerError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(l) = &self.log {
            write!(f, ": log {l}")?;
        }
        if let Some(i) = self.frame {
            write!(f, ": frame {i}")?;
        }
        if let Some(x) = &self.field {
            write!(f, ": field {x:?}")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for TrackerError {}
