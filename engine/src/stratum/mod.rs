//! Evaluating one stratum on datafrog: one `datafrog::Variable` per relation the stratum
//! defines, rotated by datafrog's semi-naive `Iteration` (recent tuples, stable batches merged
//! geometrically, new tuples deduplicated against the stable ones); a sorted, permuted copy per
//! atom access (keys first, see [`access`]): a `datafrog::Relation` for relations completed
//! before the stratum, a `Variable` of a second iteration kept in step with its relation for
//! the stratum's own; and each rule joined by [`join`] once per recursive atom reading that
//! atom's recent tuples, the recursive atoms before it the stable ones and those after it
//! both. Tuples are `[u64; W]`, `W` the widest relation of the stratum, monomorphised.
//!
//! Negation and aggregates are the planner's filters (our own antijoin by hash lookup against
//! completed lower strata: datafrog 2.0.1's `Relation::from_antijoin` returns nothing).

/// Calls `$f::<$R, W>($args…)` with `W` the tuple width that serves `$width` stored words: the
/// widths the stratum code is monomorphised for (1, 2, 3, 4, 6, 8 and the binding width `$R`,
/// [`crate::value::WIDTH`] for most programs).
macro_rules! with_width {
    ($width:expr, $f:ident::<$R:ident>($($a:expr),*)) => {
        match $width {
            1 => $f::<$R, 1>($($a),*),
            2 => $f::<$R, 2>($($a),*),
            3 => $f::<$R, 3>($($a),*),
            4 => $f::<$R, 4>($($a),*),
            5 | 6 => $f::<$R, 6>($($a),*),
            7 | 8 => $f::<$R, 8>($($a),*),
            _ => $f::<$R, $R>($($a),*),
        }
    };
}

pub(crate) mod access;
pub(crate) mod join;
pub(crate) mod once;

use std::borrow::Cow;
use std::collections::{HashMap, HashSet};
use std::time::Instant;

use datafrog::{Iteration, Relation, Variable};
use scenalog_facts::catalog::ColType;

use crate::limits::Limits;
use crate::plan::Plan;
use crate::prove::Origins;
pub(crate) use crate::rows::stored_width;
use crate::rows::Rows;
use crate::{EngineError, Options};
use access::{Access, Sig, Tup};
use join::Join;

/// What a stratum runs under: the options, when the evaluation started, and the tuples the
/// completed relations already hold.
pub(crate) struct StratumLimits<'a> {
    /// The evaluation's options.
    pub(crate) options: &'a Options,
    /// When the evaluation started.
    pub(crate) start: Instant,
    /// Tuples held by completed relations.
    pub(crate) held: usize,
}

/// Runs one stratum to its fixpoint on datafrog. Returns the relations it defines (sorted,
/// distinct) and, with provenance, the (round, plan) that first derived each tuple, aligned
/// with them.
pub(crate) fn run_stratum<const R: usize>(
    plans: &[(String, Plan<R>)],
    variants: &[Vec<(usize, Plan<R>)>],
    defined: &HashSet<&str>,
    types: &HashMap<String, Vec<ColType>>,
    complete: &HashMap<String, Rows>,
    limits: &StratumLimits<'_>,
) -> Result<(HashMap<String, Rows>, Origins), EngineError> {
    let stored = |name: &str| stored_width(types, name);
    let mut width = 1;
    for (head, p) in plans {
        width = width.max(stored(head));
        for a in &p.atoms {
            width = width.max(stored(&a.pred));
        }
    }
    for d in defined {
        width = width.max(stored(d));
    }
    let s = Stratum {
        plans,
        variants,
        defined,
        stored: &stored,
        complete,
        limits,
    };
    with_width!(width, run_at::<R>(&s))
}

/// [`Stratum::run`] with tuples of `W` words.
fn run_at<const R: usize, const W: usize>(
    s: &Stratum<'_, R>,
) -> Result<(HashMap<String, Rows>, Origins), EngineError> {
    s.run::<W>()
}

/// The inputs of one stratum's run.
struct Stratum<'a, const R: usize> {
    plans: &'a [(String, Plan<R>)],
    /// Per plan: (recursive literal, plan joining it first) of its semi-naive variants.
    variants: &'a [Vec<(usize, Plan<R>)>],
    defined: &'a HashSet<&'a str>,
    stored: &'a dyn Fn(&str) -> usize,
    complete: &'a HashMap<String, Rows>,
    limits: &'a StratumLimits<'a>,
}

/// Where an atom's copy lives.
#[derive(Clone, Copy)]
enum Src {
    /// `statics[i]`: a relation completed before the stratum.
    Static(usize),
    /// A relation of this stratum: its `vars[rel]` itself, or `indexes[i]`.
    Own { rel: usize, index: Option<usize> },
}

/// A stratum relation's sorted parts at the start of a round.
struct Parts<'a, const W: usize> {
    stable: std::cell::Ref<'a, Vec<Relation<Tup<W>>>>,
    recent: std::cell::Ref<'a, Relation<Tup<W>>>,
}

impl<const W: usize> Parts<'_, W> {
    fn stable(&self) -> impl Iterator<Item = &[Tup<W>]> {
        self.stable.iter().map(|r| &r.elements[..])
    }
}

impl<const R: usize> Stratum<'_, R> {
    fn run<const W: usize>(&self) -> Result<(HashMap<String, Rows>, Origins), EngineError> {
        let StratumLimits {
            options,
            start,
            held,
        } = *self.limits;
        let mut names: Vec<&str> = self.defined.iter().copied().collect();
        names.sort_unstable();
        let rel_of: HashMap<&str, usize> = names.iter().enumerate().map(|(i, n)| (*n, i)).collect();
        let mut iteration = Iteration::new();
        // Copies of the stratum's relations in another column order, kept in step with them.
        let mut aux = Iteration::new();
        let vars: Vec<Variable<Tup<W>>> = names.iter().map(|n| iteration.variable(n)).collect();
        let empty = Rows::new(1);
        // Relations completed before the stratum, as its atoms read them: the stored tuples
        // themselves when an atom reads them in their order at their width, else a copy.
        let mut statics: Vec<Cow<'_, [Tup<W>]>> = Vec::new();
        let mut indexes: Vec<(usize, Sig, Variable<Tup<W>>)> = Vec::new();
        let mut known: HashMap<Sig, Src> = HashMap::new();
        // Per plan, then per variant plan: the access of each atom and where its copy lives.
        let mut accesses: Vec<(Vec<Access>, Vec<Src>)> = Vec::new();
        let all = self
            .plans
            .iter()
            .map(|(_, p)| p)
            .chain(self.variants.iter().flatten().map(|(_, p)| p));
        for p in all {
            let mut list = Vec::new();
            for (i, a) in p.atoms.iter().enumerate() {
                // A completed relation read first is sorted for the next atom's lookups.
                let lead = match (i, p.atoms.get(1)) {
                    (0, Some(next)) if !rel_of.contains_key(a.pred.as_str()) => {
                        access::lead_columns(a, next)
                    }
                    _ => Vec::new(),
                };
                let acc = Access::ordered(a, (self.stored)(&a.pred), &lead);
                let src = match known.get(&acc.sig) {
                    Some(s) => *s,
                    None => {
                        let src = match rel_of.get(a.pred.as_str()) {
                            Some(&rel) if acc.sig.is_identity() => Src::Own { rel, index: None },
                            Some(&rel) => {
                                indexes.push((rel, acc.sig.clone(), aux.variable(&a.pred)));
                                Src::Own {
                                    rel,
                                    index: Some(indexes.len() - 1),
                                }
                            }
                            None => {
                                let rows = self.complete.get(&a.pred).unwrap_or(&empty);
                                statics.push(match rows.as_tuples::<W>() {
                                    Some(t) if acc.sig.is_identity() => Cow::Borrowed(t),
                                    _ => Cow::Owned(acc.sig.copy_rows(rows)),
                                });
                                Src::Static(statics.len() - 1)
                            }
                        };
                        known.insert(acc.sig.clone(), src);
                        src
                    }
                };
                list.push((acc, src));
            }
            accesses.push(list.into_iter().unzip());
        }
        // Where each variant plan's accesses are.
        let mut at = self.plans.len();
        let variant_at: Vec<Vec<(usize, usize)>> = self
            .variants
            .iter()
            .map(|vs| {
                vs.iter()
                    .map(|(lit, _)| {
                        at += 1;
                        (*lit, at - 1)
                    })
                    .collect()
            })
            .collect();
        let heads: Vec<Option<usize>> = self
            .plans
            .iter()
            .map(|(h, _)| rel_of.get(h.as_str()).copied())
            .collect();
        // With provenance, per relation: each round's new tuples with the plan of each.
        let mut batches: Vec<Vec<Batch<W>>> = (0..names.len()).map(|_| Vec::new()).collect();
        let mut first = true;
        let mut round: u64 = 0;
        loop {
            let stratum_held: usize = vars.iter().map(var_len).sum();
            // Per relation: this round's output, in plan order, with (end, plan) of each run.
            let mut outs: Vec<Vec<Tup<W>>> = vec![Vec::new(); names.len()];
            let mut runs: Vec<Vec<(usize, usize)>> = vec![Vec::new(); names.len()];
            {
                let own: Vec<Parts<'_, W>> = vars.iter().map(parts_of).collect();
                let idx: Vec<Parts<'_, W>> = indexes.iter().map(|(_, _, v)| parts_of(v)).collect();
                let parts_for = |rel: usize, index: Option<usize>| -> &Parts<'_, W> {
                    match index {
                        Some(i) => &idx[i],
                        None => &own[rel],
                    }
                };
                for (pi, (head, p)) in self.plans.iter().enumerate() {
                    let Some(h) = heads[pi] else { continue };
                    let (_, srcs) = &accesses[pi];
                    let rec: Vec<usize> = srcs
                        .iter()
                        .enumerate()
                        .filter(|(_, s)| matches!(s, Src::Own { .. }))
                        .map(|(i, _)| i)
                        .collect();
                    if first != rec.is_empty() {
                        // Rules without recursive atoms run in the first round only; rules
                        // with them from the second on (their atoms are empty before).
                        continue;
                    }
                    let pending: usize = outs.iter().map(Vec::len).sum();
                    let limits = Limits {
                        relation: head,
                        options,
                        start,
                        held: held + stratum_held + pending,
                    };
                    let out = &mut outs[h];
                    // Per variant: the plan, its accesses, and the literal read as recent
                    // tuples. Recursive atoms of earlier literals read the stable batches,
                    // later ones stable and recent alike (one fixed order per clause,
                    // whichever order each variant joins in).
                    let mut runs_of: Vec<(&Plan<R>, usize, Option<usize>)> = Vec::new();
                    if first {
                        runs_of.push((p, pi, None));
                    }
                    for &k in if first { &[][..] } else { &rec[..] } {
                        let lit = p.atoms[k].lit;
                        let chosen = variant_at[pi].iter().position(|&(l, _)| l == lit);
                        match chosen {
                            Some(v) => runs_of.push((
                                &self.variants[pi][v].1,
                                variant_at[pi][v].1,
                                Some(lit),
                            )),
                            None => runs_of.push((p, pi, Some(lit))),
                        }
                    }
                    for (plan, ai, delta) in runs_of {
                        let (access, srcs) = &accesses[ai];
                        let mut parts: Vec<Vec<&[Tup<W>]>> = Vec::new();
                        let mut recent_empty = false;
                        for (step, src) in plan.atoms.iter().zip(srcs) {
                            parts.push(match (*src, delta) {
                                (Src::Static(i), _) => vec![&statics[i][..]],
                                (Src::Own { rel, index }, Some(k)) if step.lit < k => {
                                    parts_for(rel, index).stable().collect()
                                }
                                (Src::Own { rel, index }, Some(k)) if step.lit == k => {
                                    let r = &parts_for(rel, index).recent.elements[..];
                                    recent_empty = r.is_empty();
                                    vec![r]
                                }
                                (Src::Own { rel, index }, _) => {
                                    let ps = parts_for(rel, index);
                                    let mut v: Vec<&[Tup<W>]> = ps.stable().collect();
                                    v.push(&ps.recent.elements[..]);
                                    v
                                }
                            });
                        }
                        if recent_empty {
                            continue;
                        }
                        let join = Join {
                            plan,
                            access,
                            parts,
                        };
                        join.run(out, &limits)?;
                    }
                    if options.provenance {
                        let end = out.len();
                        let r = &mut runs[h];
                        if r.last().map_or(0, |&(e, _)| e) < end {
                            r.push((end, pi));
                        }
                    }
                }
            }
            // The round's output: sorted and distinct per relation, into the variables.
            let mut firsts: Vec<Vec<(Tup<W>, u32)>> = vec![Vec::new(); names.len()];
            // Relations that one plan alone produced this round: that plan.
            let mut single: Vec<Option<u32>> = vec![None; names.len()];
            for (r, out) in outs.into_iter().enumerate() {
                if let (true, [(_, p)]) = (options.provenance, runs[r].as_slice()) {
                    single[r] = Some(*p as u32);
                }
                if options.provenance && single[r].is_none() {
                    let ends = &runs[r];
                    let mut pairs: Vec<(Tup<W>, u32)> = Vec::with_capacity(out.len());
                    let mut run = 0;
                    for (i, t) in out.into_iter().enumerate() {
                        while ends.get(run).is_some_and(|&(e, _)| e <= i) {
                            run += 1;
                        }
                        let plan = ends.get(run).map_or(u32::MAX, |&(_, p)| p as u32);
                        pairs.push((t, plan));
                    }
                    pairs.sort_unstable();
                    pairs.dedup_by(|a, b| a.0 == b.0);
                    vars[r].insert(Relation {
                        elements: pairs.iter().map(|&(t, _)| t).collect(),
                    });
                    firsts[r] = pairs;
                } else {
                    let mut out = out;
                    crate::rows::sort_tuples(&mut out);
                    out.dedup();
                    vars[r].insert(Relation { elements: out });
                }
            }
            if !iteration.changed() {
                break;
            }
            let mut total = held + stratum_held;
            for (r, v) in vars.iter().enumerate() {
                let recent = v.recent.borrow();
                total += recent.len();
                if total > options.max_tuples {
                    return Err(EngineError::TooManyTuples {
                        relation: names[r].to_string(),
                        limit: options.max_tuples,
                    });
                }
                if options.provenance && !recent.is_empty() {
                    // Each new tuple's plan: the first plan (in order) that produced it.
                    let plans = match single[r] {
                        Some(plan) => Plans::One(plan),
                        None => {
                            let firsts = &firsts[r];
                            let mut at = 0;
                            let mut each = Vec::with_capacity(recent.len());
                            for t in recent.iter() {
                                while firsts.get(at).is_some_and(|(f, _)| f < t) {
                                    at += 1;
                                }
                                each.push(firsts.get(at).map_or(u32::MAX, |&(_, p)| p));
                            }
                            Plans::Each(each)
                        }
                    };
                    batches[r].push(Batch {
                        round,
                        tuples: recent.elements.clone(),
                        plans,
                    });
                }
            }
            for (rel, sig, index) in &indexes {
                let recent = vars[*rel].recent.borrow();
                let mut copy: Vec<Tup<W>> = recent.iter().filter_map(|t| sig.apply(t)).collect();
                crate::rows::sort_tuples(&mut copy);
                copy.dedup();
                index.insert(Relation { elements: copy });
            }
            aux.changed();
            first = false;
            round += 1;
        }
        let mut done = HashMap::new();
        let mut origins = Origins::new();
        for ((r, v), name) in vars.into_iter().enumerate().zip(&names) {
            let arity = (self.stored)(name);
            let all = v.complete();
            let count = all.len();
            // At the stratum's width the tuples' words are the stored words as they are.
            let data = if arity == W {
                all.elements.into_flattened()
            } else {
                let mut data = Vec::with_capacity(all.len() * arity);
                for t in all.iter() {
                    data.extend_from_slice(&t[..arity]);
                }
                data
            };
            if options.provenance {
                let batches = std::mem::take(&mut batches[r]);
                debug_assert_eq!(batches.iter().map(|b| b.tuples.len()).sum::<usize>(), count);
                let align: crate::prove::Align = Box::new(move || align(batches));
                origins.insert(name.to_string(), crate::prove::Packed::deferred(align));
            }
            done.insert(name.to_string(), Rows::from_flat(arity, data));
        }
        Ok((done, origins))
    }
}

/// One round's new tuples of a relation (sorted, as datafrog's `recent` holds them) and the
/// plan that first derived each.
struct Batch<const W: usize> {
    round: u64,
    tuples: Vec<Tup<W>>,
    plans: Plans,
}

/// The plans of a batch's tuples: one for all (a relation that one plan alone produced in the
/// round), or one each.
enum Plans {
    One(u32),
    Each(Vec<u32>),
}

/// The packed (round, plan) stamp of every tuple of a relation, in the relation's sorted
/// order, from the batches of the rounds in which each tuple first appeared. Every tuple is new
/// in exactly one round, so the batches hold each tuple once; each batch is a sorted run, and
/// a stable sort merges the runs it finds.
fn align<const W: usize>(batches: Vec<Batch<W>>) -> Vec<u64> {
    let n = batches.iter().map(|b| b.tuples.len()).sum();
    let mut tagged: Vec<(Tup<W>, u64)> = Vec::with_capacity(n);
    for b in batches {
        match b.plans {
            Plans::One(p) => {
                let tag = crate::prove::pack(b.round, p as usize);
                tagged.extend(b.tuples.into_iter().map(|t| (t, tag)));
            }
            Plans::Each(ps) => tagged.extend(
                b.tuples
                    .into_iter()
                    .zip(ps)
                    .map(|(t, p)| (t, crate::prove::pack(b.round, p as usize))),
            ),
        }
    }
    // Stable: each batch is a sorted run, which the merges of the standard sort use.
    tagged.sort_by_key(|a| a.0);
    tagged.into_iter().map(|(_, t)| t).collect()
}

/// Tuples a variable holds (stable and recent).
fn var_len<const W: usize>(v: &Variable<Tup<W>>) -> usize {
    v.stable.borrow().iter().map(|r| r.len()).sum::<usize>() + v.recent.borrow().len()
}

fn parts_of<const W: usize>(v: &Variable<Tup<W>>) -> Parts<'_, W> {
    Parts {
        stable: v.stable.borrow(),
        recent: v.recent.borrow(),
    }
}
