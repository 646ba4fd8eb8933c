//! The engine against a small, obviously-correct naive evaluator on hundreds of random programs
//! and databases: recursion, negation, aggregates, comparisons and arithmetic.
//!
//! The naive evaluator is [`crate::oracle`], run group by group: `p0`/`p1` (mutually recursive),
//! then `p2`, then `p3`; negation and aggregates only reach earlier groups.

use scenalog_engine::{evaluate, Options};
use scenalog_facts::relation::{RelationData, Request};
use scenalog_rules::{check, CheckOptions};

use crate::oracle::{int_tuples, naive};
use crate::rng::Rng;

const DERIVED: [(&str, usize); 4] = [("p0", 2), ("p1", 2), ("p2", 1), ("p3", 2)];
const EDB: [(&str, usize); 3] = [("e1", 2), ("e2", 2), ("u", 1)];
const VARS: [&str; 4] = ["X", "Y", "Z", "W"];

fn gen_program(rng: &mut Rng) -> String {
    let mut s = String::new();
    for (p, n) in EDB.iter().chain(DERIVED.iter()) {
        let cols: Vec<String> = (0..*n).map(|i| format!("C{i}: int")).collect();
        s.push_str(&format!(".decl {p}({})\n", cols.join(", ")));
    }
    for (p, n) in EDB {
        for _ in 0..(2 + rng.below(9)) {
            let args: Vec<String> = (0..n).map(|_| rng.below(6).to_string()).collect();
            s.push_str(&format!("{p}({}).\n", args.join(", ")));
        }
    }
    for (i, (head, arity)) in DERIVED.iter().enumerate() {
        for _ in 0..(1 + rng.below(3)) {
            s.push_str(&gen_rule(rng, i, head, *arity));
        }
    }
    s
}

fn gen_rule(rng: &mut Rng, i: usize, head: &str, arity: usize) -> String {
    // p0 and p1 are mutually recursive (one group); negation only reaches earlier groups.
    let group_end = if i <= 1 { 2 } else { i + 1 };
    let group_start = if i <= 1 { 0 } else { i };
    let mut pos: Vec<(&str, usize)> = EDB.to_vec();
    pos.extend(DERIVED[..group_end].iter().copied());
    let mut neg: Vec<(&str, usize)> = EDB.to_vec();
    neg.extend(DERIVED[..group_start].iter().copied());
    let mut body = Vec::new();
    let mut bound: Vec<&str> = Vec::new();
    for _ in 0..(1 + rng.below(3)) {
        let (p, n) = *rng.pick(&pos);
        let args: Vec<String> = (0..n)
            .map(|_| {
                if rng.odds(0.15) {
                    rng.below(6).to_string()
                } else if rng.odds(0.08) {
                    "_".to_string()
                } else {
                    let v = *rng.pick(&VARS);
                    if !bound.contains(&v) {
                        bound.push(v);
                    }
                    v.to_string()
                }
            })
            .collect();
        body.push(format!("{p}({})", args.join(", ")));
    }
    if bound.is_empty() {
        bound.push("X");
        body.push("u(X)".to_string());
    }
    if rng.odds(0.4) {
        let ops = ["<", "<=", ">", ">=", "=", "!="];
        let a = *rng.pick(&bound);
        let b = if rng.odds(0.5) {
            rng.pick(&bound).to_string()
        } else {
            rng.below(6).to_string()
        };
        let a = if rng.odds(0.3) {
            format!("{a} + 1")
        } else {
            a.to_string()
        };
        body.push(format!("{a} {} {b}", rng.pick(&ops)));
    }
    if rng.odds(0.3) {
        let (p, n) = *rng.pick(&neg);
        let args: Vec<String> = (0..n)
            .map(|_| {
                if rng.odds(0.2) {
                    "_".to_string()
                } else if rng.odds(0.2) {
                    rng.below(6).to_string()
                } else {
                    rng.pick(&bound).to_string()
                }
            })
            .collect();
        body.push(format!("!{p}({})", args.join(", ")));
    }
    let mut head_args: Vec<String> = (0..arity).map(|_| rng.pick(&bound).to_string()).collect();
    if arity == 2 && rng.odds(0.2) {
        let g = *rng.pick(&bound);
        let e = if rng.odds(0.5) { "e1" } else { "e2" };
        let agg = match rng.below(7) {
            0 => format!("N = count : {{ {e}({g}, V) }}"),
            1 => format!("N = sum V : {{ {e}({g}, V) }}"),
            2 => format!("N = min V : {{ {e}({g}, V) }}"),
            3 => format!("N = max V + 1 : {{ {e}(V, {g}) }}"),
            // `_` columns and variables local to the braces: each matching tuple counts.
            4 => format!("N = count : {{ {e}({g}, _) }}"),
            5 => format!("N = sum V : {{ {e}({g}, V), {e}(V, _) }}"),
            _ => format!("N = count : {{ {e}({g}, L), u(_) }}"),
        };
        body.push(agg);
        head_args = vec![g.to_string(), "N".to_string()];
    } else if arity == 2 && rng.odds(0.15) {
        // Arithmetic binding, bounded so recursion terminates.
        let a = *rng.pick(&bound);
        body.push(format!("{a} < 8"));
        body.push(format!("N = {a} + 1"));
        head_args[1] = "N".to_string();
    }
    format!("{head}({}) :- {}.\n", head_args.join(", "), body.join(", "))
}

#[test]
fn engine_matches_the_naive_evaluator_on_random_programs() {
    let mut rng = Rng(0x5EED_1234_ABCD_0001);
    let (mut compared, mut rejected) = (0, 0);
    let mut nonempty = 0;
    for case in 0..400 {
        let src = gen_program(&mut rng);
        let outcome = check(
            &src,
            &CheckOptions {
                require_referred: false,
            },
        );
        let Some(prog) = outcome.program else {
            rejected += 1;
            continue;
        };
        let expected = naive(&prog.program, &[&["p0", "p1"], &["p2"], &["p3"]]);
        let mut provider =
            |r: &Request| -> Result<RelationData, String> { Err(format!("no {}", r.name)) };
        let ev = match evaluate(&prog, &mut provider, &Options::default()) {
            Ok(ev) => ev,
            Err(e) => panic!("case {case}: engine failed: {e}\n{src}"),
        };
        for (pred, _) in DERIVED {
            let got = int_tuples(&ev, pred);
            let want = expected.get(pred).cloned().unwrap_or_default();
            assert_eq!(got, want, "case {case}, relation {pred}:\n{src}");
            nonempty += usize::from(!want.is_empty());
        }
        compared += 1;
    }
    eprintln!("compared {compared}, rejected {rejected}, non-empty relations {nonempty}");
    assert!(
        compared >= 300,
        "only {compared} programs checked ({rejected} rejected)"
    );
    assert!(nonempty >= 300, "too few non-empty relations: {nonempty}");
}
