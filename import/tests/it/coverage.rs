//! Coverage: the 262 RefAV programs of `tests/data/refav_programs/` (the reference system's own
//! LLM output) imported into a temporary directory. Every one either imports and checks clean
//! (those written against RefAV's first API under that API's meaning) or fails with an error that
//! RefAV itself raises on it too (an undefined name, a wrong call, a syntax error); none fails on
//! Scenalog's side. Prints the failures by reason.

use std::collections::BTreeMap;
use std::path::Path;

#[test]
fn every_refav_program_imports_unless_refav_itself_rejects_it() {
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/refav_programs");
    let out = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let report = scenalog_import::import_path(&input, out.path()).unwrap_or_else(|e| panic!("{e}"));
    let mut reasons: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for f in &report.files {
        if let Some(e) = f.errors.first() {
            let name = f
                .source
                .file_name()
                .map(|n| n.to_string_lossy().to_string());
            // group by the message without the line-specific name it mentions
            let key = e
                .message
                .split(" before line")
                .next()
                .unwrap_or("")
                .to_string();
            let key = if key.starts_with("name '") {
                "NameError: a name used before it is assigned".into()
            } else {
                key
            };
            reasons.entry(key).or_default().push(format!(
                "{} (line {})",
                name.unwrap_or_default(),
                e.line
            ));
        }
    }
    println!(
        "{} programs: {} imported and checked clean, {} broken in RefAV itself, {} not imported",
        report.files.len(),
        report.imported(),
        report.refav_broken(),
        report.failed_here()
    );
    for (reason, files) in &reasons {
        println!("{:>3}  {reason}: {}", files.len(), files.join(", "));
    }
    assert_eq!(report.files.len(), 262);
    // every written program is there and checks (import_checked ran the checker; read it back)
    for f in report.files.iter().filter_map(|f| f.output.as_ref()) {
        let text = std::fs::read_to_string(f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let outcome = scenalog_rules::check(&text, &scenalog_rules::CheckOptions::default());
        assert!(outcome.program.is_some(), "{} does not check", f.display());
        assert!(text.starts_with("// description: "), "{}", f.display());
    }
    let not_imported: Vec<String> = report
        .files
        .iter()
        .filter(|f| f.output.is_none() && !f.refav_broken())
        .map(|f| format!("{}: {:?}", f.source.display(), f.errors))
        .collect();
    assert!(
        not_imported.is_empty(),
        "failed on Scenalog's side:\n{}",
        not_imported.join("\n")
    );
    // The RefAV-broken ones are the known 7 (`on_road_lane`, `reverse_relationship(scenario_or)`,
    // `scenario_not(lambda …)`, a syntax error); the 20 written against RefAV's first API
    // (`accelerating(..., thresh=...)`) import under that API's meaning.
    assert_eq!(report.refav_broken(), 7);
    assert_eq!(report.imported(), 255);
    assert_eq!(report.first_api(), 20);
    for f in report.files.iter().filter(|f| f.first_api) {
        let Some(out) = &f.output else {
            panic!("{}: first API but not written", f.source.display())
        };
        let text =
            std::fs::read_to_string(out).unwrap_or_else(|e| panic!("{}: {e}", out.display()));
        assert!(text.contains("// RefAV API: first"), "{}", out.display());
    }
}

#[test]
fn with_refav_semantics_the_same_programs_import_onto_refav_relations() {
    // `--semantics refav`, with RefAV's defects (the default) and without: the same 255 import
    // and check clean, none of them uses the Scenalog relations refav mode replaces (turning,
    // direction, crossing, crossing_detail, lane_change, on_intersection), and the defects decide which RefAV relations.
    use scenalog_import::{Defects, Semantics};
    let with = refav_relations_used(Semantics::Refav(Defects::ALL));
    assert_eq!(
        with.keys().copied().collect::<Vec<_>>(),
        [
            "refav_crossing(",
            "refav_crossing_event(",
            "refav_crosswalk(",
            "refav_direction(",
            "refav_lane_change(",
            "refav_near(",
            "refav_on_intersection(",
            "refav_order(",
            "refav_turning("
        ],
        "{with:?}"
    );
    let without = refav_relations_used(Semantics::Refav(Defects::NONE));
    assert_eq!(
        without.keys().copied().collect::<Vec<_>>(),
        [
            "refav_crossing(",
            "refav_crosswalk(",
            "refav_direction_corrected(",
            "refav_lane_change(",
            "refav_near(",
            "refav_on_intersection(",
            "refav_turning_filtered("
        ],
        "{without:?}"
    );
    // The ego's box and the crosswalks are RefAV's either way: the same programs use them.
    assert_eq!(
        with.get("refav_direction("),
        without.get("refav_direction_corrected(")
    );
    assert_eq!(
        with.get("refav_crosswalk("),
        without.get("refav_crosswalk(")
    );
    assert_eq!(
        with.get("refav_turning("),
        without.get("refav_turning_filtered(")
    );
    for r in [
        "refav_lane_change(",
        "refav_on_intersection(",
        "refav_near(",
    ] {
        assert_eq!(with.get(r), without.get(r), "{r}");
    }
}

/// Imports the 262 programs in `semantics` and counts the programs using each `refav_*` relation.
fn refav_relations_used(semantics: scenalog_import::Semantics) -> BTreeMap<&'static str, usize> {
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/refav_programs");
    let out = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let report = scenalog_import::import_path_with(&input, out.path(), semantics)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(report.imported(), 255);
    assert_eq!(report.refav_broken(), 7);
    let replaced = [
        " turning(",
        " direction(",
        " crossing(",
        " crossing_detail(",
        " lane_change(",
        " on_intersection(",
        " near(",
    ];
    let mut uses = BTreeMap::new();
    for f in report.files.iter().filter_map(|f| f.output.as_ref()) {
        let text = std::fs::read_to_string(f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        assert!(text.contains("// Semantics: refav"), "{}", f.display());
        assert!(
            text.contains(&format!(
                "// RefAV defects reproduced: {}\n",
                semantics.defects()
            )),
            "{}",
            f.display()
        );
        // Clauses only: the comments quote the RefAV source.
        let clauses: String = text
            .lines()
            .filter(|l| !l.starts_with("//"))
            .map(|l| format!(" {l}\n"))
            .collect();
        for r in replaced {
            assert!(!clauses.contains(r), "{}: uses{r}", f.display());
        }
        for r in [
            "refav_turning(",
            "refav_direction(",
            "refav_direction_corrected(",
            "refav_crossing(",
            "refav_crossing_event(",
            "refav_order(",
            "refav_crosswalk(",
            "refav_turning_filtered(",
            "refav_lane_change(",
            "refav_on_intersection(",
            "refav_near(",
        ] {
            if clauses.contains(r) {
                *uses.entry(r).or_insert(0) += 1;
            }
        }
    }
    uses
}
