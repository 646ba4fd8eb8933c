//! Computing the catalog's relations from a Scene. Being built (issue: extractors).

pub mod kinematics;
pub mod lanes;
