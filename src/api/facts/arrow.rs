//! A catalog relation's tuples as an Arrow table, for `scenalog.facts(log, relation)`: the
//! columns the catalog names, typed as `scenalog facts --relation --json` writes the values.

use std::sync::Arc;

use arrow_array::{ArrayRef, Float64Array, Int64Array, RecordBatch, StringArray, UInt32Array};
use arrow_schema::{DataType, Field, Schema};
use scenalog_facts::catalog::RelationSpec;
use scenalog_facts::relation::{RelationData, Value};
use scenalog_facts::Scene;

/// The tuples as one record batch in an Arrow IPC stream, written as `scenalog facts --relation
/// --json` writes them: tracks as uuid strings, times as frame indices (uint32), lanes as map
/// ids (int64), strings, floats (float64; a non-finite one null) and integers (int64).
pub(crate) fn relation_ipc(
    scene: &Scene,
    spec: &RelationSpec,
    data: &RelationData,
) -> Result<Vec<u8>, String> {
    let names = spec.column_names();
    let mut fields = Vec::new();
    let mut arrays: Vec<ArrayRef> = Vec::new();
    for (i, column) in data.columns.iter().enumerate() {
        let values: Vec<Option<Value>> = (0..data.len()).map(|r| column.get(r)).collect();
        let name = names.get(i).cloned().unwrap_or_else(|| format!("c{i}"));
        let (ty, array): (DataType, ArrayRef) = match spec.columns.get(i).map(|c| c.ty) {
            Some(scenalog_facts::catalog::ColType::Track) => (
                DataType::Utf8,
                Arc::new(StringArray::from_iter(values.iter().map(|v| match v {
                    Some(Value::Track(t)) => scene.tracks.get(t.index()).map(|tr| tr.uuid.clone()),
                    _ => None,
                }))),
            ),
            Some(scenalog_facts::catalog::ColType::Time) => (
                DataType::UInt32,
                Arc::new(UInt32Array::from_iter(values.iter().map(|v| match v {
                    Some(Value::Time(f)) => Some(*f),
                    _ => None,
                }))),
            ),
            Some(scenalog_facts::catalog::ColType::Lane) => (
                DataType::Int64,
                Arc::new(Int64Array::from_iter(values.iter().map(|v| match v {
                    Some(Value::Lane(l)) => Some(l.0),
                    _ => None,
                }))),
            ),
            Some(scenalog_facts::catalog::ColType::Str) => (
                DataType::Utf8,
                Arc::new(StringArray::from_iter(values.iter().map(|v| match v {
                    Some(Value::Str(s)) => Some(s.to_string()),
                    _ => None,
                }))),
            ),
            Some(scenalog_facts::catalog::ColType::Float) => (
                DataType::Float64,
                Arc::new(Float64Array::from_iter(values.iter().map(|v| match v {
                    Some(Value::Float(x)) if x.is_finite() => Some(*x),
                    _ => None,
                }))),
            ),
            Some(scenalog_facts::catalog::ColType::Int) => (
                DataType::Int64,
                Arc::new(Int64Array::from_iter(values.iter().map(|v| match v {
                    Some(Value::Int(x)) => Some(*x),
                    _ => None,
                }))),
            ),
            None => {
                return Err(format!(
                    "{}: more columns than the catalog declares",
                    spec.name
                ))
            }
        };
        fields.push(Field::new(name, ty, true));
        arrays.push(array);
    }
    let schema = Arc::new(Schema::new(fields));
    let batch = if arrays.is_empty() {
        RecordBatch::new_empty(schema.clone())
    } else {
        RecordBatch::try_new(schema.clone(), arrays).map_err(|e| e.to_string())?
    };
    let mut out = Vec::new();
    {
        let mut w = arrow_ipc::writer::StreamWriter::try_new(&mut out, &schema)
            .map_err(|e| e.to_string())?;
        w.write(&batch).map_err(|e| e.to_string())?;
        w.finish().map_err(|e| e.to_string())?;
    }
    Ok(out)
}
