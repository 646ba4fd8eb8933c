//! Rows to columns: a relation's providers push tuples (`(TrackId, Frame, f64)`, …) and
//! [`relation`] turns them into the column-wise [`RelationData`] the engine reads, each column
//! typed by what its tuples hold. One place writes the per-column loops every provider needed.

use std::sync::Arc;

use scenalog_facts::relation::{Column, RelationData};
use scenalog_facts::{Frame, LaneId, TrackId};

use crate::query::Query;

/// A value that can fill a column: the column's type follows from the Rust type.
pub(crate) trait Cell: Sized {
    /// The column holding `values`, in order.
    fn column(values: Vec<Self>) -> Column;
}

impl Cell for TrackId {
    fn column(values: Vec<Self>) -> Column {
        Column::Track(values)
    }
}

impl Cell for Frame {
    fn column(values: Vec<Self>) -> Column {
        Column::Time(values)
    }
}

impl Cell for LaneId {
    fn column(values: Vec<Self>) -> Column {
        Column::Lane(values)
    }
}

impl Cell for Arc<str> {
    fn column(values: Vec<Self>) -> Column {
        Column::Str(values)
    }
}

impl Cell for f64 {
    fn column(values: Vec<Self>) -> Column {
        Column::Float(values)
    }
}

impl Cell for i64 {
    fn column(values: Vec<Self>) -> Column {
        Column::Int(values)
    }
}

/// A tuple of [`Cell`]s: one row of a relation.
pub(crate) trait Row: Sized {
    /// The rows as columns, one per tuple field, rows kept in order.
    fn columns(rows: impl IntoIterator<Item = Self>) -> Vec<Column>;
}

macro_rules! row_impl {
    ($($t:ident $v:ident $i:tt),+) => {
        impl<$($t: Cell),+> Row for ($($t,)+) {
            fn columns(rows: impl IntoIterator<Item = Self>) -> Vec<Column> {
                $(let mut $v: Vec<$t> = Vec::new();)+
                for row in rows {
                    $($v.push(row.$i);)+
                }
                vec![$($t::column($v)),+]
            }
        }
    };
}

row_impl!(A a 0);
row_impl!(A a 0, B b 1);
row_impl!(A a 0, B b 1, C c 2);
row_impl!(A a 0, B b 1, C c 2, D d 3);
row_impl!(A a 0, B b 1, C c 2, D d 3, E e 4);
row_impl!(A a 0, B b 1, C c 2, D d 3, E e 4, F f 5);
row_impl!(A a 0, B b 1, C c 2, D d 3, E e 4, F f 5, G g 6);

/// `query`'s relation holding `rows` (in the order given; [`Query::finish`] filters and sorts).
pub(crate) fn relation<R: Row>(q: &Query, rows: impl IntoIterator<Item = R>) -> RelationData {
    RelationData {
        name: q.spec.name.into(),
        columns: R::columns(rows),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scenalog_facts::catalog::ColType;

    #[test]
    fn each_field_becomes_its_typed_column_in_row_order() {
        let rows = vec![
            (
                TrackId(2),
                7u32,
                LaneId(9),
                Arc::<str>::from("left"),
                1.5,
                3i64,
            ),
            (
                TrackId(1),
                4u32,
                LaneId(8),
                Arc::<str>::from("right"),
                -0.5,
                -1i64,
            ),
        ];
        let cols = Row::columns(rows);
        let types: Vec<ColType> = cols.iter().map(Column::ty).collect();
        assert_eq!(
            types,
            [
                ColType::Track,
                ColType::Time,
                ColType::Lane,
                ColType::Str,
                ColType::Float,
                ColType::Int
            ]
        );
        assert_eq!(cols[0], Column::Track(vec![TrackId(2), TrackId(1)]));
        assert_eq!(cols[1], Column::Time(vec![7, 4]));
        assert_eq!(cols[4], Column::Float(vec![1.5, -0.5]));
        assert_eq!(cols[5], Column::Int(vec![3, -1]));
    }

    #[test]
    fn no_rows_still_give_every_column() {
        let cols = <(TrackId, TrackId, Frame)>::columns(Vec::new());
        assert_eq!(cols.len(), 3);
        assert!(cols.iter().all(Column::is_empty));
    }
}
