//! A log's facts (`scenalog facts LOG [--relation R]`, `scenalog.facts(log, relation)`): the
//! log's summary, or one catalog relation extracted from it within one pair's [`Limits`] (the
//! tuple budget and time limit `mine` gives a pair, by default), so neither front end can fill
//! the memory or hang on a dense log.
//!
//! The relation comes back as its tuples (JSON: tracks as uuids, lanes as map ids, times as
//! frame indices, numbers as numbers), named by the catalog's columns, or as an Arrow table.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use scenalog_extractors::{Budget, ExtractError, Extractor};
use scenalog_facts::catalog::RelationSpec;
use scenalog_facts::relation::{RelationData, Request};
use scenalog_facts::{load_scene, Scene, SceneSummary};

use crate::api::error::{Error, Field, Message};
use crate::api::limits::Limits;

mod arrow;

/// A log's facts to read.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FactsRequest {
    /// The log directory (annotations, `city_SE3_egovehicle.feather`, `map/`).
    pub log: PathBuf,
    /// Extract this catalog relation (`None`: summarise the log).
    pub relation: Option<String>,
    /// The extraction's limits (one pair's of `mine` by default).
    pub limits: Limits,
}

/// What a [`FactsRequest`] gives.
pub enum Facts {
    /// The log's summary.
    Summary(LogSummary),
    /// The relation extracted.
    Relation(RelationFacts),
}

/// A log's summary and how long reading the log took.
pub struct LogSummary {
    /// The summary (tracks by category, map elements, time span, …).
    pub summary: SceneSummary,
    /// Milliseconds reading the log took.
    pub load_ms: f64,
}

impl LogSummary {
    /// The JSON `scenalog facts LOG --json` prints: the summary's keys and `load_ms`.
    pub fn json(&self) -> serde_json::Value {
        let mut json = self.summary.to_json();
        json["load_ms"] = serde_json::json!(self.load_ms);
        json
    }

    /// The text `scenalog facts LOG` prints.
    pub fn text(&self) -> String {
        format!(
            "{}  loaded in {:.1} ms\n",
            self.summary.to_text(),
            self.load_ms
        )
    }
}

/// One relation extracted from a log.
pub struct RelationFacts {
    scene: Box<Scene>,
    spec: &'static RelationSpec,
    data: Arc<RelationData>,
    /// Milliseconds the extraction took (reading the log not included).
    pub extract_ms: f64,
}

impl RelationFacts {
    /// The relation's name.
    pub fn name(&self) -> &str {
        self.spec.name
    }

    /// How many tuples it holds.
    pub fn len(&self) -> usize {
        self.data.len()
    }

    /// Whether it holds none.
    pub fn is_empty(&self) -> bool {
        self.data.len() == 0
    }

    /// The line `scenalog facts LOG --relation R` prints: `LOG_ID: R: N tuples (MS ms)`.
    pub fn text(&self) -> String {
        format!(
            "{}: {}: {} tuples ({:.1} ms)\n",
            self.scene.log_id,
            self.spec.name,
            self.data.len(),
            self.extract_ms
        )
    }

    /// The tuples as a JSON array of arrays (`scenalog facts --relation R --json`).
    pub fn tuples_json(&self) -> serde_json::Value {
        scenalog_extractors::relation_json(&self.scene, &self.data)
    }

    /// The tuples with the catalog's column names and types (`--json --columns`):
    /// `{"relation": R, "columns": [{"name", "type"}, …], "tuples": [[…], …]}`.
    pub fn columns_json(&self) -> serde_json::Value {
        let named: Vec<serde_json::Value> = self
            .spec
            .column_names()
            .into_iter()
            .zip(self.spec.types())
            .map(|(n, t)| serde_json::json!({"name": n, "type": t.to_string()}))
            .collect();
        serde_json::json!({
            "relation": self.spec.name,
            "columns": named,
            "tuples": self.tuples_json(),
        })
    }

    /// The tuples as one record batch of an Arrow IPC stream, the catalog's columns (tracks as
    /// uuid strings, times as frame indices, lanes as map ids): `scenalog.facts`'s table.
    pub fn arrow_ipc(&self) -> Result<Vec<u8>, Error> {
        arrow::relation_ipc(&self.scene, self.spec, &self.data).map_err(Error::plain)
    }
}

/// Reads the request's log and summarises it, or extracts its relation within its limits. An
/// unknown relation, an unreadable log and an extraction past a limit are errors (the command's
/// exit 2); one past the tuple budget says to raise [`Field::MaxTuples`].
pub fn facts(request: &FactsRequest) -> Result<Facts, Error> {
    request.limits.check()?;
    let spec = match &request.relation {
        Some(name) => Some(scenalog_facts::catalog::relation(name).ok_or_else(|| {
            Error::plain(format!(
                "`{name}` is not a relation of the catalog (see `scenalog catalog`)"
            ))
        })?),
        None => None,
    };
    let start = Instant::now();
    let scene = load_scene(&request.log).map_err(Error::plain)?;
    let load_ms = start.elapsed().as_secs_f64() * 1e3;
    let Some(spec) = spec else {
        return Ok(Facts::Summary(LogSummary {
            summary: SceneSummary::of(&scene),
            load_ms,
        }));
    };
    let limits = request.limits.engine(1);
    let start = Instant::now();
    let budget = Budget::new(limits.max_tuples, start, limits.timeout);
    let extracted = Extractor::new(&scene).extract_within(&Request::all(spec.name), &budget);
    let data = extracted.map_err(|e| extraction_error(spec.name, &e))?;
    let extract_ms = start.elapsed().as_secs_f64() * 1e3;
    Ok(Facts::Relation(RelationFacts {
        scene: Box::new(scene),
        spec,
        data,
        extract_ms,
    }))
}

/// `extracting R: …`, and for a relation past the tuple budget, what to raise.
fn extraction_error(name: &str, e: &ExtractError) -> Error {
    let message = Message::text(format!("extracting {name}: {e}"));
    let message = if matches!(e, ExtractError::TooManyTuples { .. }) {
        message.then(" or raise ").mention(Field::MaxTuples)
    } else {
        message
    };
    Error::from(message)
}
