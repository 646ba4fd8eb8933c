//! Small synthetic scenes built in code, for tests whose answer is known by construction.
//!
//! Frames are 10 Hz from 0 ns; the ego pose is the identity at every frame, so ego-frame and
//! city-frame coordinates agree. The ego track ("ego") is added by [`SceneBuilder::build`] unless
//! one was added explicitly.

use std::collections::HashMap;

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion};
use scenalog_facts::map::{DrivableArea, PedestrianCrossing};
use scenalog_facts::scene::{EGO_CATEGORY, EGO_CENTRE_AHEAD_OF_AXLE_M, EGO_SIZE};
use scenalog_facts::{
    Frame, LaneId, LaneSegment, LaneType, Scene, Timeline, Track, TrackBox, TrackId, VectorMap,
};

/// One pose of a synthetic track: frame, city x, y (metres) and heading (radians).
pub type Waypoint = (Frame, f64, f64, f64);

/// Builds a [`Scene`] from tracks and map parts given in code.
#[derive(Debug, Clone, Default)]
pub struct SceneBuilder {
    frames: usize,
    tracks: Vec<(String, String, [f64; 3], Vec<Waypoint>)>,
    lanes: Vec<LaneSegment>,
    crossings: Vec<PedestrianCrossing>,
    areas: Vec<DrivableArea>,
}

fn pose(x: f64, y: f64, yaw: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(x, y, 0.0),
        UnitQuaternion::from_euler_angles(0.0, 0.0, yaw),
    )
}

fn pts(p: &[[f64; 2]]) -> Vec<Point3<f64>> {
    p.iter().map(|q| Point3::new(q[0], q[1], 0.0)).collect()
}

impl SceneBuilder {
    /// A scene of `frames` frames at 10 Hz.
    pub fn new(frames: usize) -> SceneBuilder {
        SceneBuilder {
            frames,
            ..SceneBuilder::default()
        }
    }

    /// Adds a track with one box per waypoint.
    pub fn track(mut self, uuid: &str, category: &str, size: [f64; 3], way: Vec<Waypoint>) -> Self {
        self.tracks
            .push((uuid.to_string(), category.to_string(), size, way));
        self
    }

    /// Adds the ego ("ego", `EGO_VEHICLE`, [`EGO_SIZE`]) with its rear axle (where AV2 puts the
    /// ego pose) at the waypoints: its box is the car's body, centred
    /// [`EGO_CENTRE_AHEAD_OF_AXLE_M`] ahead along the heading, as the log reader builds it.
    pub fn ego_at_rear_axle(self, way: Vec<Waypoint>) -> Self {
        let body = way
            .into_iter()
            .map(|(f, x, y, yaw)| {
                let a = EGO_CENTRE_AHEAD_OF_AXLE_M;
                (f, x + a * yaw.cos(), y + a * yaw.sin(), yaw)
            })
            .collect();
        self.track("ego", EGO_CATEGORY, EGO_SIZE, body)
    }

    /// Adds a lane from its left and right boundaries (direction of travel), successors and
    /// neighbours.
    #[allow(clippy::too_many_arguments)]
    pub fn lane(
        mut self,
        id: i64,
        left: &[[f64; 2]],
        right: &[[f64; 2]],
        successors: &[i64],
        left_neighbor: Option<i64>,
        right_neighbor: Option<i64>,
        is_intersection: bool,
    ) -> Self {
        self.lanes.push(LaneSegment {
            id: LaneId(id),
            lane_type: LaneType::Vehicle,
            is_intersection,
            left_boundary: pts(left),
            right_boundary: pts(right),
            left_mark_type: "DASHED_WHITE".into(),
            right_mark_type: "SOLID_WHITE".into(),
            successors: successors.iter().map(|&s| LaneId(s)).collect(),
            predecessors: Vec::new(),
            left_neighbor: left_neighbor.map(LaneId),
            right_neighbor: right_neighbor.map(LaneId),
        });
        self
    }

    /// Adds a straight lane along +x (or -x when `x1 < x0`) between `y_right` and `y_left`.
    pub fn straight_lane(self, id: i64, x0: f64, x1: f64, y_right: f64, y_left: f64) -> Self {
        self.lane(
            id,
            &[[x0, y_left], [x1, y_left]],
            &[[x0, y_right], [x1, y_right]],
            &[],
            None,
            None,
            false,
        )
    }

    /// Sets the type of the last lane added.
    pub fn lane_type(mut self, ty: LaneType) -> Self {
        if let Some(l) = self.lanes.last_mut() {
            l.lane_type = ty;
        }
        self
    }

    /// Adds a pedestrian crossing from its two edges.
    pub fn crossing(mut self, id: i64, edge1: &[[f64; 2]], edge2: &[[f64; 2]]) -> Self {
        self.crossings.push(PedestrianCrossing {
            id,
            edge1: pts(edge1),
            edge2: pts(edge2),
        });
        self
    }

    /// Adds a drivable area polygon.
    pub fn drivable_area(mut self, id: i64, boundary: &[[f64; 2]]) -> Self {
        self.areas.push(DrivableArea {
            id,
            boundary: pts(boundary),
        });
        self
    }

    /// The scene.
    pub fn build(self) -> Scene {
        let mut tracks = self.tracks;
        if !tracks.iter().any(|t| t.1 == EGO_CATEGORY) {
            let way = (0..self.frames as Frame)
                .map(|f| (f, -1000.0, -1000.0, 0.0))
                .collect();
            tracks.push(("ego".into(), EGO_CATEGORY.into(), EGO_SIZE, way));
        }
        // The order tracks were added in is the "file's" (`Track::file_order`).
        let mut tracks: Vec<(u32, _)> = tracks
            .into_iter()
            .enumerate()
            .map(|(i, t)| (i as u32, t))
            .collect();
        tracks.sort_by(|a, b| a.1 .0.cmp(&b.1 .0));
        let tracks: Vec<Track> = tracks
            .into_iter()
            .enumerate()
            .map(|(i, (file_order, (uuid, category, size, mut way)))| {
                way.sort_by_key(|w| w.0);
                let boxes = way
                    .into_iter()
                    .map(|(frame, x, y, yaw)| TrackBox {
                        frame,
                        ego: pose(x, y, yaw),
                        city: pose(x, y, yaw),
                        size,
                        num_interior_pts: 10,
                    })
                    .collect();
                Track {
                    id: TrackId(i as u32),
                    uuid,
                    category,
                    boxes,
                    file_order,
                }
            })
            .collect();
        let ego = tracks
            .iter()
            .find(|t| t.category == EGO_CATEGORY)
            .map_or(TrackId(0), |t| t.id);
        let track_by_uuid: HashMap<String, TrackId> =
            tracks.iter().map(|t| (t.uuid.clone(), t.id)).collect();
        Scene {
            log_id: "synthetic".into(),
            city: String::new(),
            timeline: Timeline::new((0..self.frames as i64).map(|i| i * 100_000_000).collect()),
            tracks,
            ego,
            ego_poses: vec![Isometry3::identity(); self.frames],
            map: VectorMap::new(self.lanes, self.crossings, self.areas),
            track_by_uuid,
            color_cache: scenalog_facts::ColorCache::Absent,
            attributes: scenalog_facts::Attributes::Absent,
        }
    }
}

/// Waypoints of a straight drive from `(x, y)` along `yaw` at `speed` m/s over frames `from..to`.
pub fn straight(from: Frame, to: Frame, x: f64, y: f64, yaw: f64, speed: f64) -> Vec<Waypoint> {
    (from..to)
        .map(|f| {
            let s = speed * 0.1 * (f - from) as f64;
            (f, x + s * yaw.cos(), y + s * yaw.sin(), yaw)
        })
        .collect()
}
