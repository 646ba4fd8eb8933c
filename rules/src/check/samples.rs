//! W0512: a duration measured by counting samples. A `count` over moments of one object
//! (`N = count : { stopped(X, U), … }`) compared with a number of samples (`N >= 31`) means 3 s
//! at 10 Hz and 15 s at 2 Hz: the tracker's rate decides. The rate-independent idiom compares
//! the count with the window's `present` count, the window bounded in seconds.

use std::collections::{BTreeMap, HashMap, HashSet};

use scenalog_facts::catalog::ColType;

use crate::ast::{AggFunc, Clause, ExprKind, Literal};
use crate::diagnostics::{self, warning};
use crate::walk::{aggregate_vars, expr_vars, outer_vars};
use crate::Diagnostic;

/// Reports W0512 for the counts of moments in `c` compared with a number of samples.
pub fn check_clause(
    c: &Clause,
    types: &BTreeMap<String, Vec<ColType>>,
    diags: &mut Vec<Diagnostic>,
) {
    // How often each variable shows outside braces, counted once for the clause, so each
    // aggregate's own share is taken off rather than the body scanned again.
    let mut shown: HashMap<&str, usize> = HashMap::new();
    let mut all = Vec::new();
    c.head.args.iter().for_each(|e| expr_vars(e, &mut all));
    c.body.iter().for_each(|l| outer_vars(l, &mut all));
    for v in all {
        *shown.entry(v).or_default() += 1;
    }
    // Each variable's comparisons with a number of at least 2, collected once.
    let number = |e: &crate::ast::Expr| match e.kind {
        ExprKind::Int(n) => Some(n as f64),
        ExprKind::Float(f) => Some(f),
        _ => None,
    };
    let mut numbers: HashMap<&str, Vec<(&crate::ast::Comparison, f64)>> = HashMap::new();
    for l in &c.body {
        let Literal::Cmp(cmp) = l else { continue };
        let found = match (cmp.lhs.as_var(), cmp.rhs.as_var()) {
            (Some(v), _) => number(&cmp.rhs).map(|n| (v, n)),
            (_, Some(v)) => number(&cmp.lhs).map(|n| (v, n)),
            _ => None,
        };
        if let Some((v, n)) = found.filter(|&(_, n)| n >= 2.0) {
            numbers.entry(v).or_default().push((cmp, n));
        }
    }
    for l in &c.body {
        let Literal::Agg(g) = l else { continue };
        if g.func != AggFunc::Count {
            continue;
        }
        let Some(result) = g.result.as_var() else {
            continue;
        };
        if !numbers.contains_key(result) {
            continue;
        }
        let mut own = Vec::new();
        outer_vars(l, &mut own);
        let outside = |v: &str| {
            let mine = own.iter().filter(|o| **o == v).count();
            shown.get(v).copied().unwrap_or(0) > mine
        };
        let counted: HashSet<&str> = aggregate_vars(g)
            .into_iter()
            .filter(|v| !outside(v))
            .collect();
        let (mut moments, mut objects) = (false, false);
        for b in &g.body {
            let Literal::Pos(a) = b else { continue };
            let cols = super::column_types(&a.pred, types).unwrap_or_default();
            for (e, ty) in a.args.iter().zip(cols) {
                let Some(v) = e.as_var() else { continue };
                if !counted.contains(v) {
                    continue;
                }
                match ty {
                    ColType::Time => moments = true,
                    ColType::Track => objects = true,
                    _ => {}
                }
            }
        }
        if !moments || objects {
            continue;
        }
        for &(cmp, n) in numbers.get(result).map_or(&[][..], |v| &v[..]) {
            let span_s = |hz: f64| (n - 1.0) / hz;
            diags.push(
                warning(
                    diagnostics::COUNTED_SAMPLES,
                    cmp.span,
                    format!(
                        "this measures time by counting samples: {n} samples span {} s at \
                         10 Hz and {} s at 2 Hz",
                        span_s(10.0),
                        span_s(2.0)
                    ),
                )
                .with_hint(format!(
                    "bound the window in seconds and compare the count with the window's \
                     `present` count, the same at any rate: `T0 = T - {} s, N = count : {{ \
                     p(X, U), U >= T0, U <= T }}, M = count : {{ present(X, W), W >= T0, W <= T \
                     }}, N = M`",
                    span_s(10.0)
                )),
            );
        }
    }
}
