//! A relation's tuples as JSON, for `scenalog facts LOG --relation NAME --json`.

use scenalog_facts::relation::{RelationData, Value};
use scenalog_facts::Scene;

/// The tuples as a JSON array of arrays: tracks as their uuid strings, lanes as their map ids,
/// times as frame indices, strings as strings, numbers as numbers (a non-finite float as null).
pub fn relation_json(scene: &Scene, data: &RelationData) -> serde_json::Value {
    let rows = (0..data.len())
        .map(|i| {
            serde_json::Value::Array(
                data.columns
                    .iter()
                    .map(|c| match c.get(i) {
                        Some(Value::Track(t)) => scene
                            .tracks
                            .get(t.index())
                            .map_or(serde_json::Value::Null, |tr| tr.uuid.clone().into()),
                        Some(Value::Time(f)) => f.into(),
                        Some(Value::Lane(l)) => l.0.into(),
                        Some(Value::Str(s)) => (*s).into(),
                        Some(Value::Float(x)) => serde_json::Number::from_f64(x)
                            .map_or(serde_json::Value::Null, serde_json::Value::Number),
                        Some(Value::Int(x)) => x.into(),
                        None => serde_json::Value::Null,
                    })
                    .collect(),
            )
        })
        .collect();
    serde_json::Value::Array(rows)
}
