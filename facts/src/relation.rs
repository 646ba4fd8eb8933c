//! Relations as plain columnar data, and the requests that ask for them.
//!
//! This is the vocabulary shared by the extractors (which produce [`RelationData`] for a
//! [`Request`]) and the engine (which asks for the relations a program uses, with the constraints
//! the program fixes, and encodes the columns into its own tuples).

use std::sync::Arc;

use crate::catalog::ColType;
use crate::map::LaneId;
use crate::scene::{Frame, TrackId};

/// One value of a relation column.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A track of the scene.
    Track(TrackId),
    /// A frame index.
    Time(Frame),
    /// A lane segment id.
    Lane(LaneId),
    /// A string.
    Str(Arc<str>),
    /// A float.
    Float(f64),
    /// An integer.
    Int(i64),
}

/// One column of a relation, all values of one type.
#[derive(Debug, Clone, PartialEq)]
pub enum Column {
    /// Tracks.
    Track(Vec<TrackId>),
    /// Frames.
    Time(Vec<Frame>),
    /// Lanes.
    Lane(Vec<LaneId>),
    /// Strings (shared, so repeated values cost a pointer).
    Str(Vec<Arc<str>>),
    /// Floats.
    Float(Vec<f64>),
    /// Integers.
    Int(Vec<i64>),
}

impl Column {
    /// An empty column of the given type.
    pub fn empty(ty: ColType) -> Column {
        match ty {
            ColType::Track => Column::Track(Vec::new()),
            ColType::Time => Column::Time(Vec::new()),
            ColType::Lane => Column::Lane(Vec::new()),
            ColType::Str => Column::Str(Vec::new()),
            ColType::Float => Column::Float(Vec::new()),
            ColType::Int => Column::Int(Vec::new()),
        }
    }

    /// The column's type.
    pub fn ty(&self) -> ColType {
        match self {
            Column::Track(_) => ColType::Track,
            Column::Time(_) => ColType::Time,
            Column::Lane(_) => ColType::Lane,
            Column::Str(_) => ColType::Str,
            Column::Float(_) => ColType::Float,
            Column::Int(_) => ColType::Int,
        }
    }

    /// Number of values.
    pub fn len(&self) -> usize {
        match self {
            Column::Track(v) => v.len(),
            Column::Time(v) => v.len(),
            Column::Lane(v) => v.len(),
            Column::Str(v) => v.len(),
            Column::Float(v) => v.len(),
            Column::Int(v) => v.len(),
        }
    }

    /// Whether the column is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The value at row `i`, if there is one.
    pub fn get(&self, i: usize) -> Option<Value> {
        Some(match self {
            Column::Track(v) => Value::Track(*v.get(i)?),
            Column::Time(v) => Value::Time(*v.get(i)?),
            Column::Lane(v) => Value::Lane(*v.get(i)?),
            Column::Str(v) => Value::Str(v.get(i)?.clone()),
            Column::Float(v) => Value::Float(*v.get(i)?),
            Column::Int(v) => Value::Int(*v.get(i)?),
        })
    }
}

/// A relation's tuples, column by column; every column has the same length.
#[derive(Debug, Clone, PartialEq)]
pub struct RelationData {
    /// The relation's name.
    pub name: String,
    /// The columns, in the catalog's order.
    pub columns: Vec<Column>,
}

impl RelationData {
    /// An empty relation with columns of the given types.
    pub fn empty(name: &str, types: &[ColType]) -> RelationData {
        RelationData {
            name: name.to_string(),
            columns: types.iter().map(|&t| Column::empty(t)).collect(),
        }
    }

    /// Number of tuples.
    pub fn len(&self) -> usize {
        self.columns.first().map_or(0, Column::len)
    }

    /// Whether there is no tuple.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Tuple `i` as values.
    pub fn row(&self, i: usize) -> Option<Vec<Value>> {
        self.columns.iter().map(|c| c.get(i)).collect()
    }
}

/// A restriction on one column that the program fixes, so extraction can skip work.
/// Providers may ignore a constraint (returning a superset); the engine filters again.
#[derive(Debug, Clone, PartialEq)]
pub enum Constraint {
    /// The column equals this value (e.g. `crossing(B, P, T, "forward")`).
    Eq(Value),
    /// The column's track has this category or super-category (from `category(X, "BUS")`).
    Category(Arc<str>),
    /// The numeric column is `< v`.
    Lt(f64),
    /// The numeric column is `<= v`.
    Le(f64),
    /// The numeric column is `> v`.
    Gt(f64),
    /// The numeric column is `>= v`.
    Ge(f64),
    /// The column's value is one of these (sorted, distinct): the values a program's other atoms
    /// bind the column's variable to (demand from the engine, e.g. the ego's track or the
    /// tracks and frames of a derived relation). Empty means no tuple is needed.
    OneOf(Arc<[Value]>),
    /// Tuple-level demand on a pair relation: put on the relation's first track column `c`,
    /// the columns `c`, `c + 1` and `c + 2` (X, Y, T: track, track, time) hold one of these
    /// triples (sorted, distinct). The engine sends it when one complete relation of the same
    /// body binds all three variables (e.g. `near(V, L, T, D)` after `following(V, L, T)`), so
    /// the extractors look at those pairs at those frames only. Empty means no tuple is needed.
    Triples(Arc<[(TrackId, TrackId, Frame)]>),
}

/// A request for one catalog relation, with constraints on some of its columns.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    /// The relation's name in the catalog.
    pub name: String,
    /// `(column index, constraint)` pairs; all must hold for a tuple to be needed.
    pub constraints: Vec<(usize, Constraint)>,
}

impl Request {
    /// A request for the whole relation.
    pub fn all(name: &str) -> Request {
        Request {
            name: name.to_string(),
            constraints: Vec::new(),
        }
    }
}
