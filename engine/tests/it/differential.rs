//! The engine against a small, obviously-correct naive evaluator on hundreds of seeded random
//! programs and databases: recursion (self and mutual), negation, comparisons, bindings with
//! arithmetic, constants and expressions (`V + 1`, possibly joined before `V` is bound) in atoms, and count/min aggregates (with `_` columns and variables local
//! to the braces).
//!
//! The expected answer is [`crate::oracle`]'s (the same naive evaluator as `naive.rs`'s), run
//! stratum by stratum on the checked program.

use scenalog_engine::{evaluate, Options};
use scenalog_facts::relation::{RelationData, Request};
use scenalog_rules::{check, CheckOptions};

use crate::oracle::{int_tuples, naive};
use crate::rng::Rng;

#[derive(Clone, Debug)]
enum Term {
    Var(usize),
    Const(i64),
    Wild,
    /// `V + c`, in an atom after one that binds `V` (the engine may join it first).
    Add(usize, i64),
}

#[derive(Clone, Debug)]
struct Atom {
    pred: usize,
    args: Vec<Term>,
}

#[derive(Clone, Copy, Debug)]
enum Op {
    Lt,
    Le,
    Ne,
    Eq,
    Ge,
}

#[derive(Clone, Debug)]
enum Agg {
    Count,
    Min(usize),
}

#[derive(Clone, Debug)]
enum Lit {
    Pos(Atom),
    Neg(Atom),
    Cmp(Op, Term, Term),
    /// `V = W + c`.
    Bind(usize, usize, i64),
    /// `R = count : { atom }` / `R = min Y : { atom }`.
    Agg(usize, Agg, Atom),
}

#[derive(Clone, Debug)]
struct Rule {
    head: Atom,
    body: Vec<Lit>,
}

/// Predicates 0..2 are inputs given as facts (`e/2`, `u/1`, `f/2`), 3..5 level 0 (mutually
/// recursive), 6..8 level 1 (may negate and aggregate level 0 and inputs).
const NAMES: [&str; 9] = ["e", "u", "f", "a", "b", "c", "d", "g", "h"];

struct Gen {
    arity: [usize; 9],
    facts: Vec<(usize, Vec<i64>)>,
    rules: Vec<Rule>,
}

fn level(p: usize) -> usize {
    match p {
        0..=2 => 0,
        3..=5 => 1,
        _ => 2,
    }
}

fn gen(rng: &mut Rng) -> Gen {
    let mut arity = [2, 1, 2, 0, 0, 0, 0, 0, 0];
    for a in arity.iter_mut().skip(3) {
        *a = 1 + rng.below(2);
    }
    let dom = 3 + rng.below(4) as i64;
    let mut facts = Vec::new();
    for (p, &a) in arity.iter().enumerate().take(3) {
        let n = 1 + rng.below(10);
        for _ in 0..n {
            let t = (0..a).map(|_| rng.below(dom as usize) as i64).collect();
            facts.push((p, t));
        }
    }
    let mut rules = Vec::new();
    for p in 3..9 {
        let n = 1 + rng.below(3);
        for _ in 0..n {
            rules.push(gen_rule(rng, p, &arity));
        }
    }
    Gen {
        arity,
        facts,
        rules,
    }
}

fn gen_rule(rng: &mut Rng, head: usize, arity: &[usize; 9]) -> Rule {
    let lv = level(head);
    let positive: Vec<usize> = (0..9).filter(|&q| level(q) <= lv).collect();
    let negative: Vec<usize> = (0..9).filter(|&q| level(q) < lv).collect();
    let mut bound: Vec<usize> = Vec::new();
    let mut next_var = 0;
    let mut body = Vec::new();
    let n_pos = 1 + rng.below(2);
    for i in 0..n_pos {
        // The first atom of a level-0 rule may be an input, so every predicate gets a base case
        // often enough; later atoms are anything allowed.
        let pred = if i == 0 && rng.chance(50) {
            rng.below(3)
        } else {
            positive[rng.below(positive.len())]
        };
        let mut args = Vec::new();
        for _ in 0..arity[pred] {
            // `V + c` of a variable bound before this atom or earlier in it (`t(N, N + 1)`).
            let mut pool = bound.clone();
            pool.extend(args.iter().filter_map(|t| match t {
                Term::Var(v) => Some(*v),
                _ => None,
            }));
            let t = if rng.chance(12) {
                Term::Const(rng.below(4) as i64)
            } else if !pool.is_empty() && rng.chance(10) {
                Term::Add(pool[rng.below(pool.len())], rng.below(3) as i64 - 1)
            } else if !bound.is_empty() && rng.chance(50) {
                Term::Var(bound[rng.below(bound.len())])
            } else {
                next_var += 1;
                Term::Var(next_var - 1)
            };
            args.push(t);
        }
        for t in &args {
            if let Term::Var(v) = t {
                if !bound.contains(v) {
                    bound.push(*v);
                }
            }
        }
        body.push(Lit::Pos(Atom { pred, args }));
    }
    if bound.is_empty() {
        // Only constants so far: bind one variable from an input.
        body.push(Lit::Pos(Atom {
            pred: 1,
            args: vec![Term::Var(next_var)],
        }));
        bound.push(next_var);
        next_var += 1;
    }
    let pick = |rng: &mut Rng, bound: &Vec<usize>| bound[rng.below(bound.len())];
    if rng.chance(25) {
        let from = pick(rng, &bound);
        let v = next_var;
        next_var += 1;
        body.push(Lit::Bind(v, from, rng.below(4) as i64 - 1));
        body.push(Lit::Cmp(Op::Lt, Term::Var(v), Term::Const(6)));
        body.push(Lit::Cmp(Op::Ge, Term::Var(v), Term::Const(0)));
        bound.push(v);
    }
    if rng.chance(40) {
        let ops = [Op::Lt, Op::Le, Op::Ne, Op::Eq, Op::Ge];
        let op = ops[rng.below(ops.len())];
        let a = Term::Var(pick(rng, &bound));
        let b = if rng.chance(50) {
            Term::Var(pick(rng, &bound))
        } else {
            Term::Const(rng.below(5) as i64)
        };
        body.push(Lit::Cmp(op, a, b));
    }
    if !negative.is_empty() && rng.chance(40) {
        let pred = negative[rng.below(negative.len())];
        let args = (0..arity[pred])
            .map(|_| match rng.below(6) {
                0 => Term::Wild,
                1 => Term::Const(rng.below(4) as i64),
                _ => Term::Var(pick(rng, &bound)),
            })
            .collect();
        body.push(Lit::Neg(Atom { pred, args }));
    }
    if lv == 2 && rng.chance(35) {
        // Aggregate over an input or level-0 binary-or-unary predicate, grouped by a bound var.
        let pred = negative[rng.below(negative.len())];
        let fresh = next_var;
        next_var += 1;
        // A variable local to the braces (neither the group nor the target).
        let local = next_var;
        next_var += 1;
        let g = pick(rng, &bound);
        let agg = if rng.chance(50) {
            Agg::Count
        } else {
            Agg::Min(fresh)
        };
        let mut args: Vec<Term> = Vec::new();
        for i in 0..arity[pred] {
            args.push(if i == 0 && arity[pred] == 2 {
                match rng.below(5) {
                    0 => Term::Wild,
                    1 => Term::Var(local),
                    _ => Term::Var(g),
                }
            } else if matches!(agg, Agg::Count) && rng.chance(40) {
                Term::Wild
            } else {
                Term::Var(fresh)
            });
        }
        let r = next_var;
        body.push(Lit::Agg(r, agg, Atom { pred, args }));
        bound.push(r);
    }
    let head_args = (0..arity[head])
        .map(|_| {
            if rng.chance(8) {
                Term::Const(rng.below(3) as i64)
            } else {
                Term::Var(pick(rng, &bound))
            }
        })
        .collect();
    Rule {
        head: Atom {
            pred: head,
            args: head_args,
        },
        body,
    }
}

fn term_text(t: &Term) -> String {
    match t {
        Term::Var(v) => format!("V{v}"),
        Term::Const(c) => c.to_string(),
        Term::Wild => "_".to_string(),
        Term::Add(v, c) => format!("V{v} + {c}"),
    }
}

fn atom_text(a: &Atom) -> String {
    let args: Vec<String> = a.args.iter().map(term_text).collect();
    format!("{}({})", NAMES[a.pred], args.join(", "))
}

fn op_text(op: Op) -> &'static str {
    match op {
        Op::Lt => "<",
        Op::Le => "<=",
        Op::Ne => "!=",
        Op::Eq => "=",
        Op::Ge => ">=",
    }
}

fn program_text(g: &Gen) -> String {
    let mut s = String::new();
    for (p, &a) in g.arity.iter().enumerate() {
        let cols: Vec<String> = (0..a).map(|i| format!("C{i}: int")).collect();
        s.push_str(&format!(".decl {}({})\n", NAMES[p], cols.join(", ")));
    }
    for (p, t) in &g.facts {
        let args: Vec<String> = t.iter().map(|v| v.to_string()).collect();
        s.push_str(&format!("{}({}).\n", NAMES[*p], args.join(", ")));
    }
    for r in &g.rules {
        let body: Vec<String> = r
            .body
            .iter()
            .map(|l| match l {
                Lit::Pos(a) => atom_text(a),
                Lit::Neg(a) => format!("!{}", atom_text(a)),
                Lit::Cmp(op, a, b) => format!("{} {} {}", term_text(a), op_text(*op), term_text(b)),
                Lit::Bind(v, w, c) => format!("V{v} = V{w} + {c}"),
                Lit::Agg(r, Agg::Count, a) => format!("V{r} = count : {{ {} }}", atom_text(a)),
                Lit::Agg(r, Agg::Min(y), a) => {
                    format!("V{r} = min V{y} : {{ {} }}", atom_text(a))
                }
            })
            .collect();
        s.push_str(&format!("{} :- {}.\n", atom_text(&r.head), body.join(", ")));
    }
    s
}

/// With provenance on, the results are the same and every derived tuple has a proof whose
/// nodes are all tuples of their relations and whose leaves are ground facts (with `wide`, the
/// evaluation and the proofs use the widest rows).
fn check_proofs(
    case: usize,
    program: &scenalog_rules::CheckedProgram,
    plain: &scenalog_engine::Evaluation,
    text: &str,
    wide: bool,
) {
    let mut provider =
        |r: &Request| -> Result<RelationData, String> { Err(format!("asked for {}", r.name)) };
    let options = Options {
        provenance: true,
        wide_rows: wide,
        ..Options::default()
    };
    let eval = match evaluate(program, &mut provider, &options) {
        Ok(e) => e,
        Err(e) => panic!("case {case}: {e}\n{text}"),
    };
    assert_eq!(&eval, plain, "case {case}: provenance changed the results");
    fn valid(p: &scenalog_engine::Proof, eval: &scenalog_engine::Evaluation) -> bool {
        let present = eval
            .tuples(&p.relation)
            .is_some_and(|ts| ts.contains(&p.tuple));
        let leaf_is_fact = !p.children.is_empty() || p.clause.is_some();
        present && leaf_is_fact && p.children.iter().all(|c| valid(c, eval))
    }
    for name in &NAMES[3..] {
        for t in eval.tuples(name).unwrap_or_default() {
            match eval.prove(name, t) {
                Some(p) => assert!(valid(&p, &eval), "case {case}: bad proof {p:?}\n{text}"),
                None => panic!("case {case}: no proof of {name}{t:?}\n{text}"),
            }
        }
    }
}

#[test]
fn engine_matches_the_naive_evaluator_on_random_programs() {
    let mut rng = Rng(0x5eed_cafe_f00d_0001);
    let (mut compared, mut nonempty, mut with_neg, mut with_agg) = (0, 0, 0, 0);
    let (mut with_agg_wild, mut with_expr_arg, mut restricted, mut inlined) = (0, 0, 0, 0);
    for case in 0..400 {
        let g = gen(&mut rng);
        let text = program_text(&g);
        let outcome = check(
            &text,
            &CheckOptions {
                require_referred: false,
            },
        );
        let Some(program) = outcome.program else {
            panic!(
                "case {case}: generated program does not check:\n{text}\n{:?}",
                outcome.diagnostics
            );
        };
        let mut provider =
            |r: &Request| -> Result<RelationData, String> { Err(format!("asked for {}", r.name)) };
        let eval = match evaluate(&program, &mut provider, &Options::default()) {
            Ok(e) => e,
            Err(e) => panic!("case {case}: {e}\n{text}"),
        };
        // Level 1 (a, b, c: mutually recursive), then level 2 (d, g, h).
        let expected = naive(&program.program, &[&NAMES[3..6], &NAMES[6..]]);
        for (p, name) in NAMES.iter().enumerate() {
            let got = int_tuples(&eval, name);
            assert_eq!(
                got,
                expected.get(*name).cloned().unwrap_or_default(),
                "case {case}: relation {name} differs\n{text}"
            );
            if p >= 3 && !got.is_empty() {
                nonempty += 1;
            }
        }
        if case % 4 == 0 {
            check_proofs(case, &program, &eval, &text, case % 8 == 0);
        }
        // Demand: reading one relation, the relations no one else sees may be restricted to
        // what their uses bind; the one read is the same.
        let read = NAMES[3 + case % 6];
        let demand = Options {
            reads: Some(vec![read.to_string()]),
            ..Options::default()
        };
        match evaluate(&program, &mut provider, &demand) {
            Ok(d) => {
                assert_eq!(
                    int_tuples(&d, read),
                    int_tuples(&eval, read),
                    "case {case}: demand changed {read}\n{text}"
                );
                restricted += usize::from(d.names().any(|n| n.starts_with("magic_")));
                // Inlined: a relation the whole evaluation holds tuples of, derived nowhere.
                inlined += usize::from(NAMES.iter().any(|n| {
                    *n != read
                        && d.size(n) == 0
                        && eval.size(n) > 0
                        && !program
                            .program
                            .clauses
                            .iter()
                            .any(|c| c.head.pred == *n && c.body.is_empty())
                }));
            }
            Err(e) => panic!("case {case}: demand: {e}\n{text}"),
        }
        // The rows of the widest programs give the same answers (every other program).
        if case % 2 == 1 {
            let wide = Options {
                wide_rows: true,
                ..Options::default()
            };
            match evaluate(&program, &mut provider, &wide) {
                Ok(w) => assert_eq!(w, eval, "case {case}: wide rows differ\n{text}"),
                Err(e) => panic!("case {case}: wide rows: {e}\n{text}"),
            }
        }
        with_neg += usize::from(text.contains(", !"));
        with_agg += usize::from(text.contains("count") || text.contains("min "));
        with_agg_wild += usize::from(g.rules.iter().any(|r| {
            r.body.iter().any(|l| {
                matches!(l, Lit::Agg(_, _, a) if a.args.iter().any(|t| matches!(t, Term::Wild)))
            })
        }));
        with_expr_arg += usize::from(g.rules.iter().any(|r| {
            r.body.iter().any(
                |l| matches!(l, Lit::Pos(a) if a.args.iter().any(|t| matches!(t, Term::Add(..)))),
            )
        }));
        compared += 1;
    }
    eprintln!(
        "{compared} programs: {nonempty} non-empty derived relations, {with_neg} with negation, \
         {with_agg} with aggregates ({with_agg_wild} with `_` in the braces), {with_expr_arg} \
         with an expression in an atom, {restricted} with a relation restricted by demand, \
         {inlined} with one inlined"
    );
    assert_eq!(compared, 400);
    // The generator must exercise what it claims to.
    assert!(
        nonempty > 800,
        "only {nonempty} non-empty derived relations"
    );
    assert!(with_neg > 100, "only {with_neg} programs with negation");
    assert!(with_agg > 50, "only {with_agg} programs with aggregates");
    assert!(
        with_agg_wild > 20,
        "only {with_agg_wild} programs with `_` in an aggregate"
    );
    assert!(
        with_expr_arg > 50,
        "only {with_expr_arg} programs with an expression in an atom"
    );
    assert!(
        restricted > 20,
        "only {restricted} programs with a relation restricted by demand"
    );
    assert!(
        inlined > 20,
        "only {inlined} programs with a relation inlined"
    );
}
