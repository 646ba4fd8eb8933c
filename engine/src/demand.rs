//! Demand: the requests the engine sends the provider for the catalog relations a program uses.
//!
//! Two modes ([`crate::Options::pushdown`]):
//!
//! - **Off**: [`request_for`] asks for each catalog relation once, before any stratum runs, with
//!   the constraints implied by *every* use of it (their intersection).
//! - **On** (the default): a catalog relation is asked for stratum by stratum, for the uses in
//!   that stratum's clauses ([`stratum_requests`]), one request per distinct use, and the answers
//!   are unioned. Besides the use's own constants, categories and bounds ([`use_constraints`]),
//!   a track or time column whose variable the same body also binds through a positive atom over
//!   a relation that is already complete (a derived relation of a lower stratum, or a catalog
//!   relation loaded for this stratum, e.g. `ego(E)`) gets [`Constraint::OneOf`] the values that
//!   relation's column holds. That is the demand (magic-set) transformation restricted to the
//!   catalog relations: the extractors then compute pairs only for the bound subjects. When one
//!   such relation binds all three of a pair relation's (X, Y, T) variables together (e.g.
//!   `near(V, L, T, D)` in the body of `following(V, L, T)`, loaded first), the request also
//!   carries [`Constraint::Triples`]: the (X, Y, T) combinations that relation holds, so the
//!   extractors look at those pairs at those frames only instead of every pair near each other.
//!
//! Either way each use's tuples are a subset of what the relation holds for the request, so the
//! joins see every tuple they can match and the derived relations are the same.

use std::collections::{BTreeSet, HashMap};

use scenalog_facts::catalog::ColType;
use scenalog_facts::relation::{Constraint, Request, Value};
use scenalog_facts::{Frame, TrackId};
use scenalog_rules::ast::{Atom, CmpOp, ExprKind, Literal, Number};
use scenalog_rules::{CheckedProgram, PredKind};

use crate::rows::Rows;
use crate::value::{decode_value, encode_value, Symbols};

/// One use of a relation: the atom and the body (clause body or aggregate braces) it is in.
struct Use<'p> {
    atom: &'p Atom,
    body: &'p [Literal],
}

/// The uses of relation `name` in `body`, aggregate braces included.
fn collect_uses<'p>(body: &'p [Literal], name: &str, out: &mut Vec<Use<'p>>) {
    for l in body {
        match l {
            Literal::Pos(a) | Literal::Neg(a, _) if a.pred == name => {
                out.push(Use { atom: a, body })
            }
            Literal::Agg(g) => collect_uses(&g.body, name, out),
            _ => {}
        }
    }
}

/// The uses of `name` in the clauses with the given indices.
fn uses_in<'p>(program: &'p CheckedProgram, clauses: &[usize], name: &str) -> Vec<Use<'p>> {
    let mut out = Vec::new();
    for &ci in clauses {
        if let Some(c) = program.program.clauses.get(ci) {
            collect_uses(&c.body, name, &mut out);
        }
    }
    out
}

fn pred_types<'p>(program: &'p CheckedProgram, name: &str) -> &'p [ColType] {
    program
        .predicates
        .get(name)
        .map_or(&[], |p| p.types.as_slice())
}

/// The request for one catalog relation when pushdown is off: a constraint holds for the
/// request when every use of the relation in the program implies it (see [`use_constraints`]).
pub(crate) fn request_for(program: &CheckedProgram, name: &str) -> Request {
    let types = pred_types(program, name);
    let all: Vec<usize> = (0..program.program.clauses.len()).collect();
    let uses: Vec<Vec<(usize, Constraint)>> = uses_in(program, &all, name)
        .iter()
        .map(|u| use_constraints(u.atom, u.body, types))
        .collect();
    let mut request = Request::all(name);
    let Some((first, rest)) = uses.split_first() else {
        return request;
    };
    request.constraints = first
        .iter()
        .filter(|c| rest.iter().all(|u| u.contains(c)))
        .cloned()
        .collect();
    request
}

/// Whether any clause uses catalog relation `name`.
pub(crate) fn is_used(program: &CheckedProgram, name: &str) -> bool {
    let all: Vec<usize> = (0..program.program.clauses.len()).collect();
    !uses_in(program, &all, name).is_empty()
}

/// The catalog relations the clauses of stratum `si` use, in the order to load them: smaller
/// arity first (so `ego(E)` and `category(X, C)` are loaded, and can bind, before the pair
/// relations), then those every use of which fixes a constant or a numeric bound (so
/// `speed(V, T, S), S > 5.0` is loaded, and binds `V`, before `following(V, L, T)`), then by
/// name.
pub(crate) fn used_in_stratum(program: &CheckedProgram, si: usize) -> Vec<String> {
    let Some(stratum) = program.strata.get(si) else {
        return Vec::new();
    };
    let mut names: Vec<(usize, bool, &String)> = program
        .predicates
        .iter()
        .filter_map(|(name, info)| {
            if info.kind != PredKind::Catalog {
                return None;
            }
            let uses = uses_in(program, &stratum.clauses, name);
            if uses.is_empty() {
                return None;
            }
            let selective = uses.iter().all(|u| {
                use_constraints(u.atom, u.body, &info.types)
                    .iter()
                    .any(|(_, c)| !matches!(c, Constraint::Category(_)))
            });
            Some((info.types.len(), !selective, name))
        })
        .collect();
    names.sort();
    names.into_iter().map(|(_, _, n)| n.clone()).collect()
}

/// The relations a body's atoms may be bound through while loading for a stratum: complete
/// relations with their rows.
pub(crate) type Binders<'a> = dyn Fn(&str) -> Option<&'a Rows> + 'a;

/// The requests for catalog relation `name` that the uses in stratum `si` need, one per distinct
/// use, leaving out those that a request in `sent` (already answered) or another of them
/// subsumes (its constraints are a subset). `binders` gives the rows of each relation that may
/// bind a variable (complete, and not `name` itself). A use whose bound values are empty needs
/// no tuple and sends nothing.
pub(crate) fn stratum_requests(
    program: &CheckedProgram,
    si: usize,
    name: &str,
    binders: &Binders<'_>,
    symbols: &mut Symbols,
    sent: &[Request],
) -> Vec<Request> {
    let Some(stratum) = program.strata.get(si) else {
        return Vec::new();
    };
    let types = pred_types(program, name);
    let mut out: Vec<Request> = Vec::new();
    for u in uses_in(program, &stratum.clauses, name) {
        let mut constraints = use_constraints(u.atom, u.body, types);
        let mut needed = true;
        for (i, (e, &ty)) in u.atom.args.iter().zip(types).enumerate() {
            if !matches!(ty, ColType::Track | ColType::Time) {
                continue;
            }
            let Some(var) = e.as_var() else { continue };
            if let Some(values) = bound_values(program, &u, var, ty, name, binders, symbols) {
                if values.is_empty() {
                    needed = false;
                    break;
                }
                constraints.push((i, Constraint::OneOf(values.into())));
            }
        }
        if needed {
            if let Some(ts) = bound_triples(program, &u, types, name, binders, symbols) {
                if ts.is_empty() {
                    needed = false;
                } else {
                    constraints.push((0, Constraint::Triples(ts.into())));
                }
            }
        }
        if !needed {
            continue;
        }
        let request = Request {
            name: name.to_string(),
            constraints,
        };
        if sent.iter().chain(&out).any(|s| subsumes(s, &request)) {
            continue;
        }
        out.retain(|o| !subsumes(&request, o));
        out.push(request);
    }
    hull_bounds(out)
        .into_iter()
        .map(|r| scan_if_repeated(r, sent))
        .filter(|r| !sent.iter().any(|s| subsumes(s, r)))
        .collect()
}

/// `r` without its bounds when a request sent before (for an earlier stratum) differs from it
/// only in bounds: the relation is then loaded once more, unbounded, and every later variant is
/// subsumed by that load, instead of each stratum's bounds loading, sorting and merging it again.
fn scan_if_repeated(r: Request, sent: &[Request]) -> Request {
    let mine = unbounded(&r);
    if mine.len() == r.constraints.len() {
        return r;
    }
    let repeated = sent.iter().any(|s| {
        let theirs = unbounded(s);
        s.name == r.name && s.constraints.len() > theirs.len() && theirs == mine
    });
    if repeated {
        Request {
            name: r.name,
            constraints: mine,
        }
    } else {
        r
    }
}

/// A request's `(column, constraint)` pairs.
type Constraints = Vec<(usize, Constraint)>;

/// A request's constraints other than its numeric bounds, in order.
fn unbounded(r: &Request) -> Constraints {
    r.constraints
        .iter()
        .filter(|(_, c)| !is_bound(c))
        .cloned()
        .collect()
}

/// Whether a constraint is a numeric bound (`<`, `<=`, `>`, `>=`).
fn is_bound(c: &Constraint) -> bool {
    matches!(
        c,
        Constraint::Lt(_) | Constraint::Le(_) | Constraint::Gt(_) | Constraint::Ge(_)
    )
}

/// Requests that differ only in their numeric bounds become one, whose bounds on each column
/// are the loosest that keep every one of them (a column one of them leaves unbounded is left
/// unbounded): a program of a thousand rules `p_i(V, T) :- present(V, T), T > k_i.` loads
/// `present` once, where each request was loaded, sorted and merged on its own (quadratic).
/// The engine applies every rule's own bounds in its joins, so the wider answer means the same.
fn hull_bounds(requests: Vec<Request>) -> Vec<Request> {
    let mut groups: Vec<(Constraints, Vec<Request>)> = Vec::new();
    for r in requests {
        let rest = unbounded(&r);
        match groups.iter_mut().find(|(k, _)| *k == rest) {
            Some((_, g)) => g.push(r),
            None => groups.push((rest, vec![r])),
        }
    }
    groups
        .into_iter()
        .map(|(rest, mut group)| {
            if group.len() == 1 {
                return group.remove(0);
            }
            let name = group[0].name.clone();
            let columns: BTreeSet<usize> = group
                .iter()
                .flat_map(|r| r.constraints.iter())
                .filter(|(_, c)| is_bound(c))
                .map(|&(i, _)| i)
                .collect();
            let mut constraints = rest;
            for col in columns {
                // Each request's loosest bound of a side on the column; `None` when it has none.
                let side = |r: &Request, lower: bool| -> Option<(f64, bool)> {
                    r.constraints
                        .iter()
                        .filter(|(i, _)| *i == col)
                        .filter_map(|(_, c)| match (c, lower) {
                            (Constraint::Gt(v), true) | (Constraint::Lt(v), false) => {
                                Some((*v, false))
                            }
                            (Constraint::Ge(v), true) | (Constraint::Le(v), false) => {
                                Some((*v, true))
                            }
                            _ => None,
                        })
                        .reduce(|a, b| loosest(a, b, lower))
                };
                for lower in [true, false] {
                    let hull = group
                        .iter()
                        .map(|r| side(r, lower))
                        .reduce(|a, b| Some(loosest(a?, b?, lower)))
                        .flatten();
                    if let Some((v, inclusive)) = hull {
                        let c = match (lower, inclusive) {
                            (true, true) => Constraint::Ge(v),
                            (true, false) => Constraint::Gt(v),
                            (false, true) => Constraint::Le(v),
                            (false, false) => Constraint::Lt(v),
                        };
                        constraints.push((col, c));
                    }
                }
            }
            Request { name, constraints }
        })
        .collect()
}

/// Of two bounds of one side (`(value, inclusive)`), the one that lets more through: the lower
/// value for a lower bound, the higher for an upper one; inclusive at a tie.
fn loosest(a: (f64, bool), b: (f64, bool), lower: bool) -> (f64, bool) {
    let looser = if lower { b.0 < a.0 } else { b.0 > a.0 };
    if looser {
        b
    } else if a.0 == b.0 {
        (a.0, a.1 || b.1)
    } else {
        a
    }
}

/// Whether every tuple `r` asks for is asked for by `s` too (`s`'s constraints are among `r`'s).
fn subsumes(s: &Request, r: &Request) -> bool {
    s.name == r.name && s.constraints.iter().all(|c| r.constraints.contains(c))
}

/// The values variable `var` (of type `ty`) can take in use `u`, as far as the positive atoms
/// over binder relations in the same body fix them (the intersection over those atoms, sorted);
/// `None` when no such atom binds it.
fn bound_values(
    program: &CheckedProgram,
    u: &Use<'_>,
    var: &str,
    ty: ColType,
    name: &str,
    binders: &Binders<'_>,
    symbols: &mut Symbols,
) -> Option<Vec<Value>> {
    let mut acc: Option<BTreeSet<u64>> = None;
    for (b, rows, btypes) in binder_atoms(program, u, name, binders) {
        for (j, e) in b.args.iter().enumerate() {
            if e.as_var() != Some(var) || btypes.get(j) != Some(&ty) {
                continue;
            }
            let words = column_words(rows, b, btypes, j, symbols);
            acc = Some(intersect(acc, words));
        }
    }
    acc.map(|words| {
        words
            .into_iter()
            .map(|w| decode_value(w, ty, symbols))
            .collect()
    })
}

/// `words` intersected with what `acc` holds so far (all of `words` when nothing yet).
fn intersect<T: Ord + Copy>(acc: Option<BTreeSet<T>>, words: BTreeSet<T>) -> BTreeSet<T> {
    match acc {
        None => words,
        Some(a) => a.intersection(&words).copied().collect(),
    }
}

/// The positive atoms of `u`'s body (other than `u`'s atom and other uses of `name`) over binder
/// relations, with those relations' rows and column types.
fn binder_atoms<'p, 'b>(
    program: &'p CheckedProgram,
    u: &'p Use<'p>,
    name: &'p str,
    binders: &'p Binders<'b>,
) -> impl Iterator<Item = (&'p Atom, &'b Rows, &'p [ColType])> + 'p
where
    'b: 'p,
{
    u.body.iter().filter_map(move |l| {
        let Literal::Pos(b) = l else { return None };
        if std::ptr::eq(b, u.atom) || b.pred == name {
            return None;
        }
        let rows = binders(&b.pred)?;
        Some((b, rows, pred_types(program, &b.pred)))
    })
}

/// The tuple-level demand on a pair relation's use `u`: when its first three arguments are
/// variables over (track, track, time) columns and a positive atom over a binder relation in the
/// same body binds all three, the (X, Y, T) combinations such atoms allow (the intersection over
/// them, sorted, distinct); `None` when no atom binds all three.
fn bound_triples(
    program: &CheckedProgram,
    u: &Use<'_>,
    types: &[ColType],
    name: &str,
    binders: &Binders<'_>,
    symbols: &mut Symbols,
) -> Option<Vec<(TrackId, TrackId, Frame)>> {
    if types.get(..3) != Some(&[ColType::Track, ColType::Track, ColType::Time][..]) {
        return None;
    }
    let vars: Vec<&str> = u
        .atom
        .args
        .iter()
        .take(3)
        .filter_map(|e| e.as_var())
        .collect();
    if vars.len() != 3 {
        return None;
    }
    let mut acc: Option<BTreeSet<[u64; 3]>> = None;
    for (b, rows, btypes) in binder_atoms(program, u, name, binders) {
        // Where each of X, Y, T is in `b`, at a column of the same type.
        let at: Option<Vec<usize>> = vars
            .iter()
            .zip(&types[..3])
            .map(|(v, ty)| {
                b.args
                    .iter()
                    .zip(btypes)
                    .position(|(e, bt)| e.as_var() == Some(*v) && bt == ty)
            })
            .collect();
        let Some(at) = at else { continue };
        let Some(keep) = RowFilter::of(b, btypes, symbols) else {
            return Some(Vec::new());
        };
        let words: BTreeSet<[u64; 3]> = rows
            .iter()
            .filter(|r| keep.matches(r))
            .filter_map(|r| Some([*r.get(at[0])?, *r.get(at[1])?, *r.get(at[2])?]))
            .collect();
        acc = Some(intersect(acc, words));
    }
    acc.map(|words| {
        // The encodings of tracks and times are their numbers, so the order is kept.
        words
            .into_iter()
            .map(|[x, y, t]| (TrackId(x as u32), TrackId(y as u32), t as Frame))
            .collect()
    })
}

/// Which rows of a relation an atom can match on its own: its constant arguments (column,
/// encoded word) and the columns that repeat an earlier argument's variable.
struct RowFilter {
    fixed: Vec<(usize, u64)>,
    same: Vec<(usize, usize)>,
}

impl RowFilter {
    /// The filter of atom `b` over a relation with column types `types`; `None` when a constant
    /// cannot be encoded (it matches nothing).
    fn of(b: &Atom, types: &[ColType], symbols: &mut Symbols) -> Option<RowFilter> {
        let mut fixed: Vec<(usize, u64)> = Vec::new();
        for (k, (e, &ty)) in b.args.iter().zip(types).enumerate() {
            if let Some(v) = constant(&e.kind, ty) {
                fixed.push((k, encode_value(&v, ty, symbols)?));
            }
        }
        let mut same: Vec<(usize, usize)> = Vec::new();
        for (k, e) in b.args.iter().enumerate() {
            if let Some(v) = e.as_var() {
                if let Some(first) = b.args[..k].iter().position(|p| p.as_var() == Some(v)) {
                    same.push((first, k));
                }
            }
        }
        Some(RowFilter { fixed, same })
    }

    fn matches(&self, r: &[u64]) -> bool {
        self.fixed.iter().all(|&(k, w)| r.get(k) == Some(&w))
            && self.same.iter().all(|&(a, c)| r.get(a) == r.get(c))
    }
}

/// The distinct encoded values of column `j` over the rows of `b`'s relation that match `b`'s
/// constant arguments and repeated variables.
fn column_words(
    rows: &Rows,
    b: &Atom,
    types: &[ColType],
    j: usize,
    symbols: &mut Symbols,
) -> BTreeSet<u64> {
    let Some(keep) = RowFilter::of(b, types, symbols) else {
        return BTreeSet::new();
    };
    rows.iter()
        .filter(|r| keep.matches(r))
        .filter_map(|r| r.get(j).copied())
        .collect()
}

/// A literal constant as a value of a column of type `ty`, when it is one.
fn constant(e: &ExprKind, ty: ColType) -> Option<Value> {
    match (e, ty) {
        (ExprKind::Str(s), ColType::Str) => Some(Value::Str(s.as_str().into())),
        (ExprKind::Int(v), ColType::Int) => Some(Value::Int(*v)),
        (ExprKind::Int(v), ColType::Float) => Some(Value::Float(*v as f64)),
        (ExprKind::Float(v), ColType::Float) => Some(Value::Float(*v)),
        (ExprKind::Int(v), ColType::Time) => u32::try_from(*v).ok().map(Value::Time),
        (ExprKind::Quantity(q), ColType::Float) => Some(Value::Float(q.number().as_f64())),
        (ExprKind::Quantity(q), ColType::Int | ColType::Time) => match q.number() {
            Number::Int(v) if ty == ColType::Int => Some(Value::Int(v)),
            Number::Int(v) => u32::try_from(v).ok().map(Value::Time),
            Number::Float(_) => None,
        },
        _ => None,
    }
}

fn number(e: &ExprKind) -> Option<f64> {
    match e {
        ExprKind::Int(v) => Some(*v as f64),
        ExprKind::Float(v) => Some(*v),
        ExprKind::Quantity(q) => Some(q.number().as_f64()),
        _ => None,
    }
}

/// The constraints one use of a relation implies on its own: `Eq` for a column given as a
/// constant, `Category` for a column whose variable the same body also passes to a positive
/// `category(V, "…")` atom, and a bound for a numeric column whose variable the same body
/// compares with a number.
pub(crate) fn use_constraints(
    a: &Atom,
    body: &[Literal],
    types: &[ColType],
) -> Vec<(usize, Constraint)> {
    let mut out = Vec::new();
    for (i, (e, &ty)) in a.args.iter().zip(types).enumerate() {
        if let Some(c) = constant(&e.kind, ty) {
            out.push((i, Constraint::Eq(c)));
            continue;
        }
        let Some(var) = e.as_var() else { continue };
        for l in body {
            match l {
                Literal::Pos(c)
                    if c.pred == "category" && ty == ColType::Track && !std::ptr::eq(c, a) =>
                {
                    if let [x, cat] = c.args.as_slice() {
                        if let (Some(v), ExprKind::Str(s)) = (x.as_var(), &cat.kind) {
                            if v == var {
                                out.push((i, Constraint::Category(s.as_str().into())));
                            }
                        }
                    }
                }
                Literal::Cmp(c) if matches!(ty, ColType::Float | ColType::Int | ColType::Time) => {
                    let (op, n) = match (c.lhs.as_var(), c.rhs.as_var()) {
                        (Some(v), _) if v == var => match number(&c.rhs.kind) {
                            Some(n) => (c.op, n),
                            None => continue,
                        },
                        (_, Some(v)) if v == var => match number(&c.lhs.kind) {
                            Some(n) => (c.op.flipped(), n),
                            None => continue,
                        },
                        _ => continue,
                    };
                    let bound = match op {
                        CmpOp::Lt => Constraint::Lt(n),
                        CmpOp::Le => Constraint::Le(n),
                        CmpOp::Gt => Constraint::Gt(n),
                        CmpOp::Ge => Constraint::Ge(n),
                        CmpOp::Eq | CmpOp::Ne => continue,
                    };
                    out.push((i, bound));
                }
                _ => {}
            }
        }
    }
    out
}

/// Per catalog relation: the requests answered so far (pushdown on).
pub(crate) type Sent = HashMap<String, Vec<Request>>;
