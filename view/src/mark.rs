//! The geometric facts a proof (or a why-not report) contributes to a picture: a distance, a
//! sector, a lane, a crossing. Plain data, made by the caller from the proof's tuples.

use scenalog_facts::map::LaneId;
use scenalog_facts::scene::TrackId;

/// A side of an object's box, as the catalog's `direction` and `crossing` name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// Ahead of the box.
    Forward,
    /// Behind the box.
    Backward,
    /// To the box's left.
    Left,
    /// To the box's right.
    Right,
}

impl Side {
    /// Parses the catalog's name ("forward", "backward", "left", "right").
    pub fn parse(s: &str) -> Option<Side> {
        match s {
            "forward" => Some(Side::Forward),
            "backward" => Some(Side::Backward),
            "left" => Some(Side::Left),
            "right" => Some(Side::Right),
            _ => None,
        }
    }

    /// The side's direction in the box frame (x forward, y left), as a unit vector.
    pub fn unit(self) -> [f64; 2] {
        match self {
            Side::Forward => [1.0, 0.0],
            Side::Backward => [-1.0, 0.0],
            Side::Left => [0.0, 1.0],
            Side::Right => [0.0, -1.0],
        }
    }
}

/// What a geometric fact draws.
#[derive(Debug, Clone, PartialEq)]
pub enum Mark {
    /// `near(a, b, T, D)`: a line between the two objects labelled with the distance.
    Distance {
        /// First object.
        a: TrackId,
        /// Second object.
        b: TrackId,
        /// The distance between their ground rectangles, metres.
        metres: f64,
    },
    /// `direction(from, to, T, side, …)`: the sector on that side of `from`'s box.
    Sector {
        /// The object whose frame the sector is in.
        from: TrackId,
        /// The object found there.
        to: TrackId,
        /// Which side.
        side: Side,
    },
    /// `crossing(from, by, T, side)`: the 10 m half-plane on `from`'s side that `by` crosses.
    Crossing {
        /// The object whose side is crossed.
        from: TrackId,
        /// The object crossing it.
        by: TrackId,
        /// Which side.
        side: Side,
    },
    /// `in_lane(track, T, lane)`: the lane's polygon.
    Lane {
        /// The object.
        track: TrackId,
        /// The lane it is in.
        lane: LaneId,
    },
    /// `at_crosswalk(track, T, D)`: the nearest pedestrian crossing to the object.
    Crosswalk {
        /// The object.
        track: TrackId,
    },
    /// A link between two objects for any other pair fact (`following`, `at_stop_sign`, …).
    Link {
        /// First object.
        a: TrackId,
        /// Second object.
        b: TrackId,
    },
}

/// One fact to draw: the mark, the text to write by it, and whether it holds (a why-not
/// report's failing literal does not, and is drawn in the failure colour).
#[derive(Debug, Clone, PartialEq)]
pub struct Annotation {
    /// What to draw.
    pub mark: Mark,
    /// The label, e.g. `near 2.1 m`.
    pub label: String,
    /// False for the failing literal of a why-not picture.
    pub holds: bool,
}
