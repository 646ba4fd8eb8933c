//! The scenario library as in-context examples: `rules/library/*.dl`, each starting with
//! `// description: …`. Embedded at build time, or read from a directory at run time.

use std::fs;
use std::path::Path;

use crate::SynthError;

include!(concat!(env!("OUT_DIR"), "/library.rs"));

/// One example program.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Example {
    /// The file name, e.g. `stopped_car.dl`.
    pub name: String,
    /// The `// description: …` text (the file stem with spaces when there is none).
    pub description: String,
    /// The whole program text.
    pub source: String,
}

impl Example {
    /// An example from a file's name and text.
    pub fn new(name: &str, source: &str) -> Example {
        let description = description_of(source).unwrap_or_else(|| {
            name.trim_end_matches(".dl")
                .replace(['_', '-'], " ")
                .trim()
                .to_string()
        });
        Example {
            name: name.to_string(),
            description,
            source: source.to_string(),
        }
    }
}

/// The text of a program's first `// description: …` comment, trimmed.
pub fn description_of(source: &str) -> Option<String> {
    source.lines().find_map(|line| {
        let rest = line.trim().strip_prefix("//")?.trim_start();
        let text = rest.strip_prefix("description:")?.trim();
        (!text.is_empty()).then(|| text.to_string())
    })
}

/// The library as embedded when the crate was built, sorted by file name.
pub fn embedded() -> Vec<Example> {
    EMBEDDED.iter().map(|(n, s)| Example::new(n, s)).collect()
}

/// Every `*.dl` file of `dir`, sorted by file name.
pub fn load_dir(dir: &Path) -> Result<Vec<Example>, SynthError> {
    let entries = fs::read_dir(dir).map_err(|e| SynthError::io(dir, e))?;
    let mut out = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| SynthError::io(dir, e))?;
        let path = entry.path();
        if path.extension().is_none_or(|x| x != "dl") {
            continue;
        }
        let source = SynthError::read_text(&path)?;
        let name = entry.file_name().to_string_lossy().into_owned();
        out.push(Example::new(&name, &source));
    }
    out.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(out)
}

/// Keeps the examples whose program checks clean (the prompt calls them checked programs) and
/// returns the names of those dropped.
pub fn retain_clean(examples: &mut Vec<Example>) -> Vec<String> {
    let mut dropped = Vec::new();
    examples.retain(|e| {
        let ok = scenalog_rules::check(&e.source, &scenalog_rules::CheckOptions::default())
            .program
            .is_some();
        if !ok {
            dropped.push(e.name.clone());
        }
        ok
    });
    dropped
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn description_comment_or_file_stem() {
        let e = Example::new(
            "x.dl",
            "\n//   description:  stopped car \nreferred(X, T) :- ego(X), present(X, T).\n",
        );
        assert_eq!(e.description, "stopped car");
        let e = Example::new(
            "left_turn-ego.dl",
            "referred(X, T) :- ego(X), present(X, T).\n",
        );
        assert_eq!(e.description, "left turn ego");
        assert_eq!(description_of("// descr: x"), None);
    }

    #[test]
    fn loads_a_directory_sorted_and_only_dl_files() {
        let dir = tempfile::tempdir().expect("tempdir");
        fs::write(dir.path().join("b.dl"), "// description: bee\n").expect("write");
        fs::write(dir.path().join("a.dl"), "// description: ay\n").expect("write");
        fs::write(dir.path().join("notes.txt"), "not a program").expect("write");
        let lib = load_dir(dir.path()).expect("load");
        let names: Vec<_> = lib.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names, ["a.dl", "b.dl"]);
        assert_eq!(lib[1].description, "bee");
        let missing = load_dir(&dir.path().join("nope")).unwrap_err().to_string();
        assert!(missing.contains("nope"), "{missing}");
    }

    #[test]
    fn only_clean_examples_are_kept() {
        let mut lib = vec![
            Example::new(
                "good.dl",
                "// description: ego\nreferred(X, T) :- ego(X), present(X, T).\n",
            ),
            Example::new(
                "bad.dl",
                "// description: bad\nreferred(X, T) :- nope(X, T).\n",
            ),
        ];
        assert_eq!(retain_clean(&mut lib), ["bad.dl"]);
        assert_eq!(lib.len(), 1);
        assert_eq!(lib[0].name, "good.dl");
    }

    #[test]
    fn embedded_library_matches_the_directory() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../rules/library");
        if let Ok(from_dir) = load_dir(&dir) {
            assert_eq!(embedded(), from_dir);
        }
    }
}
