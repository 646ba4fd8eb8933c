//! Provenance<R> and proofs: every derived tuple is stamped with the stratum, round and clause that
//! first derived it; a proof re-runs that clause over tuples of earlier rounds only, so the
//! derivation tree is finite and its leaves are input facts (catalog tuples or ground facts).

use std::collections::{HashMap, HashSet};

use scenalog_facts::catalog::ColType;
use scenalog_facts::relation::Value;

use crate::plan::{apply, Plan};
use crate::rows::Rows;
use crate::stratum::access::Access;
use crate::value::{encode, Row, V};

/// Per derived relation, aligned with its sorted tuples: the round and plan index that first
/// derived each tuple (with provenance on), packed by [`pack`], or what computes
/// them when they are first read.
pub(crate) type Origins = HashMap<String, crate::prove::Packed>;

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

/// The stamps of one derived relation, aligned with its sorted tuples: 8 bytes a tuple (the
/// round and the plan packed by [`pack`]), the stratum and the clause of each plan kept once.
#[derive(Debug)]
pub(crate) struct Stamps {
    /// The stratum that defines the relation.
    pub(crate) stratum: usize,
    /// Per plan of the stratum: its clause's index in the program.
    pub(crate) clauses: std::sync::Arc<[usize]>,
    /// Per tuple: round and plan, packed; aligned when first read.
    pub(crate) packed: Packed,
}

/// A relation's packed stamps, or what aligns them with its sorted tuples when they are first
/// read: a recursive stratum hands over each round's new tuples with their plans, and the
/// sort that puts them in the relation's order runs only for relations whose stamps a proof
/// or [`crate::Evaluation::stamp`] reads.
pub(crate) struct Packed {
    ready: std::sync::OnceLock<Vec<u64>>,
    pending: std::sync::Mutex<Option<Align>>,
}

/// Computes a relation's packed stamps, aligned with its sorted tuples.
pub(crate) type Align = Box<dyn FnOnce() -> Vec<u64> + Send>;

impl Packed {
    /// Stamps already aligned.
    pub(crate) fn ready(packed: Vec<u64>) -> Self {
        Packed {
            ready: std::sync::OnceLock::from(packed),
            pending: std::sync::Mutex::new(None),
        }
    }

    /// Stamps `align` computes when they are first read.
    pub(crate) fn deferred(align: Align) -> Self {
        Packed {
            ready: std::sync::OnceLock::new(),
            pending: std::sync::Mutex::new(Some(align)),
        }
    }

    /// The packed stamps, aligned on the first call.
    pub(crate) fn get(&self) -> &[u64] {
        self.ready.get_or_init(|| {
            let align = self
                .pending
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .take();
            align.map_or_else(Vec::new, |f| f())
        })
    }
}

impl std::fmt::Debug for Packed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.ready.get() {
            Some(p) => write!(f, "Packed({} stamps)", p.len()),
            None => write!(f, "Packed(not aligned yet)"),
        }
    }
}

/// A round and a plan index in one word: the round in the high 32 bits, the plan in the low
/// ones (`u32::MAX` for a plan not known).
pub(crate) fn pack(round: u64, plan: usize) -> u64 {
    (round << 32) | u64::from(u32::try_from(plan).unwrap_or(u32::MAX))
}

impl Stamps {
    /// The stamp of the `i`th tuple.
    pub(crate) fn get(&self, i: usize) -> Option<Stamp> {
        let p = *self.packed.get().get(i)?;
        let plan = (p & 0xffff_ffff) as usize;
        let clause = if plan == u32::MAX as usize {
            usize::MAX
        } else {
            self.clauses.get(plan).copied().unwrap_or(usize::MAX)
        };
        Some(Stamp {
            stratum: self.stratum,
            round: (p >> 32) as usize,
            clause,
        })
    }

    /// The round of the `i`th tuple.
    pub(crate) fn round(&self, i: usize) -> Option<usize> {
        self.packed.get().get(i).map(|p| (p >> 32) as usize)
    }
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
    /// Height of the tree (a leaf has height 0), counted without recursion.
    pub fn height(&self) -> usize {
        let mut height = 0;
        let mut stack = vec![(self, 0usize)];
        while let Some((p, h)) = stack.pop() {
            height = height.max(h);
            stack.extend(p.children.iter().map(|c| (c, h + 1)));
        }
        height
    }
}

impl Drop for Proof {
    /// Frees the tree without recursion (a proof can be thousands of levels deep).
    fn drop(&mut self) {
        let mut stack = std::mem::take(&mut self.children);
        while let Some(mut p) = stack.pop() {
            stack.append(&mut p.children);
        }
    }
}

/// What an evaluation keeps to answer proofs.
#[derive(Debug)]
pub(crate) struct Provenance<const R: usize> {
    /// The evaluation's relations, types and symbols (shared with the [`crate::Evaluation`]).
    pub(crate) encoded: std::sync::Arc<crate::Encoded>,
    /// Per derived relation, aligned with its sorted tuples in `encoded.rels`.
    pub(crate) stamps: HashMap<String, Stamps>,
    /// Per stratum: head, plan and clause index (none for a stratum of facts alone).
    pub(crate) plans: Vec<Vec<(String, Plan<R>, usize)>>,
    /// Per stratum: whether it holds facts alone, evaluated without plans: a tuple stamped by
    /// one of its clauses is that fact, a leaf.
    pub(crate) facts_only: Vec<bool>,
    /// Per stratum: the predicates it defines.
    pub(crate) strata: Vec<Vec<String>>,
}

/// What an [`crate::Evaluation`] asks of its provenance, whatever the width of its rows.
pub(crate) trait Proofs: std::fmt::Debug + Send + Sync {
    /// See [`crate::Evaluation::stamp`].
    fn stamp(&self, rel: &str, tuple: &[Value]) -> Option<Stamp>;
    /// See [`crate::Evaluation::stamped`].
    fn stamped(&self, rel: &str) -> usize;
    /// See [`crate::Evaluation::prove`].
    fn prove(&self, rel: &str, tuple: &[Value]) -> Option<Proof>;
}

impl<const R: usize> Proofs for Provenance<R> {
    fn stamp(&self, rel: &str, tuple: &[Value]) -> Option<Stamp> {
        Provenance::stamp(self, rel, tuple)
    }

    fn stamped(&self, rel: &str) -> usize {
        self.stamps.get(rel).map_or(0, |s| s.packed.get().len())
    }

    fn prove(&self, rel: &str, tuple: &[Value]) -> Option<Proof> {
        Provenance::prove(self, rel, tuple)
    }
}

impl<const R: usize> Provenance<R> {
    /// Encodes a decoded tuple, without interning: `None` if a value cannot be in the relation.
    fn encode_tuple(&self, rel: &str, tuple: &[Value]) -> Option<Row<R>> {
        let types = self.encoded.types.get(rel)?;
        if types.len() != tuple.len() {
            return None;
        }
        let mut row = [0u64; R];
        for (i, (v, &ty)) in tuple.iter().zip(types).enumerate() {
            row[i] = match (v, ty) {
                (Value::Str(s), ColType::Str) => self.encoded.symbols.lookup(s)?,
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

    fn decode(&self, rel: &str, row: &Row<R>) -> Vec<Value> {
        self.encoded
            .types
            .get(rel)
            .map_or_else(Vec::new, |types| self.encoded.decode_row(types, row))
    }

    /// The stamp of a tuple of a derived relation.
    fn stamp_of(&self, rel: &str, row: &[u64]) -> Option<Stamp> {
        let stamps = self.stamps.get(rel)?;
        let i = self.encoded.rels.get(rel)?.position(row)?;
        stamps.get(i)
    }

    pub(crate) fn stamp(&self, rel: &str, tuple: &[Value]) -> Option<Stamp> {
        let row = self.encode_tuple(rel, tuple)?;
        self.stamp_of(rel, &row)
    }

    pub(crate) fn prove(&self, rel: &str, tuple: &[Value]) -> Option<Proof> {
        let row = self.encode_tuple(rel, tuple)?;
        if !self.encoded.rels.get(rel)?.contains(&row) {
            return None;
        }
        self.prove_row(rel, &row)
    }

    /// Builds the proof of a stored tuple with an explicit stack (no recursion per level, so
    /// a derivation thousands of rounds deep cannot overflow the call stack): each node is
    /// visited, its body tuples found by [`find_derivation`], its children visited in order,
    /// and the node assembled from the last proofs built once they are all done.
    fn prove_row(&self, rel: &str, row: &Row<R>) -> Option<Proof> {
        enum Task<'a, const R: usize> {
            Visit(&'a str, Row<R>),
            Build(&'a str, Row<R>, usize, usize),
        }
        let mut indexes = Indexes::default();
        let mut tasks = vec![Task::Visit(rel, *row)];
        let mut built: Vec<Proof> = Vec::new();
        while let Some(task) = tasks.pop() {
            match task {
                Task::Visit(rel, row) => {
                    let Some(stamp) = self.stamp_of(rel, &row) else {
                        // Not derived by a clause: a catalog tuple.
                        built.push(Proof {
                            relation: rel.to_string(),
                            tuple: self.decode(rel, &row),
                            clause: None,
                            children: Vec::new(),
                        });
                        continue;
                    };
                    if self.facts_only.get(stamp.stratum) == Some(&true) {
                        built.push(Proof {
                            relation: rel.to_string(),
                            tuple: self.decode(rel, &row),
                            clause: Some(stamp.clause),
                            children: Vec::new(),
                        });
                        continue;
                    }
                    let (_, plan, clause) = self
                        .plans
                        .get(stamp.stratum)?
                        .iter()
                        .find(|(_, _, c)| *c == stamp.clause)?;
                    let trail = self.find_derivation(plan, stamp, &row, &mut indexes)?;
                    tasks.push(Task::Build(rel, row, *clause, trail.len()));
                    // Reversed, so the first atom's proof is built (and pushed) first.
                    for (atom, t) in plan.atoms.iter().zip(&trail).rev() {
                        tasks.push(Task::Visit(&atom.pred, *t));
                    }
                }
                Task::Build(rel, row, clause, n) => {
                    let children = built.split_off(built.len().checked_sub(n)?);
                    built.push(Proof {
                        relation: rel.to_string(),
                        tuple: self.decode(rel, &row),
                        clause: Some(clause),
                        children,
                    });
                }
            }
        }
        built.pop()
    }

    /// The body tuples (one per atom, in join order) of a binding of `plan` whose head is
    /// `target`, using only tuples of the stamp's stratum from earlier rounds (tuples of lower
    /// strata are all usable). Each atom's candidates are found by a prefix search in a copy of
    /// its relation sorted with its constants and key columns first.
    fn find_derivation(
        &self,
        plan: &Plan<R>,
        stamp: Stamp,
        target: &Row<R>,
        indexes: &mut Indexes<R>,
    ) -> Option<Vec<Row<R>>> {
        let same: HashSet<&str> = self
            .strata
            .get(stamp.stratum)
            .map(|s| s.iter().map(|p| p.as_str()).collect())
            .unwrap_or_default();
        let mut accesses = Vec::new();
        for a in &plan.atoms {
            let acc = Access::of(a, crate::rows::stored_width(&self.encoded.types, &a.pred));
            let key = (a.pred.clone(), acc.sig.perm.clone());
            if !indexes.sorted.contains_key(&key) {
                let mut copy: Vec<(Row<R>, u32)> = Vec::new();
                if let Some(rows) = self.encoded.rels.get(&a.pred) {
                    for (i, t) in rows.iter().enumerate() {
                        let mut r = [0u64; R];
                        for (o, &c) in r.iter_mut().zip(&acc.sig.perm) {
                            *o = t.get(c).copied().unwrap_or(0);
                        }
                        copy.push((r, i as u32));
                    }
                }
                copy.sort_unstable();
                indexes.sorted.insert(key.clone(), copy);
            }
            if acc.prefix_len() == 0 && same.contains(a.pred.as_str()) {
                if let (false, Some(st)) = (
                    indexes.by_round.contains_key(&a.pred),
                    self.stamps.get(&a.pred),
                ) {
                    let mut v: Vec<(usize, u32)> = st
                        .packed
                        .get()
                        .iter()
                        .enumerate()
                        .map(|(i, p)| ((p >> 32) as usize, i as u32))
                        .collect();
                    v.sort_unstable_by(|a, b| b.cmp(a));
                    indexes.by_round.insert(a.pred.clone(), v);
                }
            }
            accesses.push((acc, key));
        }
        let search = Search {
            prov: self,
            plan,
            stamp,
            same: &same,
            accesses: &accesses,
            indexes,
            target,
        };
        let b = apply(&plan.start, [0u64; R])?;
        let mut trail = Vec::new();
        search.go(0, b, &mut trail).then_some(trail)
    }
}

/// A relation and a column order.
type CopyKey = (String, Vec<usize>);

/// Sorted, permuted copies of relations for one proof: (relation, column order) to the
/// permuted tuples with the index of each in the stored relation.
#[derive(Default)]
struct Indexes<const R: usize> {
    sorted: HashMap<CopyKey, Vec<(Row<R>, u32)>>,
    /// Per relation with stamps: (round, index) of every tuple, latest round first.
    by_round: HashMap<String, Vec<(usize, u32)>>,
}

/// The search for one derivation of `target` by `plan`.
struct Search<'a, const R: usize> {
    prov: &'a Provenance<R>,
    plan: &'a Plan<R>,
    stamp: Stamp,
    same: &'a HashSet<&'a str>,
    accesses: &'a [(Access, CopyKey)],
    indexes: &'a Indexes<R>,
    target: &'a Row<R>,
}

impl<const R: usize> Search<'_, R> {
    /// Extends binding `b` from atom `depth` on; the body tuples so far are in `trail`.
    fn go(&self, depth: usize, b: Row<R>, trail: &mut Vec<Row<R>>) -> bool {
        let (Some(step), Some((acc, key))) = (self.plan.atoms.get(depth), self.accesses.get(depth))
        else {
            return self.plan.project(&b).as_ref() == Some(self.target);
        };
        let Some(sorted) = self.indexes.sorted.get(key) else {
            return false;
        };
        let Some(rows) = self.prov.encoded.rels.get(&step.pred) else {
            return false;
        };
        let mut prefix: Vec<u64> = acc.consts.clone();
        if acc.nkeys > 0 {
            let Some(k) = step.binding_key(&b) else {
                return false;
            };
            prefix.extend_from_slice(&k[..acc.nkeys]);
        }
        let l = prefix.len();
        let recursive = self.same.contains(step.pred.as_str());
        let stamps = self.prov.stamps.get(&step.pred);
        // An atom of the stamp's stratum with nothing to look up: its tuples latest round
        // first, from the round before the stamp's (on a chain, the first one fits).
        let latest = match (l, recursive, self.indexes.by_round.get(&step.pred)) {
            (0, true, Some(v)) => {
                let from = v.partition_point(|&(r, _)| r >= self.stamp.round);
                Some(v[from..].iter().map(|&(_, i)| i))
            }
            _ => None,
        };
        let lo = sorted.partition_point(|(r, _)| r[..l] < prefix[..]);
        let matching = sorted[lo..]
            .iter()
            .take_while(|(r, _)| r[..l] == prefix[..])
            .map(|&(_, i)| i);
        let candidates: Box<dyn Iterator<Item = u32>> = match latest {
            Some(it) => Box::new(it),
            None => Box::new(matching),
        };
        for i in candidates {
            let Some(t) = rows.get(i as usize) else {
                continue;
            };
            if !step.selects(t) {
                continue;
            }
            // Tuples of the stamp's own stratum: from earlier rounds only.
            if recursive
                && stamps
                    .and_then(|s| s.round(i as usize))
                    .is_none_or(|r| r >= self.stamp.round)
            {
                continue;
            }
            if let Some(next) = apply(&step.after, step.extend(b, t)) {
                trail.push(Rows::row(t));
                if self.go(depth + 1, next, trail) {
                    return true;
                }
                trail.pop();
            }
        }
        false
    }
}
