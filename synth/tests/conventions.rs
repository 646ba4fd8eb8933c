//! The prompt, the catalog docs and the scenario library agree on the conventions: the prompt's
//! conventions are the table in `scenalog_facts::conventions`, every idiom's example checks
//! clean, and each library program named for a convention uses its threshold.

use scenalog_facts::conventions::{CONVENTIONS, HARD_BRAKING_ACCEL, STOPPED_SPEED};
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
    // No library program brakes "hard" or "heavily" at another threshold, and none calls a car
    // stopped only when it is not parked.
    let hard = format!("A <= {HARD_BRAKING_ACCEL:.1}");
    for e in &lib {
        let d = e.description.to_lowercase();
        if d.contains("braking hard") || d.contains("braking heavily") || d.contains("hard braking")
        {
            assert!(
                e.source.contains(&hard),
                "{} brakes hard at another threshold",
                e.name
            );
        }
        if d == "stopped car" || d == "stopped vehicle" {
            assert!(
                e.source.contains(&format!("< {STOPPED_SPEED}")),
                "{}",
                e.name
            );
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
    assert!(doc("accel").contains("<= -3 braking hard or heavily"));
    assert!(doc("speed").contains("< 0.5 is stopped, parked objects included"));
    assert!(doc("direction").contains("a diagonal Y holds in two directions"));
    assert!(doc("direction").contains("Lat >= 0"));
}
