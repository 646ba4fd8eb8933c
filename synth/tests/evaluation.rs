//! `evaluation`: a description set through the scripted server, with held-out prompts.

mod support;

use std::time::Duration;

use scenalog_synth::evaluation::evaluate;
use scenalog_synth::{Example, LlmConfig, SynthConfig, Synthesizer};
use support::server::{program, Reply, Server};

const LEFT: &str = "referred(V, T) :- category(V, \"VEHICLE\"), turning(V, T, \"left\").";
const STOPPED: &str = "referred(V, T) :- category(V, \"VEHICLE\"), speed(V, T, S), S < 0.5.";
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
