//! A grounded proof: the stamped clause of a derived tuple re-run with its head bound, each
//! body literal grounded to the facts and values that made it hold, down to input facts.

use super::*;

impl<'a> Cx<'a> {
    /// The grounded derivation of a tuple: the clause its stamp names, grounded over tuples of
    /// lower strata and of earlier rounds of its own stratum; catalog tuples are leaves.
    pub(crate) fn derivation(
        &mut self,
        rel: &str,
        tuple: &[Value],
        depth: usize,
    ) -> Option<Derivation> {
        let leaf = Derivation {
            relation: rel.to_string(),
            tuple: tuple.to_vec(),
            clause: None,
            binding: Vec::new(),
            body: Vec::new(),
        };
        let Some(st) = self.eval.stamp(rel, tuple) else {
            return Some(leaf);
        };
        let program = self.program;
        let clause = program.program.clauses.get(st.clause)?;
        let ci = st.clause;
        let vars = Vars::of(&clause.head, &clause.body);
        let pat: Vec<Option<Value>> = tuple.iter().cloned().map(Some).collect();
        let (b0, checks) = self.unify_head(&vars, &clause.head, &pat).ok()?;
        let order = order_items(&vars, &clause.body, &checks, &b0);
        let mut trail = Vec::new();
        let done = self
            .ground(&vars, &order, b0.clone(), &pat, Some(st), &mut trail)
            .or_else(|| {
                trail.clear();
                self.ground(&vars, &order, b0, &pat, None, &mut trail)
            })?;
        let mut body = Vec::new();
        for (step, g) in trail {
            let Step::Body(li) = step else { continue };
            let Some(lit) = clause.body.get(li) else {
                continue;
            };
            let fact = match (lit, g) {
                (Literal::Pos(a), Ground::Atom(i)) => {
                    let tuple = self.tuples(&a.pred).get(i)?.clone();
                    // Ground facts of the program and catalog tuples are leaves.
                    let rule = self
                        .eval
                        .stamp(&a.pred, &tuple)
                        .and_then(|s| program.program.clauses.get(s.clause))
                        .is_some_and(|c| !c.is_fact());
                    let derivation = if rule && depth < MAX_DEPTH {
                        self.derivation(&a.pred, &tuple, depth + 1).map(Box::new)
                    } else {
                        None
                    };
                    BodyFact::Atom {
                        literal: li,
                        relation: a.pred.clone(),
                        tuple,
                        derivation,
                    }
                }
                (Literal::Neg(a, _), Ground::Absent(pattern)) => BodyFact::Absent {
                    literal: li,
                    relation: a.pred.clone(),
                    pattern,
                },
                (Literal::Cmp(c), Ground::Cmp(lhs, rhs, binds)) => BodyFact::Comparison {
                    literal: li,
                    lhs,
                    op: c.op,
                    rhs,
                    binds: binds.and_then(|s| vars.names.get(s).cloned()),
                },
                (Literal::Agg(g), Ground::Agg(result, group_size)) => BodyFact::Aggregate {
                    literal: li,
                    func: g.func,
                    result,
                    group_size,
                },
                _ => continue,
            };
            body.push(fact);
        }
        body.sort_by_key(|f| f.literal());
        Some(Derivation {
            relation: rel.to_string(),
            tuple: tuple.to_vec(),
            clause: Some(ci),
            binding: self.binding(&vars, &done),
            body,
        })
    }
}
