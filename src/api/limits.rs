//! The limits every request that evaluates programs or extracts relations carries: one tuple
//! budget and one time limit (the defaults of [`crate::pipeline::limits`]: a budget sized to the
//! machine's memory and the pairs run at once, 120 s), so no front end can hang on a runaway
//! program or fill the memory, and every front end has the same defaults.

use crate::api::error::{invalid, Error, Field};
use crate::pipeline::limits::pair_limits;

/// One pair's (or one evaluation's, one extraction's) limits: its tuple budget and its time
/// limit; `None` for the defaults of [`crate::pipeline::limits`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Limits {
    /// Most tuples one (log, program) pair may hold, across all its relations (at least 1).
    pub max_tuples: Option<u64>,
    /// Longest one pair may take to extract and evaluate, in milliseconds (at least 1).
    pub timeout_ms: Option<u64>,
}

impl Limits {
    /// The limits checked: each at least 1.
    pub fn check(&self) -> Result<(), Error> {
        for (value, field) in [
            (self.max_tuples, Field::MaxTuples),
            (self.timeout_ms, Field::TimeoutMs),
        ] {
            if value == Some(0) {
                return Err(invalid(field, "expected at least 1, got 0"));
            }
        }
        Ok(())
    }

    /// The engine's options for one pair when `threads` pairs run at once: the tuple budget
    /// (default sized to the machine's memory shared by the threads) and the time limit
    /// (default [`crate::pipeline::limits::DEFAULT_TIMEOUT`]).
    pub fn engine(&self, threads: usize) -> scenalog_engine::Options {
        pair_limits(self.max_tuples, self.timeout_ms, threads)
    }

    /// [`Limits::engine`] for a run on `threads` worker threads (`None`: one per core).
    pub fn for_run(&self, threads: Option<usize>) -> scenalog_engine::Options {
        self.engine(threads.unwrap_or_else(rayon::current_num_threads))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::limits::{default_max_tuples, machine_memory, DEFAULT_TIMEOUT};

    /// Without values, every request has `mine`'s defaults (a program deriving forever stops);
    /// values given are kept.
    #[test]
    fn the_defaults_are_mines_and_values_given_are_kept() {
        let defaults = Limits::default().engine(1);
        assert_eq!(defaults.timeout, Some(DEFAULT_TIMEOUT));
        assert_eq!(defaults.max_tuples, default_max_tuples(machine_memory(), 1));
        let given = Limits {
            max_tuples: Some(7),
            timeout_ms: Some(9),
        };
        let options = given.engine(1);
        assert_eq!(options.max_tuples, 7);
        assert_eq!(options.timeout, Some(std::time::Duration::from_millis(9)));
        assert!(given.check().is_ok());
        let zero = Limits {
            max_tuples: Some(0),
            timeout_ms: None,
        };
        assert_eq!(
            zero.check().map_err(|e| e.flags()),
            Err("--max-tuples: expected at least 1, got 0".to_string())
        );
    }
}
