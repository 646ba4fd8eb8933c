//! The entry points: answering a [`Request`] for any catalog relation (through the relation
//! [`table`], kept by the [`Extractor`]), all relations of a scene, and many logs in parallel.

use std::sync::Arc;

use scenalog_facts::catalog;
use scenalog_facts::relation::{Constraint, RelationData, Request, Value};
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
    /// program's bound pairs, rarely asked twice, and a long key); a request adding constraints
    /// to a kept one is answered by filtering it.
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
        let kept = self.answers().get(&key).map(|(_, r)| r.clone());
        let data = match kept {
            Some(r) => r,
            None => {
                let mut query = Query::new(self.scene(), req)?;
                query.budget = *budget;
                // A kept answer under fewer of these constraints holds every tuple this one
                // does: filtered, it answers without extracting again (two programs on one log
                // often ask the same relation, one of them narrowed by what it demands).
                let data = match self.broader_answer(req) {
                    Some(broader) => query.finish(self.scene(), (*broader).clone()),
                    None => provide(self, &query)?,
                };
                let data = Arc::new(data);
                self.answers().insert(key, (req.clone(), data.clone()));
                data
            }
        };
        if data.len() > budget.max_tuples {
            return Err(ExtractError::TooManyTuples {
                relation: req.name.clone(),
                limit: budget.max_tuples,
            });
        }
        Ok(data)
    }

    /// The smallest kept answer for `req`'s relation whose every constraint `req`'s imply.
    fn broader_answer(&self, req: &Request) -> Option<Arc<RelationData>> {
        self.answers()
            .values()
            .filter(|(r, _)| {
                r.name == req.name
                    && r.constraints.iter().all(|(col, kept)| {
                        req.constraints
                            .iter()
                            .any(|(c, asked)| c == col && implies(asked, kept))
                    })
            })
            .map(|(_, data)| data.clone())
            .min_by_key(|data| data.len())
    }

    /// The relation `req` asks for, computed without keeping the answer (the derived data it
    /// needs is still cached). For one-off requests, where storing a copy would only cost.
    pub fn extract_uncached(&self, req: &Request) -> Result<RelationData, ExtractError> {
        if let Some((_, r)) = self.answers().get(&format!("{req:?}")) {
            return Ok((**r).clone());
        }
        let query = Query::new(self.scene(), req)?;
        provide(self, &query)
    }
}

/// Whether every value satisfying `asked` satisfies `kept` (on the same column): the same
/// constraint, a tighter bound, a value or set of values among `kept`'s. Anything else: no.
fn implies(asked: &Constraint, kept: &Constraint) -> bool {
    use Constraint::{Eq, Ge, Gt, Le, Lt, OneOf};
    match (asked, kept) {
        (a, k) if a == k => true,
        (Lt(a), Lt(k) | Le(k)) | (Le(a), Le(k)) => a <= k,
        (Le(a), Lt(k)) => a < k,
        (Gt(a), Gt(k) | Ge(k)) | (Ge(a), Ge(k)) => a >= k,
        (Ge(a), Gt(k)) => a > k,
        (Eq(v), OneOf(k)) => within(std::slice::from_ref(v), k),
        (OneOf(a), OneOf(k)) => within(a, k),
        _ => false,
    }
}

/// Whether every value of `a` is in `k` (tracks, times and integers by number; other values
/// only when the two lists are equal).
fn within(a: &[Value], k: &[Value]) -> bool {
    fn key(v: &Value) -> Option<(u8, i64)> {
        match v {
            Value::Track(t) => Some((0, i64::from(t.0))),
            Value::Time(f) => Some((1, i64::from(*f))),
            Value::Int(i) => Some((2, *i)),
            _ => None,
        }
    }
    // Distinct values: more than `k` holds cannot all be in it (and `false` only extracts again).
    if a.len() > k.len() {
        return false;
    }
    let kept: Option<std::collections::HashSet<(u8, i64)>> = k.iter().map(key).collect();
    match kept {
        Some(kept) => a.iter().all(|v| key(v).is_some_and(|x| kept.contains(&x))),
        None => a == k,
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

#[cfg(test)]
mod tests {
    use super::*;
    use scenalog_facts::TrackId;

    fn tracks(ids: &[u32]) -> Constraint {
        Constraint::OneOf(ids.iter().map(|&i| Value::Track(TrackId(i))).collect())
    }

    #[test]
    fn a_tighter_constraint_implies_a_looser_one_and_nothing_else_does() {
        use Constraint::{Eq, Ge, Gt, Le, Lt};
        assert!(implies(&Lt(0.3), &Lt(0.5)));
        assert!(implies(&Lt(0.5), &Le(0.5)));
        assert!(!implies(&Le(0.5), &Lt(0.5)));
        assert!(!implies(&Lt(0.6), &Lt(0.5)));
        assert!(implies(&Gt(2.0), &Ge(2.0)));
        assert!(!implies(&Ge(2.0), &Gt(2.0)));
        assert!(!implies(&Lt(0.5), &Gt(0.1)));
        assert!(implies(&tracks(&[2, 4]), &tracks(&[1, 2, 3, 4])));
        assert!(!implies(&tracks(&[2, 5]), &tracks(&[1, 2, 3, 4])));
        assert!(implies(&Eq(Value::Track(TrackId(3))), &tracks(&[3])));
        assert!(
            !implies(&Eq(Value::Time(3)), &tracks(&[3])),
            "a time is not a track"
        );
        let floats = |v: &[f64]| Constraint::OneOf(v.iter().map(|&x| Value::Float(x)).collect());
        assert!(implies(&floats(&[1.0]), &floats(&[1.0])));
        assert!(
            !implies(&floats(&[1.0]), &floats(&[1.0, 2.0])),
            "only equal lists"
        );
    }
}
