//! One lane segment's geometry ([`LaneGeom`]): plain data the map index computes and the lane
//! chains and road sides read, in a module of its own below all three.

use scenalog_facts::LaneId;

use super::geometry::{Polygon, Pt};

/// Geometry of one lane segment, in the order of [`scenalog_facts::map::VectorMap::lanes`].
#[derive(Debug, Clone, PartialEq)]
pub struct LaneGeom {
    /// The map id.
    pub id: LaneId,
    /// Right boundary followed by the reversed left boundary.
    pub polygon: Polygon,
    /// Centreline (mean of the two boundaries resampled alike), in the direction of travel.
    pub centerline: Vec<Pt>,
    /// Left boundary, in the direction of travel.
    pub left: Vec<Pt>,
    /// Right boundary, in the direction of travel.
    pub right: Vec<Pt>,
    /// Centreline length, metres.
    pub length: f64,
    /// Mean width (distance between the resampled boundaries), metres.
    pub width: f64,
    /// Heading of the centreline's first and last segment, radians.
    pub start_heading: f64,
    /// Heading of the centreline's last segment, radians.
    pub end_heading: f64,
    /// Signed heading change from start to end, degrees (+ left).
    pub turn_deg: f64,
    /// Successors present in the map (dangling ids dropped), as lane indices.
    pub successors: Vec<usize>,
    /// Predecessors present in the map: the file's plus every lane naming this one a successor.
    pub predecessors: Vec<usize>,
}
