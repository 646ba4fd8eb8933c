//! The exported grammar (`scenalog_rules::grammar`) read by a GBNF engine ported from
//! llama.cpp's (`schoolmarm`): it accepts every program of the scenario library, the prelude and
//! the word `KEEP` where allowed, and refuses text that does not parse, character by character
//! as a constrained decoder would.

use scenalog_rules::grammar::{gbnf, Answer};
use schoolmarm::{Grammar, GrammarState};

/// Whether the grammar accepts `text` whole: every character allowed in turn, and the end
/// reachable after the last.
fn accepts(grammar: &str, text: &str) -> Result<(), String> {
    let g = Grammar::new(grammar).map_err(|e| format!("the grammar does not load: {e:?}"))?;
    let mut state = GrammarState::new(g).map_err(|e| format!("no start state: {e:?}"))?;
    for (at, c) in text.char_indices() {
        let mut buf = [0u8; 4];
        if state.accept_token(c.encode_utf8(&mut buf)).is_err() {
            let line = text[..at].matches('\n').count() + 1;
            return Err(format!("refused {c:?} at byte {at} (line {line})"));
        }
    }
    if state.is_accepting() {
        Ok(())
    } else {
        Err("the text ends before the grammar does".into())
    }
}

fn library() -> Vec<(String, String)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("library");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("the library")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "dl"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| {
            (
                p.display().to_string(),
                std::fs::read_to_string(p).expect("a program"),
            )
        })
        .collect()
}

#[test]
fn every_library_program_and_the_prelude_are_accepted() {
    let grammar = gbnf(Answer::Program);
    let programs = library();
    assert!(programs.len() > 90, "{}", programs.len());
    for (path, source) in &programs {
        accepts(&grammar, source).unwrap_or_else(|e| panic!("{path}: {e}"));
    }
    accepts(&grammar, scenalog_rules::prelude::SOURCE).expect("the prelude");
    // As the prompt asks: in one code fence.
    let (_, first) = &programs[0];
    accepts(&grammar, &format!("```scenalog\n{first}```\n")).expect("fenced");
}

#[test]
fn keep_is_an_answer_only_where_allowed() {
    assert!(accepts(&gbnf(Answer::ProgramOrKeep), "KEEP").is_ok());
    assert!(accepts(&gbnf(Answer::Program), "KEEP").is_err());
    let (_, first) = &library()[0];
    assert!(accepts(&gbnf(Answer::ProgramOrKeep), first).is_ok());
}

/// Text the parser refuses is refused by the grammar, and what the grammar accepts parses.
#[test]
fn what_does_not_parse_is_refused() {
    let grammar = gbnf(Answer::Program);
    for bad in [
        "referred(V, T) :- category(V, \"BUS\")",
        "referred(V, T) :- category(V, BUS), present(V, T).\n; x",
        "referred(V, T) :- p(V, T) ; q(V, T).",
        "referred(v, T) :- 'BUS'.",
        "Referred(V, T) :- p(V, T).",
        "referred(V, T) :- X = count(V) : { p(V, T) }.",
        "referred(V, T) :- p(V, T), .",
        "referred(V, T) :- \"unterminated.",
        "referred(V, T) :- speed(V, T, S), S > 50 furlongs.",
    ] {
        assert!(accepts(&grammar, bad).is_err(), "accepted: {bad}");
        let (_, diags) = scenalog_rules::parser::parse(bad);
        assert!(!diags.is_empty(), "parses: {bad}");
    }
    for good in [
        "referred(V, T) :- p(V, T, S), S > -3.5e2, abs(S) < max(1, 2).\n",
        "r(X) :- X = min Y : { q(Y) }.  // comment at the end",
        ".decl h(X: track, T: time)\nh(X, T) :- present(X, T), not ego(X).",
        "/* block * comment */ p(1). % prolog comment\n",
        "referred(V, T) :- !stationary(V), c(V, \"a \\\"b\\\" \\\\ c\").",
        "referred(V, T) :- speed(V, T, S), S > 50 km/h, S < 30m/s, T2 - T < 3 s.",
        ".decl q(V: track, S: float<m/s>)\nq(V, S) :- speed(V, _, S).",
        "r(X, Y) :- n(X), Y = X mod 3 + -2 ^ 2 ^ X, Y > 7 mod 2.\n",
    ] {
        accepts(&grammar, good).unwrap_or_else(|e| panic!("{good}: {e}"));
        let (_, diags) = scenalog_rules::parser::parse(good);
        assert!(diags.is_empty(), "{good}: {diags:?}");
    }
}
