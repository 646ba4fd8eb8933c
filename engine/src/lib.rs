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
mod evaluate;
mod explain;
mod ground;
mod inline;
mod limits;
mod magic;
mod plan;
mod prove;
mod rows;
mod stratum;
pub mod value;

use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::sync::{Arc, OnceLock};
use std::time::Duration;

use scenalog_facts::catalog::ColType;
use scenalog_facts::relation::Value;

pub use evaluate::evaluate;
pub use explain::{
    explain, why_not, why_not_each, why_not_pattern, AggValues, Binding, BodyFact, ClauseAttempt,
    CmpValues, Derivation, Failure, NearMiss, Outcome, Reason, Step, WhyNot, WhyNotError,
    MAX_BINDINGS, MAX_DEPTH, MAX_EXAMPLES, MAX_NESTING,
};
pub use prove::{Proof, Stamp};

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
    /// Evaluate with rows of [`value::WIDEST`] words even when the program fits rows of
    /// [`value::WIDTH`] (off by default): the same answers, a little slower; the tests run
    /// programs both ways to cover the path wide programs take.
    pub wide_rows: bool,
    /// The relations the caller will read (`None`, the default: all of them). With a list, and
    /// provenance off, a derived relation no one else can see is inlined where it is used once
    /// (`inline.rs`: it is then empty) or else derived only for the values its uses bind it to
    /// (a one-level magic-set transformation, see `magic.rs`): the relations listed are the
    /// same, a restricted one holds a subset of its tuples, and the evaluation also holds the
    /// `magic_*` relations that restricted it. The scenario commands read only
    /// `referred` and `related` (see `magic.rs` for the figures).
    pub reads: Option<Vec<String>>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            max_tuples: 20_000_000,
            timeout: None,
            provenance: false,
            pushdown: true,
            wide_rows: false,
            reads: None,
        }
    }
}

/// The result of an evaluation: every relation the program uses or defines, kept encoded and
/// decoded (sorted) on first request, so a caller pays only for the relations it reads.
#[derive(Debug, Clone, Default)]
pub struct Evaluation {
    /// The encoded relations, their column types and the symbols their strings were interned
    /// as (shared with provenance).
    encoded: Arc<Encoded>,
    /// Per relation the program uses or defines: its decoded tuples once asked for.
    decoded: BTreeMap<String, OnceLock<Vec<Vec<Value>>>>,
    /// Names of the relations the program's clauses define (not catalog inputs).
    pub derived: Vec<String>,
    /// Stamps and plans for proofs, with [`Options::provenance`].
    pub(crate) provenance: Option<Arc<dyn prove::Proofs>>,
}

/// What an evaluation computed, still encoded.
#[derive(Debug, Default)]
pub(crate) struct Encoded {
    /// Column types by relation.
    pub(crate) types: HashMap<String, Vec<ColType>>,
    /// The strings interned during the evaluation.
    pub(crate) symbols: value::Symbols,
    /// Every relation used or defined, sorted and distinct in encoded order.
    pub(crate) rels: HashMap<String, rows::Rows>,
}

impl Encoded {
    /// One stored tuple decoded, its columns of `types`.
    pub(crate) fn decode_row(&self, types: &[ColType], row: &[u64]) -> Vec<Value> {
        types
            .iter()
            .zip(row)
            .map(|(&ty, &w)| value::decode_value(w, ty, &self.symbols))
            .collect()
    }
}

impl PartialEq for Evaluation {
    fn eq(&self, other: &Self) -> bool {
        self.derived == other.derived
            && self.decoded.keys().eq(other.decoded.keys())
            && self.names().all(|n| self.tuples(n) == other.tuples(n))
    }
}

impl Evaluation {
    /// The tuples of a relation, if the program uses or defines it: sorted (strings by text,
    /// floats by total order), decoded on the first call for that relation.
    pub fn tuples(&self, name: &str) -> Option<&[Vec<Value>]> {
        let cell = self.decoded.get(name)?;
        Some(cell.get_or_init(|| evaluate::decode_relation(&self.encoded, name)))
    }

    /// The names of the relations the program uses or defines, in order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.decoded.keys().map(String::as_str)
    }

    /// The number of tuples of a relation (0 when unknown), without decoding it.
    pub fn size(&self, name: &str) -> usize {
        self.encoded.rels.get(name).map_or(0, rows::Rows::len)
    }

    /// When and by which clause a derived tuple was first derived (with provenance on).
    pub fn stamp(&self, relation: &str, tuple: &[Value]) -> Option<Stamp> {
        self.provenance.as_ref()?.stamp(relation, tuple)
    }

    /// How many tuples of a derived relation carry a stamp: all of them with provenance on, 0
    /// with it off or for a relation the program does not derive. A recursive relation's stamps
    /// are put in its tuples' order when they are first read (here, by [`Evaluation::stamp`] or
    /// by a proof), not during the evaluation.
    pub fn stamped(&self, relation: &str) -> usize {
        self.provenance.as_ref().map_or(0, |p| p.stamped(relation))
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
        explain::why_not(program, self, relation, tuple)
    }

    /// Sizes of every relation.
    pub fn sizes(&self) -> BTreeMap<String, usize> {
        self.names()
            .map(|n| (n.to_string(), self.size(n)))
            .collect()
    }
}
