//! The prompt: a system message shared by every description (the task, a summary of the
//! language, the conventions, the catalog, the categories), then a user message with the
//! in-context examples most similar to the description and the description itself.
//!
//! The long system message is identical for every description, so servers with prefix caching
//! (vLLM, llama.cpp) reuse it across a batch.

use std::collections::BTreeSet;

use scenalog_facts::scene::{
    ALL_CATEGORIES, CONSTRUCTION_CATEGORIES, SUPER_CATEGORIES, VEHICLE_CATEGORIES,
};
use scenalog_facts::{catalog, conventions};

use crate::client::Message;
use crate::extract::one_line;
use crate::library::Example;

/// How many examples a prompt holds by default.
pub const DEFAULT_EXAMPLES: usize = 8;

/// What the model is asked to do and how the language works (before the catalog);
/// `{CONVENTIONS}` is replaced by the prelude's concepts (`scenalog_rules::prelude`) and the
/// conventions table (`scenalog_facts::conventions`).
const LANGUAGE: &str = r#"You write programs in Scenalog, a Datalog dialect (close to Soufflé) for finding scenarios described in words in Argoverse 2 driving logs. A program is evaluated over facts extracted from one log and says which objects the description is about, at which moments.

# Outputs
- `referred(X, T)` (required): object X is what the description is about, and the description holds for it at T. Give exactly the moments where it holds; the miner widens short runs itself.
- `related(X, Y, T)` (optional): Y is an object that referred X interacts with at T in the way the description says (the bus a pedestrian crosses in front of, the vehicle being followed). Define it when the description names a second object; every `related(X, _, T)` should have `referred(X, T)`.
- Every other predicate is a helper you define with clauses (lower_snake_case names that are not catalog relations).

# Syntax
- A rule is `head(Args) :- literal, literal, ... .` and a ground fact is `head(Args).` Every clause ends with a period.
- Comments: `// ...`, `% ...`, `/* ... */`. The first line of a program is `// description: <the description>`.
- Variables start with an upper-case letter or `_` (`X`, `Ped`, `_t`); `_` alone is an anonymous variable, fresh at each use. Strings are double-quoted (`"VEHICLE"`); numbers are integers (`3`) or floats (`0.5`, `-1.0`), and a number may carry a unit: `5 m`, `50 km/h`, `3 m/s`, `2 m/s2`, `90 deg`, `0.3 rad/s`, `2 s`, `500 ms` (converted to the column's unit; write every threshold with its unit).
- Arithmetic: `+ - * /`, `abs(E)`, `min(E1, E2)`, `max(E1, E2)`. Comparisons: `<  <=  >  >=  =  !=`. `X = expr` binds X when X is not bound yet.
- Negation: `!p(...)` or `not p(...)`. It means "no such fact"; every named variable in it must also occur in a positive atom of the same body (use `_` for columns you do not care about).
- Aggregates: `N = count : { body }`, `M = min E : { body }`, `M = max E : { body }`, `S = sum E : { body }`. Variables of the body that also occur outside the braces (in the head or the other literals) group the aggregate; the others are local to it. An aggregate folds over the matching tuples of its body, as in Soufflé: each `_` is a fresh variable, so `N = count : { near(X, _, T, _) }` counts X's neighbours at T. Example: `N = count : { near(X, P, T, D), category(P, "PEDESTRIAN"), D < 10 m }, N >= 3`.
- Helper predicates may be declared, `.decl name(X: track, T: time)`, but their types are inferred when they are not.
- Recursion is allowed (e.g. a chain over `following`), but not through negation or aggregates.
- Safety: every variable of the head, of a negation and of a comparison must occur in a positive atom of the body or be bound by `X = expr`.
- Types: track (an object; the ego is one), time (a moment of the log: `T2 - T1` is a duration, `T + 1 s` one second later, X's next sample `next_sample(X, T, T2)`), lane, str, float, int; a float column's unit follows its type (`float<m/s>`). Each column has one type: never put a track where a lane goes, or a string where a number goes. A string column with listed values takes only those values.

{CONVENTIONS}
# Answer format
Reply with the complete program in one fenced code block (```scenalog ... ```), its first line `// description: <the description>`. No explanation is needed."#;

/// The system message: the task and language, the catalog, the categories.
pub fn system_message() -> String {
    let conventions = format!(
        "# Concepts: the prelude\nThese relations are defined once, for every program: use them as they are, never define or re-derive them (a program that defines one of these names replaces it).\n{}\n# Conventions\n{}",
        scenalog_rules::prelude::render_text(),
        conventions::render_text()
    );
    let mut s = LANGUAGE.replace("{CONVENTIONS}", &conventions);
    s.push_str("\n\n# Catalog: the relations a program can use\n");
    s.push_str(&catalog::render_rules_text());
    s.push_str("\n# Categories (the second column of `category`)\n");
    s.push_str(&ALL_CATEGORIES.join(", "));
    s.push_str(&format!(
        "\nSuper-categories: {} (\"VEHICLE\" is {}; \"CONSTRUCTION\" is {}; \"ANY\" is every object).\n",
        SUPER_CATEGORIES.join(", "),
        VEHICLE_CATEGORIES.join(", "),
        CONSTRUCTION_CATEGORIES.join(", ")
    ));
    s
}

/// The user message: the examples (if any) and the description.
pub fn user_message(description: &str, examples: &[&Example]) -> String {
    let mut s = String::new();
    if !examples.is_empty() {
        s.push_str("Examples of checked programs from the scenario library:\n\n");
        for e in examples {
            s.push_str("```scenalog\n");
            s.push_str(e.source.trim_end());
            s.push_str("\n```\n\n");
        }
    }
    s.push_str(&format!(
        "Write the Scenalog program for this description:\n{}\n",
        one_line(description)
    ));
    s
}

/// The first request's messages for a description, with at most `k` examples of `library`
/// (the most similar to the description; `None`: all of them).
pub fn messages(description: &str, library: &[Example], k: Option<usize>) -> Vec<Message> {
    let chosen = choose_examples(description, library, k);
    vec![
        Message::system(system_message()),
        Message::user(user_message(description, &chosen)),
    ]
}

/// Token-set Jaccard similarity at or above which a library description counts as a
/// near-duplicate of the one asked (held-out prompts leave it out).
pub const NEAR_DUPLICATE: f64 = 0.6;

/// The library without the examples a held-out prompt must not show for `description`: its own
/// program (the same description, ignoring case and spacing) and near-duplicates (similarity at
/// least [`NEAR_DUPLICATE`]), so a measurement of synthesis does not show the model the answer.
pub fn held_out(description: &str, library: &[Example]) -> Vec<Example> {
    let query = tokens(description);
    let asked = one_line(description).to_lowercase();
    library
        .iter()
        .filter(|e| {
            one_line(&e.description).to_lowercase() != asked
                && jaccard(&query, &tokens(&e.description)) < NEAR_DUPLICATE
        })
        .cloned()
        .collect()
}

/// At most `k` examples (all with `None`), the most similar to `description` by token-set
/// Jaccard similarity of their descriptions (ties by file name), listed least similar first so
/// the closest sits next to the question.
pub fn choose_examples<'a>(
    description: &str,
    library: &'a [Example],
    k: Option<usize>,
) -> Vec<&'a Example> {
    let query = tokens(description);
    let mut scored: Vec<(f64, &Example)> = library
        .iter()
        .map(|e| (jaccard(&query, &tokens(&e.description)), e))
        .collect();
    // Most similar first, ties by name, to cut at k.
    scored.sort_by(|a, b| b.0.total_cmp(&a.0).then_with(|| a.1.name.cmp(&b.1.name)));
    scored.truncate(k.unwrap_or(usize::MAX));
    scored.reverse();
    scored.into_iter().map(|(_, e)| e).collect()
}

const STOP_WORDS: &[&str] = &[
    "a", "an", "the", "of", "to", "in", "on", "at", "by", "for", "from", "with", "and", "or", "is",
    "are", "its", "it", "that", "which", "while", "as", "into", "their", "there", "be",
];

/// Lower-case word tokens without stop words, lightly stemmed ("turning" and "turns" are "turn").
pub fn tokens(text: &str) -> BTreeSet<String> {
    text.split(|c: char| !c.is_alphanumeric())
        .map(str::to_lowercase)
        .filter(|w| !w.is_empty() && !STOP_WORDS.contains(&w.as_str()))
        .map(|w| stem(&w))
        .collect()
}

fn stem(w: &str) -> String {
    let long_enough = |r: &str| r.chars().count() >= 3;
    let mut root = w;
    if let Some(r) = root.strip_suffix("ing").filter(|r| long_enough(r)) {
        root = r;
    } else if let Some(r) = root.strip_suffix("ed").filter(|r| long_enough(r)) {
        root = r;
    } else if ["ses", "xes", "ches", "shes"]
        .iter()
        .any(|s| root.ends_with(s))
    {
        root = &root[..root.len() - 2];
    } else if let Some(r) = root
        .strip_suffix('s')
        .filter(|r| long_enough(r) && !r.ends_with('s'))
    {
        root = r;
    }
    if let Some(r) = root.strip_suffix('e').filter(|r| long_enough(r)) {
        root = r;
    }
    root.to_string()
}

/// |A ∩ B| / |A ∪ B|, 0 for two empty sets.
pub fn jaccard(a: &BTreeSet<String>, b: &BTreeSet<String>) -> f64 {
    let union = a.union(b).count();
    if union == 0 {
        return 0.0;
    }
    a.intersection(b).count() as f64 / union as f64
}

/// The messages as text, each under a `=== role ===` line (what `--print-prompt` prints).
pub fn render(messages: &[Message]) -> String {
    let mut s = String::new();
    for m in messages {
        s.push_str(&format!("=== {} ===\n{}", m.role, m.content));
        if !m.content.ends_with('\n') {
            s.push('\n');
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ex(name: &str, d: &str) -> Example {
        Example::new(
            name,
            &format!("// description: {d}\nreferred(X, T) :- ego(X), present(X, T).\n"),
        )
    }

    #[test]
    fn system_message_holds_every_relation_value_and_category() {
        let s = system_message();
        for r in catalog::catalog() {
            if r.group == catalog::Group::Refav {
                // One definition of a concept: RefAV's own are for imported programs only.
                assert!(!s.contains(&r.signature()), "{} is in the prompt", r.name);
                continue;
            }
            assert!(s.contains(&r.signature()), "missing {}", r.name);
            assert!(s.contains(r.doc), "missing doc of {}", r.name);
            for c in r.columns {
                for v in c.values {
                    assert!(s.contains(&format!("\"{v}\"")), "missing value {v}");
                }
            }
        }
        for c in ALL_CATEGORIES.iter().chain(SUPER_CATEGORIES) {
            assert!(s.contains(c), "missing category {c}");
        }
        for topic in [
            "referred(X, T)",
            "related(X, Y, T)",
            "count :",
            "!p(...)",
            "V < 0.5",
        ] {
            assert!(s.contains(topic), "missing {topic}");
        }
    }

    /// The snippets the conventions recommend, put together, check clean: the prompt does not
    /// teach anything the checker rejects.
    #[test]
    fn the_conventions_check_clean() {
        let program = r#"// description: conventions
.decl peds_near(X: track, T: time, N: int)
peds_near(X, T, N) :- category(X, "VEHICLE"), present(X, T), N = count : { near(X, P, T, D), category(P, "PEDESTRIAN"), D < 10 m }.
close(X, Y, T) :- category(X, "VEHICLE"), near(X, Y, T, D), D < 10 m, X != Y.
later_fast(X, T) :- speed(X, T, V), V < 0.5 m/s, !parked(X), speed(X, T2, V2), T2 >= T, T2 <= T + 2 s, V2 > 0.5 m/s.
ahead(X, Y, T) :- direction(X, Y, T, "forward", Dist, Lat), Lat < 1 m, Dist < 25 m.
referred(X, T) :- peds_near(X, T, N), N >= 3, close(X, _, T), later_fast(X, T), ahead(X, _, T),
    accel(X, T, A), A >= 1 m/s2, near_intersection(X, T, D), D < 10 m, at_crosswalk(X, T, C), C < 1 m,
    turning(X, T, "left"), at_an_intersection(X, T), next_sample(X, T, T3), moving(X, T3).
related(X, Y, T) :- referred(X, T), close(X, Y, T), following(X, Y, T), crossing(X, Y, T, "forward").
"#;
        let outcome = scenalog_rules::check(program, &scenalog_rules::CheckOptions::default());
        assert!(outcome.program.is_some(), "{:?}", outcome.diagnostics);
        assert!(outcome.diagnostics.is_empty(), "{:?}", outcome.diagnostics);
    }

    #[test]
    fn similar_examples_are_chosen_and_closest_last() {
        let lib = vec![
            ex("a.dl", "pedestrian crossing in front of a bus"),
            ex("b.dl", "vehicle turning left"),
            ex("c.dl", "stopped car"),
            ex("d.dl", "vehicle turning right at an intersection"),
        ];
        let chosen = choose_examples("vehicle making a left turn", &lib, Some(2));
        let names: Vec<_> = chosen.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names, ["d.dl", "b.dl"]);
        assert_eq!(choose_examples("x", &lib, None).len(), 4);
        assert!(choose_examples("x", &lib, Some(0)).is_empty());
        let m = messages("vehicle making a left turn", &lib, Some(1));
        assert_eq!(m.len(), 2);
        assert!(m[1]
            .content
            .contains("// description: vehicle turning left"));
        assert!(!m[1].content.contains("stopped car"));
        assert!(m[1]
            .content
            .ends_with("description:\nvehicle making a left turn\n"));
    }

    #[test]
    fn tokens_and_similarity() {
        let t = tokens("Vehicles turning LEFT at the intersection");
        assert_eq!(
            t.into_iter().collect::<Vec<_>>(),
            ["intersection", "left", "turn", "vehicl"]
        );
        let a = tokens("turning left");
        let b = tokens("turns left");
        assert_eq!(jaccard(&a, &b), 1.0);
        assert_eq!(jaccard(&BTreeSet::new(), &BTreeSet::new()), 0.0);
    }
}
