//! A "tidy" test (as rust-analyzer keeps them): the front ends go through the library API and
//! nothing else. It reads the sources of the command's subcommands (`src/cli/**`, `src/main.rs`)
//! and of the Python binding (`python/src/**`) and fails on any path that reaches past
//! `scenalog::api`: a workspace crate or another dependency other than the plumbing (std,
//! clap, pyo3, serde_json, libc for the binary's signal), `scenalog_view` for drawing, or a
//! module of the `scenalog` crate other than `api` (and, for the subcommands, `cli` itself).
//!
//! The checker is a small Rust lexer: comments, strings and characters are skipped (a doc
//! comment may name any crate), `use` trees are expanded into full paths, and every other path
//! is checked from its first segment. The crates a front end must not name are its package's
//! dependencies (read from its `Cargo.toml`) less the allowed ones, so a dependency added later
//! is refused too. The unit tests at the end plant violations and see each one caught.

use std::path::{Path, PathBuf};

/// A front end: its files, the crates it may name, and the modules of its own crate it may.
struct FrontEnd {
    /// Where its package's `Cargo.toml` is, relative to the workspace.
    manifest: &'static str,
    /// Its files: directories are read recursively.
    files: &'static [&'static str],
    /// What `crate::` (and `$crate::`) may be followed by; `None`: anything (its own crate).
    own: Option<&'static [&'static str]>,
    /// What `scenalog::` may be followed by.
    scenalog: &'static [&'static str],
    /// Crates it may name besides std.
    allowed: &'static [&'static str],
}

/// The command's subcommands and binary: `crate::api`, `crate::cli` and plumbing.
const CLI: FrontEnd = FrontEnd {
    manifest: "Cargo.toml",
    files: &["src/cli", "src/main.rs"],
    own: Some(&["api", "cli"]),
    scenalog: &["api", "cli"],
    allowed: &[
        "clap",
        "serde",
        "serde_json",
        "scenalog_view",
        "libc",
        "lsp_server",
        "lsp_types",
        "axum",
        "tokio",
    ],
};

/// The Python binding: `scenalog::api`, its own modules, and plumbing.
const PYTHON: FrontEnd = FrontEnd {
    manifest: "python/Cargo.toml",
    files: &["python/src"],
    own: None,
    scenalog: &["api"],
    allowed: &["pyo3", "serde_json", "scenalog_view"],
};

/// Crates every front end may name.
const ALWAYS: &[&str] = &["std", "core", "alloc"];

/// The crate names a manifest depends on (normal, target-specific, dev and build
/// dependencies), with `-` as `_`.
fn dependencies(manifest: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut in_deps = false;
    for line in manifest.lines() {
        let line = line.trim();
        if line.starts_with('[') {
            let section = line.trim_matches(|c| c == '[' || c == ']');
            in_deps = section.ends_with("dependencies") && !section.starts_with("workspace");
            continue;
        }
        if !in_deps || line.is_empty() || line.starts_with('#') {
            continue;
        }
        let name = line
            .split(['=', '.', ' '])
            .next()
            .unwrap_or_default()
            .trim_matches('"');
        if !name.is_empty() {
            out.push(name.replace('-', "_"));
        }
    }
    out
}

/// A token of Rust source, as far as paths go.
#[derive(Clone, Debug, PartialEq)]
enum Tok {
    /// An identifier or keyword (`$crate` included), with its line.
    Ident(String, usize),
    /// `::`.
    Colons,
    /// Any other punctuation character.
    Punct(char),
}

/// The tokens of `source`, without comments, strings, characters and lifetimes.
fn tokens(source: &str) -> Vec<Tok> {
    let chars: Vec<char> = source.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    let at = |i: usize| chars.get(i).copied().unwrap_or('\0');
    while i < chars.len() {
        let c = chars[i];
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if c == '/' && at(i + 1) == '/' {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if chars[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    if chars[i] == '\n' {
                        line += 1;
                    }
                    i += 1;
                }
            }
        } else if c == '"' || ((c == 'b' || c == 'c') && at(i + 1) == '"') {
            i += if c == '"' { 1 } else { 2 };
            while i < chars.len() && chars[i] != '"' {
                if chars[i] == '\\' {
                    i += 1;
                }
                if at(i) == '\n' {
                    line += 1;
                }
                i += 1;
            }
            i += 1;
        } else if (c == 'r' || (c == 'b' && at(i + 1) == 'r'))
            && matches!(at(i + usize::from(c == 'b') + 1), '"' | '#')
        {
            // A raw string: r"…", r#"…"#, br"…".
            i += usize::from(c == 'b') + 1;
            let mut hashes = 0;
            while at(i) == '#' {
                hashes += 1;
                i += 1;
            }
            if at(i) != '"' {
                continue;
            }
            i += 1;
            loop {
                if i >= chars.len() {
                    break;
                }
                if chars[i] == '"' && (0..hashes).all(|k| at(i + 1 + k) == '#') {
                    i += 1 + hashes;
                    break;
                }
                if chars[i] == '\n' {
                    line += 1;
                }
                i += 1;
            }
        } else if c == '\'' {
            // A character ('a', '\n', '\u{1F600}') or a lifetime ('a, 'static).
            if at(i + 1) == '\\' {
                // Past the quote, the backslash and the escaped character, to the closing quote.
                i += 3;
                while i < chars.len() && chars[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if at(i + 2) == '\'' {
                i += 3;
            } else {
                i += 1;
                while at(i).is_alphanumeric() || at(i) == '_' {
                    i += 1;
                }
            }
        } else if c.is_alphabetic() || c == '_' || (c == '$' && at(i + 1).is_alphabetic()) {
            let start = i;
            i += 1;
            while at(i).is_alphanumeric() || at(i) == '_' {
                i += 1;
            }
            let word: String = chars[start..i].iter().collect();
            out.push(Tok::Ident(word.trim_start_matches("r#").to_string(), line));
        } else if c == ':' && at(i + 1) == ':' {
            out.push(Tok::Colons);
            i += 2;
        } else {
            out.push(Tok::Punct(c));
            i += 1;
        }
    }
    out
}

/// The full paths of a `use` tree starting at `toks[i]` (after `use`), and where it ends.
fn use_paths(
    toks: &[Tok],
    mut i: usize,
    prefix: &[String],
    out: &mut Vec<(Vec<String>, usize)>,
) -> usize {
    let mut path = prefix.to_vec();
    let mut line = 0;
    loop {
        match toks.get(i) {
            Some(Tok::Ident(w, l)) if w == "as" => {
                // `as name`: the path is what it was.
                i += 2;
                line = line.max(*l);
            }
            Some(Tok::Ident(w, l)) => {
                path.push(w.clone());
                line = *l;
                i += 1;
            }
            Some(Tok::Colons) => i += 1,
            Some(Tok::Punct('{')) => {
                i += 1;
                loop {
                    i = use_paths(toks, i, &path, out);
                    match toks.get(i) {
                        Some(Tok::Punct(',')) => i += 1,
                        Some(Tok::Punct('}')) => {
                            i += 1;
                            break;
                        }
                        _ => break,
                    }
                    if toks.get(i) == Some(&Tok::Punct('}')) {
                        i += 1;
                        break;
                    }
                }
                return i;
            }
            Some(Tok::Punct('*')) => {
                path.push("*".to_string());
                i += 1;
            }
            _ => break,
        }
    }
    if path.len() > prefix.len() {
        out.push((path, line));
    }
    i
}

/// Every path of `source` with its line: `use` trees expanded, other paths from their first
/// segment (`a::b::c` in code, not preceded by `::` or `.`).
fn paths(source: &str) -> Vec<(Vec<String>, usize)> {
    let toks = tokens(source);
    let mut out = Vec::new();
    let mut i = 0;
    while i < toks.len() {
        match &toks[i] {
            Tok::Ident(w, _) if w == "use" => {
                let mut found = Vec::new();
                i = use_paths(&toks, i + 1, &[], &mut found);
                out.extend(found);
            }
            Tok::Ident(w, _) if w == "extern" => {
                if let (Some(Tok::Ident(k, _)), Some(Tok::Ident(name, l))) =
                    (toks.get(i + 1), toks.get(i + 2))
                {
                    if k == "crate" {
                        out.push((vec![name.clone()], *l));
                    }
                }
                i += 1;
            }
            Tok::Ident(w, l) => {
                let global = i > 0 && toks[i - 1] == Tok::Colons;
                let global_root = global
                    && !matches!(
                        toks.get(i.wrapping_sub(2)),
                        Some(Tok::Ident(..)) | Some(Tok::Punct('>'))
                    );
                let after_dot = i > 0 && toks[i - 1] == Tok::Punct('.');
                if (global && !global_root) || after_dot {
                    i += 1;
                    continue;
                }
                let mut path = vec![w.clone()];
                let mut j = i + 1;
                while toks.get(j) == Some(&Tok::Colons) {
                    match toks.get(j + 1) {
                        Some(Tok::Ident(next, _)) => {
                            path.push(next.clone());
                            j += 2;
                        }
                        _ => break,
                    }
                }
                if path.len() > 1 {
                    out.push((path, *l));
                }
                i = j.max(i + 1);
            }
            _ => i += 1,
        }
    }
    out
}

/// What is wrong with `source` for `front`, whose package depends on `deps`: one message a
/// path that reaches past the API.
fn violations(source: &str, front: &FrontEnd, deps: &[String]) -> Vec<String> {
    let mut out = Vec::new();
    for (path, line) in paths(source) {
        let root = path[0].as_str();
        let second = path.get(1).map(String::as_str);
        let shown = path.join("::");
        let bad = match root {
            "crate" | "$crate" => match (front.own, second) {
                (Some(own), Some(m)) => !own.contains(&m),
                (Some(_), None) => true,
                (None, _) => false,
            },
            "super" => second == Some("super"),
            "scenalog" => !second.is_some_and(|m| front.scenalog.contains(&m)),
            _ => {
                deps.iter().any(|d| d == root)
                    && !front.allowed.contains(&root)
                    && !ALWAYS.contains(&root)
            }
        };
        if bad {
            out.push(format!("line {line}: `{shown}` reaches past the API"));
        }
    }
    out
}

/// The `.rs` files of `path` (a file, or a directory read recursively), sorted.
fn rust_files(path: &Path) -> Vec<PathBuf> {
    if path.is_file() {
        return vec![path.to_path_buf()];
    }
    let mut out = Vec::new();
    let mut entries: Vec<PathBuf> = std::fs::read_dir(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .map(|e| e.expect("a directory entry").path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            out.extend(rust_files(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
    out
}

#[test]
fn the_front_ends_call_only_the_api() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut all = Vec::new();
    let mut files = 0;
    for front in [CLI, PYTHON] {
        let manifest = std::fs::read_to_string(root.join(front.manifest)).expect("manifest");
        let deps = dependencies(&manifest);
        assert!(
            deps.iter()
                .any(|d| d == "scenalog" || d.starts_with("scenalog_")),
            "{}: no dependency read: {deps:?}",
            front.manifest
        );
        for dir in front.files {
            for file in rust_files(&root.join(dir)) {
                files += 1;
                let source = std::fs::read_to_string(&file).expect("source");
                for v in violations(&source, &front, &deps) {
                    all.push(format!("{}: {v}", file.display()));
                }
            }
        }
    }
    assert!(files > 10, "only {files} files read");
    assert!(
        all.is_empty(),
        "the front ends must call only `scenalog::api` (add what they need there):\n{}",
        all.join("\n")
    );
}

/// The root package's dependencies, as the command's subcommands see them.
fn cli_deps() -> Vec<String> {
    let manifest = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml"))
        .expect("manifest");
    dependencies(&manifest)
}

#[test]
fn a_planted_violation_is_caught_however_it_is_written() {
    let deps = cli_deps();
    for planted in [
        "use scenalog_facts::load_scene;",
        "use crate::pipeline::limits::pair_limits;",
        "use crate::{api::mine, pipeline::run::PairStatus};",
        "use crate::input::read_text as read;",
        "fn f() { let s = scenalog_facts::load_scene(p); }",
        "fn f() -> u64 { crate::pipeline::limits::pair_limits(None, None, 1).max_tuples }",
        "fn f() { ::scenalog_eval::read_any(p); }",
        "use scenalog_engine as engine;",
        "use super::super::pipeline::run;",
        "extern crate scenalog_rules;",
        "use rayon::prelude::*;",
        "use crate as c;",
    ] {
        let found = violations(planted, &CLI, &deps);
        assert_eq!(found.len(), 1, "{planted}: {found:?}");
    }
    // The Python binding: `scenalog::` is the API only.
    let py = ["scenalog".to_string(), "pyo3".to_string()];
    for planted in [
        "use scenalog::pipeline::run::RunReport;",
        "use scenalog::cli::mine::Args;",
        "use scenalog;",
        "fn f() { scenalog::input::read_text(p); }",
    ] {
        assert_eq!(violations(planted, &PYTHON, &py).len(), 1, "{planted}");
    }
}

#[test]
fn the_api_plumbing_and_prose_are_not_violations() {
    let deps = cli_deps();
    let fine = r##"
        //! Uses `scenalog_facts::load_scene` in prose only; /* scenalog_engine::x */
        use std::path::PathBuf;
        use crate::api::mine::{plan, run as run_mine, MineRequest};
        use crate::cli::stdout::write_str;
        use scenalog_view::Reference;
        #[derive(clap::Args)]
        struct A;
        fn f<'a>(x: &'a str) -> char {
            let s = "scenalog_eval::read_any(p)";
            let r = r#"crate::pipeline::x"#;
            let json = serde_json::json!({"a": 1});
            let v: Vec<u8> = Vec::new();
            v.iter().map(|b| b.len());
            ::std::io::Write::flush(&mut o);
            $crate::cli::stdout::write_with(|o| o);
            '\''
        }
    "##;
    assert_eq!(violations(fine, &CLI, &deps), Vec::<String>::new());
    let py = ["scenalog".to_string(), "pyo3".to_string()];
    let fine = "use scenalog::api::{Error, Names};\nmod interrupt;\nuse interrupt::run;\nfn f() { crate::interrupt::run(); pyo3::Python::with_gil(|py| py); }";
    assert_eq!(violations(fine, &PYTHON, &py), Vec::<String>::new());
}
