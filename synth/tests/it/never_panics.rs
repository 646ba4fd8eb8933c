//! Whatever a model answers, taking the program out of it, giving it its description comment,
//! checking it and writing the feedback never panics; slugs are always safe file names.

use proptest::prelude::*;
use scenalog_synth::extract::{extract, with_description, Extracted};
use scenalog_synth::repair::error_feedback;
use scenalog_synth::slug::{slug, MAX_SLUG};

fn answer() -> impl Strategy<Value = String> {
    // Bits of real answers, shuffled and cut anywhere.
    let pieces = prop::collection::vec(
        prop_oneof![
            Just("```".to_string()),
            Just("```scenalog\n".to_string()),
            Just("~~~~\n".to_string()),
            Just("<think>".to_string()),
            Just("</think>".to_string()),
            Just("referred(V, T) :- ".to_string()),
            Just("category(V, \"VEHICLE\"), ".to_string()),
            Just("turning(V, T, \"left\").\n".to_string()),
            Just("// description: x\n".to_string()),
            Just("N = count : { near(V, P, T, D) }".to_string()),
            Just("\"unterminated".to_string()),
            Just("é∆\u{0}\r\n".to_string()),
            "\\PC{0,12}",
        ],
        0..24,
    );
    pieces.prop_map(|p| p.concat())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn extraction_check_and_feedback_never_panic(a in answer(), d in "\\PC{0,40}") {
        if let Extracted::Program(code) = extract(&a) {
            let program = with_description(&code, &d);
            prop_assert!(program.starts_with("// description: "));
            let is_desc = |l: &str| {
                l.trim()
                    .strip_prefix("//")
                    .is_some_and(|r| r.trim_start().starts_with("description:"))
            };
            prop_assert_eq!(program.lines().filter(|l| is_desc(l)).count(), 1);
            let outcome = scenalog_rules::check(&program, &scenalog_rules::CheckOptions::default());
            let feedback = error_feedback(&program, &outcome.diagnostics);
            prop_assert!(feedback.contains("```json"));
        }
    }

    #[test]
    fn slugs_are_safe_file_names(d in "\\PC{0,200}") {
        let s = slug(&d);
        prop_assert!(!s.is_empty() && s.len() <= MAX_SLUG);
        prop_assert!(s.bytes().all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'-'));
        prop_assert!(!s.starts_with('-') && !s.ends_with('-') && !s.contains("--"));
    }
}
