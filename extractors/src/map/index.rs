//! The map prepared for queries: lane, crossing and drivable-area polygons in `rstar` R-trees, lane
//! centrelines and turn angles, predecessors derived from successors, the lane chains and road sides.

use std::sync::OnceLock;

use rstar::primitives::{GeomWithData, Line, Rectangle};
use rstar::{RTree, AABB};
use scenalog_facts::map::VectorMap;

use super::chain::{self, LaneChains};
use super::geometry::{
    heading, point_segment_distance, polyline_length, resample, segment_polygon_distance, Polygon,
    Pt,
};
pub use super::lane_geom::LaneGeom;
use super::sides::{self, RoadSides};
use crate::kinematics::wrap_angle;

/// An R-tree entry: a polygon's bounding box and the polygon's index in its list.
pub type BoxEntry = GeomWithData<Rectangle<Pt>, u32>;

/// A vector map prepared for geometric queries. Built once per scene.
#[derive(Debug)]
pub struct MapIndex {
    /// Per lane (same order as [`VectorMap::lanes`]).
    pub lanes: Vec<LaneGeom>,
    /// Pedestrian crossing polygons (same order as [`VectorMap::crossings`]).
    pub crossings: Vec<Polygon>,
    /// Drivable area polygons (same order as [`VectorMap::drivable_areas`]).
    pub areas: Vec<Polygon>,
    /// The lane as a driver sees it, per lane.
    pub chains: LaneChains,
    /// Lanes on the same and the opposite side of the road, per lane.
    pub sides: RoadSides,
    lane_tree: RTree<BoxEntry>,
    intersection_tree: RTree<BoxEntry>,
    intersection_edges: RTree<Line<Pt>>,
    crossing_tree: RTree<BoxEntry>,
    area_tree: RTree<BoxEntry>,
    /// The drivable area's outer edges ([`MapIndex::outer_edges`]), built when `road_edge` first
    /// asks.
    road_edges: OnceLock<RTree<Line<Pt>>>,
}

fn xy(p: &[nalgebra::Point3<f64>]) -> Vec<Pt> {
    p.iter().map(|q| [q.x, q.y]).collect()
}

fn entry(poly: &Polygon, i: usize) -> BoxEntry {
    GeomWithData::new(
        Rectangle::from_corners(poly.bbox[0], poly.bbox[1]),
        i as u32,
    )
}

fn tree_of<'a>(polys: impl Iterator<Item = (usize, &'a Polygon)>) -> RTree<BoxEntry> {
    RTree::bulk_load(polys.map(|(i, p)| entry(p, i)).collect())
}

impl MapIndex {
    /// Prepares `map` for queries.
    pub fn new(map: &VectorMap) -> MapIndex {
        let mut lanes: Vec<LaneGeom> = map
            .lanes
            .iter()
            .map(|l| {
                let left = xy(&l.left_boundary);
                let right = xy(&l.right_boundary);
                let n = left.len().max(right.len()).max(2);
                let (rl, rr) = (resample(&left, n), resample(&right, n));
                let centerline: Vec<Pt> = rl
                    .iter()
                    .zip(&rr)
                    .map(|(a, b)| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])])
                    .collect();
                let width = if rl.is_empty() {
                    0.0
                } else {
                    rl.iter()
                        .zip(&rr)
                        .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
                        .sum::<f64>()
                        / rl.len() as f64
                };
                let (start_heading, end_heading) = if centerline.len() >= 2 {
                    let k = centerline.len();
                    (
                        heading(centerline[0], centerline[1]),
                        heading(centerline[k - 2], centerline[k - 1]),
                    )
                } else {
                    (0.0, 0.0)
                };
                let successors = l
                    .successors
                    .iter()
                    .filter_map(|&s| map.lane_index(s))
                    .collect();
                let predecessors = l
                    .predecessors
                    .iter()
                    .filter_map(|&s| map.lane_index(s))
                    .collect();
                LaneGeom {
                    id: l.id,
                    polygon: Polygon::new(l.polygon_xy()),
                    length: polyline_length(&centerline),
                    centerline,
                    left,
                    right,
                    width,
                    start_heading,
                    end_heading,
                    turn_deg: wrap_angle(end_heading - start_heading).to_degrees(),
                    successors,
                    predecessors,
                }
            })
            .collect();
        // AV2 map files usually leave `predecessors` empty: derive them from successors (the
        // duplicates go with the sort below, so a lane with thousands of predecessors costs no
        // scan of them per link).
        for i in 0..lanes.len() {
            for k in 0..lanes[i].successors.len() {
                let s = lanes[i].successors[k];
                lanes[s].predecessors.push(i);
            }
        }
        for l in &mut lanes {
            l.successors.sort_unstable();
            l.successors.dedup();
            l.predecessors.sort_unstable();
            l.predecessors.dedup();
        }
        let crossings: Vec<Polygon> = map
            .crossings
            .iter()
            .map(|c| Polygon::new(c.polygon_xy()))
            .collect();
        let areas: Vec<Polygon> = map
            .drivable_areas
            .iter()
            .map(|a| Polygon::new(xy(&a.boundary)))
            .collect();
        let lane_tree = tree_of(lanes.iter().map(|l| &l.polygon).enumerate());
        let intersection_tree = tree_of(
            lanes
                .iter()
                .enumerate()
                .filter(|(i, _)| map.lanes[*i].is_intersection)
                .map(|(i, l)| (i, &l.polygon)),
        );
        let intersection_edges = RTree::bulk_load(
            lanes
                .iter()
                .enumerate()
                .filter(|(i, _)| map.lanes[*i].is_intersection)
                .flat_map(|(_, l)| l.polygon.edges().map(|(a, b)| Line::new(a, b)))
                .collect(),
        );
        let crossing_tree = tree_of(crossings.iter().enumerate());
        let area_tree = tree_of(areas.iter().enumerate());
        let chains = chain::build(&lanes);
        let sides = sides::build(map, &lanes);
        MapIndex {
            lanes,
            crossings,
            areas,
            chains,
            sides,
            lane_tree,
            intersection_tree,
            intersection_edges,
            crossing_tree,
            area_tree,
            road_edges: OnceLock::new(),
        }
    }

    /// Indices of the lanes whose polygon contains `p`, ascending.
    pub fn lanes_containing(&self, p: Pt) -> Vec<usize> {
        let mut out: Vec<usize> = self
            .lane_tree
            .locate_all_at_point(p)
            .map(|e| e.data as usize)
            .filter(|&i| self.lanes[i].polygon.contains(p))
            .collect();
        out.sort_unstable();
        out
    }

    /// Indices of the lanes whose bounding box lies within `r` of `p`, ascending.
    pub fn lanes_near(&self, p: Pt, r: f64) -> Vec<usize> {
        let env = AABB::from_corners([p[0] - r, p[1] - r], [p[0] + r, p[1] + r]);
        let mut out: Vec<usize> = self
            .lane_tree
            .locate_in_envelope_intersecting(env)
            .map(|e| e.data as usize)
            .collect();
        out.sort_unstable();
        out
    }

    /// Whether `p` lies in some intersection lane.
    pub fn in_intersection(&self, p: Pt) -> bool {
        self.intersection_tree
            .locate_all_at_point(p)
            .any(|e| self.lanes[e.data as usize].polygon.contains(p))
    }

    /// Whether `p` lies in some drivable area.
    pub fn in_drivable_area(&self, p: Pt) -> bool {
        self.area_tree
            .locate_all_at_point(p)
            .any(|e| self.areas[e.data as usize].contains(p))
    }

    /// Distance from `p` to the nearest intersection lane polygon (0 inside), if one lies within
    /// `max` metres.
    pub fn intersection_distance(&self, p: Pt, max: f64) -> Option<f64> {
        self.intersection_distance_hinted(p, max, &mut None)
    }

    /// [`MapIndex::intersection_distance`] for a sequence of nearby points (one track's boxes):
    /// `hint` carries the nearest edge found last time, whose distance bounds the search radius,
    /// so a slowly moving object costs a small range query instead of a nearest-neighbour search.
    pub fn intersection_distance_hinted(
        &self,
        p: Pt,
        max: f64,
        hint: &mut Option<Line<Pt>>,
    ) -> Option<f64> {
        if self.in_intersection(p) {
            return Some(0.0);
        }
        // Outside every intersection lane: the distance is the one to the nearest of their edges.
        let hinted = hint.map(|e| (point_segment_distance(p, e.from, e.to), e));
        let bound = hinted.map_or(max, |(d, _)| d.min(max));
        // The hinted edge itself is a candidate (the range query's bound may exclude it).
        let mut best: Option<(f64, Line<Pt>)> = hinted.filter(|(d, _)| *d <= max);
        for e in self
            .intersection_edges
            .locate_within_distance(p, bound * bound)
        {
            let d = point_segment_distance(p, e.from, e.to);
            if best.is_none_or(|(b, _)| d < b) {
                best = Some((d, *e));
            }
        }
        if let Some((_, e)) = best {
            *hint = Some(e);
        }
        best.map(|(d, _)| d).filter(|&d| d <= max)
    }

    /// Distance from the polygon `shape` (an object's ground box) to the nearest edge of the
    /// drivable area (a kerb; 0 when the box lies over it), if one lies within `max` metres.
    pub fn road_edge_distance(&self, shape: &Polygon, max: f64) -> Option<f64> {
        let (c, half_diag) = centre_and_reach(shape);
        let edges = self
            .road_edges
            .get_or_init(|| RTree::bulk_load(self.outer_edges()));
        nearest(
            edges.nearest_neighbor_iter_with_distance_2(c),
            half_diag,
            max,
            |e| segment_polygon_distance(e.from, e.to, shape),
        )
    }

    /// The edges of the drivable areas that bound the road: AV2 tiles the drivable area into
    /// several polygons, and an edge two tiles share (drivable area on both sides, probed at its
    /// midpoint [`EDGE_PROBE_M`] either way) is no edge of the road.
    fn outer_edges(&self) -> Vec<Line<Pt>> {
        let mut out = Vec::new();
        for poly in &self.areas {
            for (a, b) in poly.edges() {
                let len = (b[0] - a[0]).hypot(b[1] - a[1]);
                if len == 0.0 {
                    continue;
                }
                let m = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
                let n = [
                    -(b[1] - a[1]) / len * EDGE_PROBE_M,
                    (b[0] - a[0]) / len * EDGE_PROBE_M,
                ];
                let inside_both = self.in_drivable_area([m[0] + n[0], m[1] + n[1]])
                    && self.in_drivable_area([m[0] - n[0], m[1] - n[1]]);
                if !inside_both {
                    out.push(Line::new(a, b));
                }
            }
        }
        out
    }

    /// Distance from the polygon `shape` (an object's ground box) to the nearest pedestrian
    /// crossing (0 when overlapping), if one lies within `max` metres.
    pub fn crossing_distance(&self, shape: &Polygon, max: f64) -> Option<f64> {
        let (c, half_diag) = centre_and_reach(shape);
        let polys = &self.crossings;
        let candidates = self.crossing_tree.nearest_neighbor_iter_with_distance_2(c);
        nearest(candidates, half_diag, max, |e| {
            polys[e.data as usize].distance_to_polygon(shape)
        })
    }
}

/// The centre of a shape's bounding box and how far the shape reaches from it (half the box's
/// diagonal): a point's distance to the centre less the reach bounds its distance to the shape.
fn centre_and_reach(shape: &Polygon) -> (Pt, f64) {
    let [lo, hi] = shape.bbox;
    (
        [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])],
        0.5 * (hi[0] - lo[0]).hypot(hi[1] - lo[1]),
    )
}

/// How far either side of a drivable area's edge [`MapIndex::outer_edges`] looks for drivable
/// area.
const EDGE_PROBE_M: f64 = 0.25;

/// Exact nearest distance over an R-tree's candidates in order of their squared distance from a
/// point (`nearest_neighbor_iter_with_distance_2`): that distance minus `slack` (how far the
/// query shape reaches from the point) bounds the exact distance from below, so the search stops
/// once it passes the best exact one.
fn nearest<T>(
    candidates: impl Iterator<Item = (T, f64)>,
    slack: f64,
    max: f64,
    exact: impl Fn(T) -> f64,
) -> Option<f64> {
    let mut best = f64::INFINITY;
    for (e, d2) in candidates {
        let lb = d2.sqrt() - slack;
        if lb > best || lb > max {
            break;
        }
        best = best.min(exact(e));
    }
    (best <= max).then_some(best)
}
