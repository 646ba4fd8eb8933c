//! Lane assignment: which lane segment each track's centre is in at each of its frames.
//!
//! The types here are the contract between map extraction and pair extraction.

use scenalog_facts::{LaneId, Scene};

use crate::kinematics::Kinematics;

/// Per track (indexed by `TrackId::index()`), per box (same order as `Track::boxes`): the lane the
/// track is assigned to at that frame, if its centre is in any lane.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LaneAssignment {
    /// `lanes[track][box]`.
    pub lanes: Vec<Vec<Option<LaneId>>>,
}

/// Assigns lanes to every track. (Implemented by the map work.)
pub fn assign(scene: &Scene, kin: &Kinematics) -> LaneAssignment {
    let _ = (scene, kin);
    LaneAssignment::default()
}
