//! Rendering: caret under the span for people, stable JSON for machines.

use scenalog_rules::{check, diagnostics_json, render_human, CheckOptions};

#[test]
fn human_rendering_has_code_caret_related_and_hint() {
    let src = "// description: x\nslow(X, T) :- speed(X, T, S), S < 1.0.\nreferred(X, T) :- slow(X, T, 1).\n";
    let out = check(src, &CheckOptions::default());
    let text = render_human(&out.diagnostics, src, "x.dl", false);
    assert!(
        text.contains("error[E0102]: `slow` takes 2 arguments, found 3"),
        "{text}"
    );
    assert!(text.contains("x.dl:3:19"), "{text}");
    assert!(text.contains("^^^^^^^^^^^^^"), "{text}");
    assert!(text.contains("`slow` has 2 arguments here"), "{text}");
    assert!(
        text.contains("hint: use `slow` with 2 arguments everywhere"),
        "{text}"
    );
    let colored = render_human(&out.diagnostics, src, "x.dl", true);
    assert!(colored.contains("\u{1b}["), "colour codes when asked");
}

#[test]
fn json_fields_lines_and_character_columns() {
    // "é" is two bytes: the column counts characters.
    let src = "referred(X, T) :- category(X, \"é\"), present(X, T), near(X, T).\n";
    let out = check(src, &CheckOptions::default());
    let v = diagnostics_json(&out.diagnostics, src);
    // "é" is not a category (E0104, with no fix to offer); the arity error comes after it.
    assert_eq!(v[0]["code"], "E0104");
    assert_eq!(v[0]["fix"], serde_json::json!([]));
    let Some(d) = v
        .as_array()
        .and_then(|a| a.iter().find(|d| d["code"] == "E0102"))
    else {
        panic!("no E0102 in {v:#}")
    };
    assert_eq!(d["code"], "E0102");
    assert_eq!(d["severity"], "error");
    assert_eq!(d["line"], 1);
    let byte = src.find("near").expect("near");
    assert_eq!(d["span"]["start"], byte);
    assert_eq!(d["column"], byte); // one fewer than byte + 1: "é" is one character
    assert!(d["hint"]
        .as_str()
        .is_some_and(|h| h.contains("near(X: track")));
    assert_eq!(d["related"], serde_json::json!([]));
    let keys: Vec<&String> = d.as_object().expect("object").keys().collect();
    assert_eq!(keys.len(), 9, "{keys:?}");
    // A fix is a list of edits, each a byte span and its replacement.
    let src = "referred(X, T) :- category(X, \"CAR\"), present(X, T).\n";
    let v = diagnostics_json(&check(src, &CheckOptions::default()).diagnostics, src);
    let at = src.find("\"CAR\"").expect("CAR");
    assert_eq!(
        v[0]["fix"],
        serde_json::json!([{"span": {"start": at, "end": at + 5}, "text": "\"REGULAR_VEHICLE\""}])
    );
}

#[test]
fn related_spans_in_json_have_positions() {
    let src =
        "a(X, T) :- present(X, T), !b(X, T).\nb(X, T) :- a(X, T).\nreferred(X, T) :- a(X, T).\n";
    let out = check(src, &CheckOptions::default());
    let v = diagnostics_json(&out.diagnostics, src);
    let rel = &v[0]["related"];
    assert_eq!(rel[1]["line"], 2);
    assert_eq!(rel[1]["column"], 1);
    assert!(rel[1]["message"]
        .as_str()
        .is_some_and(|m| m.contains("`b` uses `a`")));
}
