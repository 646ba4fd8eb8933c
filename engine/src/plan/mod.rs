//! Compiling rule bodies into join plans: each body's atoms joined in order of how many of
//! their arguments are already bound, comparisons, bindings and negations placed right after the
//! atom that binds their last variable. Expressions are in `expr`, the checks on a binding row
//! in `filter`, one atom's step in `atom`, range narrowing and comparison order in `narrow`, and
//! aggregates in `aggregate`.

use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use scenalog_facts::catalog::ColType;
use scenalog_rules::ast::{
    AggFunc, Aggregate, Atom, BinOp, CmpOp, Expr, ExprKind, Func, Literal, Number, Span,
};

use crate::limits::Limits;
use crate::rows::Rows;
use crate::value::{decode, encode, FastMap, FastSet, Row, Symbols, Texts, V};
use crate::EngineError;
use scenalog_rules::walk::{aggregate_vars as agg_vars, expr_vars};

mod aggregate;
mod atom;
mod dead;
mod expr;
mod filter;
mod narrow;
#[cfg(test)]
mod tests;

pub use aggregate::*;
pub use atom::*;
pub use expr::*;
pub use filter::*;
pub use narrow::*;

/// A compiled body: filters on the empty binding, then atoms in join order, then a projection.
#[derive(Debug, Clone)]
pub struct Plan<const R: usize> {
    /// Filters before any atom (bodies without atoms, constant comparisons).
    pub start: Vec<Filter<R>>,
    /// Atoms in join order, each with the filters that become ready after it.
    pub atoms: Vec<AtomStep<R>>,
    /// The output row: one expression per column, with its type.
    pub head: Vec<(CExpr, ColType)>,
}

impl<const R: usize> Plan<R> {
    /// Whether a correlated `sum` of this plan (or of an aggregate nested in it) overflowed
    /// the 64-bit integer range while it ran.
    pub fn sum_overflowed(&self) -> bool {
        let filters = self
            .start
            .iter()
            .chain(self.atoms.iter().flat_map(|a| &a.after));
        filters.into_iter().any(|f| match f {
            Filter::AggRun(c, _) => {
                c.overflowed.load(std::sync::atomic::Ordering::Relaxed) || c.plan.sum_overflowed()
            }
            _ => false,
        })
    }

    /// The output row of a complete binding.
    pub fn project(&self, b: &Row<R>) -> Option<Row<R>> {
        let mut out = [0u64; R];
        for (i, (e, ty)) in self.head.iter().enumerate() {
            out[i] = e.word(b, *ty)??;
        }
        Some(out)
    }
}

/// What the planner needs to know about the program's relations.
pub struct Ctx<'a> {
    /// Column types by predicate.
    pub types: &'a HashMap<String, Vec<ColType>>,
    /// Completed relations (for negation sets).
    pub complete: &'a HashMap<String, Rows>,
    /// Symbols.
    pub symbols: &'a mut Symbols,
    /// Limits for evaluating aggregate bodies.
    pub limits: &'a Limits<'a>,
}

pub(crate) struct Scope {
    pub(crate) slots: HashMap<String, (usize, ColType)>,
    /// The binding row's width: slots past it cannot be held.
    pub(crate) width: usize,
}

impl Scope {
    pub(crate) fn bound(&self, e: &Expr) -> bool {
        let mut vs = Vec::new();
        expr_vars(e, &mut vs);
        vs.iter().all(|v| self.slots.contains_key(*v))
    }

    /// Whether every variable of `e` has a slot below `from` (bound before the atom whose
    /// slots start there).
    pub(crate) fn bound_before(&self, e: &Expr, from: usize) -> bool {
        let mut vs = Vec::new();
        expr_vars(e, &mut vs);
        vs.iter()
            .all(|v| self.slots.get(*v).is_some_and(|&(s, _)| s < from))
    }

    pub(crate) fn new_slot(&mut self, name: &str, ty: ColType) -> Result<usize, EngineError> {
        let s = self.slots.len();
        if s >= self.width {
            return Err(EngineError::Unsupported(format!(
                "a rule has more than {} variables",
                self.width
            )));
        }
        self.slots.insert(name.to_string(), (s, ty));
        Ok(s)
    }
}

/// A body literal the planner schedules (aggregates are rewritten to atoms beforehand).
pub enum BodyLit<'a> {
    /// A positive atom.
    Pos(&'a Atom),
    /// A negated atom.
    Neg(&'a Atom),
    /// A comparison or binding.
    Cmp(CmpOp, &'a Expr, &'a Expr),
    /// An aggregate over completed relations.
    Agg(&'a Aggregate),
}

/// Collects the literals of a body.
pub fn body_lits(body: &[Literal]) -> Vec<BodyLit<'_>> {
    body.iter()
        .map(|l| match l {
            Literal::Pos(a) => BodyLit::Pos(a),
            Literal::Neg(a, _) => BodyLit::Neg(a),
            Literal::Cmp(c) => BodyLit::Cmp(c.op, &c.lhs, &c.rhs),
            Literal::Agg(g) => BodyLit::Agg(g),
        })
        .collect()
}

/// Plans a body and a head (output expressions; `head_types` gives the output column types,
/// `None` to infer them from the expressions).
pub fn plan<const R: usize>(
    lits: &[BodyLit<'_>],
    head: &[Expr],
    head_types: Option<&[ColType]>,
    ctx: &mut Ctx<'_>,
) -> Result<Plan<R>, EngineError> {
    plan_seeded(lits, head, head_types, ctx, &[], None)
}

/// [`plan`] with the positive atom `lits[first]` joined first (the semi-naive variant that
/// reads that atom's recent tuples scans them and looks the other atoms up).
pub fn plan_first<const R: usize>(
    lits: &[BodyLit<'_>],
    head: &[Expr],
    head_types: Option<&[ColType]>,
    ctx: &mut Ctx<'_>,
    first: usize,
) -> Result<Plan<R>, EngineError> {
    plan_seeded(lits, head, head_types, ctx, &[], Some(first))
}

/// The tuple a ground fact's head derives (`None` if a value cannot be stored in its column),
/// computed as the plan of a body-less clause would ([`plan`] then [`Plan::project`]), without
/// building the plan. `head_types` gives the column types, `None` to infer them.
pub(crate) fn ground_head<const R: usize>(
    head: &[Expr],
    head_types: Option<&[ColType]>,
    symbols: &mut Symbols,
) -> Result<Option<Row<R>>, EngineError> {
    let scope = Scope {
        slots: HashMap::new(),
        width: R,
    };
    let empty = [0u64; R];
    let mut out = [0u64; R];
    for (i, e) in head.iter().enumerate() {
        // A literal (`3`, `-2`, `1.5`, `"BUS"`: nearly every argument of a fact) is its value;
        // anything else is compiled and evaluated as a plan would.
        let value = match literal(e, symbols) {
            Some(v) => v,
            None => {
                let Some(v) = compile_expr(e, &scope, symbols)?.eval(&empty) else {
                    return Ok(None);
                };
                v
            }
        };
        let ty = match head_types {
            Some(t) => t.get(i).copied().unwrap_or(ColType::Int),
            None => expr_type(&CExpr::Const(value)),
        };
        let Some(word) = out.get_mut(i) else {
            return Ok(None);
        };
        match encode(value, ty) {
            Some(w) => *word = w,
            None => return Ok(None),
        }
    }
    Ok(Some(out))
}

/// The value of a literal or a negated number literal, as [`compile_expr`] then
/// [`CExpr::eval`] would compute it; `None` for any other expression (and for a negation that
/// overflows, which the general path then reports the same way).
pub(crate) fn literal(e: &Expr, symbols: &mut Symbols) -> Option<V> {
    match &e.kind {
        ExprKind::Int(i) => Some(V::Int(*i)),
        ExprKind::Float(f) => Some(V::Float(*f)),
        ExprKind::Quantity(q) => Some(match q.number() {
            Number::Int(i) => V::Int(i),
            Number::Float(f) => V::Float(f),
        }),
        ExprKind::Str(s) => Some(V::Sym(symbols.intern(s))),
        ExprKind::Neg(a) => match &a.kind {
            ExprKind::Int(i) => i.checked_neg().map(V::Int),
            ExprKind::Float(f) => Some(V::Float(-f)),
            _ => None,
        },
        _ => None,
    }
}

/// [`plan`] with variables already bound, in slots `0..seed.len()`.
pub(crate) fn plan_seeded<const R: usize>(
    lits: &[BodyLit<'_>],
    head: &[Expr],
    head_types: Option<&[ColType]>,
    ctx: &mut Ctx<'_>,
    seed: &[(&str, ColType)],
    first: Option<usize>,
) -> Result<Plan<R>, EngineError> {
    if lits.is_empty() && seed.is_empty() {
        // A ground fact (or a head over no body): nothing to schedule.
        let scope = Scope {
            slots: HashMap::new(),
            width: R,
        };
        let mut out = Vec::new();
        for (i, e) in head.iter().enumerate() {
            let ce = compile_expr(e, &scope, ctx.symbols)?;
            let ty = match head_types {
                Some(t) => t.get(i).copied().unwrap_or(ColType::Int),
                None => expr_type(&ce),
            };
            out.push((ce, ty));
        }
        return Ok(Plan {
            start: Vec::new(),
            atoms: Vec::new(),
            head: out,
        });
    }
    let mut scope = Scope {
        slots: HashMap::new(),
        width: R,
    };
    for (v, ty) in seed {
        scope.new_slot(v, *ty)?;
    }
    let mut done = vec![false; lits.len()];
    // Per literal, the variables it shows to the rest of the body (of an aggregate only its
    // result): an aggregate is grouped by those of its variables that the seed or another
    // literal shows, as Soufflé scopes it. A variable only in its own result or the head is
    // local to its braces (`Y = min Z + Y : { a(Z), a(Y) }`: the inner `Y` is not the result).
    let shown: Vec<Vec<&str>> = lits
        .iter()
        .map(|l| {
            let mut vs = Vec::new();
            match l {
                BodyLit::Pos(a) | BodyLit::Neg(a) => {
                    a.args.iter().for_each(|e| expr_vars(e, &mut vs))
                }
                BodyLit::Cmp(_, a, b) => {
                    expr_vars(a, &mut vs);
                    expr_vars(b, &mut vs);
                }
                BodyLit::Agg(g) => expr_vars(&g.result, &mut vs),
            }
            vs
        })
        .collect();
    // How often each variable occurs in the head, the body (inside aggregates too) and the
    // seed: one bound by an atom and used nowhere else is dead, and an atom binding only dead
    // variables is an existence test (`AtomStep::existential`).
    let mut uses: HashMap<&str, usize> = HashMap::new();
    {
        let mut vs: Vec<&str> = seed.iter().map(|(v, _)| *v).collect();
        for e in head {
            expr_vars(e, &mut vs);
        }
        for (l, shows) in lits.iter().zip(&shown) {
            vs.extend(shows.iter().copied());
            if let BodyLit::Agg(g) = l {
                vs.extend(agg_vars(g));
            }
        }
        for v in vs {
            *uses.entry(v).or_default() += 1;
        }
    }
    // Per aggregate literal, its group: computed once, whatever the join order.
    let groups: Vec<Vec<&str>> = lits
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let BodyLit::Agg(g) = l else {
                return Vec::new();
            };
            let mut outer: HashSet<&str> = seed.iter().map(|(v, _)| *v).collect();
            for (j, vs) in shown.iter().enumerate() {
                if j != i {
                    outer.extend(vs.iter().copied());
                }
            }
            agg_vars(g)
                .into_iter()
                .filter(|v| outer.contains(v))
                .collect()
        })
        .collect();
    let mut start = Vec::new();
    let mut atoms: Vec<AtomStep<R>> = Vec::new();
    // Per atom, per filter after it: its rank among comparisons (see `cmp_rank`); the body
    // literals whose comparisons bound an atom's range.
    let mut ranks: Vec<Vec<u8>> = Vec::new();
    let mut windowed: HashSet<usize> = HashSet::new();
    // Expression arguments joined before their variables were bound (`g(X + 1)` joined before
    // `v(X)`, `p(2 * N, N)`): each read into a hidden slot, then compared with the expression
    // once its variables are bound.
    let mut pending: Vec<(usize, ColType, &Expr)> = Vec::new();
    loop {
        // Ready filters first (comparisons, bindings, negations).
        let mut progress = true;
        while progress {
            progress = false;
            let mut k = 0;
            while k < pending.len() {
                let (slot, ty, e) = pending[k];
                if !scope.bound(e) {
                    k += 1;
                    continue;
                }
                pending.swap_remove(k);
                let ce = compile_expr(e, &scope, ctx.symbols)?;
                let f = compare_filter(CmpOp::Eq, CExpr::Slot(slot, ty), ce, ctx.symbols);
                place(
                    f,
                    cmp_rank(CmpOp::Eq, false),
                    &mut atoms,
                    &mut ranks,
                    &mut start,
                );
                progress = true;
            }
            for (i, l) in lits.iter().enumerate() {
                if done[i] {
                    continue;
                }
                let f = match l {
                    BodyLit::Cmp(op, a, b) => {
                        if scope.bound(a) && scope.bound(b) {
                            let x = compile_expr(a, &scope, ctx.symbols)?;
                            let y = compile_expr(b, &scope, ctx.symbols)?;
                            Some(compare_filter(*op, x, y, ctx.symbols))
                        } else if *op == CmpOp::Eq {
                            let (var, e) = match (a.as_var(), b.as_var()) {
                                (Some(v), _) if !scope.slots.contains_key(v) && scope.bound(b) => {
                                    (v, b)
                                }
                                (_, Some(v)) if !scope.slots.contains_key(v) && scope.bound(a) => {
                                    (v, a)
                                }
                                _ => continue,
                            };
                            let ce = compile_expr(e, &scope, ctx.symbols)?;
                            let ty = expr_type(&ce);
                            let s = scope.new_slot(var, ty)?;
                            Some(Filter::Bind(s, ce, ty))
                        } else {
                            None
                        }
                    }
                    BodyLit::Neg(a) => {
                        let ready = a
                            .args
                            .iter()
                            .all(|e| matches!(e.kind, ExprKind::Wildcard) || scope.bound(e));
                        if ready {
                            Some(neg_filter(a, &scope, ctx)?)
                        } else {
                            None
                        }
                    }
                    BodyLit::Agg(g) => {
                        let group = &groups[i];
                        if group.iter().all(|v| scope.slots.contains_key(*v)) {
                            let (f, extra) = agg_filter(g, group, &mut scope, ctx)?;
                            if let Some(x) = extra {
                                place(f, 0, &mut atoms, &mut ranks, &mut start);
                                Some(x)
                            } else {
                                Some(f)
                            }
                        } else {
                            None
                        }
                    }
                    BodyLit::Pos(_) => None,
                };
                if let Some(f) = f {
                    done[i] = true;
                    progress = true;
                    let rank = match l {
                        BodyLit::Cmp(op, ..) => cmp_rank(*op, windowed.contains(&i)),
                        _ => 0,
                    };
                    place(f, rank, &mut atoms, &mut ranks, &mut start);
                }
            }
        }
        // Next atom: the one with most bound or constant arguments, on a tie one whose
        // expression arguments can all be computed (it is looked up, not read whole).
        let mut best: Option<(usize, (usize, bool))> = None;
        for (i, l) in lits.iter().enumerate() {
            if let (false, BodyLit::Pos(a)) = (done[i], l) {
                let bound = a
                    .args
                    .iter()
                    .filter(|e| !matches!(e.kind, ExprKind::Wildcard) && scope.bound(e))
                    .count();
                let computable = a.args.iter().all(|e| {
                    matches!(e.kind, ExprKind::Wildcard | ExprKind::Var(_)) || scope.bound(e)
                });
                let forced = atoms.is_empty() && first == Some(i);
                let score = if forced {
                    (usize::MAX, true)
                } else {
                    (bound, computable)
                };
                if best.is_none_or(|(_, s)| score > s) {
                    best = Some((i, score));
                }
            }
        }
        let Some((i, _)) = best else { break };
        done[i] = true;
        let BodyLit::Pos(a) = lits[i] else { break };
        let types = ctx.types.get(&a.pred).cloned().unwrap_or_default();
        if types.len() != a.args.len() {
            return Err(EngineError::Unsupported(format!(
                "`{}` used with {} arguments but has {} columns",
                a.pred,
                a.args.len(),
                types.len()
            )));
        }
        let from = scope.slots.len();
        let mut args = Vec::new();
        for (e, &ty) in a.args.iter().zip(&types) {
            let arg = match &e.kind {
                ExprKind::Wildcard => Arg::Wild,
                ExprKind::Var(v) => match scope.slots.get(v) {
                    Some(&(s, _)) if args.iter().any(|x| matches!(x, Arg::New(n) if *n == s)) => {
                        Arg::Same(s)
                    }
                    Some(_) => Arg::Key(compile_expr(e, &scope, ctx.symbols)?, ty),
                    None => Arg::New(scope.new_slot(v, ty)?),
                },
                // A key computed before the lookup: only from variables bound before this
                // atom (`t(N, N + 1)` reads N from the same tuple, so it is compared after).
                _ if scope.bound_before(e, from) => {
                    let ce = compile_expr(e, &scope, ctx.symbols)?;
                    match ce {
                        CExpr::Const(c) => match encode(c, ty) {
                            Some(c) => Arg::Const(c),
                            None => Arg::Const(u64::MAX),
                        },
                        ce => Arg::Key(ce, ty),
                    }
                }
                _ => {
                    let hidden = format!("#arg{}", scope.slots.len());
                    let s = scope.new_slot(&hidden, ty)?;
                    pending.push((s, ty, e));
                    Arg::New(s)
                }
            };
            args.push(arg);
        }
        let dead = a.args.iter().all(|e| match &e.kind {
            ExprKind::Var(v) => {
                scope.slots.get(v).is_some_and(|&(s, _)| s < from)
                    || uses.get(v.as_str()) == Some(&1)
            }
            _ => true,
        });
        let mut step = AtomStep::new(a.pred.clone(), args, Vec::new());
        step.lit = i;
        step.existential = dead && !pending_from(&pending, from);
        // The comparisons ready once this atom is joined may bound one of its new columns.
        let mut ready = Vec::new();
        let mut ready_lits = Vec::new();
        for (j, l) in lits.iter().enumerate() {
            if let (false, BodyLit::Cmp(op, x, y)) = (done[j], l) {
                if scope.bound(x) && scope.bound(y) {
                    ready.push((
                        *op,
                        compile_expr(x, &scope, ctx.symbols)?,
                        compile_expr(y, &scope, ctx.symbols)?,
                    ));
                    ready_lits.push(j);
                }
            }
        }
        if let Some((n, used)) = narrowing(&step.news, &types, &ready, from) {
            step.narrow = Some(n);
            windowed.extend(used.iter().filter_map(|&u| ready_lits.get(u)));
        }
        atoms.push(step);
        ranks.push(Vec::new());
    }
    for (a, r) in atoms.iter_mut().zip(&ranks) {
        order_comparisons(&mut a.after, r);
    }
    if done.iter().any(|d| !d) || !pending.is_empty() {
        return Err(EngineError::Unsupported(
            "a rule body whose variables cannot all be bound".to_string(),
        ));
    }
    let mut out = Vec::new();
    for (i, e) in head.iter().enumerate() {
        let ce = compile_expr(e, &scope, ctx.symbols)?;
        let ty = match head_types {
            Some(t) => t.get(i).copied().unwrap_or(ColType::Int),
            None => expr_type(&ce),
        };
        out.push((ce, ty));
    }
    dead::mark_dead_runs(&mut atoms, &out);
    Ok(Plan {
        start,
        atoms,
        head: out,
    })
}

/// Whether an expression argument of the atom just planned (its hidden slots start at
/// `from`) waits to be compared: the atom's tuples then differ in what is checked later.
fn pending_from(pending: &[(usize, ColType, &Expr)], from: usize) -> bool {
    pending.iter().any(|&(s, _, _)| s >= from)
}

pub(crate) fn neg_filter<const R: usize>(
    a: &Atom,
    scope: &Scope,
    ctx: &mut Ctx<'_>,
) -> Result<Filter<R>, EngineError> {
    let types = ctx.types.get(&a.pred).cloned().unwrap_or_default();
    let mut args = Vec::new();
    for (e, &ty) in a.args.iter().zip(&types) {
        args.push(match e.kind {
            ExprKind::Wildcard => KeyArg::Wild,
            _ => KeyArg::Val(compile_expr(e, scope, ctx.symbols)?, ty),
        });
    }
    let slots: Option<Vec<(usize, usize)>> = args
        .iter()
        .enumerate()
        .filter_map(|(c, x)| match x {
            KeyArg::Val(CExpr::Slot(s, t), ty) if t == ty => Some(Some((c, *s))),
            KeyArg::Val(..) => Some(None),
            KeyArg::Wild => None,
        })
        .collect();
    let mut set = FastSet::default();
    let mut one = FastSet::default();
    // No wildcard (and not the one-column set): the sorted relation itself is searched.
    let whole =
        args.iter().all(|x| matches!(x, KeyArg::Val(..))) && !matches!(slots.as_deref(), Some([_]));
    let mut kept = Rows::new(types.len());
    match ctx.complete.get(&a.pred) {
        Some(rows) if whole => kept = rows.clone(),
        Some(rows) => {
            for r in rows.iter() {
                if let Some([(c, _)]) = slots.as_deref() {
                    one.insert(r[*c]);
                    continue;
                }
                let mut k = Rows::row(r);
                for (i, x) in args.iter().enumerate() {
                    if matches!(x, KeyArg::Wild) {
                        k[i] = 0;
                    }
                }
                set.insert(k);
            }
        }
        None => {}
    }
    Ok(Filter::Neg(Arc::new(NegSet {
        args,
        slots,
        one,
        rows: kept,
        set,
        hint: std::sync::atomic::AtomicUsize::new(0),
    })))
}
