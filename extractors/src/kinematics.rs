//! Kinematics of every track: smoothed city-frame positions and their derivatives, per box.
//!
//! The types here are the contract between kinematics, events, map and pair extraction.

use scenalog_facts::{Frame, Scene};

/// Kinematics of one track, one entry per box of the track (same order as `Track::boxes`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TrackKinematics {
    /// Frame of each entry.
    pub frames: Vec<Frame>,
    /// Raw city-frame box centre (x, y), metres.
    pub center: Vec<[f64; 2]>,
    /// Smoothed city-frame position (x, y), metres.
    pub pos: Vec<[f64; 2]>,
    /// Smoothed city-frame velocity (vx, vy), m/s.
    pub vel: Vec<[f64; 2]>,
    /// Speed, m/s (norm of `vel`).
    pub speed: Vec<f64>,
    /// Forward acceleration in the object's own frame, m/s².
    pub accel: Vec<f64>,
    /// Lateral acceleration in the object's own frame (+ left), m/s².
    pub lat_accel: Vec<f64>,
    /// Box heading (yaw) in the city frame, radians.
    pub yaw: Vec<f64>,
    /// Yaw rate, deg/s (+ counter-clockwise), unsmoothed.
    pub yaw_rate: Vec<f64>,
    /// Whether the whole track is stationary (smoothed positions' bounding-box diagonal < 3 m).
    pub stationary: bool,
}

impl TrackKinematics {
    /// Index of the entry at `frame`, if the track is annotated there.
    pub fn index_of(&self, frame: Frame) -> Option<usize> {
        self.frames.binary_search(&frame).ok()
    }
}

/// Kinematics of every track of a scene, indexed by `TrackId::index()`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Kinematics {
    /// One entry per track of the scene.
    pub tracks: Vec<TrackKinematics>,
}

/// Computes the kinematics of every track. (Implemented by the kinematics work.)
pub fn compute(scene: &Scene) -> Kinematics {
    let _ = scene;
    Kinematics::default()
}
