//! The vector map of a log: lane segments, pedestrian crossings and drivable areas (city frame).
//!
//! Map ids that point to lanes missing from the file (successors, neighbours) are kept as they are
//! ("dangling"); [`VectorMap::lane`] answers `None` for them and nothing ever panics on one.

use std::collections::HashMap;

use nalgebra::Point3;

/// The AV2 id of a lane segment (as in the map file).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LaneId(pub i64);

/// What a lane segment is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum LaneType {
    /// Cars and other vehicles.
    Vehicle,
    /// Bicycles.
    Bike,
    /// Buses.
    Bus,
}

impl LaneType {
    /// The name as in the map file and the catalog ("VEHICLE", "BIKE", "BUS").
    pub fn as_str(self) -> &'static str {
        match self {
            LaneType::Vehicle => "VEHICLE",
            LaneType::Bike => "BIKE",
            LaneType::Bus => "BUS",
        }
    }

    /// Parses the map file's name for a lane type.
    pub fn parse(s: &str) -> Option<LaneType> {
        match s {
            "VEHICLE" => Some(LaneType::Vehicle),
            "BIKE" => Some(LaneType::Bike),
            "BUS" => Some(LaneType::Bus),
            _ => None,
        }
    }
}

/// One lane segment of the vector map.
#[derive(Debug, Clone, PartialEq)]
pub struct LaneSegment {
    /// The map id.
    pub id: LaneId,
    /// What the lane is for.
    pub lane_type: LaneType,
    /// Whether the segment lies in an intersection.
    pub is_intersection: bool,
    /// Left boundary polyline, in the direction of travel.
    pub left_boundary: Vec<Point3<f64>>,
    /// Right boundary polyline, in the direction of travel.
    pub right_boundary: Vec<Point3<f64>>,
    /// Paint of the left boundary (e.g. "SOLID_YELLOW").
    pub left_mark_type: String,
    /// Paint of the right boundary.
    pub right_mark_type: String,
    /// Segments that continue this one (may be dangling).
    pub successors: Vec<LaneId>,
    /// Segments this one continues (may be dangling).
    pub predecessors: Vec<LaneId>,
    /// The neighbour on the left, if any (may be dangling).
    pub left_neighbor: Option<LaneId>,
    /// The neighbour on the right, if any (may be dangling).
    pub right_neighbor: Option<LaneId>,
}

impl LaneSegment {
    /// The lane polygon: the right boundary followed by the reversed left boundary (x-y only).
    pub fn polygon_xy(&self) -> Vec<[f64; 2]> {
        self.right_boundary
            .iter()
            .chain(self.left_boundary.iter().rev())
            .map(|p| [p.x, p.y])
            .collect()
    }
}

/// A pedestrian crossing: two edges, each a polyline (usually two points).
#[derive(Debug, Clone, PartialEq)]
pub struct PedestrianCrossing {
    /// The map id.
    pub id: i64,
    /// First edge.
    pub edge1: Vec<Point3<f64>>,
    /// Second edge.
    pub edge2: Vec<Point3<f64>>,
}

impl PedestrianCrossing {
    /// The crossing polygon: edge1 followed by the reversed edge2 (x-y only).
    pub fn polygon_xy(&self) -> Vec<[f64; 2]> {
        self.edge1
            .iter()
            .chain(self.edge2.iter().rev())
            .map(|p| [p.x, p.y])
            .collect()
    }
}

/// A drivable area: one closed boundary polygon.
#[derive(Debug, Clone, PartialEq)]
pub struct DrivableArea {
    /// The map id.
    pub id: i64,
    /// The boundary polygon (first point not repeated at the end unless the file does so).
    pub boundary: Vec<Point3<f64>>,
}

/// The vector map of one log.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VectorMap {
    /// Lane segments sorted by id.
    pub lanes: Vec<LaneSegment>,
    /// Pedestrian crossings sorted by id.
    pub crossings: Vec<PedestrianCrossing>,
    /// Drivable areas sorted by id.
    pub drivable_areas: Vec<DrivableArea>,
    lane_index: HashMap<LaneId, usize>,
}

impl VectorMap {
    /// Builds a map, sorting each list by id and indexing lanes.
    pub fn new(
        mut lanes: Vec<LaneSegment>,
        mut crossings: Vec<PedestrianCrossing>,
        mut drivable_areas: Vec<DrivableArea>,
    ) -> Self {
        lanes.sort_by_key(|l| l.id);
        crossings.sort_by_key(|c| c.id);
        drivable_areas.sort_by_key(|d| d.id);
        let lane_index = lanes.iter().enumerate().map(|(i, l)| (l.id, i)).collect();
        VectorMap {
            lanes,
            crossings,
            drivable_areas,
            lane_index,
        }
    }

    /// The lane with this id, or `None` if the id is dangling (not in the file).
    pub fn lane(&self, id: LaneId) -> Option<&LaneSegment> {
        self.lane_index.get(&id).map(|&i| &self.lanes[i])
    }

    /// The index of a lane in [`VectorMap::lanes`], or `None` if dangling.
    pub fn lane_index(&self, id: LaneId) -> Option<usize> {
        self.lane_index.get(&id).copied()
    }
}
