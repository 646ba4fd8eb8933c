//! Why a tuple is not derived: each clause whose head can produce it run literal by literal,
//! the first literal no binding survives reported with the bindings before it, the values that
//! failed it and the closest tuples of a missing atom.

use super::*;

impl<'a> Cx<'a> {
    pub(crate) fn why_not(
        &mut self,
        relation: &str,
        pat: &[Option<Value>],
        depth: usize,
        visited: &mut HashSet<(String, Vec<Option<Key>>)>,
    ) -> WhyNot {
        visited.insert((
            relation.to_string(),
            pat.iter().map(|v| v.as_ref().map(key)).collect(),
        ));
        let holds = !self.lookup(relation, pat).is_empty();
        let input = self
            .program
            .predicates
            .get(relation)
            .is_some_and(|p| p.kind == PredKind::Catalog);
        let relation_size = self.tuples(relation).len();
        let closest_input = if input && !holds {
            self.near_misses(relation, std::slice::from_ref(&pat.to_vec()))
        } else {
            Vec::new()
        };
        let mut attempts = Vec::new();
        let program = self.program;
        for (ci, clause) in program.program.clauses.iter().enumerate() {
            if clause.head.pred != relation {
                continue;
            }
            let outcome = self.attempt(clause, pat, depth, visited);
            attempts.push(ClauseAttempt {
                clause: ci,
                outcome,
            });
        }
        WhyNot {
            relation: relation.to_string(),
            pattern: pat.to_vec(),
            holds,
            input,
            relation_size,
            closest_input,
            attempts,
        }
    }

    pub(crate) fn attempt(
        &mut self,
        clause: &scenalog_rules::ast::Clause,
        pat: &[Option<Value>],
        depth: usize,
        visited: &mut HashSet<(String, Vec<Option<Key>>)>,
    ) -> Outcome {
        let vars = Vars::of(&clause.head, &clause.body);
        let (b0, checks) = match self.unify_head(&vars, &clause.head, pat) {
            Ok(x) => x,
            Err(o) => return *o,
        };
        let order = order_items(&vars, &clause.body, &checks, &b0);
        match self.run(&vars, &order, vec![b0], pat) {
            Run::Done(rows) => Outcome::Derives {
                binding: rows
                    .first()
                    .map(|r| self.binding(&vars, r))
                    .unwrap_or_default(),
                bindings: rows.len(),
            },
            Run::Failed {
                at,
                held,
                before,
                truncated,
            } => {
                let reason = self.reason(&vars, at, &before, pat, depth, visited);
                let text = match at {
                    Item::Lit(_, l) => scenalog_rules::printer::print_literal(l),
                    Item::Head(i, e, _) => format!(
                        "head argument {}: {}",
                        i + 1,
                        scenalog_rules::printer::print_expr(e)
                    ),
                };
                Outcome::Fails(Failure {
                    step: at.step(),
                    text,
                    held,
                    bindings: before
                        .iter()
                        .take(MAX_EXAMPLES)
                        .map(|r| self.binding(&vars, r))
                        .collect(),
                    binding_count: before.len(),
                    truncated,
                    reason,
                })
            }
        }
    }

    /// Why a step failed for every binding in `before`.
    pub(crate) fn reason(
        &mut self,
        vars: &Vars,
        at: Item<'_>,
        before: &[Partial],
        pat: &[Option<Value>],
        depth: usize,
        visited: &mut HashSet<(String, Vec<Option<Key>>)>,
    ) -> Reason {
        match at {
            Item::Head(i, e, _) => Reason::HeadValue {
                column: i,
                wanted: pat.get(i).cloned().flatten().unwrap_or(Value::Int(0)),
                values: before
                    .iter()
                    .take(MAX_EXAMPLES)
                    .map(|b| (self.binding(vars, b), self.eval_expr(vars, e, b)))
                    .collect(),
            },
            Item::Lit(_, l @ (Literal::Cmp(_) | Literal::Neg(..) | Literal::Agg(_)))
                if unbound_var(vars, l, before).is_some() =>
            {
                let v = unbound_var(vars, l, before).unwrap_or_default();
                Reason::Unevaluable(format!("variable `{v}` is bound nowhere before it"))
            }
            Item::Lit(_, Literal::Pos(a)) => {
                let mut wanted: Vec<Vec<Option<Value>>> = Vec::new();
                for b in before {
                    if let Some(p) = self.atom_pattern(vars, a, b) {
                        if !wanted.contains(&p) {
                            wanted.push(p);
                        }
                    }
                    if wanted.len() >= 16 {
                        break;
                    }
                }
                let closest = self.near_misses(&a.pred, &wanted);
                let derived = self
                    .program
                    .predicates
                    .get(&a.pred)
                    .is_some_and(|p| p.kind == PredKind::Derived);
                let nested = match wanted.first() {
                    Some(p) if derived && depth < MAX_NESTING => {
                        let k = (
                            a.pred.clone(),
                            p.iter().map(|v| v.as_ref().map(key)).collect(),
                        );
                        if visited.contains(&k) {
                            None
                        } else {
                            Some(Box::new(self.why_not(&a.pred, p, depth + 1, visited)))
                        }
                    }
                    _ => None,
                };
                wanted.truncate(MAX_EXAMPLES);
                Reason::Missing {
                    relation: a.pred.clone(),
                    relation_size: self.tuples(&a.pred).len(),
                    wanted,
                    closest,
                    nested,
                }
            }
            Item::Lit(_, Literal::Neg(a, _)) => {
                let mut found = Vec::new();
                for b in before {
                    let Some(p) = self.atom_pattern(vars, a, b) else {
                        continue;
                    };
                    if let Some(&i) = self.lookup(&a.pred, &p).first() {
                        if let Some(t) = self.tuples(&a.pred).get(i as usize) {
                            found.push((self.binding(vars, b), t.clone()));
                        }
                    }
                    if found.len() >= MAX_EXAMPLES {
                        break;
                    }
                }
                Reason::Present {
                    relation: a.pred.clone(),
                    found,
                }
            }
            Item::Lit(_, Literal::Cmp(c)) => {
                let mut values: Vec<(f64, CmpValues)> = before
                    .iter()
                    .map(|b| {
                        let lhs = self.eval_expr(vars, &c.lhs, b);
                        let rhs = self.eval_expr(vars, &c.rhs, b);
                        let g = gap(c.op, lhs.as_ref(), rhs.as_ref());
                        (
                            g,
                            CmpValues {
                                binding: self.binding(vars, b),
                                lhs,
                                rhs,
                            },
                        )
                    })
                    .collect();
                values.sort_by(|a, b| a.0.total_cmp(&b.0));
                let mut out: Vec<CmpValues> = Vec::new();
                for (_, v) in values {
                    if out.len() >= MAX_EXAMPLES {
                        break;
                    }
                    if !out.iter().any(|o| o.lhs == v.lhs && o.rhs == v.rhs) {
                        out.push(v);
                    }
                }
                Reason::Comparison {
                    op: c.op,
                    values: out,
                }
            }
            Item::Lit(_, Literal::Agg(g)) => {
                let mut values = Vec::new();
                for b in before.iter().take(MAX_EXAMPLES) {
                    let (result, group_size) = self.aggregate(vars, g, b);
                    let required = match g.result.as_var().and_then(|n| vars.slot(n)) {
                        Some(s) if b[s].is_none() => None,
                        _ => self.eval_expr(vars, &g.result, b),
                    };
                    values.push(AggValues {
                        binding: self.binding(vars, b),
                        result,
                        required,
                        group_size,
                    });
                }
                Reason::Aggregate {
                    func: g.func,
                    values,
                }
            }
        }
    }

    /// The tuples of `rel` agreeing with one of the patterns on the most determined columns,
    /// then nearest on the differing numeric ones.
    pub(crate) fn near_misses(&self, rel: &str, patterns: &[Vec<Option<Value>>]) -> Vec<NearMiss> {
        // Score: columns that agree (more first; on a tie, agreeing on earlier columns first,
        // as the subject of a relation comes first), then distance on the numeric ones.
        type Score = (usize, u64, f64);
        let better =
            |a: &Score, b: &Score| b.0.cmp(&a.0).then(b.1.cmp(&a.1)).then(a.2.total_cmp(&b.2));
        // The best MAX_EXAMPLES so far, in order (a relation asked whole holds millions of
        // tuples: only these are kept and cloned).
        let mut top: Vec<(Score, &[Value], Vec<usize>)> = Vec::with_capacity(MAX_EXAMPLES + 1);
        let order = |a: &(Score, &[Value], Vec<usize>), b: &(Score, &[Value], Vec<usize>)| {
            better(&a.0, &b.0).then_with(|| cmp_tuple(a.1, b.1))
        };
        for t in self.tuples(rel) {
            let mut best: Option<(Score, Vec<usize>)> = None;
            for p in patterns {
                let mut same = 0;
                let mut mask = 0u64;
                let mut dist = 0.0;
                let mut differs = Vec::new();
                for (c, want) in p.iter().enumerate() {
                    let (Some(w), Some(x)) = (want, t.get(c)) else {
                        continue;
                    };
                    if key(w) == key(x) {
                        same += 1;
                        mask |= 1u64 << (63 - c.min(63));
                    } else {
                        differs.push(c);
                        if let (Some(a), Some(b)) = (num(w), num(x)) {
                            dist += (f(a) - f(b)).abs();
                        }
                    }
                }
                if same == 0 && !differs.is_empty() {
                    continue;
                }
                let score = (same, mask, dist);
                if best
                    .as_ref()
                    .is_none_or(|(b, _)| better(&score, b) == Ordering::Less)
                {
                    best = Some((score, differs));
                }
            }
            if let Some((score, differs)) = best {
                let candidate = (score, t.as_slice(), differs);
                let full = top.len() >= MAX_EXAMPLES;
                if full
                    && top
                        .last()
                        .is_some_and(|w| order(&candidate, w) != Ordering::Less)
                {
                    continue;
                }
                let at = top.partition_point(|x| order(x, &candidate) != Ordering::Greater);
                top.insert(at, candidate);
                top.truncate(MAX_EXAMPLES);
            }
        }
        top.into_iter()
            .map(|(_, tuple, differs)| NearMiss {
                tuple: tuple.to_vec(),
                differs,
            })
            .collect()
    }
}
