//! Translating RefAV's scenario programs into Scenalog programs (`scenalog import refav IN -o
//! OUT`): a file or a directory in, one checked `.dl` out per program, the output folder held
//! while it is written; the report names, per program that did not import, the line and the
//! construct, and whether RefAV itself fails on it.

use std::path::PathBuf;

use crate::api::error::Error;
use crate::pipeline::lock::OutputLock;

pub use scenalog_import::{Defects, FileOutcome, ImportReport, Semantics};

/// Programs to translate.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportRequest {
    /// A RefAV program (`.py` or `.txt`), or a directory of them.
    pub input: PathBuf,
    /// Where to write the Scenalog programs (created if missing).
    pub out: PathBuf,
    /// Whose definitions the programs target where RefAV's and Scenalog's differ.
    pub semantics: Semantics,
}

/// Which of RefAV's defects `text` names: `all`, `none` or a comma-separated list (see
/// import/README.md, "RefAV's defects").
pub fn parse_defects(text: &str) -> Result<Defects, Error> {
    Defects::parse(text).map_err(Error::plain)
}

/// What an import wrote, and the output folder still held (one writer a folder) until this is
/// dropped.
pub struct Imported {
    /// Per program: its output or its errors.
    pub report: ImportReport,
    _held: OutputLock,
}

impl Imported {
    /// Whether some program failed on Scenalog's side (not counting those RefAV itself fails
    /// on): the command's exit 1.
    pub fn any_failed(&self) -> bool {
        self.report.failed_here() > 0
    }

    /// One JSON object per program: its source, output, whether RefAV itself is broken on it,
    /// which of RefAV's APIs it was written against, notes and errors (line, construct, message).
    pub fn json(&self) -> serde_json::Value {
        let rows: Vec<serde_json::Value> = self
            .report
            .files
            .iter()
            .map(|f| {
                serde_json::json!({
                    "source": f.source.display().to_string(),
                    "output": f.output.as_ref().map(|p| p.display().to_string()),
                    "refav_broken": f.refav_broken(),
                    "refav_api": if f.first_api { "first" } else { "current" },
                    "notes": f.notes,
                    "errors": f.errors.iter().map(|e| serde_json::json!({
                        "line": e.line, "construct": e.construct, "message": e.message,
                        "refav_broken": e.refav_broken,
                    })).collect::<Vec<_>>(),
                })
            })
            .collect();
        serde_json::Value::Array(rows)
    }

    /// The text `scenalog import` prints: a line per program error (`FILE:LINE: kind: construct:
    /// message`), then the summary; `out` names the folder.
    pub fn text(&self, out: &std::path::Path) -> String {
        let report = &self.report;
        let mut s = String::new();
        for f in &report.files {
            for e in &f.errors {
                let kind = if e.refav_broken {
                    "broken in RefAV"
                } else {
                    "not imported"
                };
                s.push_str(&format!(
                    "{}:{}: {kind}: {}: {}\n",
                    f.source.display(),
                    e.line,
                    e.construct,
                    e.message
                ));
            }
        }
        s.push_str(&format!(
            "{} programs: {} imported and checked clean into {} ({} written against RefAV's first \
             API), {} broken in RefAV itself, {} not imported\n",
            report.files.len(),
            report.imported(),
            out.display(),
            report.first_api(),
            report.refav_broken(),
            report.failed_here()
        ));
        s
    }
}

/// Translates the request's programs into its folder, held while it is written (a second
/// import into it is refused, naming the holder). An error means the input cannot be read or
/// the folder cannot be written (the command's exit 2); a program that does not translate is in
/// the report.
pub fn import(request: &ImportRequest) -> Result<Imported, Error> {
    let held = OutputLock::acquire(&request.out).map_err(Error::plain)?;
    let report = scenalog_import::import_path_with(&request.input, &request.out, request.semantics)
        .map_err(Error::plain)?;
    Ok(Imported {
        report,
        _held: held,
    })
}
