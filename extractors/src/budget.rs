//! [`Budget`]: how many tuples one extracted relation may hold and until when it may be computed,
//! so a dense log or a slow request fails its pair cleanly (naming the relation) instead of
//! exhausting memory or running without end. The pair relations check it as they go: every X
//! track's rows are counted as they are produced, and the clock is read every few hundred rows.

use std::sync::atomic::{AtomicU8, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use crate::error::ExtractError;

/// The limits one request is computed under.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Budget {
    /// Most tuples the relation may hold (before the request's final filter).
    pub max_tuples: usize,
    /// When the computation must stop, and the time limit it came from (for the message).
    pub deadline: Option<(Instant, Duration)>,
}

impl Budget {
    /// No limit at all.
    pub const UNLIMITED: Budget = Budget {
        max_tuples: usize::MAX,
        deadline: None,
    };

    /// A budget of `max_tuples`, ending `timeout` after `start` when there is a timeout.
    pub fn new(max_tuples: usize, start: Instant, timeout: Option<Duration>) -> Budget {
        Budget {
            max_tuples,
            deadline: timeout.map(|t| (start + t, t)),
        }
    }

    /// Whether the deadline has passed.
    pub fn expired(&self) -> bool {
        self.deadline.is_some_and(|(d, _)| Instant::now() >= d)
    }
}

impl Default for Budget {
    fn default() -> Self {
        Budget::UNLIMITED
    }
}

/// What a computation under a [`Budget`] has used: rows produced so far (over all threads) and
/// whether a limit was passed. Shared by the threads of one request.
#[derive(Debug, Default)]
pub(crate) struct Spent {
    rows: AtomicUsize,
    /// 0: within the budget; 1: too many tuples; 2: out of time.
    over: AtomicU8,
}

const TOO_MANY: u8 = 1;
const OUT_OF_TIME: u8 = 2;

impl Spent {
    /// Whether a limit has been passed (the computation should stop).
    pub(crate) fn over(&self) -> bool {
        self.over.load(Ordering::Relaxed) != 0
    }

    /// Checks the clock; marks the computation over when the deadline has passed.
    pub(crate) fn tick(&self, budget: &Budget) -> bool {
        if budget.expired() {
            self.over.store(OUT_OF_TIME, Ordering::Relaxed);
        }
        self.over()
    }

    /// Adds `n` produced rows; marks the computation over when they pass the budget. `pending`
    /// rows of the caller not yet added count too.
    pub(crate) fn add(&self, budget: &Budget, n: usize) -> bool {
        let total = self.rows.fetch_add(n, Ordering::Relaxed).saturating_add(n);
        if total > budget.max_tuples {
            self.over.store(TOO_MANY, Ordering::Relaxed);
        }
        self.over()
    }

    /// Whether `pending` more rows would pass the budget (without adding them).
    pub(crate) fn would_pass(&self, budget: &Budget, pending: usize) -> bool {
        self.rows.load(Ordering::Relaxed).saturating_add(pending) > budget.max_tuples
    }

    /// The error for a computation that passed its budget, if it did.
    pub(crate) fn error(&self, relation: &str, budget: &Budget) -> Option<ExtractError> {
        match self.over.load(Ordering::Relaxed) {
            TOO_MANY => Some(ExtractError::TooManyTuples {
                relation: relation.to_string(),
                limit: budget.max_tuples,
            }),
            OUT_OF_TIME => Some(ExtractError::Timeout {
                relation: relation.to_string(),
                limit_ms: budget.deadline.map_or(0, |(_, t)| t.as_millis()),
            }),
            _ => None,
        }
    }
}
