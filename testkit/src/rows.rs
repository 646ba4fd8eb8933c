//! A relation's tuples as rows of values, the shape tests compare.

use scenalog_facts::relation::{RelationData, Value};

/// Every tuple of `d`, in its order, as a row of values.
pub fn rows(d: &RelationData) -> Vec<Vec<Value>> {
    (0..d.len())
        .map(|i| d.row(i).expect("a row below the relation's length"))
        .collect()
}
