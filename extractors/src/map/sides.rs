//! Road sides through lane neighbours: which lanes carry traffic on the same side of the road as a
//! lane, and which on the opposite side (the relation `road_side` builds on).
//!
//! Two neighbouring lanes are on the same side when the boundary they share runs the same way in
//! both (the neighbour's boundary nearest to the lane's shared boundary points the same way), and
//! on opposite sides otherwise. Same-side links are closed transitively into groups (one group is a
//! carriageway across its lanes); a group is opposite to every group one of its lanes has an
//! opposite-direction neighbour in.

use std::collections::BTreeSet;

use scenalog_facts::map::VectorMap;
use scenalog_facts::LaneId;

use super::geometry::Pt;
use super::lane_geom::LaneGeom;

/// A road side relative to a lane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum RoadSide {
    /// Same direction of travel, reachable through same-direction neighbours.
    Same,
    /// The other direction of travel across an opposite-direction neighbour.
    Opposite,
}

impl RoadSide {
    /// The catalog's name: "same" or "opposite".
    pub fn as_str(self) -> &'static str {
        match self {
            RoadSide::Same => "same",
            RoadSide::Opposite => "opposite",
        }
    }
}

/// Road-side groups of every lane, indexed like [`VectorMap::lanes`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RoadSides {
    /// `group[i]`: the same-side group of lane `i` (a group id, not a lane index).
    pub group: Vec<usize>,
    /// `opposite[g]`: the groups on the opposite side of group `g`.
    pub opposite: Vec<BTreeSet<usize>>,
    /// `members[g]`: lane ids of group `g`, ascending.
    pub members: Vec<Vec<LaneId>>,
}

impl RoadSides {
    /// The side lane `b` is on relative to lane `a` (lane indices), if the neighbours relate them.
    pub fn side(&self, a: usize, b: usize) -> Option<RoadSide> {
        let (ga, gb) = (*self.group.get(a)?, *self.group.get(b)?);
        if ga == gb {
            Some(RoadSide::Same)
        } else if self.opposite.get(ga).is_some_and(|o| o.contains(&gb)) {
            Some(RoadSide::Opposite)
        } else {
            None
        }
    }

    /// Lane ids on the same side as lane `i` (itself included).
    pub fn same_side(&self, i: usize) -> Vec<LaneId> {
        self.group
            .get(i)
            .map(|&g| self.members[g].clone())
            .unwrap_or_default()
    }

    /// Lane ids on the opposite side of lane `i`, ascending.
    pub fn opposite_side(&self, i: usize) -> Vec<LaneId> {
        let Some(&g) = self.group.get(i) else {
            return Vec::new();
        };
        let mut out: Vec<LaneId> = self.opposite[g]
            .iter()
            .flat_map(|&o| self.members[o].iter().copied())
            .collect();
        out.sort_unstable();
        out
    }
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

fn dir(line: &[Pt]) -> Pt {
    match (line.first(), line.last()) {
        (Some(a), Some(b)) => [b[0] - a[0], b[1] - a[1]],
        _ => [0.0, 0.0],
    }
}

fn mean_endpoint_gap(a: &[Pt], b: &[Pt]) -> f64 {
    // Direction-free closeness of two polylines: their endpoints matched either way round.
    let (Some(a0), Some(a1), Some(b0), Some(b1)) = (a.first(), a.last(), b.first(), b.last())
    else {
        return f64::INFINITY;
    };
    let d = |p: &Pt, q: &Pt| (p[0] - q[0]).hypot(p[1] - q[1]);
    (d(a0, b0) + d(a1, b1)).min(d(a0, b1) + d(a1, b0))
}

/// Whether `n` (a neighbour of `l` on the given side) runs the same way as `l`: the boundary of `n`
/// nearest to `l`'s shared boundary points the same way.
fn same_way(l: &LaneGeom, n: &LaneGeom, left: bool) -> bool {
    let shared = if left { &l.left } else { &l.right };
    let theirs = if mean_endpoint_gap(shared, &n.left) < mean_endpoint_gap(shared, &n.right) {
        &n.left
    } else {
        &n.right
    };
    let (a, b) = (dir(shared), dir(theirs));
    a[0] * b[0] + a[1] * b[1] > 0.0
}

/// Builds the road-side groups from the map's neighbour links.
pub fn build(map: &VectorMap, lanes: &[LaneGeom]) -> RoadSides {
    let n = lanes.len();
    let mut parent: Vec<usize> = (0..n).collect();
    let mut opposite_links = Vec::new();
    for (i, seg) in map.lanes.iter().enumerate() {
        for (nb, left) in [(seg.left_neighbor, true), (seg.right_neighbor, false)] {
            let Some(j) = nb.and_then(|id| map.lane_index(id)) else {
                continue;
            };
            if same_way(&lanes[i], &lanes[j], left) {
                let (a, b) = (find(&mut parent, i), find(&mut parent, j));
                parent[a.max(b)] = a.min(b);
            } else {
                opposite_links.push((i, j));
            }
        }
    }
    // Dense group ids in lane order.
    let mut group = vec![usize::MAX; n];
    let mut root_group = vec![usize::MAX; n];
    let mut members: Vec<Vec<LaneId>> = Vec::new();
    for i in 0..n {
        let r = find(&mut parent, i);
        if root_group[r] == usize::MAX {
            root_group[r] = members.len();
            members.push(Vec::new());
        }
        group[i] = root_group[r];
        members[group[i]].push(lanes[i].id);
    }
    for m in &mut members {
        m.sort_unstable();
    }
    let mut opposite = vec![BTreeSet::new(); members.len()];
    for (i, j) in opposite_links {
        let (gi, gj) = (group[i], group[j]);
        if gi != gj {
            opposite[gi].insert(gj);
            opposite[gj].insert(gi);
        }
    }
    RoadSides {
        group,
        opposite,
        members,
    }
}
