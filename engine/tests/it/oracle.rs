//! The one naive evaluator the engine is compared with (`naive.rs`, `differential.rs`): obviously
//! correct and slow. It reads the checked program's syntax tree and runs every rule body by
//! backtracking over the literals in textual order, integers only; an aggregate takes one value
//! per matching combination of its braces' tuples, as Soufflé does.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use scenalog_rules::ast::{AggFunc, BinOp, CmpOp, Expr, ExprKind, Literal, Program};

/// Tuples by relation name.
pub type Db = BTreeMap<String, BTreeSet<Vec<i64>>>;
type Env = HashMap<String, i64>;

fn eval_expr(e: &Expr, env: &Env) -> Option<i64> {
    match &e.kind {
        ExprKind::Var(v) => env.get(v).copied(),
        ExprKind::Int(i) => Some(*i),
        ExprKind::Neg(a) => Some(-eval_expr(a, env)?),
        ExprKind::Binary(op, a, b) => {
            let (x, y) = (eval_expr(a, env)?, eval_expr(b, env)?);
            match op {
                BinOp::Add => Some(x + y),
                BinOp::Sub => Some(x - y),
                BinOp::Mul => Some(x * y),
                BinOp::Div => x.checked_div(y),
                BinOp::Mod => x.checked_rem(y),
                BinOp::Pow if y >= 0 => x.checked_pow(u32::try_from(y).ok()?),
                BinOp::Pow if x == 0 => None,
                BinOp::Pow => Some((x as f64).powf(y as f64).trunc() as i64),
            }
        }
        _ => None,
    }
}

/// Unifies an atom's arguments with a tuple, extending `env`; `None` if they do not match.
fn unify(args: &[Expr], t: &[i64], env: &Env) -> Option<Env> {
    let mut env = env.clone();
    for (a, &x) in args.iter().zip(t) {
        match &a.kind {
            ExprKind::Wildcard => {}
            ExprKind::Var(v) => match env.get(v) {
                Some(&y) if y != x => return None,
                Some(_) => {}
                None => {
                    env.insert(v.clone(), x);
                }
            },
            _ => {
                if eval_expr(a, &env)? != x {
                    return None;
                }
            }
        }
    }
    Some(env)
}

fn solve(body: &[Literal], env: Env, db: &Db, out: &mut Vec<Env>) {
    let Some((first, rest)) = body.split_first() else {
        out.push(env);
        return;
    };
    let empty = BTreeSet::new();
    match first {
        Literal::Pos(a) => {
            for t in db.get(&a.pred).unwrap_or(&empty) {
                if let Some(e) = unify(&a.args, t, &env) {
                    solve(rest, e, db, out);
                }
            }
        }
        Literal::Neg(a, _) => {
            let hit = db
                .get(&a.pred)
                .unwrap_or(&empty)
                .iter()
                .any(|t| unify(&a.args, t, &env).is_some());
            if !hit {
                solve(rest, env, db, out);
            }
        }
        Literal::Cmp(c) => {
            if c.op == CmpOp::Eq {
                if let (Some(v), None) = (c.lhs.as_var(), c.lhs.as_var().and_then(|v| env.get(v))) {
                    if let Some(x) = eval_expr(&c.rhs, &env) {
                        let mut e = env.clone();
                        e.insert(v.to_string(), x);
                        solve(rest, e, db, out);
                    }
                    return;
                }
            }
            let (Some(x), Some(y)) = (eval_expr(&c.lhs, &env), eval_expr(&c.rhs, &env)) else {
                return;
            };
            let ok = match c.op {
                CmpOp::Lt => x < y,
                CmpOp::Le => x <= y,
                CmpOp::Gt => x > y,
                CmpOp::Ge => x >= y,
                CmpOp::Eq => x == y,
                CmpOp::Ne => x != y,
            };
            if ok {
                solve(rest, env, db, out);
            }
        }
        Literal::Agg(g) => {
            // As in Soufflé: one value per matching combination of the body's tuples, the group
            // fixed by `env`. Backtracking over sets meets each combination exactly once, and
            // tuples that differ only in a `_` column are different combinations.
            let mut inner = Vec::new();
            solve(&g.body, env.clone(), db, &mut inner);
            let values: Vec<i64> = inner
                .iter()
                .filter_map(|e| match &g.target {
                    Some(t) => eval_expr(t, e),
                    None => Some(1),
                })
                .collect();
            let r = match g.func {
                AggFunc::Count => Some(values.len() as i64),
                AggFunc::Sum => Some(values.iter().sum()),
                AggFunc::Min => values.iter().min().copied(),
                AggFunc::Max => values.iter().max().copied(),
            };
            if let (Some(r), Some(v)) = (r, g.result.as_var()) {
                let mut e = env.clone();
                e.insert(v.to_string(), r);
                solve(rest, e, db, out);
            }
        }
    }
}

/// The relations `p` derives: its facts, then each group of `groups` in order, every rule of
/// the group re-run over all current tuples until nothing changes (a group is a stratum: its
/// relations' negations and aggregates reach only earlier groups).
pub fn naive(p: &Program, groups: &[&[&str]]) -> Db {
    let mut db: Db = Db::new();
    for c in p.clauses.iter().filter(|c| c.body.is_empty()) {
        let t: Vec<i64> = c
            .head
            .args
            .iter()
            .filter_map(|a| eval_expr(a, &Env::new()))
            .collect();
        db.entry(c.head.pred.clone()).or_default().insert(t);
    }
    for group in groups {
        loop {
            let mut new = Vec::new();
            for c in p
                .clauses
                .iter()
                .filter(|c| group.contains(&c.head.pred.as_str()) && !c.body.is_empty())
            {
                let mut sols = Vec::new();
                solve(&c.body, Env::new(), &db, &mut sols);
                for e in sols {
                    let t: Option<Vec<i64>> =
                        c.head.args.iter().map(|a| eval_expr(a, &e)).collect();
                    if let Some(t) = t {
                        new.push((c.head.pred.clone(), t));
                    }
                }
            }
            let mut changed = false;
            for (pred, t) in new {
                changed |= db.entry(pred).or_default().insert(t);
            }
            if !changed {
                break;
            }
        }
    }
    db
}

/// The engine's tuples of `relation` in the oracle's shape (integers only: a value of another
/// type fails the test, naming it).
pub fn int_tuples(ev: &scenalog_engine::Evaluation, relation: &str) -> BTreeSet<Vec<i64>> {
    ev.tuples(relation)
        .unwrap_or_default()
        .iter()
        .map(|t| {
            t.iter()
                .map(|v| match v {
                    scenalog_facts::relation::Value::Int(i) => *i,
                    other => panic!("{relation}: not an int: {other:?}"),
                })
                .collect()
        })
        .collect()
}
