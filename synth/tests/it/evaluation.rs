//! `evaluation`: a description set through the scripted server, with held-out prompts.

use crate::support;

use std::time::Duration;

use scenalog_synth::evaluation::evaluate;
use scenalog_synth::Price;
use scenalog_synth::{Example, LlmConfig, SynthConfig, Synthesizer};
use support::server::{program, with_usage, Reply, Server};

const LEFT: &str = "referred(V, T) :- category(V, \"VEHICLE\"), turning(V, T, \"left\").";
const STOPPED: &str = "referred(V, T) :- category(V, \"VEHICLE\"), speed(V, T, S), S < 0.5 m/s.";
const UNKNOWN: &str = "referred(V, T) :- category(V, \"VEHICLE\"), halted(V, T).";

fn config(server: &Server) -> SynthConfig {
    SynthConfig {
        llm: LlmConfig {
            base_url: server.base_url(),
            model: "test-model".into(),
            api_key: None,
            timeout: Duration::from_secs(5),
            connect_timeout: Duration::from_secs(2),
            max_retries: 0,
            backoff: Duration::from_millis(10),
            max_backoff: Duration::from_millis(50),
            temperature: Some(0.0),
            grammar: None,
        },
        cache_dir: None,
        rounds: 3,
        library: vec![
            Example::new(
                "stopped_vehicle.dl",
                &format!("// description: stopped vehicle\n{STOPPED}\n"),
            ),
            Example::new(
                "stopped_vehicles.dl",
                &format!("// description: Stopped vehicles\n{STOPPED}\n"),
            ),
            Example::new(
                "vehicle_turning_left.dl",
                &format!("// description: vehicle turning left\n{LEFT}\n"),
            ),
        ],
        examples: None,
        held_out: true,
        candidates: 1,
        sample_temperature: scenalog_synth::search::SAMPLE_TEMPERATURE,
        matcher: None,
        max_tokens: None,
        evidence_rounds: 0,
        evidence: None,
    }
}

#[test]
fn held_out_prompts_leave_out_the_answer_and_its_near_duplicates() {
    let server = Server::scripted(vec![program(STOPPED)]);
    let s = Synthesizer::new(config(&server)).expect("synth");
    let user = &s.prompt("stopped vehicle")[1].content;
    assert!(!user.contains("// description: stopped vehicle"), "{user}");
    assert!(!user.contains("// description: Stopped vehicles"), "{user}");
    assert!(
        user.contains("// description: vehicle turning left"),
        "{user}"
    );
    // Without held-out, the answer is among the examples.
    let mut open = config(&server);
    open.held_out = false;
    let s = Synthesizer::new(open).expect("synth");
    assert!(s.prompt("stopped vehicle")[1]
        .content
        .contains("// description: stopped vehicle"));
}

#[test]
fn the_report_counts_rounds_and_programs_that_match_nothing() {
    let prose = Reply::Completion("I cannot write that.".into());
    let server = Server::scripted(vec![
        program(LEFT),    // vehicle making a left turn: clean in round 1
        program(UNKNOWN), // stopped vehicle: an unknown predicate, then clean in round 2
        program(STOPPED),
        prose.clone(), // flying car: never any code
        prose.clone(),
        prose,
    ]);
    let s = Synthesizer::new(config(&server)).expect("synth");
    let descriptions: Vec<String> = [
        "vehicle making a left turn",
        "stopped vehicle",
        "flying car",
    ]
    .iter()
    .map(|d| d.to_string())
    .collect();
    // Stand-in for a run on the sample logs: turning programs find nothing there.
    let mut asked = Vec::new();
    let report = evaluate(&s, &descriptions, |p| {
        asked.push(p.to_string());
        Ok(if p.contains("turning") { 0 } else { 12 })
    });
    assert_eq!(asked.len(), 2, "only clean programs are run");
    assert_eq!(report.clean_first_round(), 1);
    assert_eq!(report.clean(), 2);
    assert!(
        (report.mean_rounds() - 2.0).abs() < 1e-9,
        "{}",
        report.mean_rounds()
    );
    assert_eq!(report.match_nothing(), vec!["vehicle making a left turn"]);
    let text = report.render();
    assert!(
        text.contains("clean on round 1                  1 (33 %)"),
        "{text}"
    );
    assert!(
        text.contains("clean within 3 rounds             2 (67 %)"),
        "{text}"
    );
    assert!(
        text.contains("mean rounds                       2.00"),
        "{text}"
    );
    assert!(text.contains("  not clean: flying car"), "{text}");
    // Held out: the "stopped vehicle" request showed no stopped-vehicle example.
    let reqs = server.requests();
    let stopped = reqs
        .iter()
        .find(|r| r.description() == "stopped vehicle")
        .expect("a request for stopped vehicle");
    assert!(!stopped.messages()[1].contains("// description: stopped vehicle"));
}

/// The server's `usage` per description and in total: with cached-token details, without them
/// (nothing counted as cached), and without `usage` at all (counted as such, no tokens).
#[test]
fn usage_with_and_without_cached_details_and_without_usage() {
    let server = Server::scripted(vec![
        // "vehicle turning left": wrong, then right: 1000 + 1200 prompt (0 + 900 cached).
        with_usage(program(UNKNOWN), 1000, Some(0), 40),
        with_usage(program(LEFT), 1200, Some(900), 30),
        // "stopped vehicle": no cached-token details.
        with_usage(program(STOPPED), 800, None, 20),
        // "vehicle turning right": no usage at all.
        program(LEFT),
    ]);
    let s = Synthesizer::new(config(&server)).expect("synth");
    let set = [
        "vehicle turning left".to_string(),
        "stopped vehicle".to_string(),
        "vehicle turning right".to_string(),
    ];
    let mut report = evaluate(&s, &set, |_| Ok(1));
    let u: Vec<_> = report.items.iter().map(|i| i.usage).collect();
    assert_eq!(
        (
            u[0].prompt_tokens,
            u[0].cached_tokens,
            u[0].completion_tokens,
            u[0].completions
        ),
        (2200, 900, 70, 2)
    );
    assert_eq!(u[0].uncached_tokens(), 1300);
    assert_eq!(
        (
            u[1].prompt_tokens,
            u[1].cached_tokens,
            u[1].completion_tokens
        ),
        (800, 0, 20)
    );
    assert_eq!(
        (u[2].prompt_tokens, u[2].completions, u[2].without_usage),
        (0, 1, 1)
    );
    let total = report.usage();
    assert_eq!(
        (
            total.prompt_tokens,
            total.cached_tokens,
            total.completion_tokens
        ),
        (3000, 900, 90)
    );
    assert_eq!((total.completions, total.without_usage), (4, 1));
    assert_eq!(s.stats().usage, total);
    // Priced: 2100 uncached at 2, 900 cached at 0.5, 90 output at 8 (per million).
    report.price = Some(Price::parse("2,0.5,8").expect("price"));
    let want = (2100.0 * 2.0 + 900.0 * 0.5 + 90.0 * 8.0) / 1e6;
    let j = report.to_json();
    assert!(
        (j["usage"]["cost"].as_f64().unwrap() - want).abs() < 1e-15,
        "{j:#}"
    );
    assert_eq!(j["usage"]["cached_tokens"], 900);
    assert_eq!(j["usage"]["without_usage"], 1);
    assert_eq!(j["items"][0]["usage"]["uncached_tokens"], 1300);
    assert!(j["items"][2]["usage"]["cost"].as_f64() == Some(0.0));
    let text = report.render();
    assert!(
        text.contains("tokens: cached input              900"),
        "{text}"
    );
    assert!(
        text.contains("1 of 4 server answers reported no usage"),
        "{text}"
    );
    assert!(text.contains(&format!("{want:.4}")), "{text}");
}
