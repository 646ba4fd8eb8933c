//! Imports RefAV scenario programs into Scenalog.
//!
//! RefAV programs are Python that compose RefAV's atomic functions
//! (`get_objects_of_category`, `has_objects_in_relative_direction`, `scenario_and`,
//! `scenario_not(f)(…)`, `reverse_relationship(f)(…)`, `output_scenario`, …). [`translate`] parses
//! one with a real Python parser (`rustpython-parser`) and turns each assignment into a helper
//! relation over `(track, frame)` (and `(track, related, frame)` when the value can have related
//! objects), keeping RefAV's meaning where Scenalog's relations differ; [`import_checked`] also
//! runs the result through the rule checker, so a program that comes out is one `scenalog mine`
//! runs. [`import_path`] does that for a file or every program in a directory and writes the
//! results. A construct the importer cannot translate, or that RefAV itself rejects, is an
//! [`ImportError`] naming the line and the construct, never a silently different program.
//!
//! Owns: the RefAV function table ([`signatures`]), the translation ([`translate`]) and the
//! batch import ([`batch`]). Does not own: the rule language (scenalog-rules) or the command line
//! (the root package's `src/cli/import.rs`).

#![warn(missing_docs)]

pub mod batch;
pub mod nesting;
pub mod signatures;
mod translate;

pub use batch::{import_path, import_path_with, FileOutcome, ImportReport};

/// Which definitions an imported program targets where RefAV's and Scenalog's differ (see
/// import/README.md, "RefAV semantics").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Semantics {
    /// Scenalog's definitions (the catalog's relations): the default.
    #[default]
    Scenalog,
    /// RefAV's definitions where the catalog has them (the `refav_*` relations), so the program
    /// finds what RefAV's own code finds; elsewhere Scenalog's.
    Refav,
}

impl Semantics {
    /// The name the command line and the program header use: "scenalog" or "refav".
    pub fn as_str(self) -> &'static str {
        match self {
            Semantics::Scenalog => "scenalog",
            Semantics::Refav => "refav",
        }
    }
}

/// A translated program.
#[derive(Debug, Clone, PartialEq)]
pub struct Imported {
    /// The description given to `output_scenario`, if it was a string.
    pub description: Option<String>,
    /// The Scenalog program text.
    pub program: String,
    /// Deliberate differences from RefAV this program hits (also written into the program as
    /// `// note:` comments).
    pub notes: Vec<String>,
    /// The program is written against RefAV's first API (`accelerating(..., thresh=...)`) and
    /// was imported under that API's meaning (the program's header says which API it used).
    pub first_api: bool,
}

/// Why a program was not imported.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ImportError {
    /// 1-based line in the RefAV program (0 for the emitted program as a whole).
    pub line: usize,
    /// The construct at fault (a function name, "for loop", "Python syntax", …).
    pub construct: String,
    /// What is wrong.
    pub message: String,
    /// RefAV itself fails on this program (an unknown function, a wrong keyword, a syntax
    /// error): there is no meaning to keep.
    pub refav_broken: bool,
}

impl std::fmt::Display for ImportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "line {}: {}: {}",
            self.line, self.construct, self.message
        )
    }
}

/// Translates one RefAV program (`path` is only used in messages and the program's header).
///
/// # Errors
/// Every statement that cannot be translated, each naming its line and construct.
pub fn translate(source: &str, path: &str) -> Result<Imported, Vec<ImportError>> {
    translate::translate(source, path, Semantics::Scenalog)
}

/// [`translate`] targeting the given definitions.
///
/// # Errors
/// As [`translate`].
pub fn translate_with(
    source: &str,
    path: &str,
    semantics: Semantics,
) -> Result<Imported, Vec<ImportError>> {
    translate::translate(source, path, semantics)
}

/// [`translate`], then checks the emitted program with the rule checker; a checker error
/// (e.g. an unknown category string) is reported as an [`ImportError`] on the RefAV line the
/// failing clause came from.
///
/// # Errors
/// As [`translate`], plus the checker's errors.
pub fn import_checked(source: &str, path: &str) -> Result<Imported, Vec<ImportError>> {
    import_checked_with(source, path, Semantics::Scenalog)
}

/// [`import_checked`] targeting the given definitions.
///
/// # Errors
/// As [`import_checked`].
pub fn import_checked_with(
    source: &str,
    path: &str,
    semantics: Semantics,
) -> Result<Imported, Vec<ImportError>> {
    let imported = translate_with(source, path, semantics)?;
    let outcome =
        scenalog_rules::check(&imported.program, &scenalog_rules::CheckOptions::default());
    let errors: Vec<ImportError> = outcome
        .diagnostics
        .iter()
        .filter(|d| d.severity == scenalog_rules::Severity::Error)
        .map(|d| {
            let start = d.span.start.min(imported.program.len());
            let line = refav_line_before(imported.program.get(..start).unwrap_or(""));
            ImportError {
                line,
                construct: format!("emitted rule ({})", d.code),
                message: format!(
                    "the translation does not check: {}: `{}`",
                    d.message,
                    clause_at(&imported.program, start)
                ),
                refav_broken: false,
            }
        })
        .collect();
    if errors.is_empty() && outcome.program.is_some() {
        Ok(imported)
    } else if errors.is_empty() {
        Err(vec![ImportError {
            line: 0,
            construct: "emitted program".into(),
            message: "the rule checker gave no program and no error".into(),
            refav_broken: false,
        }])
    } else {
        Err(errors)
    }
}

/// The RefAV line named by the last `// line N:` comment before a point of the emitted program.
fn refav_line_before(prefix: &str) -> usize {
    prefix
        .rfind("// line ")
        .and_then(|i| {
            let rest = &prefix[i + 8..];
            rest.split(|c: char| !c.is_ascii_digit())
                .next()?
                .parse()
                .ok()
        })
        .unwrap_or(0)
}

fn clause_at(text: &str, at: usize) -> String {
    let (Some(before), Some(after)) = (text.get(..at), text.get(at..)) else {
        return String::new();
    };
    let start = before.rfind('\n').map_or(0, |i| i + 1);
    let end = after.find('\n').map_or(text.len(), |i| at + i);
    text.get(start..end).unwrap_or("").trim().to_string()
}
