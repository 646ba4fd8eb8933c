//! A small, obviously correct interpreter of the rule AST over a finished evaluation's
//! relations: variable slots, hash indexes built on demand per relation and bound columns, a
//! body run literal by literal in source order (a literal waits until its variables are bound).

use super::*;

/// The named variables of a clause, each with a slot.
#[derive(Clone)]
pub(crate) struct Vars {
    pub(crate) names: Vec<String>,
    pub(crate) slots: HashMap<String, usize>,
}

impl Vars {
    pub(crate) fn of(head: &Atom, body: &[Literal]) -> Vars {
        let mut v = Vars {
            names: Vec::new(),
            slots: HashMap::new(),
        };
        for e in &head.args {
            v.add_expr(e);
        }
        for l in body {
            v.add_lit(l);
        }
        v
    }

    pub(crate) fn add_expr(&mut self, e: &Expr) {
        let mut vs = Vec::new();
        expr_vars(e, &mut vs);
        for name in vs {
            if !self.slots.contains_key(name) {
                self.slots.insert(name.to_string(), self.names.len());
                self.names.push(name.to_string());
            }
        }
    }

    pub(crate) fn add_lit(&mut self, l: &Literal) {
        match l {
            Literal::Pos(a) | Literal::Neg(a, _) => a.args.iter().for_each(|e| self.add_expr(e)),
            Literal::Cmp(c) => {
                self.add_expr(&c.lhs);
                self.add_expr(&c.rhs);
            }
            Literal::Agg(g) => {
                self.add_expr(&g.result);
                if let Some(t) = &g.target {
                    self.add_expr(t);
                }
                g.body.iter().for_each(|l| self.add_lit(l));
            }
        }
    }

    pub(crate) fn slot(&self, name: &str) -> Option<usize> {
        self.slots.get(name).copied()
    }
}

/// A partial binding of a clause's variables, by slot (`None`: not bound yet); distinct from the
/// planner's encoded [`crate::value::Row`].
pub(crate) type Partial = Vec<Option<Value>>;

/// A grounded literal, as found while matching (kept light).
#[derive(Clone)]
pub(crate) enum Ground {
    Atom(usize),
    Absent(Vec<Option<Value>>),
    Cmp(Value, Value, Option<usize>),
    Agg(Value, usize),
    Head,
}

/// One evaluation step of a body: a literal or a head check.
#[derive(Clone, Copy)]
pub(crate) enum Item<'p> {
    Lit(usize, &'p Literal),
    Head(usize, &'p Expr, ColType),
}

impl Item<'_> {
    pub(crate) fn step(&self) -> Step {
        match self {
            Item::Lit(i, _) => Step::Body(*i),
            Item::Head(i, _, _) => Step::Head(*i),
        }
    }
}

/// Per-relation hash indexes by the set of bound columns.
pub(crate) type Index = HashMap<u64, Vec<u32>>;

pub(crate) struct Cx<'a> {
    pub(crate) program: &'a CheckedProgram,
    pub(crate) eval: &'a Evaluation,
    pub(crate) indexes: HashMap<(String, Vec<usize>), Index>,
}

/// The outcome of running a body: every complete binding, or the failure.
pub(crate) enum Run<'p> {
    Done(Vec<Partial>),
    Failed {
        at: Item<'p>,
        held: Vec<Step>,
        before: Vec<Partial>,
        truncated: bool,
    },
}

impl<'a> Cx<'a> {
    pub(crate) fn new(program: &'a CheckedProgram, eval: &'a Evaluation) -> Cx<'a> {
        Cx {
            program,
            eval,
            indexes: HashMap::new(),
        }
    }

    pub(crate) fn types(&self, rel: &str) -> &'a [ColType] {
        self.program
            .predicates
            .get(rel)
            .map_or(&[], |p| p.types.as_slice())
    }

    pub(crate) fn tuples(&self, rel: &str) -> &'a [Vec<Value>] {
        self.eval.tuples(rel).unwrap_or_default()
    }

    pub(crate) fn check_pattern(
        &self,
        relation: &str,
        pattern: &[Option<Value>],
    ) -> Result<Vec<Option<Value>>, WhyNotError> {
        let Some(info) = self.program.predicates.get(relation) else {
            return Err(WhyNotError::UnknownRelation(relation.to_string()));
        };
        if info.types.len() != pattern.len() {
            return Err(WhyNotError::Arity {
                relation: relation.to_string(),
                expected: info.types.len(),
                found: pattern.len(),
            });
        }
        pattern
            .iter()
            .zip(&info.types)
            .enumerate()
            .map(|(i, (v, &ty))| match v {
                None => Ok(None),
                Some(v) => coerce(v, ty).map(Some).ok_or_else(|| WhyNotError::Type {
                    relation: relation.to_string(),
                    column: i,
                    expected: ty,
                    found: v.clone(),
                }),
            })
            .collect()
    }

    /// Tuple indices of `rel` that agree with the pattern on its determined columns.
    pub(crate) fn lookup(&mut self, rel: &str, pat: &[Option<Value>]) -> Vec<u32> {
        let tuples = self.tuples(rel);
        let cols: Vec<usize> = (0..pat.len()).filter(|&i| pat[i].is_some()).collect();
        if cols.is_empty() {
            return (0..tuples.len() as u32).collect();
        }
        let vals: Vec<&Value> = pat.iter().flatten().collect();
        let index = self
            .indexes
            .entry((rel.to_string(), cols.clone()))
            .or_insert_with(|| {
                let mut ix: Index = HashMap::new();
                for (i, t) in tuples.iter().enumerate() {
                    let vs: Option<Vec<&Value>> = cols.iter().map(|&c| t.get(c)).collect();
                    if let Some(vs) = vs {
                        ix.entry(fingerprint(&vs)).or_default().push(i as u32);
                    }
                }
                ix
            });
        let Some(hits) = index.get(&fingerprint(&vals)) else {
            return Vec::new();
        };
        hits.iter()
            .copied()
            .filter(|&i| {
                tuples.get(i as usize).is_some_and(|t| {
                    cols.iter()
                        .zip(&vals)
                        .all(|(&c, v)| t.get(c).is_some_and(|x| same(x, v)))
                })
            })
            .collect()
    }

    pub(crate) fn eval_expr(&self, vars: &Vars, e: &Expr, b: &Partial) -> Option<Value> {
        match &e.kind {
            ExprKind::Var(v) => b.get(vars.slot(v)?)?.clone(),
            ExprKind::Wildcard => None,
            ExprKind::Str(s) => Some(Value::Str(Arc::from(s.as_str()))),
            ExprKind::Int(i) => Some(Value::Int(*i)),
            ExprKind::Float(x) => Some(Value::Float(*x)),
            ExprKind::Quantity(q) => Some(match q.number() {
                scenalog_rules::ast::Number::Int(i) => Value::Int(i),
                scenalog_rules::ast::Number::Float(x) => Value::Float(x),
            }),
            ExprKind::Neg(a) => match num(&self.eval_expr(vars, a, b)?)? {
                Num::I(i) => i.checked_neg().map(Value::Int),
                Num::F(x) => Some(Value::Float(-x)),
            },
            ExprKind::Binary(op, x, y) => {
                let x = num(&self.eval_expr(vars, x, b)?)?;
                let y = num(&self.eval_expr(vars, y, b)?)?;
                arith(*op, x, y).map(from_num)
            }
            ExprKind::Call(func, args) => {
                let a = num(&self.eval_expr(vars, args.first()?, b)?)?;
                match func {
                    Func::Abs => match a {
                        Num::I(i) => i.checked_abs().map(Value::Int),
                        Num::F(x) => Some(Value::Float(x.abs())),
                    },
                    Func::Min | Func::Max => {
                        let c = num(&self.eval_expr(vars, args.get(1)?, b)?)?;
                        let ord = match (a, c) {
                            (Num::I(x), Num::I(y)) => x.cmp(&y),
                            (x, y) => f(x).partial_cmp(&f(y))?,
                        };
                        let take_a = ord.is_le() == (*func == Func::Min);
                        Some(from_num(if take_a { a } else { c }))
                    }
                }
            }
        }
    }

    pub(crate) fn bound(vars: &Vars, e: &Expr, b: &Partial) -> bool {
        let mut vs = Vec::new();
        expr_vars(e, &mut vs);
        vs.iter().all(|v| {
            vars.slot(v)
                .is_some_and(|s| b.get(s).is_some_and(|x| x.is_some()))
        })
    }

    /// What an atom asks of each column under a binding: `Some(value)` where it is determined.
    /// `None` overall when a determined value cannot be in the column.
    pub(crate) fn atom_pattern(
        &self,
        vars: &Vars,
        a: &Atom,
        b: &Partial,
    ) -> Option<Vec<Option<Value>>> {
        let types = self.types(&a.pred);
        a.args
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let ty = types.get(i).copied().unwrap_or(ColType::Int);
                match &e.kind {
                    ExprKind::Wildcard => Some(None),
                    ExprKind::Var(v) => match vars.slot(v).and_then(|s| b.get(s).cloned()) {
                        Some(Some(x)) => coerce(&x, ty).map(Some),
                        _ => Some(None),
                    },
                    _ => coerce(&self.eval_expr(vars, e, b)?, ty).map(Some),
                }
            })
            .collect()
    }

    /// Matches of a positive atom under a binding: extended bindings and tuple indices.
    pub(crate) fn match_atom(
        &mut self,
        vars: &Vars,
        a: &Atom,
        b: &Partial,
    ) -> Vec<(Partial, usize)> {
        let Some(pat) = self.atom_pattern(vars, a, b) else {
            return Vec::new();
        };
        let hits = self.lookup(&a.pred, &pat);
        let tuples = self.tuples(&a.pred);
        let mut out = Vec::new();
        'tuples: for i in hits {
            let Some(t) = tuples.get(i as usize) else {
                continue;
            };
            let mut nb = b.clone();
            for (c, e) in a.args.iter().enumerate() {
                if pat[c].is_some() {
                    continue;
                }
                if let (Some(v), Some(x)) = (e.as_var(), t.get(c)) {
                    let Some(s) = vars.slot(v) else { continue };
                    match &nb[s] {
                        Some(old) if key(old) != key(x) => continue 'tuples,
                        Some(_) => {}
                        None => nb[s] = Some(x.clone()),
                    }
                }
            }
            out.push((nb, i as usize));
        }
        out
    }

    /// Evaluates one step under one binding.
    pub(crate) fn apply(
        &mut self,
        vars: &Vars,
        item: Item<'_>,
        b: &Partial,
        pat: &[Option<Value>],
    ) -> Vec<(Partial, Ground)> {
        match item {
            Item::Head(i, e, ty) => {
                let v = self.eval_expr(vars, e, b).and_then(|v| coerce(&v, ty));
                match (v, pat.get(i).cloned().flatten()) {
                    (Some(v), Some(w)) if key(&v) == key(&w) => vec![(b.clone(), Ground::Head)],
                    _ => Vec::new(),
                }
            }
            Item::Lit(_, Literal::Pos(a)) => self
                .match_atom(vars, a, b)
                .into_iter()
                .map(|(r, i)| (r, Ground::Atom(i)))
                .collect(),
            Item::Lit(_, Literal::Neg(a, _)) => {
                let Some(p) = self.atom_pattern(vars, a, b) else {
                    // A value that fits no column is in no tuple: the negation holds.
                    return vec![(b.clone(), Ground::Absent(Vec::new()))];
                };
                if self.lookup(&a.pred, &p).is_empty() {
                    vec![(b.clone(), Ground::Absent(p))]
                } else {
                    Vec::new()
                }
            }
            Item::Lit(_, Literal::Cmp(c)) => {
                let l = Self::bound(vars, &c.lhs, b);
                let r = Self::bound(vars, &c.rhs, b);
                if c.op == CmpOp::Eq && (!l || !r) {
                    let (var, e) = if !l {
                        (&c.lhs, &c.rhs)
                    } else {
                        (&c.rhs, &c.lhs)
                    };
                    let (Some(s), Some(v)) = (
                        var.as_var().and_then(|n| vars.slot(n)),
                        self.eval_expr(vars, e, b),
                    ) else {
                        return Vec::new();
                    };
                    let mut nb = b.clone();
                    nb[s] = Some(v.clone());
                    return vec![(nb, Ground::Cmp(v.clone(), v, Some(s)))];
                }
                match (
                    self.eval_expr(vars, &c.lhs, b),
                    self.eval_expr(vars, &c.rhs, b),
                ) {
                    (Some(x), Some(y)) if cmp_holds(c.op, &x, &y) => {
                        vec![(b.clone(), Ground::Cmp(x, y, None))]
                    }
                    _ => Vec::new(),
                }
            }
            Item::Lit(_, Literal::Agg(g)) => {
                let (res, size) = self.aggregate(vars, g, b);
                let Some(res) = res else {
                    return Vec::new();
                };
                match g.result.as_var().and_then(|n| vars.slot(n)) {
                    Some(s) if b[s].is_none() => {
                        let mut nb = b.clone();
                        nb[s] = Some(res.clone());
                        vec![(nb, Ground::Agg(res, size))]
                    }
                    _ => match self.eval_expr(vars, &g.result, b) {
                        Some(want) if compare(&want, &res) == Some(Ordering::Equal) => {
                            vec![(b.clone(), Ground::Agg(res, size))]
                        }
                        _ => Vec::new(),
                    },
                }
            }
        }
    }

    /// An aggregate's value and group size under a binding.
    pub(crate) fn aggregate(
        &mut self,
        vars: &Vars,
        g: &Aggregate,
        b: &Partial,
    ) -> (Option<Value>, usize) {
        // The body's matching tuples count, so each `_` of the braces becomes a fresh variable
        // with a slot of its own after the clause's.
        let named = crate::agg_body::name_wildcards(g);
        let g = &named;
        let mut wide = vars.clone();
        g.body.iter().for_each(|l| wide.add_lit(l));
        let vars = &wide;
        let mut b = b.clone();
        b.resize(vars.names.len(), None);
        let b = &b;
        let order = order_items(vars, &g.body, &[], b);
        let inner = match self.run(vars, &order, vec![b.clone()], &[]) {
            Run::Done(rows) => rows,
            Run::Failed { .. } => Vec::new(),
        };
        let body_vars: Vec<usize> = agg_vars(g)
            .into_iter()
            .filter_map(|v| vars.slot(v))
            .filter(|&s| b.get(s).is_some_and(|x| x.is_none()))
            .collect();
        let mut seen: HashSet<Vec<Option<Key>>> = HashSet::new();
        let mut values: Vec<Option<Value>> = Vec::new();
        for r in &inner {
            let target = g.target.as_ref().and_then(|t| self.eval_expr(vars, t, r));
            let mut k: Vec<Option<Key>> = body_vars
                .iter()
                .map(|&s| r.get(s).cloned().flatten().map(|v| key(&v)))
                .collect();
            k.push(target.as_ref().map(key));
            let k = match g.func {
                AggFunc::Min | AggFunc::Max => vec![target.as_ref().map(key)],
                _ => k,
            };
            if seen.insert(k) {
                values.push(target);
            }
        }
        let size = values.len();
        let result = match g.func {
            AggFunc::Count => Some(Value::Int(size as i64)),
            AggFunc::Sum => {
                let mut acc = Num::I(0);
                for v in values.iter().flatten() {
                    if let Some(n) = num(v) {
                        acc = match (acc, n) {
                            (Num::I(a), Num::I(x)) => Num::I(a.saturating_add(x)),
                            (a, x) => Num::F(f(a) + f(x)),
                        };
                    }
                }
                Some(from_num(acc))
            }
            AggFunc::Min | AggFunc::Max => {
                let want = if g.func == AggFunc::Min {
                    Ordering::Less
                } else {
                    Ordering::Greater
                };
                let mut best: Option<Value> = None;
                for v in values.into_iter().flatten() {
                    best = match best {
                        Some(cur) if compare(&v, &cur) != Some(want) => Some(cur),
                        _ => Some(v),
                    };
                }
                best
            }
        };
        (result, size)
    }

    /// Runs steps breadth-first from the given bindings.
    pub(crate) fn run<'p>(
        &mut self,
        vars: &Vars,
        order: &[Item<'p>],
        start: Vec<Partial>,
        pat: &[Option<Value>],
    ) -> Run<'p> {
        let mut rows = start;
        let mut held = Vec::new();
        let mut truncated = false;
        for &item in order {
            let mut next = Vec::new();
            let mut seen: HashSet<Vec<Option<Key>>> = HashSet::new();
            'rows: for b in &rows {
                for (r, _) in self.apply(vars, item, b, pat) {
                    let k: Vec<Option<Key>> = r.iter().map(|v| v.as_ref().map(key)).collect();
                    if seen.insert(k) {
                        if next.len() >= MAX_BINDINGS {
                            truncated = true;
                            break 'rows;
                        }
                        next.push(r);
                    }
                }
            }
            if next.is_empty() {
                return Run::Failed {
                    at: item,
                    held,
                    before: rows,
                    truncated,
                };
            }
            held.push(item.step());
            rows = next;
        }
        Run::Done(rows)
    }

    /// Depth-first search for one complete binding, with the grounded literals on the way.
    /// With `limit` (the stamp of the tuple being derived), positive atoms over relations of
    /// the same stratum may only match tuples first derived in an earlier round, so the
    /// derivation is well founded.
    pub(crate) fn ground(
        &mut self,
        vars: &Vars,
        order: &[Item<'_>],
        b: Partial,
        pat: &[Option<Value>],
        limit: Option<Stamp>,
        trail: &mut Vec<(Step, Ground)>,
    ) -> Option<Partial> {
        let Some((&item, rest)) = order.split_first() else {
            return Some(b);
        };
        for (r, g) in self.apply(vars, item, &b, pat) {
            if let (Some(st), Item::Lit(_, Literal::Pos(a)), Ground::Atom(i)) = (limit, item, &g) {
                let same = self
                    .program
                    .strata
                    .get(st.stratum)
                    .is_some_and(|s| s.predicates.contains(&a.pred));
                if same {
                    let earlier = self
                        .tuples(&a.pred)
                        .get(*i)
                        .and_then(|t| self.eval.stamp(&a.pred, t))
                        .is_some_and(|s| s.round < st.round);
                    if !earlier {
                        continue;
                    }
                }
            }
            trail.push((item.step(), g));
            if let Some(done) = self.ground(vars, rest, r, pat, limit, trail) {
                return Some(done);
            }
            trail.pop();
        }
        None
    }

    /// Unifies a clause head with a pattern: the starting binding and the head expressions left
    /// to check, or the mismatch.
    pub(crate) fn unify_head<'p>(
        &self,
        vars: &Vars,
        head: &'p Atom,
        pat: &[Option<Value>],
    ) -> Result<(Partial, Vec<Item<'p>>), Box<Outcome>> {
        let types = self.types(&head.pred);
        let mut b: Partial = vec![None; vars.names.len()];
        let mut checks = Vec::new();
        for (i, e) in head.args.iter().enumerate() {
            let Some(Some(want)) = pat.get(i) else {
                continue;
            };
            let ty = types.get(i).copied().unwrap_or(ColType::Int);
            let mismatch = || Outcome::HeadMismatch {
                column: i,
                expected: scenalog_rules::printer::print_expr(e),
                found: want.clone(),
            };
            match &e.kind {
                ExprKind::Wildcard => {}
                ExprKind::Var(v) => {
                    let Some(s) = vars.slot(v) else { continue };
                    match &b[s] {
                        Some(old) if key(old) != key(want) => return Err(Box::new(mismatch())),
                        _ => b[s] = Some(want.clone()),
                    }
                }
                _ => {
                    let mut vs = Vec::new();
                    expr_vars(e, &mut vs);
                    if vs.is_empty() {
                        let v = self.eval_expr(vars, e, &b).and_then(|v| coerce(&v, ty));
                        if v.map(|v| key(&v)) != Some(key(want)) {
                            return Err(Box::new(mismatch()));
                        }
                    } else {
                        checks.push(Item::Head(i, e, ty));
                    }
                }
            }
        }
        Ok((b, checks))
    }

    pub(crate) fn binding(&self, vars: &Vars, b: &Partial) -> Binding {
        vars.names
            .iter()
            .zip(b)
            .filter_map(|(n, v)| v.clone().map(|v| (n.clone(), v)))
            .collect()
    }
}

/// A variable a comparison or negation needs (for a binding `X = e`, of `e`) that the first
/// binding leaves unbound.
pub(crate) fn unbound_var(vars: &Vars, l: &Literal, before: &[Partial]) -> Option<String> {
    let b = before.first()?;
    let is_bound = |v: &str| {
        vars.slot(v)
            .is_some_and(|s| b.get(s).is_some_and(|x| x.is_some()))
    };
    let mut vs = Vec::new();
    match l {
        Literal::Cmp(c) => {
            let (mut l, mut r) = (Vec::new(), Vec::new());
            expr_vars(&c.lhs, &mut l);
            expr_vars(&c.rhs, &mut r);
            let lb = l.iter().all(|v| is_bound(v));
            let rb = r.iter().all(|v| is_bound(v));
            if c.op == CmpOp::Eq && c.lhs.as_var().is_some() && !lb && rb {
                return None;
            }
            if c.op == CmpOp::Eq && c.rhs.as_var().is_some() && !rb && lb {
                return None;
            }
            vs.extend(l);
            vs.extend(r);
        }
        Literal::Neg(a, _) => a.args.iter().for_each(|e| expr_vars(e, &mut vs)),
        Literal::Agg(g) => expr_vars(&g.result, &mut vs),
        Literal::Pos(_) => {}
    }
    let _ = &mut vs;
    vs.into_iter()
        .find(|v| !is_bound(v) && !matches!(l, Literal::Agg(_)))
        .map(str::to_string)
}

pub(crate) fn cmp_tuple(a: &[Value], b: &[Value]) -> Ordering {
    a.iter()
        .zip(b)
        .map(|(x, y)| cmp_value(x, y))
        .find(|o| o.is_ne())
        .unwrap_or_else(|| a.len().cmp(&b.len()))
}

/// The evaluation order of a body: source order, each literal as soon as it can be evaluated
/// (its expressions' variables bound; for an aggregate, its group variables), head checks as
/// soon as their variables are bound.
pub(crate) fn order_items<'p>(
    vars: &Vars,
    body: &'p [Literal],
    checks: &[Item<'p>],
    start: &Partial,
) -> Vec<Item<'p>> {
    let mut bound: Vec<bool> = start.iter().map(|v| v.is_some()).collect();
    let is_bound = |bound: &[bool], e: &Expr| {
        let mut vs = Vec::new();
        expr_vars(e, &mut vs);
        vs.iter().all(|v| {
            vars.slot(v)
                .is_some_and(|s| bound.get(s).copied().unwrap_or(false))
        })
    };
    let bind = |bound: &mut Vec<bool>, e: &Expr| {
        let mut vs = Vec::new();
        expr_vars(e, &mut vs);
        for v in vs {
            if let Some(s) = vars.slot(v) {
                if let Some(x) = bound.get_mut(s) {
                    *x = true;
                }
            }
        }
    };
    // Variables outside aggregate bodies (they group the aggregates that use them).
    let mut outer: HashSet<&str> = HashSet::new();
    {
        let mut vs = Vec::new();
        for (s, name) in vars.names.iter().enumerate() {
            if start.get(s).is_some_and(|v| v.is_some()) {
                vs.push(name.as_str());
            }
        }
        for l in body {
            outer_vars(l, &mut vs);
        }
        for c in checks {
            if let Item::Head(_, e, _) = c {
                expr_vars(e, &mut vs);
            }
        }
        outer.extend(vs);
    }
    let mut done = vec![false; body.len()];
    let mut checks_done = vec![false; checks.len()];
    let mut out = Vec::new();
    loop {
        let mut next: Option<usize> = None;
        for (i, l) in body.iter().enumerate() {
            if done[i] {
                continue;
            }
            let ready = match l {
                Literal::Pos(a) => a.args.iter().all(|e| {
                    e.as_var().is_some()
                        || matches!(e.kind, ExprKind::Wildcard)
                        || is_bound(&bound, e)
                }),
                Literal::Neg(a, _) => a
                    .args
                    .iter()
                    .all(|e| matches!(e.kind, ExprKind::Wildcard) || is_bound(&bound, e)),
                Literal::Cmp(c) => {
                    let (l, r) = (is_bound(&bound, &c.lhs), is_bound(&bound, &c.rhs));
                    (l && r)
                        || (c.op == CmpOp::Eq
                            && ((c.lhs.as_var().is_some() && r) || (c.rhs.as_var().is_some() && l)))
                }
                Literal::Agg(g) => agg_vars(g).iter().filter(|v| outer.contains(*v)).all(|v| {
                    vars.slot(v)
                        .is_some_and(|s| bound.get(s).copied().unwrap_or(false))
                }),
            };
            if ready {
                next = Some(i);
                break;
            }
        }
        let Some(i) = next.or_else(|| done.iter().position(|d| !d)) else {
            break;
        };
        done[i] = true;
        let lit = &body[i];
        out.push(Item::Lit(i, lit));
        match lit {
            Literal::Pos(a) => a.args.iter().for_each(|e| bind(&mut bound, e)),
            Literal::Cmp(c) => {
                bind(&mut bound, &c.lhs);
                bind(&mut bound, &c.rhs);
            }
            Literal::Agg(g) => bind(&mut bound, &g.result),
            Literal::Neg(..) => {}
        }
        for (j, c) in checks.iter().enumerate() {
            if let (false, Item::Head(_, e, _)) = (checks_done[j], c) {
                if is_bound(&bound, e) {
                    checks_done[j] = true;
                    out.push(*c);
                }
            }
        }
    }
    for (j, c) in checks.iter().enumerate() {
        if !checks_done[j] {
            out.push(*c);
        }
    }
    out
}
