//! The repair loop, the client and the cache against a real HTTP server on 127.0.0.1 that
//! answers from a script.

use crate::support;

use std::time::Duration;

use scenalog_synth::repair::{RoundResult, NO_CODE_FEEDBACK};
use scenalog_synth::{
    Cache, ClientError, Example, LlmConfig, Message, Outcome, SynthConfig, Synthesizer,
};
use support::server::{program, Reply, Server};

const GOOD: &str = "referred(V, T) :- category(V, \"VEHICLE\"), turning(V, T, \"left\").";
const UNKNOWN: &str = "referred(V, T) :- category(V, \"VEHICLE\"), turning_left(V, T).";
const DESCRIPTION: &str = "vehicle making a left turn";

fn llm(server: &Server) -> LlmConfig {
    LlmConfig {
        base_url: server.base_url(),
        model: "test-model".into(),
        api_key: Some("sk-test".into()),
        timeout: Duration::from_secs(5),
        connect_timeout: Duration::from_secs(2),
        max_retries: 2,
        backoff: Duration::from_millis(10),
        max_backoff: Duration::from_millis(200),
        temperature: Some(0.0),
        grammar: None,
    }
}

fn config(server: &Server) -> SynthConfig {
    SynthConfig {
        llm: llm(server),
        cache_dir: None,
        rounds: 3,
        library: vec![Example::new(
            "stopped_vehicle.dl",
            "// description: stopped vehicle\nreferred(V, T) :- category(V, \"VEHICLE\"), speed(V, T, S), S < 0.5 m/s.\n",
        )],
        examples: None,
        held_out: false,
        candidates: 1,
        sample_temperature: scenalog_synth::search::SAMPLE_TEMPERATURE,
        matcher: None,
        max_tokens: None,
        evidence_rounds: 0,
        evidence: None,
    }
}

fn synth(config: SynthConfig) -> Synthesizer {
    Synthesizer::new(config).expect("synthesizer")
}

#[test]
fn a_correct_program_is_clean_in_round_one() {
    let server = Server::scripted(vec![program(GOOD)]);
    let s = synth(config(&server));
    let t = s.synthesize(DESCRIPTION);
    assert_eq!(t.outcome, Outcome::Clean { round: 1 }, "{}", t.to_json());
    assert_eq!(t.rounds.len(), 1);
    assert_eq!(t.rounds[0].result, RoundResult::Clean);
    assert!(!t.rounds[0].cached);
    assert_eq!(
        t.program(),
        Some(format!("// description: {DESCRIPTION}\n{GOOD}\n").as_str())
    );
    // The request speaks the protocol.
    let reqs = server.requests();
    assert_eq!(reqs.len(), 1);
    assert_eq!(reqs[0].line, "POST /v1/chat/completions HTTP/1.1");
    assert_eq!(reqs[0].header("authorization"), Some("Bearer sk-test"));
    assert_eq!(reqs[0].json["model"], "test-model");
    assert_eq!(reqs[0].json["temperature"], 0.0);
    let roles: Vec<_> = reqs[0].json["messages"]
        .as_array()
        .expect("messages")
        .iter()
        .map(|m| m["role"].as_str().unwrap_or_default().to_string())
        .collect();
    assert_eq!(roles, ["system", "user"]);
    assert!(reqs[0].messages()[0].contains("lane_change(X: track, T: time, Dir: str)"));
    assert!(reqs[0].messages()[1].contains("// description: stopped vehicle"));
    assert_eq!(reqs[0].description(), DESCRIPTION);
    assert_eq!(s.stats().requests, 1);
}

#[test]
fn an_unknown_predicate_is_sent_back_and_repaired() {
    let server = Server::scripted(vec![program(UNKNOWN), program(GOOD)]);
    let s = synth(config(&server));
    let t = s.synthesize(DESCRIPTION);
    assert_eq!(t.outcome, Outcome::Clean { round: 2 }, "{}", t.to_json());
    let r1 = &t.rounds[0];
    assert_eq!(r1.result, RoundResult::Errors);
    assert!(r1.errors >= 1);
    let diags = r1.diagnostics.as_array().expect("array");
    let unknown = diags
        .iter()
        .find(|d| {
            d["message"]
                .as_str()
                .unwrap_or_default()
                .contains("turning_left")
        })
        .expect("a diagnostic naming turning_left");
    assert_eq!(unknown["severity"], "error");
    // Line 2: the description comment is line 1.
    assert_eq!(unknown["line"], 2);
    let feedback = r1.feedback.as_deref().expect("feedback");
    // The JSON block parses and is the round's diagnostics.
    let json = feedback
        .split_once("```json\n")
        .and_then(|(_, rest)| rest.split_once("\n```"))
        .map(|(j, _)| j)
        .expect("a json block");
    let parsed: serde_json::Value = serde_json::from_str(json).expect("feedback json");
    assert_eq!(parsed, r1.diagnostics);
    assert!(
        feedback.contains(&format!("   2 | {UNKNOWN}")),
        "{feedback}"
    );
    // The second request carries the first answer and the feedback.
    let reqs = server.requests();
    assert_eq!(reqs.len(), 2);
    let m = reqs[1].json["messages"].as_array().expect("messages");
    assert_eq!(m.len(), 4);
    assert_eq!(m[2]["role"], "assistant");
    assert_eq!(m[2]["content"], r1.completion.as_str());
    assert_eq!(m[3]["role"], "user");
    assert_eq!(m[3]["content"], feedback);
    assert_eq!(t.rounds[1].result, RoundResult::Clean);
    assert!(t.rounds[1].feedback.is_none());
}

#[test]
fn prose_without_code_is_a_failed_round_with_a_clear_message() {
    let prose = Reply::Completion("A left turn is when a vehicle turns to the left.".into());
    let server = Server::scripted(vec![prose, program(GOOD)]);
    let t = synth(config(&server)).synthesize(DESCRIPTION);
    assert_eq!(t.outcome, Outcome::Clean { round: 2 });
    assert_eq!(t.rounds[0].result, RoundResult::NoCode);
    assert_eq!(t.rounds[0].program, None);
    assert_eq!(t.rounds[0].feedback.as_deref(), Some(NO_CODE_FEEDBACK));
    assert_eq!(server.requests()[1].last_message(), NO_CODE_FEEDBACK);
}

#[test]
fn rounds_run_out_and_the_last_attempt_is_kept() {
    let server = Server::start(|_, _| program(UNKNOWN));
    let mut c = config(&server);
    c.rounds = 3;
    let t = synth(c).synthesize(DESCRIPTION);
    assert_eq!(t.outcome, Outcome::Failed);
    assert_eq!(t.rounds.len(), 3);
    assert!(t.rounds.iter().all(|r| r.result == RoundResult::Errors));
    // Feedback went back after rounds 1 and 2, not after the last.
    assert!(t.rounds[0].feedback.is_some() && t.rounds[1].feedback.is_some());
    assert!(t.rounds[2].feedback.is_none());
    assert_eq!(server.count(), 3);
    assert_eq!(
        server.requests()[2].json["messages"]
            .as_array()
            .map(Vec::len),
        Some(6)
    );
    assert!(t.program().is_some_and(|p| p.contains("turning_left")));
    assert!(!t.diagnostics().as_array().expect("array").is_empty());
    // The transcript serialises.
    let json: serde_json::Value = serde_json::from_str(&t.to_json()).expect("json");
    assert_eq!(json["outcome"]["status"], "failed");
    assert_eq!(json["rounds"].as_array().map(Vec::len), Some(3));
}

#[test]
fn a_429_is_retried_after_retry_after() {
    let server = Server::scripted(vec![
        Reply::Error {
            status: 429,
            message: "slow down".into(),
            retry_after: Some("0".into()),
        },
        Reply::Error {
            status: 503,
            message: "loading model".into(),
            retry_after: None,
        },
        program(GOOD),
    ]);
    let s = synth(config(&server));
    let t = s.synthesize(DESCRIPTION);
    assert_eq!(t.outcome, Outcome::Clean { round: 1 });
    assert_eq!(server.count(), 3);
    // One completion, however many HTTP attempts it took.
    assert_eq!(s.stats().requests, 1);
}

#[test]
fn retries_stop_and_the_status_is_reported() {
    let server = Server::start(|_, _| Reply::Error {
        status: 500,
        message: "out of memory".into(),
        retry_after: None,
    });
    let client = scenalog_synth::Client::new(llm(&server));
    let e = client.complete(&[Message::user("hi")]).unwrap_err();
    match &e {
        ClientError::Status {
            status,
            attempts,
            message,
            ..
        } => {
            assert_eq!((*status, *attempts), (500, 3));
            assert_eq!(message, "out of memory");
        }
        other => panic!("expected a status error, got {other:?}"),
    }
    assert_eq!(server.count(), 3);
}

#[test]
fn a_401_fails_at_once_with_the_servers_message() {
    let server = Server::scripted(vec![Reply::Error {
        status: 401,
        message: "Incorrect API key provided".into(),
        retry_after: None,
    }]);
    let t = synth(config(&server)).synthesize(DESCRIPTION);
    match &t.outcome {
        Outcome::Unreachable { error } => {
            assert!(error.contains("401"), "{error}");
            assert!(error.contains("Incorrect API key provided"), "{error}");
        }
        other => panic!("expected unreachable, got {other:?}"),
    }
    assert!(t.rounds.is_empty());
    assert_eq!(server.count(), 1);
}

#[test]
fn malformed_json_is_reported_not_retried() {
    let server = Server::scripted(vec![Reply::Raw {
        status: 200,
        body: "{\"choices\": [ {\"message\": ".into(),
    }]);
    let t = synth(config(&server)).synthesize(DESCRIPTION);
    match &t.outcome {
        Outcome::Unreachable { error } => {
            assert!(error.contains("not a chat completion"), "{error}");
            assert!(error.contains("invalid JSON"), "{error}");
        }
        other => panic!("expected unreachable, got {other:?}"),
    }
    assert_eq!(server.count(), 1);
}

#[test]
fn a_timeout_is_retried_then_reported() {
    // One hang, then an answer: the retry succeeds.
    let server = Server::scripted(vec![
        Reply::Hang(Duration::from_millis(2500)),
        program(GOOD),
    ]);
    let mut c = config(&server);
    c.llm.timeout = Duration::from_secs(1);
    let t = synth(c).synthesize(DESCRIPTION);
    assert_eq!(t.outcome, Outcome::Clean { round: 1 });
    assert_eq!(server.count(), 2);

    // Always hanging: the client gives up after its retries with a transport error.
    let server = Server::start(|_, _| Reply::Hang(Duration::from_secs(2)));
    let mut l = llm(&server);
    l.timeout = Duration::from_millis(800);
    l.max_retries = 1;
    let e = scenalog_synth::Client::new(l)
        .complete(&[Message::user("hi")])
        .unwrap_err();
    match &e {
        ClientError::Unreachable {
            attempts, message, ..
        } => {
            assert_eq!(*attempts, 2);
            assert!(
                message.to_lowercase().contains("timeout")
                    || message.to_lowercase().contains("timed out"),
                "{message}"
            );
        }
        other => panic!("expected unreachable, got {other:?}"),
    }
    assert_eq!(server.count(), 2);
}

#[test]
fn nothing_listening_is_unreachable() {
    // A port that was free a moment ago.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("port");
    let l = LlmConfig {
        base_url: format!("http://127.0.0.1:{port}/v1"),
        max_retries: 1,
        backoff: Duration::from_millis(1),
        ..LlmConfig::default()
    };
    let e = scenalog_synth::Client::new(l)
        .complete(&[Message::user("hi")])
        .unwrap_err();
    assert!(
        matches!(e, ClientError::Unreachable { attempts: 2, .. }),
        "{e:?}"
    );
    assert!(e.to_string().contains(&port.to_string()));
}

#[test]
fn the_cache_answers_a_rerun_without_requests() {
    let dir = tempfile::tempdir().expect("tempdir");
    let server = Server::scripted(vec![program(UNKNOWN), program(GOOD)]);
    let mut c = config(&server);
    c.cache_dir = Some(dir.path().join("cache"));
    let first = synth(c.clone()).synthesize(DESCRIPTION);
    assert_eq!(first.outcome, Outcome::Clean { round: 2 });
    assert_eq!(server.count(), 2);
    // Both completions are on disk, named by the hash of the model and the messages.
    let entries = std::fs::read_dir(dir.path().join("cache"))
        .expect("cache dir")
        .count();
    assert_eq!(entries, 2);

    let s = synth(c);
    let second = s.synthesize(DESCRIPTION);
    assert_eq!(server.count(), 2, "the rerun asked the server");
    assert_eq!(s.stats().requests, 0);
    assert_eq!(s.stats().cache_hits, 2);
    assert!(second.rounds.iter().all(|r| r.cached));
    assert_eq!(second.outcome, first.outcome);
    assert_eq!(second.program(), first.program());

    // A different model is a different key.
    let key = Cache::key("test-model", &s.prompt(DESCRIPTION));
    assert!(dir
        .path()
        .join("cache")
        .join(format!("{key}.json"))
        .exists());
    assert_ne!(key, Cache::key("other-model", &s.prompt(DESCRIPTION)));
}

#[test]
fn a_completion_is_cached_before_a_later_failure() {
    let dir = tempfile::tempdir().expect("tempdir");
    // Round 1 answers, round 2's request finds the server refusing (401).
    let server = Server::scripted(vec![
        program(UNKNOWN),
        Reply::Error {
            status: 401,
            message: "key revoked".into(),
            retry_after: None,
        },
    ]);
    let mut c = config(&server);
    c.cache_dir = Some(dir.path().to_path_buf());
    let t = synth(c.clone()).synthesize(DESCRIPTION);
    assert!(matches!(t.outcome, Outcome::Unreachable { .. }));
    assert_eq!(t.rounds.len(), 1, "the answered round is kept");

    // With the server back, only the missing completion is asked for.
    let server2 = Server::scripted(vec![program(GOOD)]);
    c.llm.base_url = server2.base_url();
    let t = synth(c).synthesize(DESCRIPTION);
    assert_eq!(t.outcome, Outcome::Clean { round: 2 });
    assert!(t.rounds[0].cached && !t.rounds[1].cached);
    assert_eq!(server2.count(), 1);
}

#[test]
fn a_warning_that_changes_meaning_is_sent_back_once() {
    // `>= 2.0` compares a time with a bare float: 0.2 s, not two seconds (W0504).
    const FRAMES: &str = "referred(V, T2) :- category(V, \"VEHICLE\"), turning(V, T1, \"left\"), turning(V, T2, \"left\"), T2 - T1 >= 2.0.";
    const FIXED: &str = "referred(V, T2) :- category(V, \"VEHICLE\"), turning(V, T1, \"left\"), turning(V, T2, \"left\"), T2 - T1 >= 2 s.";
    let server = Server::scripted(vec![program(FRAMES), program(FIXED)]);
    let s = synth(config(&server));
    let t = s.synthesize(DESCRIPTION);
    assert_eq!(t.outcome, Outcome::Clean { round: 2 }, "{}", t.to_json());
    assert_eq!(t.rounds[0].result, RoundResult::Warnings);
    assert_eq!(t.rounds[0].errors, 0);
    let feedback = t.rounds[0].feedback.as_deref().expect("feedback");
    assert!(
        feedback.contains("W0504") && feedback.contains("`T2 - T1 >= 2 s`"),
        "{feedback}"
    );
    assert!(t.program().is_some_and(|p| p.contains(">= 2 s.")));
    // Kept as it is after the warning: clean, not sent back again.
    let server = Server::scripted(vec![program(FRAMES), program(FRAMES), program(GOOD)]);
    let t = synth(config(&server)).synthesize(DESCRIPTION);
    assert_eq!(t.outcome, Outcome::Clean { round: 2 }, "{}", t.to_json());
    assert_eq!(server.requests().len(), 2);
}
