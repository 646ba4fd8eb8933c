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

/// The values a prelude relation's string column can hold, read from its clauses: the string
/// constants written in that head position, and the closed values of every catalog column the
/// head's variable is bound by in a body; `None` when a clause binds it otherwise (through
/// another prelude relation), so the column's values are not known from its own clauses.
fn prelude_column_values(
    prelude: &scenalog_rules::ast::Program,
    name: &str,
    col: usize,
) -> Option<std::collections::BTreeSet<&'static str>> {
    use scenalog_rules::ast::{ExprKind, Literal};
    let mut values = std::collections::BTreeSet::new();
    for c in prelude.clauses.iter().filter(|c| c.head.pred == name) {
        match &c.head.args.get(col)?.kind {
            ExprKind::Str(s) => {
                values.insert(scenalog_facts::catalog::catalog().iter().find_map(|r| {
                    r.columns
                        .iter()
                        .flat_map(|c| c.values.iter())
                        .find(|v| *v == s)
                        .copied()
                })?);
            }
            ExprKind::Var(v) => {
                let mut bound = false;
                for l in &c.body {
                    let Literal::Pos(a) = l else { continue };
                    let Some(r) = scenalog_facts::catalog::relation(&a.pred) else {
                        continue;
                    };
                    for (j, arg) in a.args.iter().enumerate() {
                        if matches!(&arg.kind, ExprKind::Var(w) if w == v)
                            && !r.columns[j].values.is_empty()
                        {
                            values.extend(r.columns[j].values.iter().copied());
                            bound = true;
                        }
                    }
                }
                if !bound {
                    return None;
                }
            }
            _ => return None,
        }
    }
    Some(values)
}

/// Every string column of a prelude concept whose values its own clauses say, joined with every
/// closed string column of the catalog sharing one of them (`turn_lane(L, Dir), turning(V, T,
/// Dir)`), checks without an error placed in the prelude: the prelude is checked clean on its
/// own, and a program's join narrowing one of its columns (to "left" and "right" here) must not
/// make a comparison the prelude writes (once `Dir != "straight"`) an error the program's author
/// cannot fix.
#[test]
fn prelude_concepts_joined_with_closed_columns_raise_no_error_in_the_prelude() {
    use scenalog_facts::catalog::{catalog, ColType};
    let (prelude, _) = scenalog_rules::parse(scenalog_rules::prelude::SOURCE);
    let mut checked = 0;
    let mut wrong = Vec::new();
    for p in scenalog_rules::prelude::relations() {
        for (i, (_, ty)) in p.columns.iter().enumerate() {
            if *ty != ColType::Str {
                continue;
            }
            let Some(own) = prelude_column_values(&prelude, &p.name, i) else {
                continue;
            };
            for r in catalog() {
                for (j, c) in r.columns.iter().enumerate() {
                    if !c.values.iter().any(|v| own.contains(v)) {
                        continue;
                    }
                    let args = |n: usize, at: usize| -> String {
                        (0..n)
                            .map(|k| if k == at { "D" } else { "_" })
                            .collect::<Vec<_>>()
                            .join(", ")
                    };
                    let src = format!(
                        "referred(X, T) :- present(X, T), {}({}), {}({}).\n",
                        p.name,
                        args(p.columns.len(), i),
                        r.name,
                        args(r.columns.len(), j)
                    );
                    let out = check(&src, &CheckOptions::default());
                    checked += 1;
                    if let Some(d) = out
                        .diagnostics
                        .iter()
                        .find(|d| d.message.starts_with("in the prelude"))
                    {
                        wrong.push(format!("{src}  {}", d.message));
                    }
                }
            }
        }
    }
    assert!(checked > 10, "{checked}");
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}
