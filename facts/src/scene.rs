//! The Scene model: one Argoverse 2 log as typed data (tracks, ego poses, vector map).
//!
//! Everything here is plain data. Reading it from disk lives in [`crate::read`].

use std::collections::HashMap;

use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};

use crate::map::VectorMap;
use crate::time::Timeline;

pub use crate::ids::{Frame, TrackId};

/// The category AV2 gives the ego vehicle.
pub const EGO_CATEGORY: &str = "EGO_VEHICLE";

/// Size (length, width, height in metres) AV2 uses for the ego vehicle's box.
pub const EGO_SIZE: [f64; 3] = [4.877, 2.0, 1.473];

/// How far the ego vehicle's body reaches behind its rear axle, in metres. The ego pose (and the
/// `EGO_VEHICLE` rows AV2 and RefAV write) is the rear axle's, but the car extends from about
/// 1.0 m behind it to about 3.9 m ahead of it.
pub const EGO_REAR_OVERHANG_M: f64 = 1.0;

/// How far ahead of the rear axle the centre of the ego vehicle's body lies, along its heading:
/// half the length ([`EGO_SIZE`]) less the rear overhang, so the box spans −1.0 m to +3.877 m.
pub const EGO_CENTRE_AHEAD_OF_AXLE_M: f64 = EGO_SIZE[0] / 2.0 - EGO_REAR_OVERHANG_M;

/// The pose of the ego vehicle's box in the ego frame (the rear axle's): its body, not the axle.
pub fn ego_box_in_ego_frame() -> Pose {
    Pose::translation(EGO_CENTRE_AHEAD_OF_AXLE_M, 0.0, 0.0)
}

/// The AV2 categories that make up the "VEHICLE" super-category (the catalog's `category` doc
/// and the prompt's conventions use the same list).
pub const VEHICLE_CATEGORIES: &[&str] = &[
    "EGO_VEHICLE",
    "ARTICULATED_BUS",
    "BOX_TRUCK",
    "BUS",
    "LARGE_VEHICLE",
    "MOTORCYCLE",
    "RAILED_VEHICLE",
    "REGULAR_VEHICLE",
    "SCHOOL_BUS",
    "TRUCK",
    "TRUCK_CAB",
];

/// Every category of the AV2 sensor dataset's annotation taxonomy, plus the ego.
pub const ALL_CATEGORIES: &[&str] = &[
    "ANIMAL",
    "ARTICULATED_BUS",
    "BICYCLE",
    "BICYCLIST",
    "BOLLARD",
    "BOX_TRUCK",
    "BUS",
    "CONSTRUCTION_BARREL",
    "CONSTRUCTION_CONE",
    "DOG",
    "EGO_VEHICLE",
    "LARGE_VEHICLE",
    "MESSAGE_BOARD_TRAILER",
    "MOBILE_PEDESTRIAN_CROSSING_SIGN",
    "MOTORCYCLE",
    "MOTORCYCLIST",
    "OFFICIAL_SIGNALER",
    "PEDESTRIAN",
    "RAILED_VEHICLE",
    "REGULAR_VEHICLE",
    "SCHOOL_BUS",
    "SIGN",
    "STOP_SIGN",
    "STROLLER",
    "TRAFFIC_LIGHT_TRAILER",
    "TRUCK",
    "TRUCK_CAB",
    "VEHICULAR_TRAILER",
    "WHEELCHAIR",
    "WHEELED_DEVICE",
    "WHEELED_RIDER",
];

/// Super-categories that name groups of AV2 categories ("ANY" is every object).
pub const SUPER_CATEGORIES: &[&str] = &["VEHICLE", "ANY", "CONSTRUCTION"];

/// Whether `category` belongs to the "VEHICLE" super-category.
pub fn is_vehicle_category(category: &str) -> bool {
    VEHICLE_CATEGORIES.contains(&category)
}

/// The AV2 categories of the "CONSTRUCTION" super-category: the temporary traffic-control
/// objects of road works (cones, barrels, message-board and traffic-light trailers, mobile
/// pedestrian-crossing signs). AV2 has no construction-sign class (`SIGN` is any sign) and
/// bollards are permanent, so neither is included; nor is `OFFICIAL_SIGNALER` (a person).
pub const CONSTRUCTION_CATEGORIES: &[&str] = &[
    "CONSTRUCTION_BARREL",
    "CONSTRUCTION_CONE",
    "MESSAGE_BOARD_TRAILER",
    "MOBILE_PEDESTRIAN_CROSSING_SIGN",
    "TRAFFIC_LIGHT_TRAILER",
];

/// Whether `category` belongs to the "CONSTRUCTION" super-category.
pub fn is_construction_category(category: &str) -> bool {
    CONSTRUCTION_CATEGORIES.contains(&category)
}

/// A rigid pose: rotation then translation, `p_out = R p_in + t`.
pub type Pose = Isometry3<f64>;

/// One annotated box of a track at one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackBox {
    /// The frame this box belongs to.
    pub frame: Frame,
    /// Box pose in the ego frame at this timestamp, as stored in the annotations.
    pub ego: Pose,
    /// Box pose in the city frame: `ego_pose(frame) * ego`.
    pub city: Pose,
    /// Length (along the box x axis), width (y) and height (z), metres.
    pub size: [f64; 3],
    /// LiDAR points inside the box (0 for the synthesised ego track).
    pub num_interior_pts: i64,
}

impl TrackBox {
    /// Box centre in the city frame.
    pub fn city_center(&self) -> Point3<f64> {
        Point3::from(self.city.translation.vector)
    }

    /// Heading (rotation about z) of the box in the city frame, radians in (-π, π].
    pub fn city_yaw(&self) -> f64 {
        yaw_of(&self.city.rotation)
    }

    /// Heading of the box in the ego frame, radians in (-π, π].
    pub fn ego_yaw(&self) -> f64 {
        yaw_of(&self.ego.rotation)
    }
}

/// The yaw (rotation about +z) of a rotation, radians in (-π, π].
pub fn yaw_of(q: &UnitQuaternion<f64>) -> f64 {
    let r = q.to_rotation_matrix();
    let m = r.matrix();
    m[(1, 0)].atan2(m[(0, 0)])
}

/// One tracked object of a log: its identity and one box per annotated frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    /// The compact id: this track's index in [`Scene::tracks`].
    pub id: TrackId,
    /// The AV2 track uuid.
    pub uuid: String,
    /// The AV2 category, e.g. "REGULAR_VEHICLE".
    pub category: String,
    /// Boxes sorted by frame, at most one per frame.
    pub boxes: Vec<TrackBox>,
    /// The track's rank among the annotation file's tracks by the row where each first appears
    /// (0 for the first): RefAV's order of candidates (`track_uuid.unique()`). An ego the loader
    /// adds comes last; a tracker's scene, which has no annotation rows, orders its tracks by
    /// first frame, then tracker id.
    pub file_order: u32,
}

impl Track {
    /// The box at `frame`, if the track is annotated there.
    pub fn box_at(&self, frame: Frame) -> Option<&TrackBox> {
        self.boxes
            .binary_search_by_key(&frame, |b| b.frame)
            .ok()
            .map(|i| &self.boxes[i])
    }

    /// First and last annotated frame.
    pub fn frame_span(&self) -> Option<(Frame, Frame)> {
        Some((self.boxes.first()?.frame, self.boxes.last()?.frame))
    }
}

/// One Argoverse 2 log: its timeline, tracks (the ego among them), ego poses and vector map.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The log id (the log directory's name).
    pub log_id: String,
    /// City code from the map file name ("MIA", "PIT", …), empty when unknown.
    pub city: String,
    /// The timestamps as frames on the 10 Hz grid (`time.rs`).
    pub timeline: Timeline,
    /// Every track, the ego included; `tracks[i].id == TrackId(i)`. Sorted by uuid.
    pub tracks: Vec<Track>,
    /// The ego vehicle's track.
    pub ego: TrackId,
    /// The ego pose in the city frame at each frame of the grid (`p_city = pose * p_ego`); a
    /// frame without a timestamp has the pose of the frame before it.
    pub ego_poses: Vec<Pose>,
    /// The vector map.
    pub map: VectorMap,
    /// uuid → track id.
    pub track_by_uuid: HashMap<String, TrackId>,
    /// RefAV's colour cache of the log (`cache/color_cache.json`), for `refav_color`.
    pub color_cache: crate::color::ColorCache,
    /// The log's attributes file (`attributes.csv`), for `attribute`.
    pub attributes: crate::attributes::Attributes,
}

impl Scene {
    /// The track with this id. Ids come from this scene, so this is an index.
    pub fn track(&self, id: TrackId) -> &Track {
        &self.tracks[id.index()]
    }

    /// The track with this uuid, if any.
    pub fn track_by_uuid(&self, uuid: &str) -> Option<&Track> {
        self.track_by_uuid.get(uuid).map(|&id| self.track(id))
    }

    /// Number of frames of the grid, the last frame plus one (the number of timestamps for a
    /// 10 Hz log; frames between a slower input's timestamps hold no boxes).
    pub fn num_frames(&self) -> usize {
        self.timeline.frame_count()
    }

    /// Maps a point in the ego frame at `frame` to the city frame.
    pub fn ego_to_city(&self, frame: Frame, p: &Point3<f64>) -> Option<Point3<f64>> {
        self.ego_poses.get(frame as usize).map(|pose| pose * p)
    }

    /// Maps a point in the city frame to the ego frame at `frame`.
    pub fn city_to_ego(&self, frame: Frame, p: &Point3<f64>) -> Option<Point3<f64>> {
        self.ego_poses
            .get(frame as usize)
            .map(|pose| pose.inverse_transform_point(p))
    }

    /// Number of tracks per category, sorted by category.
    pub fn tracks_by_category(&self) -> std::collections::BTreeMap<String, usize> {
        let mut out = std::collections::BTreeMap::new();
        for t in &self.tracks {
            *out.entry(t.category.clone()).or_insert(0) += 1;
        }
        out
    }

    /// Total number of boxes over all tracks (the ego's included).
    pub fn num_boxes(&self) -> usize {
        self.tracks.iter().map(|t| t.boxes.len()).sum()
    }
}

/// Builds a pose from a scalar-first quaternion and a translation, normalising the quaternion.
pub fn pose_from_parts(qw: f64, qx: f64, qy: f64, qz: f64, t: [f64; 3]) -> Pose {
    let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(qw, qx, qy, qz));
    Isometry3::from_parts(Vector3::new(t[0], t[1], t[2]).into(), q)
}
