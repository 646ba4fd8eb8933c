//! The entry points: answering a [`Request`] for any catalog relation (through the relation
//! [`table`], kept by the [`Extractor`]), all relations of a scene, and many logs in parallel.

use std::sync::Arc;

use scenalog_facts::catalog;
use scenalog_facts::relation::{Constraint, RelationData, Request};
use scenalog_facts::Scene;

use crate::budget::Budget;
use crate::cache::Extractor;
use crate::query::{ExtractError, Query};
use crate::table;

/// Computes the tuples of `query`'s relation (unfiltered, unsorted), then filters and sorts them.
fn provide(ex: &Extractor, q: &Query) -> Result<RelationData, ExtractError> {
    let data = match table::tuples(ex, q) {
        Some(data) => data?,
        None => return Err(ExtractError::NotProvided(q.spec.name.to_string())),
    };
    // A computation stopped by its budget returns what it had: an error, never that.
    if let Some(e) = q.spent.error(q.spec.name, &q.budget) {
        return Err(e);
    }
    if data.len() > q.budget.max_tuples {
        return Err(ExtractError::TooManyTuples {
            relation: q.spec.name.to_string(),
            limit: q.budget.max_tuples,
        });
    }
    Ok(q.finish(ex.scene(), data))
}

impl Extractor<'_> {
    /// The relation `req` asks for: only tuples satisfying every constraint, sorted. Answers are
    /// cached per request, except those of a tuple-level demand ([`Constraint::Triples`]: one
    /// program's bound pairs, rarely asked twice, and a long key).
    pub fn extract(&self, req: &Request) -> Result<Arc<RelationData>, ExtractError> {
        self.extract_within(req, &Budget::UNLIMITED)
    }

    /// [`Extractor::extract`] under a budget: an answer larger than `budget.max_tuples`, or not
    /// computed by its deadline, is an error naming the relation (and is not kept). The pair
    /// relations check the budget as they produce rows, so a dense log stops early instead of
    /// filling memory. A kept answer is returned whatever its size.
    pub fn extract_within(
        &self,
        req: &Request,
        budget: &Budget,
    ) -> Result<Arc<RelationData>, ExtractError> {
        let tuple_level = req
            .constraints
            .iter()
            .any(|(_, c)| matches!(c, Constraint::Triples(_)));
        if tuple_level {
            let mut query = Query::new(self.scene(), req)?;
            query.budget = *budget;
            return Ok(Arc::new(provide(self, &query)?));
        }
        let key = format!("{req:?}");
        if let Some(r) = self.answers().get(&key) {
            if r.len() > budget.max_tuples {
                return Err(ExtractError::TooManyTuples {
                    relation: req.name.clone(),
                    limit: budget.max_tuples,
                });
            }
            return Ok(r.clone());
        }
        let mut query = Query::new(self.scene(), req)?;
        query.budget = *budget;
        let data = Arc::new(provide(self, &query)?);
        self.answers().insert(key, data.clone());
        Ok(data)
    }

    /// The relation `req` asks for, computed without keeping the answer (the derived data it
    /// needs is still cached). For one-off requests, where storing a copy would only cost.
    pub fn extract_uncached(&self, req: &Request) -> Result<RelationData, ExtractError> {
        if let Some(r) = self.answers().get(&format!("{req:?}")) {
            return Ok((**r).clone());
        }
        let query = Query::new(self.scene(), req)?;
        provide(self, &query)
    }
}

/// The relation `req` asks for over `scene`: only tuples satisfying every constraint, sorted.
/// (One-off; use an [`Extractor`] to share work between requests on one scene.)
pub fn extract(scene: &Scene, req: &Request) -> Result<RelationData, ExtractError> {
    Extractor::new(scene).extract_uncached(req)
}

/// Every relation of the catalog the extractors provide, in catalog order (relations in parallel;
/// the output does not depend on the thread count).
pub fn extract_all(scene: &Scene) -> Vec<RelationData> {
    extract_all_with(&Extractor::new(scene))
}

/// [`extract_all`] with an existing context.
pub fn extract_all_with(ex: &Extractor) -> Vec<RelationData> {
    use rayon::prelude::*;
    ex.prepare();
    catalog::catalog()
        .par_iter()
        .filter_map(|spec| ex.extract_uncached(&Request::all(spec.name)).ok())
        .collect()
}

/// Answers the same requests on many logs in parallel: per scene, the answers in request order.
pub fn extract_logs(
    scenes: &[Scene],
    requests: &[Request],
) -> Vec<Result<Vec<RelationData>, ExtractError>> {
    use rayon::prelude::*;
    scenes
        .par_iter()
        .map(|scene| {
            let ex = Extractor::new(scene);
            requests.iter().map(|r| ex.extract_uncached(r)).collect()
        })
        .collect()
}
