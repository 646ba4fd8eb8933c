//! `scenalog lsp` driven as an editor drives it: JSON-RPC messages framed with `Content-Length`
//! over the built binary's standard input and output, on a library program and on broken ones.

use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, ChildStdin, ChildStdout, Stdio};

use serde_json::{json, Value};

/// A running `scenalog lsp` and its pipes.
struct Server {
    child: Child,
    input: ChildStdin,
    output: BufReader<ChildStdout>,
    next_id: i64,
}

impl Server {
    /// Starts the server and completes the `initialize` handshake; the capabilities it sent.
    fn start() -> (Server, Value) {
        let mut child = crate::util::scenalog()
            .arg("lsp")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start scenalog lsp");
        let input = child.stdin.take().expect("stdin");
        let output = BufReader::new(child.stdout.take().expect("stdout"));
        let mut server = Server {
            child,
            input,
            output,
            next_id: 0,
        };
        let init = server.request("initialize", json!({ "capabilities": {} }));
        server.notify("initialized", json!({}));
        (server, init["result"]["capabilities"].clone())
    }

    fn write(&mut self, body: &[u8]) {
        let header = format!("Content-Length: {}\r\n\r\n", body.len());
        self.input.write_all(header.as_bytes()).expect("write");
        self.input.write_all(body).expect("write");
        self.input.flush().expect("flush");
    }

    fn send(&mut self, msg: Value) {
        self.write(msg.to_string().as_bytes());
    }

    /// The next message from the server.
    fn receive(&mut self) -> Value {
        let mut length = None;
        loop {
            let mut line = String::new();
            self.output.read_line(&mut line).expect("read a header");
            let line = line.trim_end();
            if line.is_empty() {
                break;
            }
            if let Some(v) = line.strip_prefix("Content-Length: ") {
                length = v.parse::<usize>().ok();
            }
        }
        let mut body = vec![0; length.expect("a Content-Length header")];
        self.output.read_exact(&mut body).expect("read a body");
        serde_json::from_slice(&body).expect("a JSON body")
    }

    /// Sends a request and returns its response (notifications before it are skipped).
    fn request(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        self.send(json!({ "jsonrpc": "2.0", "id": id, "method": method, "params": params }));
        loop {
            let msg = self.receive();
            if msg["id"] == json!(id) {
                return msg;
            }
        }
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(json!({ "jsonrpc": "2.0", "method": method, "params": params }));
    }

    /// The next `publishDiagnostics` notification's diagnostics.
    fn diagnostics(&mut self) -> Vec<Value> {
        loop {
            let msg = self.receive();
            if msg["method"] == "textDocument/publishDiagnostics" {
                return msg["params"]["diagnostics"]
                    .as_array()
                    .cloned()
                    .unwrap_or_default();
            }
        }
    }

    /// Asks it to shut down and exit; its exit status.
    fn stop(mut self) -> std::process::ExitStatus {
        let r = self.request("shutdown", Value::Null);
        assert_eq!(r["result"], Value::Null, "{r}");
        self.notify("exit", Value::Null);
        self.child.wait().expect("wait")
    }
}

const URI: &str = "file:///work/scenario.dl";

fn open(server: &mut Server, text: &str) -> Vec<Value> {
    server.notify(
        "textDocument/didOpen",
        json!({ "textDocument": { "uri": URI, "languageId": "scenalog", "version": 1, "text": text } }),
    );
    server.diagnostics()
}

fn change(server: &mut Server, version: i64, text: &str) -> Vec<Value> {
    server.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": URI, "version": version }, "contentChanges": [{ "text": text }] }),
    );
    server.diagnostics()
}

fn at(line: u32, character: u32) -> Value {
    json!({ "textDocument": { "uri": URI }, "position": { "line": line, "character": character } })
}

/// The text a range covers (one line).
fn covered<'a>(text: &'a str, range: &Value) -> &'a str {
    let line = text
        .lines()
        .nth(range["start"]["line"].as_u64().expect("line") as usize)
        .expect("a line");
    let (a, b) = (
        range["start"]["character"].as_u64().expect("start") as usize,
        range["end"]["character"].as_u64().expect("end") as usize,
    );
    &line[a..b]
}

/// Applies a workspace edit's edits of the document (one line each) to `text`.
fn apply(text: &str, edit: &Value) -> String {
    let edits = edit["changes"][URI].as_array().expect("edits");
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut sorted: Vec<&Value> = edits.iter().collect();
    sorted.sort_by_key(|e| {
        let s = &e["range"]["start"];
        std::cmp::Reverse((s["line"].as_u64(), s["character"].as_u64()))
    });
    for e in sorted {
        let r = &e["range"];
        let line = r["start"]["line"].as_u64().expect("line") as usize;
        assert_eq!(r["end"]["line"], r["start"]["line"], "one-line edits");
        let (a, b) = (
            r["start"]["character"].as_u64().expect("start") as usize,
            r["end"]["character"].as_u64().expect("end") as usize,
        );
        lines[line].replace_range(a..b, e["newText"].as_str().expect("text"));
    }
    lines.join("\n") + "\n"
}

#[test]
fn a_library_program_is_clean_and_a_broken_one_shows_its_diagnostics_where_they_are() {
    let (mut server, caps) = Server::start();
    assert_eq!(caps["hoverProvider"], true);
    assert_eq!(caps["codeActionProvider"], true);
    assert!(caps["completionProvider"].is_object());
    let library =
        std::fs::read_to_string(scenalog_testkit::repo_root().join("rules/library/stopped_car.dl"))
            .expect("read the library program");
    assert!(open(&mut server, &library).is_empty());
    // A misspelt category and a bare number read in the column's unit (W0511).
    let broken = "referred(X, T) :- category(X, \"PEDESTRAIN\"), speed(X, T, V), V > 2.0.\n";
    let diags = change(&mut server, 2, broken);
    let code = |c: &str| {
        diags
            .iter()
            .find(|d| d["code"] == c)
            .unwrap_or_else(|| panic!("no {c} in {diags:?}"))
    };
    let typo = code("E0104");
    assert_eq!(typo["severity"], 1);
    assert_eq!(covered(broken, &typo["range"]), "\"PEDESTRAIN\"");
    assert!(typo["message"]
        .as_str()
        .is_some_and(|m| m.contains("did you mean \"PEDESTRIAN\"")));
    let bare = code("W0511");
    assert_eq!(bare["severity"], 2);
    assert_eq!(covered(broken, &bare["range"]), "2.0");
    // The quick fix for the bare number, applied as an editor applies it, writes its unit; the
    // category fixed by hand, the program is clean.
    let actions = server.request(
        "textDocument/codeAction",
        json!({ "textDocument": { "uri": URI }, "range": bare["range"], "context": { "diagnostics": [] } }),
    );
    let actions = actions["result"].as_array().expect("actions").clone();
    let fix = actions
        .iter()
        .find(|a| a["diagnostics"][0]["code"] == "W0511")
        .unwrap_or_else(|| panic!("no fix for W0511 in {actions:?}"));
    assert_eq!(fix["kind"], "quickfix");
    let fixed = apply(broken, &fix["edit"]).replace("PEDESTRAIN", "PEDESTRIAN");
    assert!(fixed.contains("2.0 m/s"), "{fixed}");
    assert!(change(&mut server, 3, &fixed).is_empty(), "{fixed}");
    assert!(server.stop().success());
}

#[test]
fn hover_documents_relations_and_concepts_and_completion_offers_what_fits() {
    let (mut server, _) = Server::start();
    let helper = "close(X, Y, T) :- near(X, Y, T, D), D < 2 m.\n";
    let text = "referred(X, T) :- near(X, Y, T, D), stopped(X, T), category(Y, \"\n";
    open(&mut server, &format!("{helper}{text}"));
    let hover = |server: &mut Server, word: &str| -> Value {
        let c = text.find(word).expect("the word") as u32 + 1;
        server.request("textDocument/hover", at(1, c))["result"].clone()
    };
    let near = hover(&mut server, "near(");
    let value = near["contents"]["value"].as_str().expect("markdown");
    assert!(
        value.contains("near(X: track, Y: track, T: time, D: float<m>)"),
        "{value}"
    );
    assert!(value.contains("ground rectangles"), "{value}");
    let range = &near["range"];
    assert_eq!(range["start"]["line"], 1);
    assert_eq!(
        covered(
            text,
            &json!({ "start": { "line": 0, "character": range["start"]["character"] }, "end": { "line": 0, "character": range["end"]["character"] } })
        ),
        "near"
    );
    let stopped = hover(&mut server, "stopped(");
    let value = stopped["contents"]["value"].as_str().expect("markdown");
    assert!(
        value.contains("(prelude)") && value.contains("speed(X, T, V)"),
        "{value}"
    );
    // A variable, and a place in no name: nothing.
    assert_eq!(hover(&mut server, "Y, T, D"), Value::Null);
    // Inside the string of category's second column: its values, and nothing else.
    let in_string = text.rfind('"').expect("quote") as u32 + 1;
    let values = server.request("textDocument/completion", at(1, in_string));
    let labels: Vec<&str> = values["result"]
        .as_array()
        .expect("items")
        .iter()
        .filter_map(|i| i["label"].as_str())
        .collect();
    assert!(
        labels.contains(&"PEDESTRIAN") && labels.contains(&"VEHICLE"),
        "{labels:?}"
    );
    assert!(!labels.contains(&"near"), "{labels:?}");
    // At the start of a body: relations with their arguments, concepts, the program's own.
    let items = server.request("textDocument/completion", at(1, 18))["result"].clone();
    let item = |label: &str| {
        items
            .as_array()
            .expect("items")
            .iter()
            .find(|i| i["label"] == label)
            .cloned()
            .unwrap_or_else(|| panic!("no {label}"))
    };
    assert_eq!(
        item("near")["insertText"],
        "near(${1:X}, ${2:Y}, ${3:T}, ${4:D})"
    );
    assert_eq!(item("near")["insertTextFormat"], 2);
    assert!(item("stopped")["documentation"]
        .as_str()
        .is_some_and(|d| d.contains("0.5 m/s")));
    assert_eq!(
        item("close")["insertText"],
        "close(${1:A1}, ${2:A2}, ${3:A3})"
    );
    assert!(server.stop().success());
}

#[test]
fn unknown_methods_and_malformed_messages_get_errors_never_a_crash() {
    let (mut server, _) = Server::start();
    let unknown = server.request("textDocument/teleport", json!({}));
    assert_eq!(unknown["error"]["code"], -32601, "{unknown}");
    let malformed = server.request("textDocument/hover", json!({ "position": "here" }));
    assert_eq!(malformed["error"]["code"], -32602, "{malformed}");
    // A hover on a document never opened: nothing, not an error.
    let unopened = server.request("textDocument/hover", at(3, 4));
    assert_eq!(unopened["result"], Value::Null, "{unopened}");
    // Still serving after all that.
    assert!(open(&mut server, "referred(X, T) :- present(X, T).\n").is_empty());
    assert!(server.stop().success());
    // A body that is not JSON: the server stops with a message and a failure, never a panic.
    let (mut server, _) = Server::start();
    server.write(b"{ this is not json");
    drop(server.input);
    let out = server.child.wait_with_output().expect("wait");
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("scenalog lsp: "), "{err}");
}

#[test]
fn definitions_references_rename_symbols_and_variable_types() {
    let (mut server, caps) = Server::start();
    for cap in [
        "definitionProvider",
        "referencesProvider",
        "renameProvider",
        "documentSymbolProvider",
    ] {
        assert_eq!(caps[cap], true, "{cap}");
    }
    let text = "close(X, Y, T) :- near(X, Y, T, D), D < 2 m.\n\
                referred(X, T) :- close(X, Y, T), stopped(Y, T), category(Y, \"BUS\").\n";
    assert!(open(&mut server, text).is_empty());
    let line1 = text.lines().nth(1).expect("line 1");
    let col = |line: &str, word: &str| line.find(word).expect("the word") as u32 + 1;
    // The helper's use leads to its rule's head; the prelude concept to its declaration.
    let def = server.request("textDocument/definition", at(1, col(line1, "close(")));
    assert_eq!(
        def["result"][0]["range"]["start"],
        json!({ "line": 0, "character": 0 })
    );
    let def = server.request("textDocument/definition", at(1, col(line1, "stopped(")));
    let location = &def["result"];
    assert!(location["uri"]
        .as_str()
        .is_some_and(|u| u.starts_with("file://") && u.ends_with("rules/prelude.dl")));
    let line = location["range"]["start"]["line"].as_u64().expect("line") as usize;
    let prelude = std::fs::read_to_string(scenalog_testkit::repo_root().join("rules/prelude.dl"))
        .expect("the prelude");
    assert!(prelude
        .lines()
        .nth(line)
        .is_some_and(|l| l.starts_with(".decl stopped(")));
    // A catalog relation is written nowhere.
    let def = server.request("textDocument/definition", at(1, col(line1, "category(")));
    assert_eq!(def["result"], Value::Null);
    // References: the helper in both clauses; `Y` in its clause only.
    let refs = server.request(
        "textDocument/references",
        json!({
        "textDocument": { "uri": URI }, "position": { "line": 0, "character": 1 },
        "context": { "includeDeclaration": true } }),
    );
    assert_eq!(refs["result"].as_array().map(Vec::len), Some(2), "{refs}");
    let refs = server.request("textDocument/references", json!({
        "textDocument": { "uri": URI }, "position": { "line": 1, "character": col(line1, "Y,") - 1 },
        "context": { "includeDeclaration": true } }));
    let lines: Vec<u64> = refs["result"]
        .as_array()
        .expect("refs")
        .iter()
        .filter_map(|r| r["range"]["start"]["line"].as_u64())
        .collect();
    assert_eq!(lines, vec![1, 1, 1], "{refs}");
    // Rename the helper everywhere; the edited program still checks clean.
    let rename = |server: &mut Server, line: u32, character: u32, to: &str| {
        server.request(
            "textDocument/rename",
            json!({ "textDocument": { "uri": URI }, "position": { "line": line, "character": character }, "newName": to }),
        )
    };
    let renamed = rename(&mut server, 0, 2, "beside");
    let edited = apply(text, &renamed["result"]);
    assert_eq!(edited.matches("beside(").count(), 2, "{edited}");
    assert!(change(&mut server, 2, &edited).is_empty(), "{edited}");
    // A variable is renamed in its clause only.
    let var = rename(&mut server, 1, col(line1, "X,") - 1, "Obj");
    let lines: Vec<u64> = var["result"]["changes"][URI]
        .as_array()
        .expect("edits")
        .iter()
        .filter_map(|e| e["range"]["start"]["line"].as_u64())
        .collect();
    assert_eq!(lines, vec![1, 1], "{var}");
    // What cannot be renamed says why.
    for (line, character, to, why) in [
        (1, 2, "answer", "names the program's answer"),
        (
            1,
            col(line1, "stopped("),
            "halted",
            "not defined in this program",
        ),
        (0, 2, "near", "already a relation's name"),
        (0, 2, "Beside", "not a relation name"),
        (0, col(&edited, "X,") - 1, "Y", "already has a variable `Y`"),
    ] {
        let r = rename(&mut server, line, character, to);
        let message = r["error"]["message"].as_str().unwrap_or_default();
        assert!(message.contains(why), "{to}: {r}");
    }
    // The outline: one symbol a rule, named by its head.
    let symbols = server.request(
        "textDocument/documentSymbol",
        json!({ "textDocument": { "uri": URI } }),
    );
    let names: Vec<&str> = symbols["result"]
        .as_array()
        .expect("symbols")
        .iter()
        .filter_map(|s| s["name"].as_str())
        .collect();
    assert_eq!(names, vec!["beside", "referred"]);
    // A variable's type, from the catalog column it fills.
    let edited_line0 = edited.lines().next().expect("line 0");
    let d = edited_line0.rfind("D <").expect("D") as u32;
    let hover = server.request("textDocument/hover", at(0, d));
    let value = hover["result"]["contents"]["value"]
        .as_str()
        .unwrap_or_default();
    assert!(
        value.contains("D: float<m>, from `near`'s column 4 (D)"),
        "{hover}"
    );
    assert!(server.stop().success());
}
