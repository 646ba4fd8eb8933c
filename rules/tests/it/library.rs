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

/// The predicates that mean "X stays put" in `program`: `stationary`, the prelude's `parked`, and
/// the program's helpers that hold only where one of them does (derived positively from one).
fn parked_meanings(program: &scenalog_rules::Program) -> std::collections::BTreeSet<String> {
    use scenalog_rules::ast::Literal;
    let mut out: std::collections::BTreeSet<String> =
        ["stationary", "parked"].map(String::from).into();
    loop {
        let before = out.len();
        for c in &program.clauses {
            let from_parked = c
                .body
                .iter()
                .any(|l| matches!(l, Literal::Pos(a) if out.contains(&a.pred)));
            if from_parked {
                out.insert(c.head.pred.clone());
            }
        }
        if out.len() == before {
            return out;
        }
    }
}

/// One meaning per concept, by what the programs do rather than what they are named: a program
/// that leaves out parked objects (a negation of `stationary`, `parked` or a helper built on them)
/// says so in its description ("active", "not parked", "moving"; overtaking is of a vehicle under
/// way); one that leaves out the ego says
/// so; "at an intersection" is the prelude's `at_an_intersection`, never `on_intersection` alone;
/// "stopped" is the prelude's `stopped` (where parked cars are stopped too); no comment cites a
/// file the model reading the examples cannot see.
#[test]
fn library_programs_mean_what_the_prelude_means() {
    use scenalog_rules::ast::Literal;
    let mut wrong = Vec::new();
    let cites_file = |text: &str| {
        text.split(|c: char| c.is_whitespace() || "`()[],;:'\"".contains(c))
            .any(|w| {
                let w = w.trim_end_matches('.');
                [".dl", ".rs", ".md", ".py", ".json"]
                    .iter()
                    .any(|ext| w.len() > ext.len() && w.ends_with(ext))
            })
    };
    for (path, text) in library() {
        let (program, _) = scenalog_rules::parse(&text);
        let description = program
            .description
            .clone()
            .unwrap_or_default()
            .to_lowercase();
        let parked = parked_meanings(&program);
        let negated = |names: &dyn Fn(&str) -> bool| {
            program.clauses.iter().any(|c| {
                c.body
                    .iter()
                    .any(|l| matches!(l, Literal::Neg(a, _) if names(&a.pred)))
            })
        };
        let uses = |name: &str| {
            program.clauses.iter().any(|c| {
                scenalog_rules::walk::body_atoms(&c.body)
                    .iter()
                    .any(|(a, _)| a.pred == name)
            })
        };
        let says = |words: &[&str]| words.iter().any(|w| description.contains(w));
        if negated(&|p| parked.contains(p))
            && !says(&["active", "not parked", "moving", "non-parked", "overtak"])
        {
            wrong.push(format!(
                "{path}: leaves out parked objects, which \"{description}\" does not"
            ));
        }
        if negated(&|p| p == "ego") && !says(&["ego", "other than"]) {
            wrong.push(format!(
                "{path}: leaves out the ego, which \"{description}\" does not"
            ));
        }
        if says(&[
            "at intersection",
            "at an intersection",
            "at the intersection",
        ]) && (!uses("at_an_intersection") || uses("on_intersection"))
        {
            wrong.push(format!(
                "{path}: \"at an intersection\" is the prelude's `at_an_intersection`"
            ));
        }
        if says(&["stopped"]) && !says(&["nearly stopped"]) && !uses("stopped") {
            wrong.push(format!("{path}: \"stopped\" is the prelude's `stopped`"));
        }
        let comments: String = text
            .lines()
            .filter(|l| l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n");
        if cites_file(&comments) {
            wrong.push(format!("{path}: a comment cites a file"));
        }
    }
    for c in scenalog_facts::conventions::CONVENTIONS {
        if cites_file(c.idiom) || cites_file(c.example) {
            wrong.push(format!("convention \"{}\" cites a file", c.phrase));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// Mirror programs mirror each other: where the library has a description and its left/right
/// mirror, the programs are the same with the sides swapped (the same thresholds on both sides).
#[test]
fn mirror_programs_use_the_same_thresholds() {
    let swap = |s: &str| {
        s.replace("left", "\u{0}")
            .replace("right", "left")
            .replace('\u{0}', "right")
    };
    let code = |t: &str| {
        t.lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let progs = library();
    let by_description: std::collections::BTreeMap<String, String> = progs
        .iter()
        .map(|(_, t)| {
            let d = scenalog_rules::parse(t).0.description.unwrap_or_default();
            (d, code(t))
        })
        .collect();
    let mut pairs = 0;
    for (d, program) in &by_description {
        if !d.contains("left") {
            continue;
        }
        if let Some(mirror) = by_description.get(&swap(d)) {
            pairs += 1;
            assert_eq!(&swap(program), mirror, "{d:?} and its mirror differ");
        }
    }
    assert!(pairs >= 1, "no mirrored pair in the library");
}
