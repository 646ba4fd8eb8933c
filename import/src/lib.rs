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
    /// finds what RefAV's own code finds; elsewhere Scenalog's. The set says which of RefAV's
    /// defects are reproduced ([`Defects::ALL`] for RefAV's answers as its code gives them).
    Refav(Defects),
}

impl Semantics {
    /// The name the command line and the program header use: "scenalog" or "refav".
    pub fn as_str(self) -> &'static str {
        match self {
            Semantics::Scenalog => "scenalog",
            Semantics::Refav(_) => "refav",
        }
    }

    /// The defects reproduced: none in Scenalog's definitions.
    pub fn defects(self) -> Defects {
        match self {
            Semantics::Scenalog => Defects::NONE,
            Semantics::Refav(d) => d,
        }
    }

    /// RefAV's definitions reproduce `defect`.
    pub fn reproduces(self, defect: Defect) -> bool {
        self.defects().contains(defect)
    }
}

/// A defect of RefAV's code that `--semantics refav` reproduces or not, by its name (each is
/// described with a minimal example in import/README.md, "RefAV's defects").
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Defect {
    /// The ego's back edge has a sign slip (+1.02 m ahead of the rear axle where −1.02 m is
    /// meant), so "behind the ego" includes objects beside it.
    EgoBackEdge,
    /// `being_crossed_by` overwrites its `direction` argument after the first crossing it finds,
    /// so later candidates (in RefAV's candidate order) are tested against the forward plane.
    CrossingDirection,
    /// `reverse_relationship` (and `get_objects_in_relative_direction`) makes a track's earlier
    /// related objects that are among the candidates referred objects.
    ReverseCarryOver,
    /// `at_pedestrian_crossing` reassigns the list of crossings it loops over to those the
    /// object overlaps at the frame, so the next frame tests only those: an object off every
    /// crossing at one frame is never at one again.
    CrosswalkLoop,
    /// `turning` sums runs of same-sign raw yaw rate, so a one-frame heading spike (two rates of
    /// opposite sign beside it) splits a real turn into runs too short to count.
    TurningSpikes,
}

impl Defect {
    /// Every defect the option knows, in the order the README lists them.
    pub const ALL: [Defect; 5] = [
        Defect::EgoBackEdge,
        Defect::CrossingDirection,
        Defect::ReverseCarryOver,
        Defect::CrosswalkLoop,
        Defect::TurningSpikes,
    ];

    /// The name the command line (`--defects`) and the program header use.
    pub fn name(self) -> &'static str {
        match self {
            Defect::EgoBackEdge => "ego-back-edge",
            Defect::CrossingDirection => "crossing-direction",
            Defect::ReverseCarryOver => "reverse-carry-over",
            Defect::CrosswalkLoop => "crosswalk-loop",
            Defect::TurningSpikes => "turning-spikes",
        }
    }

    /// The defect named `name`, if there is one.
    pub fn from_name(name: &str) -> Option<Defect> {
        Defect::ALL.into_iter().find(|d| d.name() == name)
    }

    fn bit(self) -> u8 {
        1 << (self as u8)
    }
}

/// A set of [`Defect`]s.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Defects(u8);

impl Defects {
    /// No defect reproduced: RefAV's definitions as they are meant.
    pub const NONE: Defects = Defects(0);
    /// Every defect reproduced: RefAV's answers as its code gives them.
    pub const ALL: Defects = Defects((1 << Defect::ALL.len()) - 1);

    /// The set holds `defect`.
    pub fn contains(self, defect: Defect) -> bool {
        self.0 & defect.bit() != 0
    }

    /// The set with `defect` added.
    pub fn with(self, defect: Defect) -> Defects {
        Defects(self.0 | defect.bit())
    }

    /// The set's defects, in [`Defect::ALL`]'s order.
    pub fn iter(self) -> impl Iterator<Item = Defect> {
        Defect::ALL.into_iter().filter(move |d| self.contains(*d))
    }

    /// Reads `all`, `none` or a comma-separated list of defect names.
    ///
    /// # Errors
    /// A name that is not a defect's, listing the names there are.
    pub fn parse(text: &str) -> Result<Defects, String> {
        match text.trim() {
            "all" => return Ok(Defects::ALL),
            "none" | "" => return Ok(Defects::NONE),
            _ => {}
        }
        let mut set = Defects::NONE;
        for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            match Defect::from_name(part) {
                Some(d) => set = set.with(d),
                None => {
                    let names: Vec<&str> = Defect::ALL.iter().map(|d| d.name()).collect();
                    return Err(format!(
                        "unknown RefAV defect `{part}`: expected `all`, `none` or a comma-separated list of {}",
                        names.join(", ")
                    ));
                }
            }
        }
        Ok(set)
    }
}

impl std::fmt::Display for Defects {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names: Vec<&str> = self.iter().map(Defect::name).collect();
        if names.is_empty() {
            f.write_str("none")
        } else {
            f.write_str(&names.join(","))
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
    let mut imported = translate_with(source, path, semantics)?;
    let mut outcome =
        scenalog_rules::check(&imported.program, &scenalog_rules::CheckOptions::default());
    // Every threshold carries its unit: the checker reads each bare number in its column's
    // unit, and its fix writes that unit, so the meaning is the translation's.
    if outcome.program.is_some() {
        let units: Vec<scenalog_rules::Diagnostic> = outcome
            .diagnostics
            .iter()
            .filter(|d| d.code == scenalog_rules::diagnostics::BARE_NUMBER)
            .cloned()
            .collect();
        let (with_units, n) = scenalog_rules::apply_fixes(&imported.program, &units);
        if n > 0 {
            let again =
                scenalog_rules::check(&with_units, &scenalog_rules::CheckOptions::default());
            if again.program.is_some() {
                imported.program = with_units;
                outcome = again;
            }
        }
    }
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
