//! Importing a file or a directory of RefAV programs and writing the Scenalog programs.

use std::path::{Path, PathBuf};

use crate::{import_checked_with, ImportError, Semantics};

/// What became of one RefAV program.
#[derive(Debug, Clone)]
pub struct FileOutcome {
    /// The RefAV program.
    pub source: PathBuf,
    /// The Scenalog program written, when it imported and checked clean.
    pub output: Option<PathBuf>,
    /// The deliberate differences it hits (empty on failure).
    pub notes: Vec<String>,
    /// Why it was not imported (empty on success).
    pub errors: Vec<ImportError>,
    /// It imported as a program written against RefAV's first API
    /// (`accelerating(..., thresh=...)`).
    pub first_api: bool,
}

impl FileOutcome {
    /// Every error is one RefAV itself raises on the program.
    pub fn refav_broken(&self) -> bool {
        !self.errors.is_empty() && self.errors.iter().all(|e| e.refav_broken)
    }
}

/// The outcome of [`import_path`], one entry per program in file-name order.
#[derive(Debug, Clone, Default)]
pub struct ImportReport {
    /// Per program.
    pub files: Vec<FileOutcome>,
}

impl ImportReport {
    /// Programs that imported and checked clean.
    pub fn imported(&self) -> usize {
        self.files.iter().filter(|f| f.output.is_some()).count()
    }
    /// Programs that failed because RefAV itself fails on them.
    pub fn refav_broken(&self) -> usize {
        self.files.iter().filter(|f| f.refav_broken()).count()
    }
    /// Imported programs written against RefAV's first API.
    pub fn first_api(&self) -> usize {
        self.files.iter().filter(|f| f.first_api).count()
    }
    /// Programs that failed for a reason on Scenalog's side.
    pub fn failed_here(&self) -> usize {
        self.files.len() - self.imported() - self.refav_broken()
    }
}

/// The RefAV programs a path names: the file itself, or every `*.py` / `*.txt` file directly in
/// the directory (not `README*`), sorted by name.
///
/// # Errors
/// The path or directory cannot be read.
pub fn programs_in(input: &Path) -> Result<Vec<PathBuf>, String> {
    let meta =
        std::fs::metadata(input).map_err(|e| format!("{}: cannot read: {e}", input.display()))?;
    if meta.is_file() {
        return Ok(vec![input.to_path_buf()]);
    }
    if let Err(problem) = scenalog_input::directory(input) {
        return Err(format!(
            "{}: {problem} (give a program file or a directory of them)",
            input.display()
        ));
    }
    let mut files = Vec::new();
    let entries = std::fs::read_dir(input)
        .map_err(|e| format!("{}: cannot list the directory: {e}", input.display()))?;
    for entry in entries {
        let entry =
            entry.map_err(|e| format!("{}: cannot list the directory: {e}", input.display()))?;
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().to_string();
        let ext_ok = matches!(
            path.extension().and_then(|e| e.to_str()),
            Some("py" | "txt")
        );
        if path.is_file() && ext_ok && !name.starts_with("README") {
            files.push(path);
        }
    }
    files.sort();
    Ok(files)
}

/// The output file name for a RefAV program: its file stem in lower case, every run of other
/// characters than letters and digits one `_`, with `.dl`.
pub fn output_name(source: &Path) -> String {
    let stem = source
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    let mut out = String::new();
    for c in stem.chars() {
        if c.is_ascii_alphanumeric() {
            out.push(c.to_ascii_lowercase());
        } else if !out.ends_with('_') {
            out.push('_');
        }
    }
    let out = out.trim_matches('_');
    if out.is_empty() {
        "program.dl".into()
    } else {
        format!("{out}.dl")
    }
}

/// Imports every RefAV program `input` names (see [`programs_in`]) into `out_dir` (created if
/// missing), one `.dl` per program that imports and checks clean; each file is written to a
/// temporary name and renamed. Failures are reported in the result, not written.
///
/// # Errors
/// The input cannot be listed or the output directory cannot be created or written.
pub fn import_path(input: &Path, out_dir: &Path) -> Result<ImportReport, String> {
    import_path_with(input, out_dir, Semantics::Scenalog)
}

/// [`import_path`] targeting the given definitions.
///
/// # Errors
/// As [`import_path`].
pub fn import_path_with(
    input: &Path,
    out_dir: &Path,
    semantics: Semantics,
) -> Result<ImportReport, String> {
    let files = programs_in(input)?;
    std::fs::create_dir_all(out_dir)
        .map_err(|e| format!("{}: cannot create the directory: {e}", out_dir.display()))?;
    let mut report = ImportReport::default();
    let mut taken = std::collections::BTreeSet::new();
    for source in files {
        let text = match scenalog_input::read_text_file(&source, scenalog_input::TEXT_LIMIT) {
            Ok(t) => t,
            Err(scenalog_input::FileProblem::NotUtf8(_)) => {
                report
                    .files
                    .push(failure(source, "file", "not UTF-8 text".into()));
                continue;
            }
            Err(e) => {
                report
                    .files
                    .push(failure(source, "file", format!("cannot read: {e}")));
                continue;
            }
        };
        let label = source
            .file_name()
            .map(|n| n.to_string_lossy().to_string())
            .unwrap_or_default();
        match import_checked_with(&text, &label, semantics) {
            Ok(imported) => {
                let mut name = output_name(&source);
                let mut k = 2;
                while taken.contains(&name) {
                    name = format!("{}_{k}.dl", output_name(&source).trim_end_matches(".dl"));
                    k += 1;
                }
                taken.insert(name.clone());
                let path = out_dir.join(&name);
                write_atomic(&path, &imported.program)?;
                report.files.push(FileOutcome {
                    source,
                    output: Some(path),
                    notes: imported.notes,
                    errors: Vec::new(),
                    first_api: imported.first_api,
                });
            }
            Err(errors) => report.files.push(FileOutcome {
                source,
                output: None,
                notes: Vec::new(),
                errors,
                first_api: false,
            }),
        }
    }
    Ok(report)
}

fn failure(source: PathBuf, construct: &str, message: String) -> FileOutcome {
    FileOutcome {
        source,
        output: None,
        notes: Vec::new(),
        errors: vec![ImportError {
            line: 0,
            construct: construct.into(),
            message,
            refav_broken: false,
        }],
        first_api: false,
    }
}

fn write_atomic(path: &Path, text: &str) -> Result<(), String> {
    scenalog_input::out_dir::write_atomic(path, text.as_bytes(), false)
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))
}
