//! Aggregates in a plan: folding a body's tuples by group ([`fold`], integer `sum` overflow
//! an error), correlated aggregates run per outer binding ([`Correlated<R>`]), and the filter that
//! looks an aggregate's result up.

use super::*;

pub(crate) fn var_expr(name: &str) -> Expr {
    Expr {
        kind: ExprKind::Var(name.to_string()),
        span: Span::default(),
    }
}

/// A `sum` of integers left the 64-bit range (the fold's error: never a saturated result).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SumOverflow;

/// Aggregates rows `group prefix (g_len columns) ++ … ++ target (column last)` by group; a
/// `count` reads no target (its rows may have no column at all: `count : { a(1) }`). `min`
/// and `max` of strings order them by text (`texts`).
pub(crate) fn fold<const R: usize>(
    func: AggFunc,
    rows: &Rows,
    (g_len, last): (usize, usize),
    (target_ty, out_ty): (ColType, ColType),
    texts: &Texts,
) -> Result<FastMap<Row<R>, u64>, SumOverflow> {
    let mut acc: FastMap<Row<R>, V> = FastMap::default();
    for r in rows.iter() {
        let mut key = [0u64; R];
        key[..g_len].copy_from_slice(&r[..g_len]);
        let x = match func {
            AggFunc::Count => V::Int(0),
            _ => decode(r[last], target_ty),
        };
        let slot = acc.entry(key);
        match func {
            AggFunc::Count => {
                let e = slot.or_insert(V::Int(0));
                if let V::Int(n) = e {
                    *n += 1;
                }
            }
            AggFunc::Sum => {
                let e = slot.or_insert(if out_ty == ColType::Float {
                    V::Float(0.0)
                } else {
                    V::Int(0)
                });
                *e = match (*e, x) {
                    (V::Int(a), V::Int(b)) => V::Int(a.checked_add(b).ok_or(SumOverflow)?),
                    (V::Float(a), V::Float(b)) => V::Float(a + b),
                    (V::Float(a), V::Int(b)) => V::Float(a + b as f64),
                    (a, _) => a,
                };
            }
            AggFunc::Min | AggFunc::Max => {
                let want = if func == AggFunc::Min {
                    std::cmp::Ordering::Less
                } else {
                    std::cmp::Ordering::Greater
                };
                let order = |x: V, e: V| match target_ty {
                    ColType::Str => texts.compare(x, e),
                    _ => x.compare(e),
                };
                slot.and_modify(|e| {
                    if order(x, *e) == Some(want) {
                        *e = x;
                    }
                })
                .or_insert(x);
            }
        }
    }
    let mut table = FastMap::default();
    for (k, v) in acc {
        if let Some(u) = encode(v, out_ty) {
            table.insert(k, u);
        }
    }
    Ok(table)
}

/// An aggregate whose body uses outer variables only in comparisons or expressions: its body
/// is run for each outer binding, with the group variables bound first.
#[derive(Debug)]
pub struct Correlated<const R: usize> {
    pub(crate) plan: Plan<R>,
    /// Per inner atom: its selected tuples by join key.
    pub(crate) indexes: Vec<FastMap<Row<R>, Vec<Row<R>>>>,
    pub(crate) group: Vec<usize>,
    pub(crate) func: AggFunc,
    pub(crate) g_len: usize,
    pub(crate) last: usize,
    pub(crate) target_ty: ColType,
    pub(crate) out_ty: ColType,
    /// The strings' texts, for `min` and `max` of strings.
    pub(crate) texts: Texts,
    pub(crate) default: Option<u64>,
    /// Set when a `sum` overflowed for some binding; the evaluation then fails (see
    /// [`Plan::sum_overflowed`]) instead of using a wrong number.
    pub(crate) overflowed: std::sync::atomic::AtomicBool,
}

impl<const R: usize> Correlated<R> {
    pub(crate) fn run(&self, outer: &Row<R>) -> Option<u64> {
        let mut start = [0u64; R];
        for (i, s) in self.group.iter().enumerate() {
            start[i] = outer[*s];
        }
        let mut bindings: Vec<Row<R>> = apply(&self.plan.start, start).into_iter().collect();
        for (step, index) in self.plan.atoms.iter().zip(&self.indexes) {
            let mut next = Vec::new();
            for b in &bindings {
                let Some(k) = step.binding_key(b) else {
                    continue;
                };
                for t in index.get(&k).into_iter().flatten() {
                    next.extend(apply(&step.after, step.extend(*b, t)));
                }
            }
            bindings = next;
        }
        let mut rows = Rows::new(self.plan.head.len());
        for b in &bindings {
            if let Some(r) = self.plan.project(b) {
                rows.push(&r);
            }
        }
        rows.sort_dedup();
        let table = match fold::<R>(
            self.func,
            &rows,
            (self.g_len, self.last),
            (self.target_ty, self.out_ty),
            &self.texts,
        ) {
            Ok(t) => t,
            Err(SumOverflow) => {
                self.overflowed
                    .store(true, std::sync::atomic::Ordering::Relaxed);
                return None;
            }
        };
        match table.into_values().next() {
            Some(v) => Some(v),
            None => self.default,
        }
    }
}

/// Evaluates an aggregate's body over the completed relations and returns the filter that
/// looks its result up by group, plus a comparison when the result is not a fresh variable.
pub(crate) fn agg_filter<const R: usize>(
    g: &Aggregate,
    group: &[&str],
    scope: &mut Scope,
    ctx: &mut Ctx<'_>,
) -> Result<(Filter<R>, Option<Filter<R>>), EngineError> {
    // The body's matching tuples, not its named bindings: `_` columns are fresh variables.
    let named = crate::agg_body::name_wildcards(g);
    let g = &named;
    let lits = body_lits(&g.body);
    let mut head: Vec<Expr> = group.iter().map(|v| var_expr(v)).collect();
    let g_len = head.len();
    if matches!(g.func, AggFunc::Count | AggFunc::Sum) {
        for v in scenalog_rules::walk::aggregate_level_vars(g) {
            if !group.contains(&v) {
                head.push(var_expr(v));
            }
        }
    }
    if g.func != AggFunc::Count {
        match &g.target {
            Some(t) => head.push(t.clone()),
            None => {
                return Err(EngineError::Unsupported(format!(
                    "`{}` without a target expression",
                    g.func.as_str()
                )))
            }
        }
    }
    if head.len() > R {
        return Err(EngineError::Unsupported(format!(
            "an aggregate with more than {R} variables"
        )));
    }
    // The group variables the braces' atoms bind themselves (as a plain argument: in `u(B + 1)`
    // `B` is computed from, not bound); otherwise the body runs per outer binding.
    let mut in_atoms = Vec::new();
    for l in &lits {
        if let BodyLit::Pos(a) = l {
            in_atoms.extend(a.args.iter().filter_map(|e| e.as_var()));
        }
    }
    if !group.iter().all(|v| in_atoms.contains(v)) {
        return correlated(g, group, head, g_len, scope, ctx);
    }
    let inner = plan::<R>(&lits, &head, None, ctx)?;
    let rows = crate::stratum::once::run_plan(&inner, ctx.complete, ctx.types, ctx.limits)?;
    let target_ty = inner.head.last().map_or(ColType::Int, |(_, t)| *t);
    let (out_ty, default) = result_type(g.func, target_ty);
    let last = head.len().saturating_sub(1);
    let texts = ctx.symbols.texts();
    let table = fold(g.func, &rows, (g_len, last), (target_ty, out_ty), &texts)
        .map_err(|SumOverflow| ctx.limits.sum_overflow())?;
    let group_slots = group
        .iter()
        .map(|v| scope.slots.get(*v).map(|s| s.0))
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| EngineError::Unsupported("an aggregate's group is unbound".into()))?;
    bind_result(g, out_ty, scope, ctx, |out| Filter::Agg {
        group: group_slots,
        table: Arc::new(table),
        default,
        out,
    })
}

/// An aggregate's result type for a target of type `target_ty`, and its encoded value over no
/// tuples (0 for count and sum; none, so the body fails, for min and max).
fn result_type(func: AggFunc, target_ty: ColType) -> (ColType, Option<u64>) {
    let out_ty = match func {
        AggFunc::Count => ColType::Int,
        AggFunc::Sum if target_ty == ColType::Float => ColType::Float,
        AggFunc::Sum => ColType::Int,
        AggFunc::Min | AggFunc::Max => target_ty,
    };
    let default = match func {
        AggFunc::Count => encode(V::Int(0), ColType::Int),
        AggFunc::Sum if out_ty == ColType::Float => encode(V::Float(0.0), ColType::Float),
        AggFunc::Sum => encode(V::Int(0), ColType::Int),
        AggFunc::Min | AggFunc::Max => None,
    };
    (out_ty, default)
}

/// The filter `make` builds for the slot holding an aggregate's result: the result variable's
/// own slot when the variable is new here, else a fresh slot and a second filter comparing it
/// with the result expression.
fn bind_result<const R: usize>(
    g: &Aggregate,
    out_ty: ColType,
    scope: &mut Scope,
    ctx: &mut Ctx<'_>,
    make: impl FnOnce(usize) -> Filter<R>,
) -> Result<(Filter<R>, Option<Filter<R>>), EngineError> {
    let fresh = match g.result.as_var() {
        Some(v) if !scope.slots.contains_key(v) => Some(v),
        _ => None,
    };
    let out = match fresh {
        Some(v) => scope.new_slot(v, out_ty)?,
        None => scope.new_slot(&format!("#agg{}", scope.slots.len()), out_ty)?,
    };
    let f = make(out);
    if fresh.is_some() {
        return Ok((f, None));
    }
    let cmp = Filter::Cmp(
        CmpOp::Eq,
        compile_expr(&g.result, scope, ctx.symbols)?,
        CExpr::Slot(out, out_ty),
    );
    Ok((f, Some(cmp)))
}

/// Plans a correlated aggregate (see [`Correlated<R>`]).
pub(crate) fn correlated<const R: usize>(
    g: &Aggregate,
    group: &[&str],
    head: Vec<Expr>,
    g_len: usize,
    scope: &mut Scope,
    ctx: &mut Ctx<'_>,
) -> Result<(Filter<R>, Option<Filter<R>>), EngineError> {
    let lits = body_lits(&g.body);
    let mut seed = Vec::new();
    let mut group_slots = Vec::new();
    for v in group {
        let (s, ty) = *scope
            .slots
            .get(*v)
            .ok_or_else(|| EngineError::Unsupported("an aggregate's group is unbound".into()))?;
        seed.push((*v, ty));
        group_slots.push(s);
    }
    let inner = plan_seeded(&lits, &head, None, ctx, &seed, None)?;
    let empty = Rows::new(0);
    let indexes = inner
        .atoms
        .iter()
        .map(|step| {
            let mut index: FastMap<Row<R>, Vec<Row<R>>> = FastMap::default();
            for t in ctx.complete.get(&step.pred).unwrap_or(&empty).iter() {
                if step.selects(t) {
                    index
                        .entry(step.tuple_key(t))
                        .or_default()
                        .push(Rows::row(t));
                }
            }
            index
        })
        .collect();
    let target_ty = inner.head.last().map_or(ColType::Int, |(_, t)| *t);
    let (out_ty, default) = result_type(g.func, target_ty);
    let c = Correlated {
        plan: inner,
        indexes,
        group: group_slots,
        func: g.func,
        g_len,
        last: head.len().saturating_sub(1),
        target_ty,
        out_ty,
        texts: ctx.symbols.texts(),
        default,
        overflowed: std::sync::atomic::AtomicBool::new(false),
    };
    bind_result(g, out_ty, scope, ctx, |out| {
        Filter::AggRun(Arc::new(c), out)
    })
}
