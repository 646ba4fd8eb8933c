//! Provenance and proofs: every derived tuple is stamped with the stratum, round and clause that
//! first derived it; a proof re-runs that clause over tuples of earlier rounds only, so the
//! derivation tree is finite and its leaves are input facts (catalog tuples or ground facts).

use std::collections::{HashMap, HashSet};

use scenalog_facts::catalog::ColType;
use scenalog_facts::relation::Value;

use crate::plan::{apply, Plan};
use crate::rows::Rows;
use crate::value::{decode_value, encode, Row, Symbols, V, WIDTH};

/// When and how a derived tuple was first derived.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stamp {
    /// Index into the checked program's strata.
    pub stratum: usize,
    /// Semi-naive round within the stratum (0 for rules without a recursive atom).
    pub round: usize,
    /// Index into the program's clauses of the clause that derived it.
    pub clause: usize,
}

/// A derivation tree.
#[derive(Debug, Clone, PartialEq)]
pub struct Proof {
    /// The relation.
    pub relation: String,
    /// The tuple.
    pub tuple: Vec<Value>,
    /// The clause that derived it (a ground fact has no children); `None` for a catalog tuple.
    pub clause: Option<usize>,
    /// Proofs of the positive body atoms' tuples, in the clause's join order. Negated atoms
    /// and aggregates held against completed lower strata and have no subtree.
    pub children: Vec<Proof>,
}

impl Proof {
    /// Height of the tree (a leaf has height 0).
    pub fn height(&self) -> usize {
        self.children
            .iter()
            .map(|c| c.height() + 1)
            .max()
            .unwrap_or(0)
    }
}

/// What an evaluation keeps to answer proofs.
#[derive(Debug)]
pub(crate) struct Provenance {
    pub(crate) types: HashMap<String, Vec<ColType>>,
    pub(crate) symbols: Symbols,
    pub(crate) rels: HashMap<String, Rows>,
    /// Per derived relation, aligned with its sorted tuples in `rels`.
    pub(crate) stamps: HashMap<String, Vec<Stamp>>,
    /// Per stratum: head, plan and clause index.
    pub(crate) plans: Vec<Vec<(String, Plan, usize)>>,
    /// Per stratum: the predicates it defines.
    pub(crate) strata: Vec<Vec<String>>,
}

impl Provenance {
    /// Encodes a decoded tuple, without interning: `None` if a value cannot be in the relation.
    fn encode_tuple(&self, rel: &str, tuple: &[Value]) -> Option<Row> {
        let types = self.types.get(rel)?;
        if types.len() != tuple.len() {
            return None;
        }
        let mut row = [0u64; WIDTH];
        for (i, (v, &ty)) in tuple.iter().zip(types).enumerate() {
            row[i] = match (v, ty) {
                (Value::Str(s), ColType::Str) => self.symbols.lookup(s)?,
                (Value::Track(t), ColType::Track) => u64::from(t.0),
                (Value::Lane(l), ColType::Lane) => encode(V::Int(l.0), ColType::Int)?,
                (Value::Time(t), _) => encode(V::Int(i64::from(*t)), ty)?,
                (Value::Int(x), _) => encode(V::Int(*x), ty)?,
                (Value::Float(x), _) => encode(V::Float(*x), ty)?,
                _ => return None,
            };
        }
        Some(row)
    }

    fn decode(&self, rel: &str, row: &Row) -> Vec<Value> {
        self.types.get(rel).map_or_else(Vec::new, |types| {
            types
                .iter()
                .enumerate()
                .map(|(i, &ty)| decode_value(row[i], ty, &self.symbols))
                .collect()
        })
    }

    /// The stamp of a tuple of a derived relation.
    fn stamp_of(&self, rel: &str, row: &[u64]) -> Option<Stamp> {
        let stamps = self.stamps.get(rel)?;
        let i = self.rels.get(rel)?.position(row)?;
        stamps.get(i).copied()
    }

    pub(crate) fn stamp(&self, rel: &str, tuple: &[Value]) -> Option<Stamp> {
        let row = self.encode_tuple(rel, tuple)?;
        self.stamp_of(rel, &row)
    }

    pub(crate) fn prove(&self, rel: &str, tuple: &[Value]) -> Option<Proof> {
        let row = self.encode_tuple(rel, tuple)?;
        if !self.rels.get(rel)?.contains(&row) {
            return None;
        }
        self.prove_row(rel, &row)
    }

    fn prove_row(&self, rel: &str, row: &Row) -> Option<Proof> {
        let tuple = self.decode(rel, row);
        let Some(stamp) = self.stamp_of(rel, row) else {
            // Not derived by a clause: a catalog tuple.
            return Some(Proof {
                relation: rel.to_string(),
                tuple,
                clause: None,
                children: Vec::new(),
            });
        };
        let (_, plan, clause) = self
            .plans
            .get(stamp.stratum)?
            .iter()
            .find(|(_, _, c)| *c == stamp.clause)?;
        let same: HashSet<&str> = self
            .strata
            .get(stamp.stratum)
            .map(|s| s.iter().map(|p| p.as_str()).collect())
            .unwrap_or_default();
        // Sources: tuples of this stratum's relations from earlier rounds only.
        let sources: Vec<Vec<Row>> = plan
            .atoms
            .iter()
            .map(|a| {
                let Some(all) = self.rels.get(&a.pred) else {
                    return Vec::new();
                };
                if same.contains(a.pred.as_str()) {
                    let stamps = self.stamps.get(&a.pred);
                    all.iter()
                        .enumerate()
                        .filter(|(i, _)| {
                            stamps
                                .and_then(|s| s.get(*i))
                                .is_some_and(|s| s.round < stamp.round)
                        })
                        .map(|(_, t)| Rows::row(t))
                        .collect()
                } else {
                    all.iter().map(Rows::row).collect()
                }
            })
            .collect();
        let trail = find_derivation(plan, &sources, row)?;
        let mut children = Vec::new();
        for (atom, t) in plan.atoms.iter().zip(&trail) {
            children.push(self.prove_row(&atom.pred, t)?);
        }
        Some(Proof {
            relation: rel.to_string(),
            tuple,
            clause: Some(*clause),
            children,
        })
    }
}

/// The body tuples (one per atom, in join order) of a binding of `plan` whose head is `target`.
fn find_derivation(plan: &Plan, sources: &[Vec<Row>], target: &Row) -> Option<Vec<Row>> {
    fn go(
        plan: &Plan,
        sources: &[Vec<Row>],
        target: &Row,
        depth: usize,
        b: Row,
        trail: &mut Vec<Row>,
    ) -> bool {
        let Some(step) = plan.atoms.get(depth) else {
            return plan.project(&b).as_ref() == Some(target);
        };
        let key = step.binding_key(&b);
        for t in sources.get(depth).into_iter().flatten() {
            if !step.selects(t) || key != Some(step.tuple_key(t)) {
                continue;
            }
            if let Some(next) = apply(&step.after, step.extend(b, t)) {
                trail.push(*t);
                if go(plan, sources, target, depth + 1, next, trail) {
                    return true;
                }
                trail.pop();
            }
        }
        false
    }
    let b = apply(&plan.start, [0u64; WIDTH])?;
    let mut trail = Vec::new();
    go(plan, sources, target, 0, b, &mut trail).then_some(trail)
}
