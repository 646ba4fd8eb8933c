//! What a rule evaluation checks as it produces tuples ([`Limits`]): the tuple budget and the
//! time limit of [`crate::Options`], in a module below everything that evaluates.

use std::time::Instant;

use crate::{EngineError, Options};

/// What a rule evaluation checks as it produces tuples: [`Options::max_tuples`] counts the
/// tuples every relation of the evaluation holds (`held`, inputs included) plus those produced,
/// and [`Options::timeout`] the time since `start`.
pub(crate) struct Limits<'a> {
    pub(crate) relation: &'a str,
    pub(crate) options: &'a Options,
    pub(crate) start: Instant,
    pub(crate) held: usize,
}

impl Limits<'_> {
    /// The error for a `sum` that overflowed in a rule deriving this relation.
    pub(crate) fn sum_overflow(&self) -> EngineError {
        EngineError::Overflow {
            relation: self.relation.to_string(),
        }
    }

    pub(crate) fn check(&self, produced: usize) -> Result<(), EngineError> {
        if self.held.saturating_add(produced) > self.options.max_tuples {
            return Err(EngineError::TooManyTuples {
                relation: self.relation.to_string(),
                limit: self.options.max_tuples,
            });
        }
        if let Some(limit) = self.options.timeout {
            if self.start.elapsed() > limit {
                return Err(EngineError::Timeout {
                    relation: self.relation.to_string(),
                    limit,
                });
            }
        }
        Ok(())
    }
}
