//! The evaluation loop: asking the provider for catalog relations, then each stratum in order
//! with semi-naive iteration over sorted, deduplicated fixed-width rows.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::sync::Arc;
use std::time::Instant;

use scenalog_facts::catalog::ColType;
use scenalog_facts::relation::{RelationData, Request, Value};
use scenalog_rules::{CheckedProgram, PredKind};

use crate::demand;
pub(crate) use crate::limits::Limits;
use crate::plan::{body_lits, plan, plan_first, BodyLit, Ctx, Plan};
pub(crate) use crate::prove::Origins;
use crate::prove::{Proofs, Provenance, Stamps};
use crate::rows::Rows;
use crate::value::{cmp_value, encode_value, Symbols, WIDEST, WIDTH};
use crate::{Encoded, EngineError, Evaluation, Options};

/// Evaluates a checked program. Catalog relations the program uses are asked from `provider`,
/// once each, with the constants the program fixes in every use of a column as
/// [`Constraint::Eq`]; providers may return a superset. Ground facts of the program are inputs
/// too. Returns every used or defined relation, decoded and sorted.
pub fn evaluate(
    program: &CheckedProgram,
    provider: &mut dyn FnMut(&Request) -> Result<RelationData, String>,
    options: &Options,
) -> Result<Evaluation, EngineError> {
    // Relations the caller does not read: inlined where used once, then restricted to what
    // their uses ask for (demand).
    let (inlined, restricted);
    let program = match &options.reads {
        Some(reads) if !options.provenance => {
            inlined = crate::inline::inline(program, reads);
            let program = inlined.as_ref().unwrap_or(program);
            restricted = crate::magic::restrict(program, reads);
            restricted.as_ref().unwrap_or(program)
        }
        _ => program,
    };
    let width = row_width(program);
    if width <= WIDTH && !options.wide_rows {
        evaluate_at::<WIDTH>(program, provider, options)
    } else if width <= WIDEST {
        evaluate_at::<WIDEST>(program, provider, options)
    } else {
        Err(EngineError::Unsupported(format!(
            "a rule or relation {width} values wide; at most {WIDEST} are supported"
        )))
    }
}

/// The binding-row width `program` needs: its widest relation and the most binding slots of any
/// clause ([`scenalog_rules::walk::binding_slots`], an upper bound on what the planner uses).
pub(crate) fn row_width(program: &CheckedProgram) -> usize {
    let relations = program.predicates.values().map(|p| p.types.len());
    // A clause without a body (a fact; the checker makes its head ground) binds nothing: skipped
    // without a walk, since a program may hold many thousands of facts.
    let clauses = program
        .program
        .clauses
        .iter()
        .filter(|c| !c.body.is_empty())
        .map(scenalog_rules::walk::binding_slots);
    relations.chain(clauses).max().unwrap_or(0)
}

/// [`evaluate`] with binding rows of `R` words (the program's widest relation and rule fit).
fn evaluate_at<const R: usize>(
    program: &CheckedProgram,
    provider: &mut dyn FnMut(&Request) -> Result<RelationData, String>,
    options: &Options,
) -> Result<Evaluation, EngineError> {
    let start = Instant::now();
    let mut symbols = Symbols::default();
    let types: HashMap<String, Vec<ColType>> = program
        .predicates
        .iter()
        .map(|(k, p)| (k.clone(), p.types.clone()))
        .collect();
    let mut complete: HashMap<String, Rows> = HashMap::new();
    // Tuples held by completed relations, inputs included: one budget for the whole evaluation.
    let mut held = 0usize;
    // Catalog relations: all up front with pushdown off; with it on, only those no clause uses
    // (each stratum asks for the ones its clauses use, see `load_demanded`).
    for (name, info) in &program.predicates {
        if info.kind != PredKind::Catalog || (options.pushdown && demand::is_used(program, name)) {
            continue;
        }
        let request = demand::request_for(program, name);
        let rows = load_requested(
            &request,
            &info.types,
            provider,
            options,
            start,
            held,
            &mut symbols,
        )?;
        held += rows.len();
        complete.insert(name.clone(), rows);
    }
    let mut sent = demand::Sent::new();
    let mut loaded_for: HashMap<String, usize> = HashMap::new();
    let clauses = &program.program.clauses;
    let mut stamps: HashMap<String, Stamps> = HashMap::new();
    let mut all_plans: Vec<Vec<(String, Plan<R>, usize)>> = Vec::new();
    // Per stratum: whether it holds facts alone (evaluated without plans).
    let mut facts_only: Vec<bool> = Vec::new();
    for (si, stratum) in program.strata.iter().enumerate() {
        if options.pushdown {
            let cx = Loading {
                provider: &mut *provider,
                options,
                start,
            };
            held = load_demanded(
                program,
                si,
                cx,
                &mut complete,
                &mut sent,
                &mut loaded_for,
                &mut symbols,
                held,
            )?;
        }
        let defined: HashSet<&str> = stratum.predicates.iter().map(|s| s.as_str()).collect();
        let stratum_clauses: Vec<(usize, &scenalog_rules::ast::Clause)> = stratum
            .clauses
            .iter()
            .filter_map(|&ci| clauses.get(ci).map(|c| (ci, c)))
            .collect();
        if stratum_clauses.iter().all(|(_, c)| c.body.is_empty()) {
            // Facts alone: evaluated without plans; their proofs are leaves (`Provenance::facts_only`).
            let heads: Vec<&scenalog_rules::ast::Clause> =
                stratum_clauses.iter().map(|&(_, c)| c).collect();
            let cx = (options, start, held);
            let (derived, origins) =
                crate::ground::facts::<R>(&heads, &defined, &types, &mut symbols, cx)?;
            held += derived.values().map(Rows::len).sum::<usize>();
            complete.extend(derived);
            let clause_of = stratum_clauses.iter().map(|&(ci, _)| ci).collect();
            keep_stamps(&mut stamps, origins, si, clause_of);
            if options.provenance {
                all_plans.push(Vec::new());
            }
            facts_only.push(true);
            continue;
        }
        facts_only.push(false);
        let mut plans: Vec<(String, Plan<R>)> = Vec::new();
        // Per plan: the plans of its semi-naive variants, by the recursive literal read first.
        let mut variants: Vec<Vec<(usize, Plan<R>)>> = Vec::new();
        let mut clause_of: Vec<usize> = Vec::new();
        for &ci in &stratum.clauses {
            let Some(clause) = clauses.get(ci) else {
                continue;
            };
            let lits = body_lits(&clause.body);
            let head_types = types.get(&clause.head.pred).cloned();
            let limits = Limits {
                relation: &clause.head.pred,
                options,
                start,
                held,
            };
            let mut ctx = Ctx {
                types: &types,
                complete: &complete,
                symbols: &mut symbols,
                limits: &limits,
            };
            let p = plan(&lits, &clause.head.args, head_types.as_deref(), &mut ctx)?;
            // Each recursive atom's variant joins that atom (its recent tuples, usually few)
            // first. Bodies with aggregates keep one plan (planning evaluates the aggregate).
            let mut vs = Vec::new();
            let has_agg = lits.iter().any(|l| matches!(l, BodyLit::Agg(_)));
            let lead = p.atoms.first().map(|a| a.lit);
            for (i, l) in lits.iter().enumerate() {
                let recursive =
                    matches!(l, BodyLit::Pos(a) if stratum.predicates.contains(&a.pred));
                if has_agg || !recursive || lead == Some(i) {
                    continue;
                }
                let head_args = &clause.head.args;
                if let Ok(v) = plan_first(&lits, head_args, head_types.as_deref(), &mut ctx, i) {
                    vs.push((i, v));
                }
            }
            variants.push(vs);
            plans.push((clause.head.pred.clone(), p));
            clause_of.push(ci);
        }
        let (derived, origins) = if crate::ground::applies(&plans) {
            crate::ground::run(&plans, &defined, &types, options, start, held)?
        } else {
            let limits = crate::stratum::StratumLimits {
                options,
                start,
                held,
            };
            crate::stratum::run_stratum(&plans, &variants, &defined, &types, &complete, &limits)?
        };
        held += derived.values().map(Rows::len).sum::<usize>();
        complete.extend(derived);
        keep_stamps(
            &mut stamps,
            origins,
            si,
            clause_of.iter().copied().collect(),
        );
        if options.provenance {
            all_plans.push(
                plans
                    .into_iter()
                    .zip(&clause_of)
                    .map(|((h, p), &c)| (h, p, c))
                    .collect(),
            );
        }
    }
    let mut rels = HashMap::new();
    let mut decoded = BTreeMap::new();
    let mut derived = Vec::new();
    for (name, info) in &program.predicates {
        let rows = complete
            .remove(name)
            .unwrap_or_else(|| Rows::new(info.types.len()));
        rels.insert(name.clone(), rows);
        decoded.insert(name.clone(), std::sync::OnceLock::new());
        if info.kind == PredKind::Derived {
            derived.push(name.clone());
        }
    }
    let encoded = Arc::new(Encoded {
        types,
        symbols,
        rels,
    });
    let provenance = options.provenance.then(|| -> Arc<dyn Proofs> {
        Arc::new(Provenance::<R> {
            encoded: encoded.clone(),
            stamps,
            plans: all_plans,
            facts_only,
            strata: program
                .strata
                .iter()
                .map(|s| s.predicates.clone())
                .collect(),
        })
    });
    Ok(Evaluation {
        encoded,
        decoded,
        derived,
        provenance,
    })
}

/// A relation of an evaluation decoded and sorted by value (empty when unknown).
pub(crate) fn decode_relation(encoded: &Encoded, name: &str) -> Vec<Vec<Value>> {
    let (Some(rows), Some(types)) = (encoded.rels.get(name), encoded.types.get(name)) else {
        return Vec::new();
    };
    let mut decoded: Vec<Vec<Value>> = rows.iter().map(|r| encoded.decode_row(types, r)).collect();
    // Rows are sorted and distinct in encoded order, which is value order for every type but
    // strings (interned in order of first sight): only those need sorting again.
    if types.contains(&ColType::Str) {
        decoded.sort_by(|a, b| {
            a.iter()
                .zip(b)
                .map(|(x, y)| cmp_value(x, y))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
    }
    decoded
}

/// What loading a catalog relation needs besides the evaluation's state.
struct Loading<'a> {
    provider: &'a mut dyn FnMut(&Request) -> Result<RelationData, String>,
    options: &'a Options,
    start: Instant,
}

/// Asks the provider for `request` and encodes the answer, checking the budget (`held` tuples
/// are held already) and the clock.
fn load_requested(
    request: &Request,
    types: &[ColType],
    provider: &mut dyn FnMut(&Request) -> Result<RelationData, String>,
    options: &Options,
    start: Instant,
    held: usize,
    symbols: &mut Symbols,
) -> Result<Rows, EngineError> {
    let name = &request.name;
    let data = provider(request).map_err(|message| EngineError::Provider {
        relation: name.clone(),
        message,
    })?;
    let loading = Limits {
        relation: name,
        options,
        start,
        held,
    };
    loading.check(data.len())?;
    load(&data, name, types, symbols)
}

/// Pushdown: asks for the catalog relations the clauses of stratum `si` use, in
/// [`demand::used_in_stratum`]'s order, with the requests [`demand::stratum_requests`] gives
/// (bound through relations complete so far), and merges the answers into `complete`. Returns
/// the tuples held afterwards.
#[allow(clippy::too_many_arguments)]
fn load_demanded(
    program: &CheckedProgram,
    si: usize,
    cx: Loading<'_>,
    complete: &mut HashMap<String, Rows>,
    sent: &mut demand::Sent,
    loaded_for: &mut HashMap<String, usize>,
    symbols: &mut Symbols,
    mut held: usize,
) -> Result<usize, EngineError> {
    for name in demand::used_in_stratum(program, si) {
        let types: &[ColType] = program
            .predicates
            .get(&name)
            .map_or(&[], |p| p.types.as_slice());
        let requests = {
            let binders = |p: &str| -> Option<&Rows> {
                let catalog = program
                    .predicates
                    .get(p)
                    .is_some_and(|i| i.kind == PredKind::Catalog);
                if catalog && loaded_for.get(p) != Some(&si) {
                    return None;
                }
                complete.get(p)
            };
            let already = sent.get(&name).map_or(&[][..], |v| v.as_slice());
            demand::stratum_requests(program, si, &name, &binders, symbols, already)
        };
        let mut rows = complete
            .remove(&name)
            .unwrap_or_else(|| Rows::new(types.len()));
        for request in requests {
            let fresh = load_requested(
                &request,
                types,
                &mut *cx.provider,
                cx.options,
                cx.start,
                held,
                symbols,
            )?;
            let before = rows.len();
            rows = if rows.is_empty() {
                fresh
            } else {
                rows.merge(&fresh)
            };
            held += rows.len() - before;
            sent.entry(name.clone()).or_default().push(request);
        }
        complete.insert(name.clone(), rows);
        loaded_for.insert(name, si);
    }
    Ok(held)
}

/// Keeps a stratum's stamps: `origins` per relation, `clause_of` the program clause of each
/// plan index in them.
fn keep_stamps(
    stamps: &mut HashMap<String, Stamps>,
    origins: Origins,
    stratum: usize,
    clause_of: Arc<[usize]>,
) {
    for (name, packed) in origins {
        let list = Stamps {
            stratum,
            clauses: clause_of.clone(),
            packed,
        };
        stamps.insert(name, list);
    }
}

/// Encodes a provided relation into sorted, deduplicated rows.
fn load(
    data: &RelationData,
    name: &str,
    types: &[ColType],
    symbols: &mut Symbols,
) -> Result<Rows, EngineError> {
    let bad = |message: String| EngineError::BadInput {
        relation: name.to_string(),
        message,
    };
    if data.columns.len() != types.len() {
        return Err(bad(format!(
            "{} columns, the catalog says {}",
            data.columns.len(),
            types.len()
        )));
    }
    let n = data.len();
    if let Some((i, c)) = data.columns.iter().enumerate().find(|(_, c)| c.len() != n) {
        return Err(bad(format!(
            "column {i} has {} values, column 0 has {n}",
            c.len()
        )));
    }
    let stride = types.len().max(1);
    let mut flat = vec![0u64; n * stride];
    for (ci, (col, &ty)) in data.columns.iter().zip(types).enumerate() {
        for (ri, row) in flat.chunks_exact_mut(stride).enumerate() {
            let v = col
                .get(ri)
                .ok_or_else(|| bad(format!("column {ci} ends early")))?;
            row[ci] = encode_value(&v, ty, symbols)
                .ok_or_else(|| bad(format!("column {ci}, tuple {ri}: {v:?} is not a {ty:?}")))?;
        }
    }
    let mut out = Rows::from_flat(types.len(), flat);
    out.sort_dedup();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{Arg, Filter};
    use scenalog_facts::relation::Column;
    use scenalog_rules::{check, CheckOptions};

    /// A planning function: literals, head arguments, head types, context.
    type PlanWith = dyn Fn(
        &[crate::plan::BodyLit<'_>],
        &[scenalog_rules::ast::Expr],
        Option<&[ColType]>,
        &mut Ctx<'_>,
    ) -> Result<Plan<WIDTH>, EngineError>;

    /// Plans the first (`last`: the last) clause defining `head` in a program without catalog
    /// relations with `plan_with(literals, head arguments, head types, context)`.
    fn plan_clause(src: &str, head: &str, last: bool, plan_with: &PlanWith) -> Plan<WIDTH> {
        let outcome = check(
            src,
            &CheckOptions {
                require_referred: false,
            },
        );
        let Some(program) = outcome.program else {
            panic!("does not check: {:?}", outcome.diagnostics);
        };
        let types: HashMap<String, Vec<ColType>> = program
            .predicates
            .iter()
            .map(|(k, p)| (k.clone(), p.types.clone()))
            .collect();
        let complete = HashMap::new();
        let mut symbols = Symbols::default();
        let options = Options::default();
        let limits = Limits {
            relation: "test",
            options: &options,
            start: Instant::now(),
            held: 0,
        };
        let mut ctx = Ctx {
            types: &types,
            complete: &complete,
            symbols: &mut symbols,
            limits: &limits,
        };
        let mut defining = program
            .program
            .clauses
            .iter()
            .filter(|c| c.head.pred == head);
        let found = if last {
            defining.next_back()
        } else {
            defining.next()
        };
        let Some(clause) = found else {
            panic!("no clause for {head}");
        };
        let head_types = types.get(&clause.head.pred).cloned();
        let lits = body_lits(&clause.body);
        match plan_with(&lits, &clause.head.args, head_types.as_deref(), &mut ctx) {
            Ok(p) => p,
            Err(e) => panic!("does not plan: {e}"),
        }
    }

    /// Plans the first clause defining `head` as the evaluation does.
    fn plan_of(src: &str, head: &str) -> Plan<WIDTH> {
        plan_clause(src, head, false, &|l, h, t, c| plan(l, h, t, c))
    }

    #[test]
    fn constants_are_selections_joined_first_and_comparisons_run_when_bound() {
        let src = ".decl cat(V: int, C: str)\n.decl spd(V: int, T: int, S: float)\n\
                   .decl fast_bus(V: int, T: int)\n\
                   cat(1, \"BUS\"). cat(2, \"CAR\"). spd(1, 0, 9.0). spd(2, 0, 3.0).\n\
                   fast_bus(V, T) :- spd(V, T, S), cat(V, \"BUS\"), S > 5.0, V != 7.\n";
        let p = plan_of(src, "fast_bus");
        // The atom with a constant is joined first, its constant a selection on the column.
        assert_eq!(p.atoms[0].pred, "cat");
        assert!(
            matches!(p.atoms[0].args[1], Arg::Const(_)),
            "{:?}",
            p.atoms[0]
        );
        // `V != 7` needs only `V`: it runs right after the first atom, before the join.
        assert!(
            matches!(p.atoms[0].after.as_slice(), [Filter::CmpRaw(..)]),
            "{:?}",
            p.atoms[0].after
        );
        // `S > 5.0` runs after `spd`, joined on `V`.
        assert_eq!(p.atoms[1].pred, "spd");
        assert!(matches!(p.atoms[1].args[0], Arg::Key(..)));
        assert_eq!(p.atoms[1].after.len(), 1);
    }

    #[test]
    fn window_comparisons_narrow_the_next_column_to_a_range() {
        let src = ".decl a(V: int, T: time)\n.decl b(V: int, T: time)\n\
                   .decl pair(V: int, T1: time, T2: time)\n\
                   .decl close_x(V: int, X: float, Y: float)\n.decl q(V: int, X: float)\n\
                   a(1, 5). b(1, 7). q(1, 0.5).\n\
                   pair(V, T1, T2) :- a(V, T1), b(V, T2), T2 > T1, T2 - T1 <= 10.\n\
                   close_x(V, X, Y) :- q(V, X), q(V, Y), abs(X - Y) < 2.5.\n";
        let p = plan_of(src, "pair");
        assert_eq!(p.atoms[1].pred, "b");
        let Some(n) = &p.atoms[1].narrow else {
            panic!("no narrowing: {:?}", p.atoms[1]);
        };
        assert_eq!(n.col, 1);
        // Both comparisons still run on the candidates in the range.
        assert_eq!(p.atoms[1].after.len(), 2);
        let mut b = [0u64; WIDTH];
        b[1] = 5; // T1 (slot 1, after V)

        // `T2 > T1` is `T2 >= 6` on times; `T2 - T1 <= 10` includes its end.
        assert_eq!(n.range(&b), Some((6, 15)));
        let p = plan_of(src, "close_x");
        let Some(n) = &p.atoms[1].narrow else {
            panic!("no narrowing: {:?}", p.atoms[1]);
        };
        b[1] = crate::value::enc_float(1.0);
        let Some((lo, hi)) = n.range(&b) else {
            panic!("empty range");
        };
        let (lo, hi) = (crate::value::dec_float(lo), crate::value::dec_float(hi));
        // A little wider than (-1.5, 3.5), never narrower.
        assert!(
            (-1.5001..=-1.5).contains(&lo) && (3.5..3.5001).contains(&hi),
            "{lo} {hi}"
        );
    }

    #[test]
    fn strict_int_windows_exclude_their_ends_and_window_checks_run_last() {
        let src = ".decl pos(O: int, T: int, X: int, L: int)\n\
                   .decl close(A: int, B: int, T: int)\n\
                   pos(1, 0, 10, 2).\n\
                   close(A, B, T) :- pos(A, T, XA, LA), pos(B, T, XB, LB), A != B, \
                   abs(XA - XB) < 100, abs(LA - LB) <= 1.\n";
        let p = plan_of(src, "close");
        let Some(n) = &p.atoms[1].narrow else {
            panic!("no narrowing: {:?}", p.atoms[1]);
        };
        // XB is narrowed by `abs(XA - XB) < 100`: with XA = 10 (slot 2), 10 - 99 ..= 10 + 99.
        assert_eq!(n.col, 2);
        let mut b = [0u64; WIDTH];
        b[2] = crate::value::enc_int(10);
        let dec = crate::value::dec_int;
        let range = n.range(&b).map(|(lo, hi)| (dec(lo), dec(hi)));
        assert_eq!(range, Some((-89, 109)));
        // The lane check rejects most candidates and runs first; `A != B` next; the check
        // the range already enforces last. All three still run.
        let after = &p.atoms[1].after;
        assert!(
            matches!(
                after.as_slice(),
                [
                    Filter::CmpDiff {
                        op: scenalog_rules::ast::CmpOp::Le,
                        ..
                    },
                    Filter::CmpRaw(scenalog_rules::ast::CmpOp::Ne, ..),
                    Filter::CmpDiff {
                        op: scenalog_rules::ast::CmpOp::Lt,
                        ..
                    }
                ]
            ),
            "{after:?}"
        );
        // A bound that overflows (`XA - 100` below `i64::MIN`) leaves its side open.
        b[2] = crate::value::enc_int(i64::MIN + 99);
        let range = n.range(&b).map(|(lo, hi)| (dec(lo), dec(hi)));
        assert_eq!(range, Some((i64::MIN, i64::MIN + 198)));
    }

    #[test]
    fn a_semi_naive_variant_joins_its_recursive_atom_first() {
        let src = ".decl parent(C: int, P: int)\n.decl sg(A: int, B: int)\n\
                   parent(2, 1). parent(3, 1).\n\
                   sg(X, Y) :- parent(X, P), parent(Y, P), X != Y.\n\
                   sg(X, Y) :- parent(X, A), sg(A, B), parent(Y, B).\n";
        let base = plan_clause(src, "sg", true, &|l, h, t, c| plan(l, h, t, c));
        // The planner alone starts with `parent` (written first, nothing bound yet).
        assert_eq!(base.atoms[0].pred, "parent");
        let first = plan_clause(src, "sg", true, &|l, h, t, c| plan_first(l, h, t, c, 1));
        // The variant reading `sg`'s recent tuples scans them and looks both parents up.
        assert_eq!(first.atoms[0].pred, "sg");
        assert_eq!(first.atoms[0].lit, 1);
        assert!(first.atoms[1..].iter().all(|a| !a.keys.is_empty()));
    }

    #[test]
    fn stored_tuples_take_their_arity_in_words() {
        let edges = RelationData {
            name: "e".to_string(),
            columns: vec![Column::Int(vec![1, 2]), Column::Int(vec![2, 3])],
        };
        let mut symbols = Symbols::default();
        let rows = match load(&edges, "e", &[ColType::Int, ColType::Int], &mut symbols) {
            Ok(r) => r,
            Err(e) => panic!("{e}"),
        };
        assert_eq!(rows.len(), 2);
        assert_eq!(rows.arity(), 2);
        assert_eq!(rows.iter().map(|t| t.len()).collect::<Vec<_>>(), vec![2, 2]);
    }
}
