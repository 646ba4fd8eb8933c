//! Computing the catalog's relations from a Scene. Being built (issue: extractors).

#![warn(missing_docs)]

pub mod kinematics;
pub mod lanes;
pub mod map;
pub mod pairs;
pub mod synthetic;
pub mod thresholds;
