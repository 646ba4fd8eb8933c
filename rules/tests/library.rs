//! Every program of the scenario library checks clean: no error and no warning.

use std::path::Path;

use scenalog_rules::{check, print_program, render_human, CheckOptions};

fn library() -> Vec<(String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("library");
    let mut out: Vec<(String, String)> = std::fs::read_dir(&dir)
        .expect("read rules/library")
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "dl"))
        .map(|p| {
            let text = std::fs::read_to_string(&p).expect("read a library program");
            (p.display().to_string(), text)
        })
        .collect();
    out.sort();
    out
}

#[test]
fn library_has_at_least_ten_programs_and_the_required_ones() {
    let progs = library();
    assert!(progs.len() >= 10, "only {} programs", progs.len());
    let descriptions: Vec<String> = progs
        .iter()
        .map(|(_, t)| scenalog_rules::parse(t).0.description.unwrap_or_default())
        .collect();
    assert!(descriptions.iter().any(|d| d == "stopped car"));
    assert!(descriptions
        .iter()
        .any(|d| d == "vehicle with a bicycle to its right"));
}

#[test]
fn every_library_program_checks_clean() {
    for (path, text) in library() {
        let out = check(&text, &CheckOptions::default());
        assert!(
            out.diagnostics.is_empty(),
            "{path}:\n{}",
            render_human(&out.diagnostics, &text, &path, false)
        );
        let checked = out.program.expect("a clean program is checked");
        assert!(
            checked
                .program
                .description
                .as_deref()
                .is_some_and(|d| !d.is_empty()),
            "{path} has no description"
        );
        assert!(checked.predicates.contains_key("referred"), "{path}");
        assert!(!checked.strata.is_empty(), "{path}");
        // Printing and re-parsing the program gives the same text again.
        let printed = print_program(&checked.program);
        let (again, diags) = scenalog_rules::parse(&printed);
        assert!(
            diags.is_empty(),
            "{path}: printed form does not parse:\n{printed}"
        );
        assert_eq!(print_program(&again), printed, "{path}");
    }
}

#[test]
fn no_library_program_writes_out_a_prelude_relation() {
    let mut found = Vec::new();
    for (path, text) in library() {
        let (program, _) = scenalog_rules::parse(&text);
        for (i, name) in scenalog_rules::prelude::rederivations(&program) {
            found.push(format!(
                "{path}: `{}` re-derives the prelude's `{name}`; use `{name}` instead",
                scenalog_rules::printer::print_clause(&program.clauses[i])
            ));
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}
