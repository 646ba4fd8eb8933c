//! Explanations over a finished evaluation: why a tuple was *not* derived ([`why_not`]), and a
//! proof with every body literal grounded to the facts and values that made it hold
//! ([`explain`]).
//!
//! Both re-run one clause body at a time over the evaluation's final relations with a small,
//! obviously-correct interpreter of the rule AST (hash indexes built on demand per relation and
//! set of bound columns), so they do not depend on how the planner ordered the joins. Literals
//! are taken in source order, except that a literal whose variables are not bound yet (a
//! comparison written before the atom that binds its variable, say) waits until they are.
//!
//! `why_not` keeps, after each literal, every binding that survived so far; the first literal
//! that no binding survives is the one that fails, and the bindings reached just before it are
//! what the report shows, with the values that failed it (the `S` of `S < 0.5`, the tuple that
//! exists for a negation, the result of an aggregate, the closest tuples of a missing atom).

use std::cmp::Ordering;
use std::collections::{HashMap, HashSet};
use std::fmt;
use std::sync::Arc;

use scenalog_facts::catalog::ColType;
use scenalog_facts::relation::Value;
use scenalog_rules::ast::{AggFunc, Aggregate, Atom, BinOp, CmpOp, Expr, ExprKind, Func, Literal};
use scenalog_rules::{CheckedProgram, PredKind};

use crate::value::cmp_value;
use crate::{Evaluation, Stamp};

/// Most bindings kept after one literal; past it, the rest are dropped and the report says so.
pub const MAX_BINDINGS: usize = 100_000;

/// Most examples (bindings, values, near misses) a report lists for one failing literal.
pub const MAX_EXAMPLES: usize = 5;

/// Deepest derivation [`explain`] builds (proofs are well founded, so this only guards
/// against a stamp that names no usable clause).
pub const MAX_DEPTH: usize = 64;

/// How deep [`why_not`] follows a missing atom of a derived relation into that relation's own
/// clauses.
pub const MAX_NESTING: usize = 3;

/// Variable bindings: `(name, value)` for every bound named variable of the clause, in order of
/// first appearance in the clause.
pub type Binding = Vec<(String, Value)>;

/// Why [`why_not`] or [`explain`] could not even start.
#[derive(Debug, Clone, PartialEq)]
pub enum WhyNotError {
    /// The program neither defines nor uses the relation.
    UnknownRelation(String),
    /// The tuple has the wrong number of values.
    Arity {
        /// The relation.
        relation: String,
        /// Its number of columns.
        expected: usize,
        /// Values given.
        found: usize,
    },
    /// A value does not fit its column.
    Type {
        /// The relation.
        relation: String,
        /// The column (0-based).
        column: usize,
        /// The column's type.
        expected: ColType,
        /// The value given.
        found: Value,
    },
}

impl fmt::Display for WhyNotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WhyNotError::UnknownRelation(r) => {
                write!(f, "the program neither defines nor uses `{r}`")
            }
            WhyNotError::Arity {
                relation,
                expected,
                found,
            } => write!(
                f,
                "`{relation}` has {expected} columns, the tuple has {found} values"
            ),
            WhyNotError::Type {
                relation,
                column,
                expected,
                found,
            } => write!(
                f,
                "column {column} of `{relation}` is a {expected}, the tuple gives {found:?}"
            ),
        }
    }
}

impl std::error::Error for WhyNotError {}

/// The answer of [`why_not`] for one relation and tuple (or pattern).
#[derive(Debug, Clone, PartialEq)]
pub struct WhyNot {
    /// The relation asked about.
    pub relation: String,
    /// The tuple asked about; `None` columns are unknown (nested reports on atoms with
    /// unbound variables).
    pub pattern: Vec<Option<Value>>,
    /// Whether the relation holds a tuple matching the pattern (for a full tuple: whether the
    /// tuple IS derived, or provided).
    pub holds: bool,
    /// Whether the relation is a catalog (input) relation; it then has no clauses.
    pub input: bool,
    /// Number of tuples the relation holds.
    pub relation_size: usize,
    /// For an input relation without the tuple: the closest tuples it holds.
    pub closest_input: Vec<NearMiss>,
    /// One attempt per clause whose head is the relation, in program order.
    pub attempts: Vec<ClauseAttempt>,
}

impl WhyNot {
    /// The attempt that came closest: a clause that derives the tuple if any, else the one
    /// that held the most body literals before failing (heads that do not unify come last;
    /// ties go to the earlier clause).
    pub fn closest(&self) -> Option<&ClauseAttempt> {
        self.attempts.iter().max_by(|a, b| {
            a.rank()
                .cmp(&b.rank())
                .then_with(|| b.clause.cmp(&a.clause))
        })
    }
}

/// One clause's attempt at deriving the tuple.
#[derive(Debug, Clone, PartialEq)]
pub struct ClauseAttempt {
    /// Index of the clause in the program's clauses.
    pub clause: usize,
    /// What happened.
    pub outcome: Outcome,
}

impl ClauseAttempt {
    fn rank(&self) -> (u8, usize) {
        match &self.outcome {
            Outcome::Derives { .. } => (2, 0),
            Outcome::Fails(f) => (1, f.held.len()),
            Outcome::HeadMismatch { .. } => (0, 0),
        }
    }
}

/// The result of one clause's attempt.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// The head does not unify with the tuple: a constant (or a repeated variable) differs.
    HeadMismatch {
        /// The head column that differs.
        column: usize,
        /// The head's argument there, as written.
        expected: String,
        /// The tuple's value there.
        found: Value,
    },
    /// Every body literal holds: the clause derives the tuple.
    Derives {
        /// One complete binding of the clause's variables.
        binding: Binding,
        /// How many distinct complete bindings there are (at most [`MAX_BINDINGS`]).
        bindings: usize,
    },
    /// A body literal fails for every binding that reached it.
    Fails(Failure),
}

/// Which part of a clause a step is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// The body literal with this index (source order).
    Body(usize),
    /// The head argument with this index: an expression (like `T + 1`) checked against the
    /// tuple once its variables are bound.
    Head(usize),
}

/// The first literal of a clause that fails, and what was known just before it.
#[derive(Debug, Clone, PartialEq)]
pub struct Failure {
    /// The failing literal.
    pub step: Step,
    /// The literal as written (printed from the AST).
    pub text: String,
    /// The steps that held before it, in the order they were evaluated.
    pub held: Vec<Step>,
    /// Up to [`MAX_EXAMPLES`] of the bindings reached just before the failing literal.
    pub bindings: Vec<Binding>,
    /// How many distinct bindings reached it.
    pub binding_count: usize,
    /// Whether bindings were dropped at [`MAX_BINDINGS`] on the way (the failure is then only
    /// known for the bindings kept).
    pub truncated: bool,
    /// Why it fails, with the values that failed it.
    pub reason: Reason,
}

/// Why a literal fails.
#[derive(Debug, Clone, PartialEq)]
pub enum Reason {
    /// A positive atom matches no tuple.
    Missing {
        /// The atom's relation.
        relation: String,
        /// The number of tuples the relation holds.
        relation_size: usize,
        /// The values the atom looked for (per column, `None` where it binds or ignores), for
        /// the first bindings.
        wanted: Vec<Vec<Option<Value>>>,
        /// The relation's tuples agreeing with a wanted pattern on the most columns (then
        /// nearest on the numeric ones).
        closest: Vec<NearMiss>,
        /// For a derived relation: why the first wanted pattern is not derived, in turn.
        nested: Option<Box<WhyNot>>,
    },
    /// A comparison is false (or cannot be computed) for every binding.
    Comparison {
        /// The operator.
        op: CmpOp,
        /// The values of both sides, closest to holding first.
        values: Vec<CmpValues>,
    },
    /// A negated atom's tuple exists.
    Present {
        /// The negated relation.
        relation: String,
        /// Tuples that exist, with the binding that asked for each.
        found: Vec<(Binding, Vec<Value>)>,
    },
    /// An aggregate gave no value (`min`/`max` of an empty group) or not the required one.
    Aggregate {
        /// The aggregate function.
        func: AggFunc,
        /// Per binding: the result and the group size.
        values: Vec<AggValues>,
    },
    /// A head expression evaluates to a value other than the tuple's.
    HeadValue {
        /// The head column.
        column: usize,
        /// The tuple's value there.
        wanted: Value,
        /// Values the expression took, with their bindings (`None`: it could not be computed).
        values: Vec<(Binding, Option<Value>)>,
    },
    /// The literal could not be evaluated (a variable bound nowhere before it).
    Unevaluable(String),
}

/// A tuple that agrees with a wanted pattern on some columns but not all.
#[derive(Debug, Clone, PartialEq)]
pub struct NearMiss {
    /// The tuple.
    pub tuple: Vec<Value>,
    /// Columns where it differs from the wanted value.
    pub differs: Vec<usize>,
}

/// Both sides of a failing comparison for one binding.
#[derive(Debug, Clone, PartialEq)]
pub struct CmpValues {
    /// The binding.
    pub binding: Binding,
    /// The left side's value (`None`: it could not be computed).
    pub lhs: Option<Value>,
    /// The right side's value.
    pub rhs: Option<Value>,
}

/// An aggregate's value for one binding.
#[derive(Debug, Clone, PartialEq)]
pub struct AggValues {
    /// The binding (group variables included).
    pub binding: Binding,
    /// The result (`None` for `min`/`max` of an empty group).
    pub result: Option<Value>,
    /// The value the result had to equal, when the result was not a fresh variable.
    pub required: Option<Value>,
    /// Distinct bindings of the aggregate's body in the group.
    pub group_size: usize,
}

/// A derived (or input) tuple with the clause that derived it and every body literal grounded.
#[derive(Debug, Clone, PartialEq)]
pub struct Derivation {
    /// The relation.
    pub relation: String,
    /// The tuple.
    pub tuple: Vec<Value>,
    /// The clause (a ground fact has an empty body); `None` for a catalog (input) tuple.
    pub clause: Option<usize>,
    /// The clause's variables as bound.
    pub binding: Binding,
    /// One entry per body literal, in source order.
    pub body: Vec<BodyFact>,
}

/// One body literal of a derivation, grounded.
#[derive(Debug, Clone, PartialEq)]
pub enum BodyFact {
    /// A positive atom and the tuple it matched.
    Atom {
        /// Body literal index.
        literal: usize,
        /// The relation.
        relation: String,
        /// The matched tuple.
        tuple: Vec<Value>,
        /// How that tuple was derived (`None` for catalog tuples).
        derivation: Option<Box<Derivation>>,
    },
    /// A negated atom with no matching tuple.
    Absent {
        /// Body literal index.
        literal: usize,
        /// The relation.
        relation: String,
        /// The values looked for (`None` for `_`).
        pattern: Vec<Option<Value>>,
    },
    /// A comparison that held, or a binding `X = expr`.
    Comparison {
        /// Body literal index.
        literal: usize,
        /// Left value.
        lhs: Value,
        /// The operator.
        op: CmpOp,
        /// Right value.
        rhs: Value,
        /// The variable it bound, for a binding.
        binds: Option<String>,
    },
    /// An aggregate and its value.
    Aggregate {
        /// Body literal index.
        literal: usize,
        /// The function.
        func: AggFunc,
        /// Its result.
        result: Value,
        /// Distinct bindings of its body in the group.
        group_size: usize,
    },
}

impl BodyFact {
    /// The body literal index.
    pub fn literal(&self) -> usize {
        match self {
            BodyFact::Atom { literal, .. }
            | BodyFact::Absent { literal, .. }
            | BodyFact::Comparison { literal, .. }
            | BodyFact::Aggregate { literal, .. } => *literal,
        }
    }
}

/// Says why `relation(tuple)` is not derived: for every clause whose head could derive it, the
/// first body literal that fails, the bindings reached before it and the values that failed it;
/// or that a clause does derive it. Works on the final relations of `evaluation`, which must be
/// the evaluation of `program` (provenance is not needed).
pub fn why_not(
    program: &CheckedProgram,
    evaluation: &Evaluation,
    relation: &str,
    tuple: &[Value],
) -> Result<WhyNot, WhyNotError> {
    let pattern: Vec<Option<Value>> = tuple.iter().cloned().map(Some).collect();
    why_not_pattern(program, evaluation, relation, &pattern)
}

/// [`why_not`] for a pattern: `None` columns may take any value.
pub fn why_not_pattern(
    program: &CheckedProgram,
    evaluation: &Evaluation,
    relation: &str,
    pattern: &[Option<Value>],
) -> Result<WhyNot, WhyNotError> {
    let mut cx = Cx::new(program, evaluation);
    let pattern = cx.check_pattern(relation, pattern)?;
    Ok(cx.why_not(relation, &pattern, 0, &mut HashSet::new()))
}

/// The proof of a derived tuple with every body literal grounded: the matched tuples, the
/// compared values, the absent negated tuples, the aggregate results. Like
/// [`Evaluation::prove`], each tuple is derived by the clause of its stamp from tuples of lower
/// strata or earlier rounds, so the tree is finite; leaves are catalog tuples and ground facts.
/// `None` when the tuple is not in the relation or the evaluation ran without provenance.
pub fn explain(
    program: &CheckedProgram,
    evaluation: &Evaluation,
    relation: &str,
    tuple: &[Value],
) -> Result<Option<Derivation>, WhyNotError> {
    let mut cx = Cx::new(program, evaluation);
    let pattern: Vec<Option<Value>> = tuple.iter().cloned().map(Some).collect();
    cx.check_pattern(relation, &pattern)?;
    let derived = program
        .predicates
        .get(relation)
        .is_some_and(|p| p.kind == PredKind::Derived);
    let present = !cx.lookup(relation, &pattern).is_empty();
    if !present || (derived && evaluation.stamp(relation, tuple).is_none()) {
        return Ok(None);
    }
    Ok(cx.derivation(relation, tuple, 0))
}

// ---------------------------------------------------------------------------------------------
// The interpreter.

/// A hashable form of a value (floats by their bits, -0.0 as 0.0).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
enum Key {
    Track(u32),
    Time(u32),
    Lane(i64),
    Str(Arc<str>),
    Float(u64),
    Int(i64),
}

fn key(v: &Value) -> Key {
    match v {
        Value::Track(t) => Key::Track(t.0),
        Value::Time(t) => Key::Time(*t),
        Value::Lane(l) => Key::Lane(l.0),
        Value::Str(s) => Key::Str(s.clone()),
        Value::Float(f) => Key::Float(if *f == 0.0 { 0.0f64 } else { *f }.to_bits()),
        Value::Int(i) => Key::Int(*i),
    }
}

/// Equality of stored values (floats by value, so -0.0 equals 0.0).
fn same(a: &Value, b: &Value) -> bool {
    a == b
}

/// A hash of some column values, for the on-demand indexes (collisions are checked).
fn fingerprint(vs: &[&Value]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for v in vs {
        match v {
            Value::Track(t) => (0u8, t.0).hash(&mut h),
            Value::Time(t) => (1u8, *t).hash(&mut h),
            Value::Lane(l) => (2u8, l.0).hash(&mut h),
            Value::Str(s) => (3u8, s.as_ref()).hash(&mut h),
            Value::Float(x) => (4u8, if *x == 0.0 { 0.0f64 } else { *x }.to_bits()).hash(&mut h),
            Value::Int(i) => (5u8, *i).hash(&mut h),
        }
    }
    h.finish()
}

/// A value as a value of a column of type `ty` (as the engine encodes it), if it fits.
fn coerce(v: &Value, ty: ColType) -> Option<Value> {
    let whole = |f: f64| f.is_finite() && f.fract() == 0.0;
    Some(match (ty, v) {
        (ColType::Track, Value::Track(_))
        | (ColType::Lane, Value::Lane(_))
        | (ColType::Str, Value::Str(_)) => v.clone(),
        (ColType::Time, Value::Time(t)) => Value::Time(*t),
        (ColType::Time, Value::Int(i)) => Value::Time(u32::try_from(*i).ok()?),
        (ColType::Time, Value::Float(f)) if whole(*f) => {
            Value::Time(u32::try_from(*f as i64).ok()?)
        }
        (ColType::Int, Value::Int(i)) => Value::Int(*i),
        (ColType::Int, Value::Time(t)) => Value::Int(i64::from(*t)),
        (ColType::Int, Value::Float(f)) if whole(*f) => Value::Int(*f as i64),
        (ColType::Float, Value::Float(f)) if !f.is_nan() => {
            Value::Float(if *f == 0.0 { 0.0 } else { *f })
        }
        (ColType::Float, Value::Int(i)) => Value::Float(*i as f64),
        (ColType::Float, Value::Time(t)) => Value::Float(f64::from(*t)),
        _ => return None,
    })
}

#[derive(Clone, Copy)]
enum Num {
    I(i64),
    F(f64),
}

fn num(v: &Value) -> Option<Num> {
    match v {
        Value::Int(i) => Some(Num::I(*i)),
        Value::Time(t) => Some(Num::I(i64::from(*t))),
        Value::Float(f) => Some(Num::F(*f)),
        _ => None,
    }
}

fn f(n: Num) -> f64 {
    match n {
        Num::I(i) => i as f64,
        Num::F(x) => x,
    }
}

fn from_num(n: Num) -> Value {
    match n {
        Num::I(i) => Value::Int(i),
        Num::F(x) => Value::Float(x),
    }
}

/// Compares as the engine does: numbers numerically (int with int exactly), other values of the
/// same kind by identity (strings by text).
fn compare(a: &Value, b: &Value) -> Option<Ordering> {
    match (num(a), num(b)) {
        (Some(Num::I(x)), Some(Num::I(y))) => Some(x.cmp(&y)),
        (Some(x), Some(y)) => f(x).partial_cmp(&f(y)),
        (None, None) => match (a, b) {
            (Value::Track(x), Value::Track(y)) => Some(x.cmp(y)),
            (Value::Lane(x), Value::Lane(y)) => Some(x.cmp(y)),
            (Value::Str(x), Value::Str(y)) => Some(x.cmp(y)),
            _ => None,
        },
        _ => None,
    }
}

fn cmp_holds(op: CmpOp, a: &Value, b: &Value) -> bool {
    let Some(o) = compare(a, b) else {
        return false;
    };
    match op {
        CmpOp::Lt => o.is_lt(),
        CmpOp::Le => o.is_le(),
        CmpOp::Gt => o.is_gt(),
        CmpOp::Ge => o.is_ge(),
        CmpOp::Eq => o.is_eq(),
        CmpOp::Ne => o.is_ne(),
    }
}

/// How far a comparison is from holding (0 when it holds; infinite when not numeric).
fn gap(op: CmpOp, a: Option<&Value>, b: Option<&Value>) -> f64 {
    let (Some(a), Some(b)) = (a, b) else {
        return f64::INFINITY;
    };
    if cmp_holds(op, a, b) {
        return 0.0;
    }
    match (num(a), num(b)) {
        (Some(x), Some(y)) => (f(x) - f(y)).abs(),
        _ => f64::INFINITY,
    }
}

fn arith(op: BinOp, a: Num, b: Num) -> Option<Num> {
    match (a, b) {
        (Num::I(x), Num::I(y)) => crate::value::int_op(op, x, y).map(Num::I),
        (a, b) => crate::value::float_op(op, f(a), f(b)).map(Num::F),
    }
}

/// The named variables of a clause, each with a slot.
#[derive(Clone)]
struct Vars {
    names: Vec<String>,
    slots: HashMap<String, usize>,
}

impl Vars {
    fn of(head: &Atom, body: &[Literal]) -> Vars {
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

    fn add_expr(&mut self, e: &Expr) {
        let mut vs = Vec::new();
        expr_vars(e, &mut vs);
        for name in vs {
            if !self.slots.contains_key(name) {
                self.slots.insert(name.to_string(), self.names.len());
                self.names.push(name.to_string());
            }
        }
    }

    fn add_lit(&mut self, l: &Literal) {
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

    fn slot(&self, name: &str) -> Option<usize> {
        self.slots.get(name).copied()
    }
}

fn expr_vars<'e>(e: &'e Expr, out: &mut Vec<&'e str>) {
    match &e.kind {
        ExprKind::Var(v) => out.push(v),
        ExprKind::Neg(a) => expr_vars(a, out),
        ExprKind::Binary(_, a, b) => {
            expr_vars(a, out);
            expr_vars(b, out);
        }
        ExprKind::Call(_, args) => args.iter().for_each(|a| expr_vars(a, out)),
        _ => {}
    }
}

/// Variables of a literal outside aggregate bodies (an aggregate contributes its result).
fn lit_outer_vars<'e>(l: &'e Literal, out: &mut Vec<&'e str>) {
    match l {
        Literal::Pos(a) | Literal::Neg(a, _) => a.args.iter().for_each(|e| expr_vars(e, out)),
        Literal::Cmp(c) => {
            expr_vars(&c.lhs, out);
            expr_vars(&c.rhs, out);
        }
        Literal::Agg(g) => expr_vars(&g.result, out),
    }
}

/// Every variable of an aggregate's body and target.
fn agg_vars(g: &Aggregate) -> Vec<&str> {
    fn lit<'e>(l: &'e Literal, vs: &mut Vec<&'e str>) {
        match l {
            Literal::Agg(g) => {
                expr_vars(&g.result, vs);
                if let Some(t) = &g.target {
                    expr_vars(t, vs);
                }
                g.body.iter().for_each(|l| lit(l, vs));
            }
            other => lit_outer_vars(other, vs),
        }
    }
    let mut vs = Vec::new();
    g.body.iter().for_each(|l| lit(l, &mut vs));
    if let Some(t) = &g.target {
        expr_vars(t, &mut vs);
    }
    let mut seen = HashSet::new();
    vs.retain(|v| seen.insert(*v));
    vs
}

type Row = Vec<Option<Value>>;

/// A grounded literal, as found while matching (kept light).
#[derive(Clone)]
enum Ground {
    Atom(usize),
    Absent(Vec<Option<Value>>),
    Cmp(Value, Value, Option<usize>),
    Agg(Value, usize),
    Head,
}

/// One evaluation step of a body: a literal or a head check.
#[derive(Clone, Copy)]
enum Item<'p> {
    Lit(usize, &'p Literal),
    Head(usize, &'p Expr, ColType),
}

impl Item<'_> {
    fn step(&self) -> Step {
        match self {
            Item::Lit(i, _) => Step::Body(*i),
            Item::Head(i, _, _) => Step::Head(*i),
        }
    }
}

/// Per-relation hash indexes by the set of bound columns.
type Index = HashMap<u64, Vec<u32>>;

struct Cx<'a> {
    program: &'a CheckedProgram,
    eval: &'a Evaluation,
    indexes: HashMap<(String, Vec<usize>), Index>,
}

/// The outcome of running a body: every complete binding, or the failure.
enum Run<'p> {
    Done(Vec<Row>),
    Failed {
        at: Item<'p>,
        held: Vec<Step>,
        before: Vec<Row>,
        truncated: bool,
    },
}

impl<'a> Cx<'a> {
    fn new(program: &'a CheckedProgram, eval: &'a Evaluation) -> Cx<'a> {
        Cx {
            program,
            eval,
            indexes: HashMap::new(),
        }
    }

    fn types(&self, rel: &str) -> &'a [ColType] {
        self.program
            .predicates
            .get(rel)
            .map_or(&[], |p| p.types.as_slice())
    }

    fn tuples(&self, rel: &str) -> &'a [Vec<Value>] {
        self.eval.tuples(rel).unwrap_or_default()
    }

    fn check_pattern(
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
    fn lookup(&mut self, rel: &str, pat: &[Option<Value>]) -> Vec<u32> {
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

    fn eval_expr(&self, vars: &Vars, e: &Expr, b: &Row) -> Option<Value> {
        match &e.kind {
            ExprKind::Var(v) => b.get(vars.slot(v)?)?.clone(),
            ExprKind::Wildcard => None,
            ExprKind::Str(s) => Some(Value::Str(Arc::from(s.as_str()))),
            ExprKind::Int(i) => Some(Value::Int(*i)),
            ExprKind::Float(x) => Some(Value::Float(*x)),
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

    fn bound(vars: &Vars, e: &Expr, b: &Row) -> bool {
        let mut vs = Vec::new();
        expr_vars(e, &mut vs);
        vs.iter().all(|v| {
            vars.slot(v)
                .is_some_and(|s| b.get(s).is_some_and(|x| x.is_some()))
        })
    }

    /// What an atom asks of each column under a binding: `Some(value)` where it is determined.
    /// `None` overall when a determined value cannot be in the column.
    fn atom_pattern(&self, vars: &Vars, a: &Atom, b: &Row) -> Option<Vec<Option<Value>>> {
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
    fn match_atom(&mut self, vars: &Vars, a: &Atom, b: &Row) -> Vec<(Row, usize)> {
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
    fn apply(
        &mut self,
        vars: &Vars,
        item: Item<'_>,
        b: &Row,
        pat: &[Option<Value>],
    ) -> Vec<(Row, Ground)> {
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
    fn aggregate(&mut self, vars: &Vars, g: &Aggregate, b: &Row) -> (Option<Value>, usize) {
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
    fn run<'p>(
        &mut self,
        vars: &Vars,
        order: &[Item<'p>],
        start: Vec<Row>,
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
    fn ground(
        &mut self,
        vars: &Vars,
        order: &[Item<'_>],
        b: Row,
        pat: &[Option<Value>],
        limit: Option<Stamp>,
        trail: &mut Vec<(Step, Ground)>,
    ) -> Option<Row> {
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
    fn unify_head<'p>(
        &self,
        vars: &Vars,
        head: &'p Atom,
        pat: &[Option<Value>],
    ) -> Result<(Row, Vec<Item<'p>>), Box<Outcome>> {
        let types = self.types(&head.pred);
        let mut b: Row = vec![None; vars.names.len()];
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

    fn binding(&self, vars: &Vars, b: &Row) -> Binding {
        vars.names
            .iter()
            .zip(b)
            .filter_map(|(n, v)| v.clone().map(|v| (n.clone(), v)))
            .collect()
    }

    fn why_not(
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

    fn attempt(
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
    fn reason(
        &mut self,
        vars: &Vars,
        at: Item<'_>,
        before: &[Row],
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
    fn near_misses(&self, rel: &str, patterns: &[Vec<Option<Value>>]) -> Vec<NearMiss> {
        // Score: columns that agree (more first; on a tie, agreeing on earlier columns first,
        // as the subject of a relation comes first), then distance on the numeric ones.
        type Score = (usize, u64, f64);
        let better =
            |a: &Score, b: &Score| b.0.cmp(&a.0).then(b.1.cmp(&a.1)).then(a.2.total_cmp(&b.2));
        let mut scored: Vec<(Score, NearMiss)> = Vec::new();
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
                scored.push((
                    score,
                    NearMiss {
                        tuple: t.clone(),
                        differs,
                    },
                ));
            }
        }
        scored.sort_by(|a, b| better(&a.0, &b.0).then_with(|| cmp_tuple(&a.1.tuple, &b.1.tuple)));
        scored.truncate(MAX_EXAMPLES);
        scored.into_iter().map(|(_, m)| m).collect()
    }

    /// The grounded derivation of a tuple: the clause its stamp names, grounded over tuples of
    /// lower strata and of earlier rounds of its own stratum; catalog tuples are leaves.
    fn derivation(&mut self, rel: &str, tuple: &[Value], depth: usize) -> Option<Derivation> {
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

/// A variable a comparison or negation needs (for a binding `X = e`, of `e`) that the first
/// binding leaves unbound.
fn unbound_var(vars: &Vars, l: &Literal, before: &[Row]) -> Option<String> {
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

fn cmp_tuple(a: &[Value], b: &[Value]) -> Ordering {
    a.iter()
        .zip(b)
        .map(|(x, y)| cmp_value(x, y))
        .find(|o| o.is_ne())
        .unwrap_or_else(|| a.len().cmp(&b.len()))
}

/// The evaluation order of a body: source order, each literal as soon as it can be evaluated
/// (its expressions' variables bound; for an aggregate, its group variables), head checks as
/// soon as their variables are bound.
fn order_items<'p>(
    vars: &Vars,
    body: &'p [Literal],
    checks: &[Item<'p>],
    start: &Row,
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
            lit_outer_vars(l, &mut vs);
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
