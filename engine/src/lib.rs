//! Evaluating checked Scenalog programs: values encoded as order-preserving `u64`s in fixed-width
//! rows, rule bodies planned into joins with early filters, semi-naive iteration per stratum,
//! negation by an antijoin against completed lower strata, and aggregates grouped by the outer
//! variables.
//!
//! This crate owns evaluation only. It does not parse or check programs (`scenalog-rules`) and
//! does not extract relations from logs (`scenalog-extractors`): catalog relations come from a
//! provider closure the caller passes to [`evaluate`], asked only for relations the program uses.
#![warn(missing_docs)]

mod agg_body;
mod demand;
mod eval;
mod frog;
mod plan;
mod prove;
mod rows;
pub mod value;
mod why_not;

use std::collections::BTreeMap;
use std::fmt;
use std::time::Duration;

use scenalog_facts::relation::Value;

pub use eval::evaluate;
#[doc(hidden)]
pub use eval::evaluate_interpreted;
pub use prove::{Proof, Stamp};
pub use why_not::{
    explain, why_not, why_not_pattern, AggValues, Binding, BodyFact, ClauseAttempt, CmpValues,
    Derivation, Failure, NearMiss, Outcome, Reason, Step, WhyNot, WhyNotError, MAX_BINDINGS,
    MAX_DEPTH, MAX_EXAMPLES, MAX_NESTING,
};

/// Why an evaluation failed.
#[derive(Debug, Clone, PartialEq)]
pub enum EngineError {
    /// The program uses something the engine cannot evaluate.
    Unsupported(String),
    /// The provider could not give a relation.
    Provider {
        /// The relation asked for.
        relation: String,
        /// The provider's message.
        message: String,
    },
    /// A provided relation does not match the catalog (column count or types).
    BadInput {
        /// The relation.
        relation: String,
        /// What is wrong.
        message: String,
    },
    /// The evaluation's tuples grew past [`Options::max_tuples`] while this relation was
    /// provided or derived.
    TooManyTuples {
        /// The relation that grew.
        relation: String,
        /// The limit.
        limit: usize,
    },
    /// A `sum` of integers in a rule deriving `relation` left the 64-bit range.
    Overflow {
        /// The head relation of the rule with the `sum`.
        relation: String,
    },
    /// The evaluation ran longer than [`Options::timeout`].
    Timeout {
        /// The relation being derived when time ran out.
        relation: String,
        /// The limit.
        limit: Duration,
    },
}

impl fmt::Display for EngineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EngineError::Unsupported(m) => write!(f, "cannot evaluate: {m}"),
            EngineError::Provider { relation, message } => {
                write!(f, "relation `{relation}` could not be provided: {message}")
            }
            EngineError::BadInput { relation, message } => {
                write!(
                    f,
                    "relation `{relation}` as provided is malformed: {message}"
                )
            }
            EngineError::TooManyTuples { relation, limit } => write!(
                f,
                "the program's relations grew past the budget of {limit} tuples while `{relation}` \
                 was provided or derived; the program probably derives far more than intended"
            ),
            EngineError::Overflow { relation } => write!(
                f,
                "a `sum` in a rule for `{relation}` overflowed the 64-bit integer range \
                 (from -9223372036854775808 to 9223372036854775807); sum floats instead"
            ),
            EngineError::Timeout { relation, limit } => write!(
                f,
                "evaluation ran longer than {:.1} s while deriving `{relation}`",
                limit.as_secs_f64()
            ),
        }
    }
}

impl std::error::Error for EngineError {}

/// Limits of one evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Most tuples the evaluation may hold at once, across all its relations: the provided
    /// (catalog) inputs, every derived relation, and the output a rule is producing. One
    /// budget, so many small relations cannot add up past it unnoticed.
    pub max_tuples: usize,
    /// Longest an evaluation may run; `None` for no limit.
    pub timeout: Option<Duration>,
    /// Stamp every derived tuple so [`Evaluation::prove`] can answer (off by default).
    pub provenance: bool,
    /// Demand pushdown (on by default): ask for each catalog relation stratum by stratum, one
    /// request per distinct use, with [`scenalog_facts::relation::Constraint::OneOf`] the values
    /// a complete relation of the same body binds a track or time column to. The derived
    /// relations are the same either way; the catalog relations in the [`Evaluation`] then hold
    /// only the demanded tuples (off: every use's common constraints, asked once up front).
    pub pushdown: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            max_tuples: 20_000_000,
            timeout: None,
            provenance: false,
            pushdown: true,
        }
    }
}

/// The result of an evaluation: every relation the program uses or defines, decoded and sorted.
#[derive(Debug, Clone, Default)]
pub struct Evaluation {
    /// Tuples by relation name, each sorted (strings by text, floats by total order).
    pub relations: BTreeMap<String, Vec<Vec<Value>>>,
    /// Names of the relations the program's clauses define (not catalog inputs).
    pub derived: Vec<String>,
    /// Stamps and plans for proofs, with [`Options::provenance`].
    pub(crate) provenance: Option<std::sync::Arc<prove::Provenance>>,
}

impl PartialEq for Evaluation {
    fn eq(&self, other: &Self) -> bool {
        self.relations == other.relations && self.derived == other.derived
    }
}

impl Evaluation {
    /// The tuples of a relation, if the program uses or defines it.
    pub fn tuples(&self, name: &str) -> Option<&[Vec<Value>]> {
        self.relations.get(name).map(|v| v.as_slice())
    }

    /// The number of tuples of a relation (0 when unknown).
    pub fn size(&self, name: &str) -> usize {
        self.relations.get(name).map_or(0, |v| v.len())
    }

    /// When and by which clause a derived tuple was first derived (with provenance on).
    pub fn stamp(&self, relation: &str, tuple: &[Value]) -> Option<Stamp> {
        self.provenance.as_ref()?.stamp(relation, tuple)
    }

    /// A derivation tree of a tuple whose leaves are input facts (catalog tuples, or ground
    /// facts of the program), built by re-running the stamping clause over tuples of earlier
    /// rounds only. `None` when the tuple is not in the relation or provenance was off.
    pub fn prove(&self, relation: &str, tuple: &[Value]) -> Option<Proof> {
        self.provenance.as_ref()?.prove(relation, tuple)
    }

    /// Why `relation(tuple)` is not derived (or which clause derives it): see [`why_not()`].
    /// `program` must be the program this evaluation ran.
    pub fn why_not(
        &self,
        program: &scenalog_rules::CheckedProgram,
        relation: &str,
        tuple: &[Value],
    ) -> Result<WhyNot, WhyNotError> {
        why_not::why_not(program, self, relation, tuple)
    }

    /// Sizes of every relation.
    pub fn sizes(&self) -> BTreeMap<String, usize> {
        self.relations
            .iter()
            .map(|(k, v)| (k.clone(), v.len()))
            .collect()
    }
}
