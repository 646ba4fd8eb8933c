//! What an explanation reports: why a tuple is not derived ([`WhyNot`], per clause the first
//! failing literal with the bindings that reached it and its near misses) and a grounded proof
//! ([`Derivation`], each body literal with the facts and values that made it hold).

use super::*;

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
    pub(crate) fn rank(&self) -> (u8, usize) {
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
