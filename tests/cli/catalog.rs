//! `scenalog catalog` end to end: the built binary prints the catalog as text and JSON.

use std::process::Output;

use scenalog_facts::catalog;

fn scenalog(args: &[&str]) -> Output {
    crate::util::scenalog()
        .args(args)
        .output()
        .expect("run scenalog")
}

#[test]
fn text_lists_every_relation_with_its_signature_and_doc() {
    let out = scenalog(&["catalog"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with(&format!("{} relations.", catalog::catalog().len())));
    for r in catalog::catalog() {
        assert!(text.contains(&r.signature()), "missing {}", r.signature());
        assert!(text.contains(r.doc), "missing doc of {}", r.name);
    }
    for title in ["Objects and time", "Kinematics", "Map", "Pairs"] {
        assert!(text.contains(title), "missing group {title}");
    }
    assert!(text.contains("near(X: track, Y: track, T: time, D: float<m>)"));
}

#[test]
fn json_is_an_array_of_relations_with_typed_columns() {
    let out = scenalog(&["catalog", "--json"]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let arr = v.as_array().expect("array");
    let prelude = scenalog_rules::prelude::relations();
    assert_eq!(arr.len(), catalog::catalog().len() + prelude.len());
    let stopped = arr
        .iter()
        .find(|r| r["name"] == "stopped")
        .expect("stopped");
    assert_eq!(stopped["prelude"], true);
    assert_eq!(
        stopped["definition"],
        serde_json::json!(["stopped(X, T) :- speed(X, T, V), V < 0.5 m/s."])
    );
    let near = arr.iter().find(|r| r["name"] == "near").expect("near");
    let types: Vec<&str> = near["columns"]
        .as_array()
        .expect("columns")
        .iter()
        .filter_map(|c| c["type"].as_str())
        .collect();
    assert_eq!(types, ["track", "track", "time", "float"]);
    let turning = arr
        .iter()
        .find(|r| r["name"] == "turning")
        .expect("turning");
    assert_eq!(
        turning["columns"][2]["values"],
        serde_json::json!(["left", "right"])
    );
    for r in arr {
        assert!(r["doc"].as_str().is_some_and(|d| !d.is_empty()), "{r}");
        assert!(r["group"].as_str().is_some(), "{r}");
    }
}

#[test]
fn the_prelude_concepts_are_listed_with_their_definitions() {
    let out = scenalog(&["catalog"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Concepts (the prelude"), "{text}");
    assert!(
        text.contains("group_size(P: track, T: time, N: int): P is in a group"),
        "{text}"
    );
    let out = scenalog(&["catalog", "nearby"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.starts_with("nearby(X: track, Y: track, T: time) (prelude)"),
        "{text}"
    );
    assert!(
        text.contains("nearby(X, Y, T) :- near(X, Y, T, D), D <= 10.0 m, X != Y."),
        "{text}"
    );
}

#[test]
fn one_relation_by_name_and_unknown_names() {
    let out = scenalog(&["catalog", "direction"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with(
        "direction(X: track, Y: track, T: time, Dir: str, Dist: float<m>, Lat: float<m>)"
    ));
    assert!(text.contains("Dir: str, one of \"forward\""), "{text}");

    let out = scenalog(&["catalog", "--json", "speed"]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(v["name"], "speed");
    assert_eq!(v["columns"][2]["type"], "float");
    assert_eq!(v["columns"][2]["unit"], "m/s");

    let out = scenalog(&["catalog", "sped"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no relation `sped`") && err.contains("speed"),
        "{err}"
    );
}
