//! Checking a program (`scenalog check`, `scenalog.check`): its text, or a file's, checked
//! against the catalog; the diagnostics as `scenalog check --json` prints them.

use std::path::{Path, PathBuf};

use scenalog_rules::{diagnostics_json, render_human, CheckOptions, CheckOutcome};

use crate::api::error::{Error, ErrorKind};

/// Where a program comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ProgramSource {
    /// The program's text.
    Text(String),
    /// A file holding it (`-`: standard input).
    File(PathBuf),
}

/// A program to check.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CheckRequest {
    /// The program.
    pub source: ProgramSource,
    /// Require a `referred` rule (off for programs run with `scenalog run`).
    pub require_referred: bool,
}

/// A checked program: its text and the checker's outcome.
pub struct Checked {
    /// The text checked.
    pub text: String,
    /// The diagnostics, and the checked program when there is no error.
    pub outcome: CheckOutcome,
}

impl Checked {
    /// The diagnostics as the JSON array `scenalog check --json` prints for one file.
    pub fn diagnostics_json(&self) -> serde_json::Value {
        diagnostics_json(&self.outcome.diagnostics, &self.text)
    }

    /// The diagnostics for a person, each with the source lines it points at, the file called
    /// `display` (`color` for a terminal).
    pub fn diagnostics_text(&self, display: &str, color: bool) -> String {
        render_human(&self.outcome.diagnostics, &self.text, display, color)
    }

    /// Whether the program checks (no error; warnings allowed).
    pub fn is_clean(&self) -> bool {
        self.outcome.program.is_some()
    }

    /// The errors and the warnings, counted.
    pub fn counts(&self) -> (usize, usize) {
        let errors = self
            .outcome
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .count();
        (errors, self.outcome.diagnostics.len() - errors)
    }
}

/// Reads a program file through `scenalog-input`; a path where nothing is is an error of kind
/// [`ErrorKind::NotFound`].
pub fn read_program(path: &Path) -> Result<String, Error> {
    crate::input::read_text(path).map_err(|e| {
        let missing = path.as_os_str() != "-" && !path.exists();
        let kind = if missing {
            ErrorKind::NotFound
        } else {
            ErrorKind::Failed
        };
        Error::plain(e).of_kind(kind)
    })
}

/// Most rounds of [`fix`]: a fix may let the checker see what the next one fixes.
const FIX_ROUNDS: usize = 4;

/// A program with the checker's fixes applied.
pub struct Fixed {
    /// The program as it was read.
    pub original: String,
    /// How many diagnostics were fixed, in all rounds.
    pub applied: usize,
    /// The fixed program checked: its text and what is left to say about it.
    pub checked: Checked,
}

/// Checks the request's program and applies every machine-applicable fix (`check --fix`): the
/// units written where a bare number was read in one, Soufflé habits, the hints that carry a
/// fix; again on the result, until nothing is left to fix.
pub fn fix(request: &CheckRequest) -> Result<Fixed, Error> {
    let mut checked = check(request)?;
    let original = checked.text.clone();
    let mut applied = 0;
    for _ in 0..FIX_ROUNDS {
        let (text, n) = scenalog_rules::apply_fixes(&checked.text, &checked.outcome.diagnostics);
        if n == 0 || text == checked.text {
            break;
        }
        applied += n;
        checked = check(&CheckRequest {
            source: ProgramSource::Text(text),
            require_referred: request.require_referred,
        })?;
    }
    Ok(Fixed {
        original,
        applied,
        checked,
    })
}

/// Writes a fixed program over its file (a temporary file renamed over it); a link is refused,
/// not written through or replaced.
pub fn write_fixed(path: &Path, text: &str) -> Result<(), Error> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => {
            return Err(Error::plain(format!(
                "`{}` is a symbolic link: not rewritten; run `--fix` on the file it points to",
                path.display()
            )))
        }
        Ok(_) => {}
        Err(e) => {
            return Err(Error::plain(format!(
                "cannot write `{}`: {e}",
                path.display()
            )))
        }
    }
    scenalog_input::out_dir::write_atomic(path, text.as_bytes(), true)
        .map_err(|e| Error::plain(format!("cannot write `{}`: {e}", path.display())))
}

/// Checks the request's program; an error only when its file cannot be read.
pub fn check(request: &CheckRequest) -> Result<Checked, Error> {
    let text = match &request.source {
        ProgramSource::Text(t) => t.clone(),
        ProgramSource::File(p) => read_program(p)?,
    };
    let options = CheckOptions {
        require_referred: request.require_referred,
    };
    let outcome = scenalog_rules::check(&text, &options);
    Ok(Checked { text, outcome })
}
