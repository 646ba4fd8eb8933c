//! Why a request of the extractors cannot be answered ([`ExtractError`]): its own module, so the
//! query, the budget and the relations all take it from below.

use scenalog_facts::catalog::ColType;

/// Why a request cannot be answered.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExtractError {
    /// The catalog has no relation of this name.
    #[error("unknown relation `{0}`; expected a catalog relation (see `scenalog catalog`)")]
    UnknownRelation(String),
    /// A constraint names a column the relation does not have.
    #[error("relation `{relation}` has {arity} columns; a constraint names column {column}")]
    NoSuchColumn {
        /// The relation.
        relation: String,
        /// Its number of columns.
        arity: usize,
        /// The column index given.
        column: usize,
    },
    /// A constraint does not fit its column's type.
    #[error("relation `{relation}` column {column} is a {ty} column; constraint {constraint} does not apply to it")]
    BadConstraint {
        /// The relation.
        relation: String,
        /// The column index.
        column: usize,
        /// The column's type.
        ty: ColType,
        /// The constraint, printed.
        constraint: String,
    },
    /// The relation exists in the catalog but no extractor provides it yet.
    #[error("relation `{0}` is in the catalog but not provided by the extractors yet")]
    NotProvided(String),
    /// Computing the relation would pass the tuple budget ([`crate::Budget::max_tuples`]). The
    /// message says how to narrow the relation's use; a caller that knows where the budget is set
    /// adds "or raise" and that setting (the command adds `--max-tuples`).
    #[error("relation `{relation}` would hold more than {limit} tuples (the tuple budget); constrain its use (a category, a track, a time range, a distance bound)")]
    TooManyTuples {
        /// The relation.
        relation: String,
        /// The budget.
        limit: usize,
    },
    /// Computing the relation ran past the deadline ([`crate::Budget::deadline`]).
    #[error("computing relation `{relation}` ran past the time limit of {limit_ms} ms")]
    Timeout {
        /// The relation.
        relation: String,
        /// The time limit, in milliseconds.
        limit_ms: u128,
    },
    /// An input the relation is computed from cannot be read (e.g. a log's colour cache).
    #[error("relation `{relation}` cannot be computed: {message}")]
    BadInput {
        /// The relation.
        relation: String,
        /// What is wrong, naming the file.
        message: String,
    },
}
