//! The prompt, the catalog docs and the scenario library agree on the conventions: the prompt's
//! conventions are the table in `scenalog_facts::conventions`, every idiom's example checks
//! clean, and each library program named for a convention uses its threshold.

use scenalog_facts::conventions::CONVENTIONS;
use scenalog_rules::{check, CheckOptions};
use scenalog_synth::library;
use scenalog_synth::prompt::system_message;

#[test]
fn the_prompt_lists_every_convention_from_the_table() {
    let prompt = system_message();
    for c in CONVENTIONS {
        assert!(prompt.contains(c.idiom), "the prompt lacks {:?}", c.phrase);
    }
    // The contradictions the table removed.
    assert!(
        !prompt.contains("Stopped (not parked)"),
        "stopped excludes parked again"
    );
    // Every prelude concept is in the prompt with its definition.
    for r in scenalog_rules::prelude::relations() {
        assert!(
            prompt.contains(&r.definition[0]),
            "the prompt lacks {}",
            r.name
        );
    }
    assert!(!prompt.contains("{CONVENTIONS}"));
    assert!(prompt.contains("a `//` comment what it approximates"));
}

#[test]
fn every_conventions_example_checks_clean() {
    for c in CONVENTIONS {
        let out = check(c.example, &CheckOptions::default());
        assert!(
            out.diagnostics.is_empty(),
            "{}: {}\n{:#?}",
            c.phrase,
            c.example,
            out.diagnostics
        );
    }
}

#[test]
fn library_programs_use_the_conventions_thresholds() {
    let lib = library::embedded();
    let mut checked = 0;
    for c in CONVENTIONS {
        for (stem, fragment) in c.library {
            let name = format!("{stem}.dl");
            let Some(e) = lib.iter().find(|e| e.name == name) else {
                panic!("{}: no library program {name}", c.phrase)
            };
            assert!(
                e.source.contains(fragment),
                "{name} does not use the `{}` convention ({fragment})",
                c.phrase
            );
            checked += 1;
        }
    }
    assert!(
        checked >= 6,
        "only {checked} library programs tied to conventions"
    );
    // "Stopped car" says stopped with the prelude's one meaning: parked cars included.
    for e in &lib {
        let d = e.description.to_lowercase();
        if d == "stopped car" || d == "stopped vehicle" {
            assert!(e.source.contains("stopped(V, T)"), "{}", e.name);
            assert!(
                !e.source.contains("!stationary"),
                "{} excludes parked",
                e.name
            );
        }
    }
}

#[test]
fn catalog_docs_agree_with_the_conventions() {
    let doc = |name: &str| {
        scenalog_facts::catalog::relation(name)
            .map(|r| r.doc)
            .unwrap_or_default()
    };
    // The concepts are the prelude's: the catalog points there instead of restating thresholds.
    assert!(doc("accel").contains("`braking_hard`") && !doc("accel").contains("<= -3"));
    assert!(doc("speed").contains("`stopped`") && !doc("speed").contains("< 0.5"));
    assert!(doc("direction").contains("a diagonal Y holds in two directions"));
    assert!(doc("direction").contains("Lat >= 0"));
}

/// The held-out prompts of the fixture's two descriptions teach one meaning per concept: no
/// example they show defines a prelude relation again or writes one out, and none makes a
/// bicycle of a bicyclist.
#[test]
fn held_out_fixture_prompts_show_one_meaning_per_concept() {
    use scenalog_synth::prompt::{held_out, messages, DEFAULT_EXAMPLES};
    let lib = library::embedded();
    for description in ["stopped car", "vehicle with a bicycle to its right"] {
        let shown = held_out(description, &lib);
        let prompt = messages(description, &shown, Some(DEFAULT_EXAMPLES));
        let user = &prompt[1].content;
        let examples: Vec<&str> = user
            .split("```scenalog\n")
            .skip(1)
            .filter_map(|b| b.split("```").next())
            .collect();
        assert_eq!(examples.len(), DEFAULT_EXAMPLES, "{user}");
        for e in examples {
            let (program, _) = scenalog_rules::parse(e);
            for c in &program.clauses {
                assert!(
                    scenalog_rules::prelude::relation(&c.head.pred).is_none(),
                    "an example for {description:?} defines the prelude's `{}` again:\n{e}",
                    c.head.pred
                );
            }
            assert!(
                scenalog_rules::prelude::rederivations(&program).is_empty(),
                "an example for {description:?} writes out a prelude concept:\n{e}"
            );
            assert!(
                !(e.contains("\"BICYCLIST\"") && e.contains("\"BICYCLE\"")),
                "an example for {description:?} counts a bicyclist as a bicycle:\n{e}"
            );
        }
        // "Stopped" has one meaning in the prompt: the prelude's, parked objects included.
        let system = &prompt[0].content;
        assert!(system.contains("stopped(X, T) :- speed(X, T, V), V < 0.5 m/s."));
        assert!(!system.contains("(not parked)"));
    }
}
