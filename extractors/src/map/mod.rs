//! The vector map prepared for queries and the map relations.
//!
//! - [`geometry`]: polygons and polylines in the ground plane.
//! - [`index`]: [`MapIndex`], lane/crossing/drivable-area polygons in R-trees.
//! - [`lane_geom`]: [`LaneGeom`], one lane segment's geometry.
//! - [`chain`]: the lane as a driver sees it (straight predecessors and successors).
//! - [`sides`]: same and opposite road sides through lane neighbours.
//! - [`cross_section`]: the lanes across the road at a lane, each way.

pub mod chain;
pub mod cross_section;
pub mod geometry;
pub mod index;
pub mod lane_geom;
pub mod sides;
pub mod stop_signs;

pub use chain::LaneChains;
pub use index::{LaneGeom, MapIndex};
pub use sides::{RoadSide, RoadSides};
