//! The lane as a driver sees it: a lane segment with the predecessors and successors that continue
//! it straight (the relation `same_lane` and `following` build on).
//!
//! Rule: from a segment, the chain continues forward into its successor when that successor is the
//! only one, or when it is the straightest successor and both the angle at the joint and the
//! successor's own heading change stay under [`LANE_CHAIN_STRAIGHT_MAX_DEG`] (so at an intersection
//! the chain goes straight on, not into the turn lanes). Backwards likewise with predecessors.
//! The chain reaches [`LANE_CHAIN_REACH_M`] of centreline beyond the segment each way (at most
//! [`LANE_CHAIN_MAX_SEGMENTS`] segments, so a map of degenerate, near-zero-length lanes cannot
//! make every chain as long as the map) and never loops.

use scenalog_facts::LaneId;

use super::lane_geom::LaneGeom;
use crate::kinematics::wrap_angle;
use crate::thresholds::{LANE_CHAIN_MAX_SEGMENTS, LANE_CHAIN_REACH_M, LANE_CHAIN_STRAIGHT_MAX_DEG};

/// The chain of every lane, indexed like [`scenalog_facts::VectorMap::lanes`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LaneChains {
    /// `chains[i]`: lane ids in driving order, from the farthest predecessor to the farthest
    /// successor, lane `i` itself included.
    pub chains: Vec<Vec<LaneId>>,
    /// `position[i]`: where lane `i` sits in `chains[i]` (earlier entries are behind it, later
    /// ones ahead).
    pub position: Vec<usize>,
}

impl LaneChains {
    /// The chain of the lane at index `i` (empty for an index out of range).
    pub fn chain(&self, i: usize) -> &[LaneId] {
        self.chains.get(i).map_or(&[], Vec::as_slice)
    }

    /// The lanes of lane `i`'s chain that lie ahead of it, nearest first.
    pub fn ahead(&self, i: usize) -> &[LaneId] {
        match (self.chains.get(i), self.position.get(i)) {
            (Some(c), Some(&p)) => &c[p + 1..],
            _ => &[],
        }
    }

    /// The lanes of lane `i`'s chain that lie behind it, farthest first.
    pub fn behind(&self, i: usize) -> &[LaneId] {
        match (self.chains.get(i), self.position.get(i)) {
            (Some(c), Some(&p)) => &c[..p],
            _ => &[],
        }
    }
}

fn angle_deg(a: f64, b: f64) -> f64 {
    wrap_angle(b - a).to_degrees().abs()
}

/// The successor of `c` that continues it straight, if any.
fn straight_successor(lanes: &[LaneGeom], c: usize) -> Option<usize> {
    let succ = &lanes[c].successors;
    if succ.len() == 1 {
        return Some(succ[0]);
    }
    succ.iter()
        .map(|&s| {
            let joint = angle_deg(lanes[c].end_heading, lanes[s].start_heading);
            (s, joint, lanes[s].turn_deg.abs())
        })
        .filter(|&(_, j, t)| j < LANE_CHAIN_STRAIGHT_MAX_DEG && t < LANE_CHAIN_STRAIGHT_MAX_DEG)
        .min_by(|a, b| (a.1 + a.2).total_cmp(&(b.1 + b.2)).then(a.0.cmp(&b.0)))
        .map(|(s, _, _)| s)
}

/// The predecessor of `c` that it continues straight, if any.
fn straight_predecessor(lanes: &[LaneGeom], c: usize) -> Option<usize> {
    let pred = &lanes[c].predecessors;
    if pred.len() == 1 {
        return Some(pred[0]);
    }
    pred.iter()
        .map(|&p| {
            let joint = angle_deg(lanes[p].end_heading, lanes[c].start_heading);
            (p, joint, lanes[p].turn_deg.abs())
        })
        .filter(|&(_, j, t)| j < LANE_CHAIN_STRAIGHT_MAX_DEG && t < LANE_CHAIN_STRAIGHT_MAX_DEG)
        .min_by(|a, b| (a.1 + a.2).total_cmp(&(b.1 + b.2)).then(a.0.cmp(&b.0)))
        .map(|(p, _, _)| p)
}

/// Lanes marked as seen in the current walk: a stamp per lane, so starting a new walk costs
/// nothing and a lookup is one comparison (no scan of the walk so far).
struct Seen {
    stamp: Vec<u32>,
    round: u32,
}

impl Seen {
    fn new(n: usize) -> Seen {
        Seen {
            stamp: vec![0; n],
            round: 0,
        }
    }

    /// Forgets every lane marked so far.
    fn clear(&mut self) {
        self.round += 1;
    }

    fn mark(&mut self, i: usize) {
        self.stamp[i] = self.round;
    }

    fn has(&self, i: usize) -> bool {
        self.stamp[i] == self.round
    }
}

/// From `start`, the lanes that continue it one `next` after another, until the chain reaches
/// [`LANE_CHAIN_REACH_M`] of centreline, [`LANE_CHAIN_MAX_SEGMENTS`] lanes, a dead end or a lane
/// already in it.
fn walk(next: &[Option<usize>], lanes: &[LaneGeom], start: usize, seen: &mut Seen) -> Vec<usize> {
    let mut out = Vec::new();
    let mut reach = 0.0;
    let mut cur = start;
    seen.clear();
    seen.mark(start);
    while reach < LANE_CHAIN_REACH_M && out.len() < LANE_CHAIN_MAX_SEGMENTS {
        let Some(n) = next[cur] else { break };
        if seen.has(n) {
            break;
        }
        seen.mark(n);
        out.push(n);
        reach += lanes[n].length;
        cur = n;
    }
    out
}

/// Builds the chain of every lane: each lane's straight successor and predecessor are chosen once
/// (linear in the map's links, however many a lane has), then each chain is walked in time
/// linear in its length.
pub fn build(lanes: &[LaneGeom]) -> LaneChains {
    let ahead: Vec<Option<usize>> = (0..lanes.len())
        .map(|i| straight_successor(lanes, i))
        .collect();
    let behind: Vec<Option<usize>> = (0..lanes.len())
        .map(|i| straight_predecessor(lanes, i))
        .collect();
    let mut seen = Seen::new(lanes.len());
    let mut chains = Vec::with_capacity(lanes.len());
    let mut position = Vec::with_capacity(lanes.len());
    for i in 0..lanes.len() {
        let mut back = walk(&behind, lanes, i, &mut seen);
        let fwd = walk(&ahead, lanes, i, &mut seen);
        // `seen` now holds the forward walk (and `i`): what the backward one shares with it goes.
        back.retain(|&b| !seen.has(b));
        back.reverse();
        position.push(back.len());
        let chain: Vec<LaneId> = back
            .iter()
            .chain(std::iter::once(&i))
            .chain(&fwd)
            .map(|&k| lanes[k].id)
            .collect();
        chains.push(chain);
    }
    LaneChains { chains, position }
}
