//! W0513: a distance the relation produces only within its range, bounded as if it went on.
//!
//! `near` holds only for objects at most 50 m apart (`near_intersection` and `at_crosswalk` only
//! up to 50 m from the map feature; the catalog's `ColumnSpec::range`). So "pedestrians more than
//! 30 m from the ego" written `near(E, P, T, D), D > 30.0` finds the ones 30–50 m away and quietly
//! drops every one farther: a silent wrong answer. Two shapes are flagged:
//!
//! - a lower bound on the distance with no upper bound: the hint, and a machine-applicable fix
//!   when the clause allows it, write the meant program, a negation ("not within 30 m"), which
//!   also holds for objects past the range: `within_30_m` ← `near(…, D), D <= 30.0`, then
//!   `present(E, T), present(P, T), E != P, !within_30_m(E, P, T)`;
//! - an upper bound past the range (`D < 80.0`): it bounds nothing the relation produces (one at
//!   the range, `D <= 50 m`, says what the relation holds and is fine).

use scenalog_facts::catalog::{self, ColType};

use super::meaning::{free_relation_name, literal_names};
use crate::ast::{Atom, Clause, CmpOp, Comparison, Expr, ExprKind, Literal, Program, Span};
use crate::diagnostics::{self, warning};
use crate::walk;
use crate::Diagnostic;

/// Most W0513 warnings one program gets: past that, the rest are the same mistake again.
const MAX_WARNINGS: usize = 64;

/// Runs the check over every clause of the program.
pub fn check_program(program: &Program, diags: &mut Vec<Diagnostic>) {
    let defined: Vec<&str> = program
        .clauses
        .iter()
        .map(|c| c.head.pred.as_str())
        .collect();
    let mut given = 0;
    for c in &program.clauses {
        for (n, l) in c.body.iter().enumerate() {
            let Literal::Pos(atom) = l else {
                continue;
            };
            let Some(spec) = catalog::relation(&atom.pred) else {
                continue;
            };
            for (col, cs) in spec.columns.iter().enumerate() {
                let (Some(range), Some(var)) =
                    (cs.range, atom.args.get(col).and_then(Expr::as_var))
                else {
                    continue;
                };
                if given >= MAX_WARNINGS {
                    return;
                }
                if let Some(d) = bounds_warning(c, n, atom, spec, (cs.name, var, range), &defined) {
                    diags.push(d);
                    given += 1;
                }
            }
        }
    }
}

/// One comparison of the body bounding a variable by a number.
struct Bound {
    /// The comparison's index in the body.
    at: usize,
    /// The number, in the column's unit (metres).
    value: f64,
    /// `var > k` / `var >= k` (a lower bound) or `var < k` / `var <= k` (an upper bound).
    lower: bool,
    /// Whether the bound excludes `k` itself (`>`, `<`).
    strict: bool,
    /// The number as written (with its unit, if any).
    written: Expr,
}

/// The warning for atom `n` of clause `c`, whose column `name` holds variable `var` and is
/// produced only up to `range` metres, if the clause bounds it as if it went on.
fn bounds_warning(
    c: &Clause,
    n: usize,
    atom: &Atom,
    spec: &catalog::RelationSpec,
    (name, var, range): (&str, &str, u32),
    defined: &[&str],
) -> Option<Diagnostic> {
    let bounds: Vec<Bound> = c
        .body
        .iter()
        .enumerate()
        .filter_map(|(i, l)| match l {
            Literal::Cmp(cmp) => bound_on(cmp, var).map(|b| Bound { at: i, ..b }),
            _ => None,
        })
        .collect();
    let range_f = f64::from(range);
    let pred = &atom.pred;
    if let Some(b) = bounds.iter().find(|b| !b.lower && b.value > range_f) {
        return Some(
            warning(
                diagnostics::BEYOND_RANGE,
                c.body[b.at].span(),
                format!(
                    "`{pred}` holds only within {range} m, so this bound on `{var}` ({name}) removes nothing: an object farther than {range} m has no `{pred}` fact at all"
                ),
            )
            .with_hint(format!(
                "`{pred}` cannot say anything about objects farther than {range} m; to mean \"within {range} m\" drop the bound, to mean something farther use positions another way"
            )),
        );
    }
    if bounds.iter().any(|b| !b.lower) {
        return None;
    }
    let lower: Vec<&Bound> = bounds.iter().filter(|b| b.lower).collect();
    let first = lower.first()?;
    let shown = crate::printer::print_expr(&first.written);
    let op = if first.strict { ">" } else { ">=" };
    let mut d = warning(
        diagnostics::BEYOND_RANGE,
        c.body[first.at].span(),
        format!(
            "`{pred}` holds only within {range} m: `{var} {op} {shown}` finds the objects between {shown} and {range} m away, not every object farther than {shown}"
        ),
    );
    match negation_fix(c, n, atom, spec, var, &lower, defined) {
        Some((helper, rewritten)) => {
            let helper_text = crate::printer::print_clause(&helper);
            let clause_text = crate::printer::print_clause(&rewritten);
            let hint = format!(
                "say \"not within {shown}\", which also holds past {range} m: `{}` then `{}`",
                helper_text.trim_end(),
                clause_text.trim_end()
            );
            d.hint = Some(hint.split_whitespace().collect::<Vec<_>>().join(" "));
            d.fix = vec![crate::Edit {
                span: c.span,
                text: format!("{}\n{}", helper_text.trim_end(), clause_text.trim_end()),
            }];
        }
        None => {
            d.hint = Some(format!(
                "say \"not within {shown}\", which also holds past {range} m: a helper `close(…) :- {}, {var} {} {shown}.` and `!close(…)` with both objects bound by `present(…, T)`",
                crate::printer::print_atom(atom),
                if first.strict { "<=" } else { "<" },
            ));
        }
    }
    Some(d)
}

/// `cmp` as a bound on `var` by a number, if it is one (`var > 30.0`, `30 m < var`, …).
fn bound_on(cmp: &Comparison, var: &str) -> Option<Bound> {
    let (op, k) = if cmp.lhs.as_var() == Some(var) {
        (cmp.op, &cmp.rhs)
    } else if cmp.rhs.as_var() == Some(var) {
        (cmp.op.flipped(), &cmp.lhs)
    } else {
        return None;
    };
    let value = number(k)?;
    let (lower, strict) = match op {
        CmpOp::Gt => (true, true),
        CmpOp::Ge => (true, false),
        CmpOp::Lt => (false, true),
        CmpOp::Le => (false, false),
        CmpOp::Eq | CmpOp::Ne => return None,
    };
    Some(Bound {
        at: 0,
        value,
        lower,
        strict,
        written: k.clone(),
    })
}

/// A constant number's value in its place's unit (a quantity as the checker read it).
fn number(e: &Expr) -> Option<f64> {
    match &e.kind {
        ExprKind::Int(i) => Some(*i as f64),
        ExprKind::Float(f) => Some(*f),
        ExprKind::Quantity(q) => Some(q.number().as_f64()),
        ExprKind::Neg(inner) => number(inner).map(|v| -v),
        _ => None,
    }
}

/// The helper rule ("within k") and the clause rewritten to negate it, when the distance
/// variable is used only by atom `n` and one lower bound, the atom's objects and time are
/// variables, and its other variables are bound elsewhere in the clause (or used nowhere else).
fn negation_fix(
    c: &Clause,
    n: usize,
    atom: &Atom,
    spec: &catalog::RelationSpec,
    var: &str,
    lower: &[&Bound],
    defined: &[&str],
) -> Option<(Clause, Clause)> {
    let [bound] = lower else {
        return None;
    };
    // Whether the head or a literal other than the atom and its bound mentions `v`.
    let used_elsewhere = |v: &str| {
        c.head.args.iter().any(|a| walk::expr_names(a).contains(&v))
            || c.body
                .iter()
                .enumerate()
                .any(|(i, l)| i != n && i != bound.at && literal_names(l).contains(&v))
    };
    // The distance is used only here and in its bound.
    let once = atom.args.iter().filter(|a| a.as_var() == Some(var)).count() == 1;
    if used_elsewhere(var) || !once {
        return None;
    }
    // The objects and the time: variables, bound by `present` in the rewritten clause.
    let col_var = |ty: ColType| -> Option<Vec<&str>> {
        spec.columns
            .iter()
            .zip(&atom.args)
            .filter(|(cs, _)| cs.ty == ty)
            .map(|(_, a)| a.as_var())
            .collect()
    };
    let tracks = col_var(ColType::Track)?;
    let times = col_var(ColType::Time)?;
    let [time] = times.as_slice() else {
        return None;
    };
    if tracks.is_empty() {
        return None;
    }
    // The atom's objects and time, and its other variables the clause uses elsewhere, are the
    // helper's head; its other variables are `_` in the helper.
    let span = Span::default();
    let var_expr = Expr::var;
    let mut head_vars: Vec<&str> = Vec::new();
    let mut helper_args = Vec::new();
    for a in &atom.args {
        match &a.kind {
            ExprKind::Var(v) if v == var => helper_args.push(a.clone()),
            ExprKind::Var(v) if tracks.contains(&v.as_str()) || v == time || used_elsewhere(v) => {
                if !head_vars.contains(&v.as_str()) {
                    head_vars.push(v);
                }
                helper_args.push(a.clone());
            }
            ExprKind::Var(_) | ExprKind::Wildcard => helper_args.push(Expr {
                kind: ExprKind::Wildcard,
                span,
            }),
            _ => helper_args.push(a.clone()),
        }
    }
    let k = bound.value;
    let k_name = if k.fract() == 0.0 {
        format!("{}", k as i64)
    } else {
        format!("{k}").replace(['.', '-'], "_")
    };
    let name = free_relation_name(&format!("{}_within_{k_name}_m", atom.pred), |n| {
        defined.contains(&n) || catalog::relation(n).is_some()
    })?;
    let head = Atom {
        pred: name,
        pred_span: span,
        args: head_vars.iter().map(|v| var_expr(v)).collect(),
        span,
    };
    let close = Comparison {
        op: if bound.strict { CmpOp::Le } else { CmpOp::Lt },
        lhs: var_expr(var),
        rhs: bound.written.clone(),
        span,
    };
    let helper = Clause {
        head: head.clone(),
        body: vec![
            Literal::Pos(Atom {
                pred: atom.pred.clone(),
                pred_span: span,
                args: helper_args,
                span,
            }),
            Literal::Cmp(close),
        ],
        span,
    };
    let mut replacement: Vec<Literal> = Vec::new();
    for t in &tracks {
        replacement.push(Literal::Pos(Atom {
            pred: "present".into(),
            pred_span: span,
            args: vec![var_expr(t), var_expr(time)],
            span,
        }));
    }
    // A pair relation never relates an object to itself; "not within k m" must not either.
    for (i, x) in tracks.iter().enumerate() {
        for y in &tracks[i + 1..] {
            replacement.push(Literal::Cmp(Comparison {
                op: CmpOp::Ne,
                lhs: var_expr(x),
                rhs: var_expr(y),
                span,
            }));
        }
    }
    replacement.push(Literal::Neg(head, span));
    let mut rewritten = c.clone();
    rewritten.body = Vec::new();
    for (i, l) in c.body.iter().enumerate() {
        if i == n {
            rewritten.body.extend(replacement.iter().cloned());
        } else if i != bound.at {
            rewritten.body.push(l.clone());
        }
    }
    Some((helper, rewritten))
}
