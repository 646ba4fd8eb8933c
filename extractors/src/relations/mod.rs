//! The providers of the single-object relations, grouped as in the catalog: objects and time,
//! kinematics and events, map, the road's structure. Each takes the per-scene [`crate::Extractor`] and a checked
//! [`crate::Query`] and returns the relation's columns (the caller filters and sorts).

pub mod between;
pub mod lane_direction;
pub mod map;
pub mod motion;
pub mod objects;
pub mod road;
pub mod towing;

use std::sync::Arc;

/// A shared string for a column value.
pub(crate) fn s(v: &str) -> Arc<str> {
    Arc::from(v)
}
