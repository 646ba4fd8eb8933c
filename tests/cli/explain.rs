//! End-to-end tests of `scenalog explain` on the real logs: a known match of the stopped-car
//! scenario (the track found from the log's own `speed`, `category` and `stationary` facts),
//! known non-matches with `--why-not` (a moving vehicle fails `S < 0.5` with its speed; a
//! parked one fails `!stationary(V)`), the JSON shape, and bad inputs.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use expect_test::expect_file;
use serde_json::Value as Json;

const STOPPED: &str = "tests/support/stopped_not_parked.dl";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn logs() -> Vec<PathBuf> {
    let dir = scenalog_testkit::sample_logs_dir();
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    v.sort();
    v
}

/// Runs the binary: (exit code, stdout, stderr).
fn scenalog(args: &[&str]) -> (i32, String, String) {
    let out = crate::util::scenalog()
        .args(args)
        .current_dir(root())
        .output()
        .unwrap_or_else(|e| panic!("cannot run scenalog: {e}"));
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn relation(log: &Path, name: &str) -> Vec<Vec<Json>> {
    let log = log.to_string_lossy();
    let (code, out, err) = scenalog(&["facts", &log, "--relation", name, "--json"]);
    assert_eq!(code, 0, "facts --relation {name}: {err}");
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("facts json for {name}: {e}"))
}

/// What the tests need to know about one log, from `scenalog facts`.
struct LogFacts {
    /// Speed per (uuid, frame).
    speed: BTreeMap<String, BTreeMap<u64, f64>>,
    vehicles: BTreeSet<String>,
    stationary: BTreeSet<String>,
    seconds: BTreeMap<u64, f64>,
}

fn facts(log: &Path) -> LogFacts {
    let mut speed: BTreeMap<String, BTreeMap<u64, f64>> = BTreeMap::new();
    for r in relation(log, "speed") {
        if let (Some(u), Some(t), Some(s)) = (r[0].as_str(), r[1].as_u64(), r[2].as_f64()) {
            speed.entry(u.to_string()).or_default().insert(t, s);
        }
    }
    let vehicles = relation(log, "category")
        .into_iter()
        .filter(|r| r[1].as_str() == Some("VEHICLE"))
        .filter_map(|r| r[0].as_str().map(str::to_string))
        .collect();
    let stationary = relation(log, "stationary")
        .into_iter()
        .filter_map(|r| r[0].as_str().map(str::to_string))
        .collect();
    let seconds = relation(log, "seconds")
        .into_iter()
        .filter_map(|r| Some((r[0].as_u64()?, r[1].as_f64()?)))
        .collect();
    LogFacts {
        speed,
        vehicles,
        stationary,
        seconds,
    }
}

/// A stopped car by the rule's own definition, computed from the log's facts: a vehicle, not
/// stationary, with some frame of speed < 0.5. Returns (log, uuid, frames where it is stopped).
fn stopped_car() -> (PathBuf, LogFacts, String, Vec<(u64, f64)>) {
    for log in logs() {
        let f = facts(&log);
        let found = f
            .vehicles
            .iter()
            .filter(|u| !f.stationary.contains(*u) && !u.starts_with("ego"))
            .find_map(|u| {
                let slow: Vec<(u64, f64)> = f
                    .speed
                    .get(u)?
                    .iter()
                    .filter(|(_, s)| **s < 0.5)
                    .map(|(t, s)| (*t, *s))
                    .collect();
                (!slow.is_empty()).then(|| (u.clone(), slow))
            });
        if let Some((u, slow)) = found {
            return (log, f, u, slow);
        }
    }
    panic!("no log has a stopped car by the facts");
}

/// A moving vehicle: not stationary and never below 0.5 m/s.
fn moving_car(f: &LogFacts) -> Option<(String, u64, f64)> {
    f.vehicles
        .iter()
        .filter(|u| !f.stationary.contains(*u))
        .find_map(|u| {
            let sp = f.speed.get(u)?;
            if sp.values().all(|s| *s >= 0.5) && sp.len() > 10 {
                let (t, s) = sp.iter().nth(sp.len() / 2)?;
                Some((u.clone(), *t, *s))
            } else {
                None
            }
        })
}

#[test]
fn a_stopped_car_is_explained_with_its_speed_and_rule() {
    let (log, f, uuid, slow) = stopped_car();
    let log_s = log.to_string_lossy();
    let (code, out, err) = scenalog(&[
        "explain", "--rules", STOPPED, "--log", &log_s, "--track", &uuid,
    ]);
    assert_eq!(code, 0, "{err}\n{out}");
    // Referred exactly in the frames where its speed is below 0.5.
    assert!(
        out.contains(&format!("is referred in {} frame", slow.len())),
        "{out}"
    );
    let (first, s) = slow[0];
    let secs = f.seconds[&first];
    assert!(
        out.contains(&format!("at {secs:.1} s (frame {first}): referred")),
        "{out}"
    );
    // Each body fact with its value: the speed the log holds.
    assert!(out.contains(&uuid[..8]), "{out}");
    assert!(
        out.contains(&format!("speed = {s:.2} m/s < 0.5")),
        "expected speed {s:.2}:\n{out}"
    );
    // The whole text (the rule's source, the proof's facts, no why-not): its wording is the
    // snapshot's, updated with `UPDATE_EXPECT=1 cargo test --test cli explain::`.
    assert!(!out.contains("Why not:"), "{out}");
    expect_file!["snapshots/explain_stopped_car.txt"].assert_eq(&placeless(&out));
}

/// `text` with this checkout's root written `<repo>`, so a snapshot is the same everywhere.
fn placeless(text: &str) -> String {
    text.replace(&root().to_string_lossy().into_owned(), "<repo>")
}

#[test]
fn a_moving_car_is_not_referred_and_why_not_names_the_comparison_and_its_value() {
    let (log, f, _, _) = stopped_car();
    let Some((uuid, t, s)) = moving_car(&f) else {
        panic!("no moving vehicle in {}", log.display());
    };
    let log_s = log.to_string_lossy();
    let at = format!("{}", f.seconds[&t]);
    let (code, out, err) = scenalog(&[
        "explain",
        "--rules",
        STOPPED,
        "--log",
        &log_s,
        "--track",
        &uuid,
        "--at",
        &at,
        "--why-not",
    ]);
    assert_eq!(code, 0, "{err}\n{out}");
    assert!(out.contains("is referred in 0 frames"), "{out}");
    assert!(out.contains(&format!("(frame {t}): NOT referred")), "{out}");
    assert!(
        out.contains(&format!("speed = {s:.2} m/s < 0.5  is false")),
        "expected speed {s:.2}:\n{out}"
    );
    // The literals before it held: the whole text is the snapshot's.
    expect_file!["snapshots/explain_moving_car_why_not.txt"].assert_eq(&placeless(&out));
}

#[test]
fn a_parked_car_fails_the_negation_and_the_report_is_automatic() {
    let mut checked = 0;
    for log in logs() {
        let f = facts(&log);
        let Some(uuid) = f.vehicles.iter().find(|u| {
            f.stationary.contains(*u)
                && f.speed
                    .get(*u)
                    .is_some_and(|s| s.values().any(|v| *v < 0.5))
        }) else {
            continue;
        };
        let log_s = log.to_string_lossy();
        // No --why-not: not referred anywhere, so the report comes by itself.
        let (code, out, err) = scenalog(&[
            "explain", "--rules", STOPPED, "--log", &log_s, "--track", uuid,
        ]);
        assert_eq!(code, 0, "{err}\n{out}");
        assert!(out.contains("Why not:"), "{out}");
        assert!(out.contains("is referred in 0 frames"), "{out}");
        // At a slow frame the comparison holds and the negation fails.
        let (t, _) = f.speed[uuid]
            .iter()
            .find(|(_, v)| **v < 0.5)
            .map(|(t, v)| (*t, *v))
            .unwrap_or_default();
        let at = format!("{}", f.seconds[&t]);
        let (code, out, err) = scenalog(&[
            "explain", "--rules", STOPPED, "--log", &log_s, "--track", uuid, "--at", &at,
        ]);
        assert_eq!(code, 0, "{err}\n{out}");
        assert!(out.contains("✓ S < 0.5"), "{out}");
        assert!(out.contains("✗ !stationary(V)"), "{out}");
        assert!(out.contains(&format!("stationary({}", &uuid[..8])), "{out}");
        assert!(out.contains(") holds"), "{out}");
        checked += 1;
        break;
    }
    assert_eq!(checked, 1, "no log has a parked vehicle with a slow frame");
}

#[test]
fn json_output_has_the_documented_shape() {
    let (log, f, uuid, slow) = stopped_car();
    let log_s = log.to_string_lossy();
    let (code, out, err) = scenalog(&[
        "explain", "--rules", STOPPED, "--log", &log_s, "--track", &uuid, "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let j: Json = serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"));
    assert_eq!(j["track"]["uuid"], Json::from(uuid.clone()));
    assert_eq!(j["referred"], Json::Bool(true));
    assert_eq!(j["referred_frames"], Json::from(slow.len()));
    assert_eq!(j["frame"], Json::from(slow[0].0));
    assert!((j["seconds"].as_f64().unwrap_or(f64::NAN) - f.seconds[&slow[0].0]).abs() < 1e-9);
    assert_eq!(j["why_not"], Json::Null);
    let proof = &j["proof"];
    assert_eq!(proof["relation"], "referred");
    assert!(proof["clause"]["text"]
        .as_str()
        .is_some_and(|t| t.starts_with("referred(V, T)")));
    assert_eq!(proof["binding"]["V"], Json::from(uuid.clone()));
    let kinds: Vec<&str> = proof["body"]
        .as_array()
        .map(|b| b.iter().filter_map(|x| x["kind"].as_str()).collect())
        .unwrap_or_default();
    assert_eq!(kinds, vec!["atom", "atom", "comparison", "absent"]);
    let cmp = &proof["body"][2];
    assert_eq!(cmp["op"], "<");
    assert!((cmp["lhs"].as_f64().unwrap_or(f64::NAN) - slow[0].1).abs() < 1e-9);
    assert_eq!(cmp["rhs"].as_f64(), Some(0.5));
    assert_eq!(proof["body"][1]["relation"], "speed");
    assert_eq!(proof["body"][3]["relation"], "stationary");

    // A non-match: the why-not report with the failing literal and its values.
    let Some((moving, t, s)) = moving_car(&f) else {
        panic!("no moving vehicle");
    };
    let at = format!("{}", f.seconds[&t]);
    let (code, out, err) = scenalog(&[
        "explain", "--rules", STOPPED, "--log", &log_s, "--track", &moving, "--at", &at, "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let j: Json = serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"));
    assert_eq!(j["referred"], Json::Bool(false));
    assert_eq!(j["proof"], Json::Null);
    let w = &j["why_not"];
    assert_eq!(w["holds"], Json::Bool(false));
    assert_eq!(w["closest_clause"], Json::from(0));
    let a = &w["attempts"][0];
    assert_eq!(a["outcome"], "fails");
    assert_eq!(a["failure"]["literal"], "S < 0.5");
    assert_eq!(a["failure"]["step"]["body"], Json::from(2));
    assert_eq!(a["failure"]["binding_count"], Json::from(1));
    let r = &a["failure"]["reason"];
    assert_eq!(r["kind"], "comparison");
    assert!((r["values"][0]["lhs"].as_f64().unwrap_or(f64::NAN) - s).abs() < 1e-9);
    assert_eq!(r["values"][0]["binding"]["T"], Json::from(t));
}

#[test]
fn bad_inputs_are_clear_errors() {
    let log = logs().remove(0);
    let log_s = log.to_string_lossy();
    // Unknown track.
    let (code, _, err) = scenalog(&[
        "explain",
        "--rules",
        STOPPED,
        "--log",
        &log_s,
        "--track",
        "not-a-track",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("no track `not-a-track`"), "{err}");
    // Unreadable log.
    let (code, _, err) = scenalog(&[
        "explain",
        "--rules",
        STOPPED,
        "--log",
        "tests/data/no-such-log",
        "--track",
        "x",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("no-such-log"), "{err}");
    // Unreadable rules.
    let (code, _, err) = scenalog(&[
        "explain",
        "--rules",
        "rules/library/no_such.dl",
        "--log",
        &log_s,
        "--track",
        "x",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("no_such.dl"), "{err}");
    // Rules that do not check: diagnostics, exit 1.
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let bad = dir.path().join("bad.dl");
    std::fs::write(&bad, "referred(V, T) :- speeed(V, T, S), S < 0.5.\n")
        .unwrap_or_else(|e| panic!("{e}"));
    let bad_s = bad.to_string_lossy();
    let (code, _, err) = scenalog(&[
        "explain", "--rules", &bad_s, "--log", &log_s, "--track", "x",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("does not check"), "{err}");
    assert!(err.contains("speeed"), "{err}");
    assert!(err.contains("speed"), "{err}");
}

/// A program with a helper: the proof goes through `bicycle_right`, and the why-not report of
/// a vehicle without a bicycle follows the missing helper atom into its own rule. The expected
/// vehicle comes from the log's `direction` and `category` facts.
#[test]
fn helper_relations_are_proved_and_followed_in_why_not() {
    const RULES: &str = "rules/library/vehicle_with_bicycle_to_its_right.dl";
    let mut done = false;
    for log in logs() {
        let cats = relation(&log, "category");
        let is = |u: &str, c: &str| {
            cats.iter()
                .any(|r| r[0].as_str() == Some(u) && r[1].as_str() == Some(c))
        };
        if !cats.iter().any(|r| r[1].as_str() == Some("BICYCLE")) {
            continue;
        }
        // (vehicle, frame) -> the qualifying distances.
        let mut hits: BTreeMap<(String, u64), Vec<f64>> = BTreeMap::new();
        for r in relation(&log, "direction") {
            let (Some(v), Some(b), Some(t), Some(d), Some(dist), Some(lat)) = (
                r[0].as_str(),
                r[1].as_str(),
                r[2].as_u64(),
                r[3].as_str(),
                r[4].as_f64(),
                r[5].as_f64(),
            ) else {
                continue;
            };
            if d == "right" && dist <= 3.0 && lat <= 5.0 && is(v, "VEHICLE") && is(b, "BICYCLE") {
                hits.entry((v.to_string(), t)).or_default().push(dist);
            }
        }
        let Some(((v, t), dists)) = hits.iter().next() else {
            continue;
        };
        let n = hits.keys().filter(|(u, _)| u == v).count();
        let log_s = log.to_string_lossy();
        let (code, out, err) =
            scenalog(&["explain", "--rules", RULES, "--log", &log_s, "--track", v]);
        assert_eq!(code, 0, "{err}\n{out}");
        assert!(out.contains(&format!("is referred in {n} frame")), "{out}");
        assert!(out.contains(&format!("(frame {t}): referred")), "{out}");
        assert!(out.contains("✓ bicycle_right(V, _, T)"), "{out}");
        assert!(out.contains(&format!("{RULES}:3:")), "{out}");
        assert!(
            dists
                .iter()
                .any(|d| out.contains(&format!("Dist = {d:.2} m <= 3 m"))),
            "expected one of {dists:?}:\n{out}"
        );
        // A vehicle never referred: the report follows bicycle_right into its rule.
        let Some(other) = cats
            .iter()
            .filter(|r| r[1].as_str() == Some("REGULAR_VEHICLE"))
            .filter_map(|r| r[0].as_str())
            .find(|u| !hits.keys().any(|(x, _)| x == u))
        else {
            continue;
        };
        let (code, out, err) = scenalog(&[
            "explain", "--rules", RULES, "--log", &log_s, "--track", other,
        ]);
        assert_eq!(code, 0, "{err}\n{out}");
        assert!(out.contains("NOT referred"), "{out}");
        assert!(out.contains("✗ bicycle_right(V, _, T)"), "{out}");
        assert!(
            out.contains(&format!("why no bicycle_right({}", &other[..8])),
            "{out}"
        );
        assert!(out.contains("✓ category(V, \"VEHICLE\")"), "{out}");
        done = true;
        break;
    }
    assert!(done, "no log has a vehicle with a bicycle to its right");
}

#[test]
fn a_runaway_program_stops_at_the_limits_with_a_clear_error() {
    // A program that checks clean but would run for many minutes (`mine`'s runaway reproducer):
    // `explain` evaluates it within `--timeout-ms` / `--max-tuples`, as `mine` does, and says
    // which limit stopped it instead of hanging.
    let (log, _, uuid, _) = stopped_car();
    let log_s = log.to_string_lossy();
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("tempdir: {e}"));
    let rules = dir.path().join("runaway.dl");
    std::fs::write(
        &rules,
        "// description: runaway\nreferred(A, T) :- present(A, T), present(B, T), \
         present(C, T3), T3 * T < 0, A != B, B != C.\n",
    )
    .unwrap_or_else(|e| panic!("write: {e}"));
    let rules_s = rules.to_string_lossy();
    let base = [
        "explain", "--rules", &rules_s, "--log", &log_s, "--track", &uuid,
    ];
    let (code, _, err) = scenalog(&[&base[..], &["--timeout-ms", "300"]].concat());
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("ran longer than 0.3 s"), "{err}");
    let (code, _, err) = scenalog(&[&base[..], &["--max-tuples", "5000"]].concat());
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("5000"), "{err}");
}

/// A proof descends into a prelude relation like into any other rule, and says where that rule
/// is: the library's stopped car uses the prelude's `stopped`.
#[test]
fn a_proof_descends_into_the_prelude() {
    let log = &logs()[0];
    let (code, out, err) = scenalog(&[
        "explain",
        "--rules",
        "rules/library/stopped_car.dl",
        "--log",
        log.to_str().unwrap_or_default(),
        "--track",
        "0f0d16d4",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("✓ stopped(V, T)"), "{out}");
    assert!(
        out.contains("by the rule at the prelude, rules/prelude.dl:"),
        "{out}"
    );
    assert!(
        out.contains("| stopped(X, T) :- speed(X, T, V), V < 0.5 m/s."),
        "{out}"
    );
    assert!(out.contains("✓ V < 0.5 m/s"), "{out}");
}

/// Why-not on a prelude relation with two rules (`at_an_intersection`): the rule not chosen as
/// the closest is labelled with the prelude's file, not the program's; and the near misses of
/// a missing `stopped` tuple a frame apart are one span, not a line each.
#[test]
fn why_not_labels_prelude_rules_and_gives_near_misses_as_one_span() {
    let log = &logs()[0];
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let program = dir.path().join("x21.dl");
    std::fs::write(
        &program,
        "referred(X, T) :- category(X, \"REGULAR_VEHICLE\"), at_an_intersection(X, T).\n",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let (code, out, err) = scenalog(&[
        "explain",
        "--rules",
        program.to_str().unwrap_or_default(),
        "--log",
        log.to_str().unwrap_or_default(),
        "--track",
        "0f0d16d4",
        "--at",
        "12.0",
    ]);
    assert_eq!(code, 0, "{err}");
    let rules: Vec<&str> = out.lines().filter(|l| l.contains("the rule at")).collect();
    assert!(rules.len() >= 3, "{out}");
    assert!(rules[0].contains("x21.dl:1"), "{out}");
    for r in &rules[1..] {
        assert!(
            r.contains("the rule at the prelude, rules/prelude.dl:"),
            "{out}"
        );
        assert!(!r.contains("x21.dl"), "{out}");
    }
    let (code, out, err) = scenalog(&[
        "explain",
        "--rules",
        "rules/library/stopped_car.dl",
        "--log",
        log.to_str().unwrap_or_default(),
        "--track",
        "0f0d16d4",
        "--at",
        "12.0",
    ]);
    assert_eq!(code, 0, "{err}");
    let closest: Vec<&str> = out.lines().filter(|l| l.contains("closest:")).collect();
    assert_eq!(closest.len(), 1, "{out}");
    assert!(
        closest[0].contains("stopped(0f0d16d4 (REGULAR_VEHICLE), T) for T from 7.6 s to 8.0 s"),
        "{out}"
    );
}

/// `--at` past either end of the log is an error naming the log's time range (it used to
/// explain the last frame in silence); a time inside the range still explains the nearest frame.
#[test]
fn at_outside_the_log_is_an_error_naming_its_range() {
    let log = logs().into_iter().next().expect("a log");
    let log = log.to_string_lossy();
    let track = relation(Path::new(log.as_ref()), "category")
        .into_iter()
        .find_map(|row| row.first().and_then(|t| t.as_str().map(str::to_string)))
        .expect("a track");
    for at in ["999", "-0.5"] {
        let (code, _, err) = scenalog(&[
            "explain", "--rules", STOPPED, "--log", &log, "--track", &track, "--at", at,
        ]);
        assert_eq!(code, 2, "--at {at}: {err}");
        if at == "999" {
            assert!(
                err.contains("--at 999") && err.contains("runs from 0.0 s to "),
                "{err}"
            );
        }
    }
    let (code, out, err) = scenalog(&[
        "explain", "--rules", STOPPED, "--log", &log, "--track", &track, "--at", "3.04",
    ]);
    assert!(code == 0 || code == 1, "{err}");
    assert!(out.contains("at 3.0 s (frame 30)"), "{out}");
}

/// The hint of an unknown track points at a command that lists the log's track uuids, and it
/// does list them.
#[test]
fn an_unknown_track_names_a_command_that_lists_the_tracks() {
    let log = logs().into_iter().next().expect("a log");
    let log_s = log.to_string_lossy();
    let (code, _, err) = scenalog(&[
        "explain", "--rules", STOPPED, "--log", &log_s, "--track", "zzzz",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("scenalog facts LOG_DIR --relation category --json"),
        "{err}"
    );
    let rows = relation(&log, "category");
    let uuids: BTreeSet<&str> = rows.iter().filter_map(|r| r[0].as_str()).collect();
    let tracks: usize = err
        .split(" tracks;")
        .next()
        .and_then(|h| h.rsplit('(').next())
        .and_then(|n| n.trim().parse().ok())
        .expect("the track count");
    assert_eq!(uuids.len(), tracks, "every track listed: {err}");
}

/// Arithmetic on times reads as times: a difference of two moments is a duration in seconds
/// (`T2 - T = 3.0 s <= 3 s`, not the 30 frames it is held as) and a moment moved by a duration
/// is a moment (`T0 = 3.9 s`, not 39). The car that cuts in front of the ego on 3bffdcff.
#[test]
fn time_arithmetic_in_a_proof_reads_in_seconds() {
    let log = scenalog_testkit::sample_log(scenalog_testkit::SAMPLE_LOGS[1]);
    let (code, out, err) = scenalog(&[
        "explain",
        "--rules",
        "rules/library/vehicle_cutting_in_front_of_the_ego_vehicle.dl",
        "--log",
        &log.to_string_lossy(),
        "--track",
        "23f72b4f-0098-495f-ad55-20b3d2c6a66f",
        "--at",
        "4.9",
    ]);
    assert_eq!(code, 0, "{err}\n{out}");
    assert!(out.contains("T2 - T = 3.0 s <= 3 s"), "{out}");
    assert!(out.contains("T0 = 3.9 s"), "{out}");
    expect_file!["snapshots/explain_cut_in_time_arithmetic.txt"].assert_eq(&placeless(&out));
}
