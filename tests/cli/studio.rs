//! `scenalog studio` as its users meet it: started on a free loopback port on a real log, its
//! answers compared with `scenalog mine`'s, hostile requests refused with errors, stopped by
//! Ctrl-C; and its page driven in headless Chromium over the DevTools protocol (type a broken
//! rule, see the diagnostic; fix it, see the matches; click a match and an object on the map,
//! read the proof and the why-not report). The browser part is skipped, with a message, when no
//! Chromium is installed (`.ci/run` installs it).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use crate::util::browser;

const LOG_ID: &str = "3bffdcff-c3a7-38b6-a0f2-64196d130958";
const LOG: &str = "tests/data/av2/logs/3bffdcff-c3a7-38b6-a0f2-64196d130958";
const RULES: &str = "rules/library/stopped_car.dl";

/// A running studio and the address it printed.
struct Studio {
    child: Child,
    address: String,
}

impl Studio {
    fn start(extra: &[&str]) -> Studio {
        let mut child = crate::util::scenalog()
            .args(["studio", "--port", "0", "--logs", LOG])
            .args(extra)
            .env_remove("SCENALOG_LLM_BASE_URL")
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start scenalog studio");
        let mut line = String::new();
        BufReader::new(child.stdout.take().expect("stdout"))
            .read_line(&mut line)
            .expect("the studio's first line");
        let address = line
            .split_whitespace()
            .find_map(|w| w.strip_prefix("http://"))
            .unwrap_or_else(|| panic!("no address in {line:?}"))
            .trim_end_matches('/')
            .to_string();
        Studio { child, address }
    }

    /// Sends raw bytes and returns the status code and the body.
    fn raw(&self, request: &[u8]) -> (u16, String) {
        let mut stream = TcpStream::connect(&self.address).expect("connect");
        stream
            .set_read_timeout(Some(Duration::from_secs(120)))
            .expect("timeout");
        // A server that answers before reading a huge body may close early: a write error is
        // then not the test's failure, the answer is what counts.
        let _ = stream.write_all(request);
        let mut answer = Vec::new();
        let _ = stream.read_to_end(&mut answer);
        let text = String::from_utf8_lossy(&answer).to_string();
        let status = text
            .split_whitespace()
            .nth(1)
            .and_then(|s| s.parse().ok())
            .unwrap_or(0);
        let body = text
            .split_once("\r\n\r\n")
            .map_or(String::new(), |(_, b)| b.to_string());
        (status, body)
    }

    fn get(&self, path: &str) -> (u16, String) {
        self.raw(
            format!(
                "GET {path} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\n\r\n",
                self.address
            )
            .as_bytes(),
        )
    }

    fn post(&self, path: &str, body: &[u8], headers: &str) -> (u16, String) {
        let mut request = format!(
            "POST {path} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\nContent-Length: {}\r\n{headers}\r\n",
            self.address,
            body.len()
        )
        .into_bytes();
        request.extend_from_slice(body);
        self.raw(&request)
    }

    fn post_json(&self, path: &str, body: &Value) -> (u16, Value) {
        let (status, text) = self.post(
            path,
            body.to_string().as_bytes(),
            "Content-Type: application/json\r\n",
        );
        let value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}: {text}"));
        (status, value)
    }

    /// Ctrl-C, then the exit status and what it wrote to standard error.
    fn interrupt(mut self) -> (Option<i32>, String) {
        let pid = self.child.id().to_string();
        let sent = Command::new("kill")
            .args(["-INT", &pid])
            .status()
            .expect("kill");
        assert!(sent.success());
        let status = self.child.wait().expect("wait");
        let mut err = String::new();
        if let Some(mut e) = self.child.stderr.take() {
            let _ = e.read_to_string(&mut err);
        }
        (status.code(), err)
    }
}

impl Drop for Studio {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `scenalog mine` of the test's program on the test's log, into `out`.
fn mine(out: &std::path::Path) -> std::process::Output {
    crate::util::scenalog()
        .args([
            "mine",
            "--rules",
            RULES,
            "--logs",
            LOG,
            "--threads",
            "1",
            "--out",
        ])
        .arg(out)
        .output()
        .expect("mine")
}

fn program(path: &str) -> String {
    std::fs::read_to_string(path).expect("program")
}

#[test]
fn studio_matches_are_mines_and_its_answers_are_what_the_page_needs() {
    let studio = Studio::start(&[]);
    let (status, logs) = studio.get("/api/logs");
    assert_eq!(status, 200, "{logs}");
    let logs: Value = serde_json::from_str(&logs).expect("json");
    assert_eq!(logs["logs"][0]["id"], LOG_ID);
    assert!(logs["programs"]
        .as_array()
        .expect("programs")
        .contains(&json!("stopped_car")));

    // The studio's matches of a library program are `mine`'s on the same log.
    let (status, mined) = studio.post_json("/api/mine", &json!({ "text": program(RULES) }));
    assert_eq!(status, 200);
    let tracks = mined["logs"][0]["tracks"].as_array().expect("tracks");
    let studio_matches: std::collections::BTreeMap<String, usize> = tracks
        .iter()
        .map(|t| {
            (
                t["uuid"].as_str().expect("uuid").to_string(),
                t["frames"].as_array().expect("frames").len(),
            )
        })
        .collect();
    let out = tempfile::tempdir().expect("tempdir");
    let o = mine(out.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let matches: Value = serde_json::from_str(
        &std::fs::read_to_string(out.path().join("matches.json")).expect("matches.json"),
    )
    .expect("json");
    let mine_matches: std::collections::BTreeMap<String, usize> = matches
        .as_array()
        .expect("array")
        .iter()
        .map(|m| {
            (
                m["track_uuid"].as_str().expect("uuid").to_string(),
                m["frames"].as_u64().expect("frames") as usize,
            )
        })
        .collect();
    assert!(!mine_matches.is_empty());
    assert_eq!(studio_matches, mine_matches);

    // A program with an error: its diagnostics, no matches.
    let (_, broken) = studio.post_json(
        "/api/mine",
        &json!({ "text": "referred(V, T) :- stoped(V, T).\n" }),
    );
    assert!(broken.get("logs").is_none());
    assert_eq!(broken["diagnostics"][0]["level"], "error");
    assert_eq!(broken["diagnostics"][0]["range"]["start"]["character"], 18);

    // Why a matched track is referred, and why the ego vehicle is not.
    let uuid = tracks[0]["uuid"].as_str().expect("uuid");
    let frame = tracks[0]["frames"][0].clone();
    let (_, why) = studio.post_json(
        "/api/explain",
        &json!({ "text": program(RULES), "log": LOG_ID, "track": uuid, "frame": frame }),
    );
    assert_eq!(why["referred"], true, "{why}");
    assert!(why["text"].as_str().expect("text").contains("Proof:"));
    let (_, scene) = studio.get(&format!("/api/scene?log={LOG_ID}"));
    let scene: Value = serde_json::from_str(&scene).expect("scene json");
    assert_eq!(scene["times"].as_array().expect("times").len(), 156);
    let ego = scene["tracks"]
        .as_array()
        .expect("tracks")
        .iter()
        .find(|t| t["category"] == "EGO_VEHICLE")
        .expect("the ego vehicle");
    assert!(!scene["lanes"].as_array().expect("lanes").is_empty());
    let (_, why_not) = studio.post_json(
        "/api/explain",
        &json!({ "text": program(RULES), "log": LOG_ID, "track": ego["uuid"], "frame": 50 }),
    );
    assert_eq!(why_not["referred"], false);
    let text = why_not["text"].as_str().expect("text");
    assert!(
        text.contains("Why not:") && text.contains("✗ category(V, \"REGULAR_VEHICLE\")"),
        "{text}"
    );

    let (code, err) = studio.interrupt();
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("studio: stopped"), "{err}");
}

#[test]
fn studio_refuses_hostile_requests_and_keeps_serving() {
    let studio = Studio::start(&[]);
    let not_found = [
        "/api/scene?log=..%2F..%2F..%2Fetc%2Fpasswd",
        "/api/scene?log=/etc",
        "/api/program?name=..%2F..%2FCargo.toml",
        "/api/program?name=%2Fetc%2Fpasswd",
        "/../../etc/passwd",
        "/studio.js/../../Cargo.toml",
    ];
    for path in not_found {
        let (status, body) = studio.get(path);
        assert_eq!(status, 404, "{path}: {body}");
        assert!(body.contains("\"error\""), "{path}: {body}");
        assert!(!body.contains("root:") && !body.contains("[workspace]"));
    }
    let (status, body) = studio.get("/api/scene");
    assert_eq!(status, 400, "{body}");

    // A body past the cap, malformed JSON, the wrong type, unknown fields.
    let huge = vec![b'a'; 2 * 1024 * 1024];
    let (status, _) = studio.post("/api/mine", &huge, "Content-Type: application/json\r\n");
    assert_eq!(status, 413);
    let (status, body) = studio.post(
        "/api/mine",
        b"{\"text\": ",
        "Content-Type: application/json\r\n",
    );
    assert_eq!(status, 400, "{body}");
    assert!(body.contains("malformed request"), "{body}");
    let (status, _) = studio.post("/api/mine", b"{\"text\": \"a\"}", "");
    assert_eq!(status, 415);
    let (status, _) = studio.post_json("/api/mine", &json!({ "text": 7 }));
    assert_eq!(status, 400);
    let (status, _) = studio.post_json("/api/mine", &json!({ "text": "", "path": "/etc" }));
    assert_eq!(status, 400);
    let (status, body) = studio.post_json(
        "/api/explain",
        &json!({ "text": program(RULES), "log": LOG_ID, "track": "nope", "frame": 1 }),
    );
    assert_eq!(status, 200);
    assert!(body["error"].as_str().expect("error").contains("no track"));
    let (_, body) = studio.post_json(
        "/api/explain",
        &json!({ "text": program(RULES), "log": LOG_ID, "track": "04a25b36", "frame": 99999 }),
    );
    assert!(body["error"].as_str().expect("error").contains("no frame"));

    // Another host name (a rebound DNS name) and another origin are refused.
    let (status, _) =
        studio.raw(b"GET /api/logs HTTP/1.1\r\nHost: evil.example\r\nConnection: close\r\n\r\n");
    assert_eq!(status, 403);
    let (status, _) = studio.post(
        "/api/mine",
        b"{\"text\": \"\"}",
        "Content-Type: application/json\r\nOrigin: http://evil.example\r\n",
    );
    assert_eq!(status, 403);

    // Bytes that are not HTTP: an error or a closed connection, and the studio still serves.
    let (status, _) = studio.raw(b"\x00\x01garbage\r\n\r\n");
    assert!(status == 400 || status == 0, "{status}");
    let (status, _) = studio.get("/api/logs");
    assert_eq!(status, 200);

    // A program deriving without end stops at the limit with an error, not a hang.
    let (status, body) = studio.post_json(
        "/api/mine",
        &json!({ "text": "n(0).\nn(X + 1) :- n(X).\nreferred(V, T) :- category(V, \"BUS\"), stopped(V, T), n(_).\n" }),
    );
    assert_eq!(status, 200);
    assert!(
        body["logs"][0]["error"].is_string(),
        "expected the limit's error: {body}"
    );
    let (code, err) = studio.interrupt();
    assert_eq!(code, Some(0), "{err}");
}

#[test]
fn studio_writes_a_rule_from_a_description_with_the_configured_llm_server() {
    let rule = "referred(V, T) :-\n    category(V, \"PEDESTRIAN\"),\n    stopped(V, T).";
    let llm = crate::server::Server::start(move |_, _| crate::server::program(rule));
    let studio = Studio::start(&["--base-url", &llm.base_url()]);
    let (_, logs) = studio.get("/api/logs");
    assert!(logs.contains("\"synthesize\":true"), "{logs}");
    let (status, written) = studio.post_json(
        "/api/synth",
        &json!({ "description": "stopped pedestrian" }),
    );
    assert_eq!(status, 200);
    assert_eq!(
        written["program"],
        format!("// description: stopped pedestrian\n{rule}\n"),
        "{written}"
    );
    assert_eq!(written["clean"], true);
    assert!(llm.requests()[0]
        .description()
        .contains("stopped pedestrian"));
    let (_, empty) = studio.post_json("/api/synth", &json!({ "description": "  " }));
    assert!(empty["error"].as_str().expect("error").contains("empty"));

    // In the page: the description's rule lands in the editor and is mined.
    if let Some(binary) = browser() {
        let mut page = Browser::open(&binary, &format!("http://{}/", studio.address));
        page.wait_for(
            "document.getElementById('describe').hidden === false && document.querySelectorAll('#matches button.match').length > 0",
            "the page with its description field",
        );
        page.eval("(() => { document.getElementById('description').value = 'stopped pedestrian'; document.getElementById('write').click(); return true; })()");
        page.wait_for(
            "document.getElementById('text').value.includes('PEDESTRIAN') && document.querySelectorAll('#matches button.match').length > 0 && [...document.querySelectorAll('#matches button.match')].every(b => b.textContent.includes(' PEDESTRIAN '))",
            "the written rule's matches",
        );
    }

    // Without a server, the page offers no synthesis and the request says why.
    let plain = Studio::start(&[]);
    let (_, logs) = plain.get("/api/logs");
    assert!(logs.contains("\"synthesize\":false"), "{logs}");
    let (_, refused) = plain.post_json("/api/synth", &json!({ "description": "bus" }));
    assert!(refused["error"]
        .as_str()
        .expect("error")
        .contains("no LLM server"));
}

#[test]
fn studio_refuses_a_non_loopback_address_unless_told_what_it_exposes() {
    let o = crate::util::scenalog()
        .args([
            "studio",
            "--address",
            "0.0.0.0",
            "--port",
            "0",
            "--logs",
            LOG,
        ])
        .output()
        .expect("run");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--expose-logs-to-network"), "{err}");
    let o = crate::util::scenalog()
        .args(["studio", "--port", "0", "--logs", "no/such/log"])
        .output()
        .expect("run");
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no/such/log"));
}

// ---- the page in a browser ---------------------------------------------------------------------

/// A headless Chromium showing one page, driven over the DevTools protocol.
struct Browser {
    child: Child,
    socket: tungstenite::WebSocket<TcpStream>,
    next_id: u64,
    _profile: tempfile::TempDir,
}

impl Browser {
    fn open(binary: &PathBuf, url: &str) -> Browser {
        let profile = tempfile::tempdir().expect("profile dir");
        let mut child = Command::new(binary)
            .args([
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--no-first-run",
                "--window-size=1600,900",
                "--remote-debugging-port=0",
            ])
            .arg(format!("--user-data-dir={}", profile.path().display()))
            .arg(url)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start chromium");
        // Chromium prints its DevTools address on stderr; the rest of stderr is drained by the
        // thread so the browser never blocks on a full pipe.
        let stderr = BufReader::new(child.stderr.take().expect("stderr"));
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for line in stderr.lines().map_while(Result::ok) {
                if let Some(rest) = line.split("ws://").nth(1) {
                    let port = rest
                        .split('/')
                        .next()
                        .and_then(|hp| hp.rsplit(':').next())
                        .map(str::to_string);
                    let _ = tx.send(port);
                }
            }
        });
        let port = rx.recv_timeout(Duration::from_secs(60)).ok().flatten();
        let port = port.expect("chromium printed no DevTools address");

        // The page's own socket, from the list of targets.
        let deadline = Instant::now() + Duration::from_secs(30);
        let ws = loop {
            let mut s = TcpStream::connect(format!("127.0.0.1:{port}")).expect("devtools");
            write!(
                s,
                "GET /json/list HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n"
            )
            .expect("write");
            // The DevTools server may keep the connection open: read what comes within a second.
            s.set_read_timeout(Some(Duration::from_secs(1)))
                .expect("timeout");
            let mut bytes = Vec::new();
            let _ = s.read_to_end(&mut bytes);
            let text = String::from_utf8_lossy(&bytes);
            let body = text.split_once("\r\n\r\n").map_or("", |(_, b)| b);
            let list: Value = serde_json::from_str(body).unwrap_or(json!([]));
            let found = list.as_array().and_then(|l| {
                l.iter()
                    .find(|t| t["type"] == "page")
                    .and_then(|t| t["webSocketDebuggerUrl"].as_str().map(str::to_string))
            });
            if let Some(ws) = found {
                break ws;
            }
            assert!(Instant::now() < deadline, "no page target: {body}");
            std::thread::sleep(Duration::from_millis(200));
        };
        let stream = TcpStream::connect(format!("127.0.0.1:{port}")).expect("devtools socket");
        stream
            .set_read_timeout(Some(Duration::from_secs(60)))
            .expect("timeout");
        let (socket, _) = tungstenite::client::client(ws.as_str(), stream).expect("handshake");
        Browser {
            child,
            socket,
            next_id: 0,
            _profile: profile,
        }
    }

    /// Sends a DevTools command and waits for its answer (events in between are skipped).
    fn call(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        let message = json!({ "id": id, "method": method, "params": params }).to_string();
        self.socket
            .send(tungstenite::Message::text(message))
            .expect("send");
        loop {
            let m = self.socket.read().expect("read");
            if let tungstenite::Message::Text(t) = m {
                let v: Value = serde_json::from_str(t.as_str()).expect("json");
                if v["id"] == id {
                    assert!(v.get("error").is_none(), "{method}: {v}");
                    return v["result"].clone();
                }
            }
        }
    }

    /// The value of a JavaScript expression in the page.
    fn eval(&mut self, expression: &str) -> Value {
        let r = self.call(
            "Runtime.evaluate",
            json!({ "expression": expression, "returnByValue": true, "awaitPromise": true }),
        );
        r["result"]["value"].clone()
    }

    /// Waits until the expression is true in the page (up to a minute).
    fn wait_for(&mut self, expression: &str, what: &str) {
        let deadline = Instant::now() + Duration::from_secs(60);
        while self.eval(expression) != json!(true) {
            if Instant::now() > deadline {
                let page = self.eval(
                    "['status', 'diagnostics', 'matches', 'proof'].map(id => document.getElementById(id).textContent).join(' | ')",
                );
                panic!("timed out waiting for {what}; the page shows: {page}");
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// Replaces the editor's text as typing does (select all, insert).
    fn type_text(&mut self, text: &str) {
        self.eval("(() => { const t = document.getElementById('text'); t.focus(); t.select(); return true; })()");
        self.call("Input.insertText", json!({ "text": text }));
    }

    /// Clicks at a point of the page (CSS pixels).
    fn click(&mut self, x: f64, y: f64) {
        for kind in ["mousePressed", "mouseReleased"] {
            self.call(
                "Input.dispatchMouseEvent",
                json!({ "type": kind, "x": x, "y": y, "button": "left", "clickCount": 1 }),
            );
        }
    }

    fn text_of(&mut self, id: &str) -> String {
        self.eval(&format!("document.getElementById('{id}').textContent"))
            .as_str()
            .unwrap_or_default()
            .to_string()
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn studio_page_shows_diagnostics_matches_and_the_proof_of_a_clicked_track() {
    let Some(binary) = browser() else {
        eprintln!(
            "skipped the browser check: no chromium on PATH (Debian: apt-get install -y chromium)"
        );
        return;
    };
    let studio = Studio::start(&[]);
    let mut page = Browser::open(
        &binary,
        &format!("http://{}/#program=stopped_car", studio.address),
    );
    page.wait_for(
        "document.querySelectorAll('#matches button.match').length > 0",
        "the library program's matches",
    );

    // A misspelt relation: the diagnostic is listed and marked in the text; no mining.
    page.type_text("referred(V, T) :-\n    category(V, \"PEDESTRIAN\"),\n    stoped(V, T).\n");
    page.wait_for(
        "[...document.querySelectorAll('#diagnostics li.error')].some(l => l.textContent.includes('stoped'))",
        "the diagnostic of the misspelt relation",
    );
    let marked = page.eval("document.querySelector('#backdrop mark.error').textContent");
    assert_eq!(marked, json!("stoped"));

    // Fixed: clean, and the matches are this program's (pedestrians only).
    page.type_text("referred(V, T) :-\n    category(V, \"PEDESTRIAN\"),\n    stopped(V, T).\n");
    page.wait_for(
        "document.querySelector('#diagnostics li.clean') !== null && document.querySelectorAll('#matches button.match').length > 0 && [...document.querySelectorAll('#matches button.match')].every(b => b.textContent.includes(' PEDESTRIAN '))",
        "the fixed program's matches",
    );
    let status = page.text_of("status");
    assert!(status.contains("matched tracks on 1 logs in"), "{status}");

    // Click the first match: its proof.
    let rect = page.eval("(() => { const r = document.querySelector('#matches button.match').getBoundingClientRect(); return [r.x + r.width / 2, r.y + r.height / 2]; })()");
    let uuid = page.eval("document.querySelector('#matches button.match').dataset.track");
    let uuid = uuid.as_str().expect("uuid").to_string();
    page.click(rect[0].as_f64().expect("x"), rect[1].as_f64().expect("y"));
    page.wait_for(
        "document.getElementById('proof').textContent.includes('Proof:')",
        "the proof of the clicked match",
    );
    let proof = page.text_of("proof");
    assert!(
        proof.contains(&uuid) && proof.contains("stopped(V, T)"),
        "{proof}"
    );
    let hash = page.eval("location.hash");
    assert!(
        hash.as_str()
            .expect("hash")
            .contains(&format!("track={uuid}")),
        "{hash}"
    );

    // Click the ego vehicle on the map (brought into view as panning would): why it is not
    // referred, with the failing literal.
    let at = page.eval(
        "(() => { const s = state.scenes[state.log]; const ego = s.tracks.find(t => t.category === 'EGO_VEHICLE'); centreOn(ego.uuid); draw(); const b = boxAt(ego, state.frame); const [px, py] = toPixel(b[0], b[1]); const r = document.getElementById('map').getBoundingClientRect(); const k = r.width / document.getElementById('map').width; return [r.x + px * k, r.y + py * k]; })()",
    );
    page.click(at[0].as_f64().expect("x"), at[1].as_f64().expect("y"));
    page.wait_for(
        "document.getElementById('proof').textContent.includes('Why not:')",
        "the why-not report of the ego vehicle",
    );
    let why_not = page.text_of("proof");
    assert!(
        why_not.contains("EGO_VEHICLE") && why_not.contains("✗ category(V, \"PEDESTRIAN\")"),
        "{why_not}"
    );

    // The address `mine` prints for its first match opens the studio at that match (here as a
    // new address in the same tab, as when a link is pasted).
    let out = tempfile::tempdir().expect("tempdir");
    let o = mine(out.path());
    let printed = String::from_utf8_lossy(&o.stdout);
    assert!(
        printed.contains(&format!(
            "scenalog studio --rules rules/library --logs {LOG}"
        )),
        "{printed}"
    );
    let url = printed
        .split_whitespace()
        .find(|w| w.starts_with("http://127.0.0.1:7878/#program=stopped_car&log="))
        .unwrap_or_else(|| panic!("no studio address in: {printed}"));
    let track = url
        .split("track=")
        .nth(1)
        .and_then(|r| r.split('&').next())
        .expect("track")
        .to_string();
    let here = url.replacen("127.0.0.1:7878", &studio.address, 1);
    page.call("Page.navigate", json!({ "url": here }));
    page.wait_for(
        &format!("document.getElementById('proof').textContent.includes('track {track}') && document.getElementById('proof').textContent.includes('Proof:') && document.getElementById('program').value === 'stopped_car'"),
        "the match mine printed, opened from its address",
    );
    drop(page);
    let (code, err) = studio.interrupt();
    assert_eq!(code, Some(0), "{err}");
}
