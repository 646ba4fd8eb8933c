//! Scenalog's tracker input: a 3D tracker's output as scenes the extractors and rules mine
//! exactly as they mine ground-truth annotations.
//!
//! Owns: reading the Argoverse 2 3D-tracking submission pickle (`{log_id: [frame, …]}`, each frame
//! a dict of numpy arrays `translation_m` (N×3, city frame), `size` (N×3, length/width/height),
//! `yaw` (N, city frame), `velocity_m_per_s` (optional), `label`, `name` (AV2 category strings),
//! `score`, `track_id`, and `timestamp_ns`), validating it, filtering spurious tracks, and building
//! one [`TrackedLog`] (a [`Scene`](scenalog_facts::Scene) plus each box's tracker score) per log with the ego poses and
//! vector map of the log's directory in the AV2 split. Does not own: unpickling itself (the `eval`
//! crate's generic layer, [`scenalog_eval::parse_pickle`]) or mining.
//!
//! **Coordinates.** Annotations store each box in the ego frame at its timestamp, upright in that
//! frame (a rotation about the ego's z axis), and a box's city pose is `ego_pose · box`. A
//! tracker box is given in the city frame as a centre `c` and a yaw `ψ`. With the ego pose
//! `P = (R, t)` of `city_SE3_egovehicle.feather` at the frame's timestamp, the box becomes:
//! centre `Rᵀ(c − t)` in the ego frame, rotation `Rz(θ)` about the ego's z axis (upright in the
//! ego frame, as annotations are) with `θ` the angle whose city pose has exactly the tracker's
//! yaw (`yaw(R·Rz(θ)) = ψ`, solved in closed form), and city pose `P · box`, as for
//! annotations. So a tracker file written from a log's own annotations (city centre `P·e`, city
//! yaw that of `R·R_e`) gives the annotations' boxes back to rounding, and the same facts.
//!
//! **Track ids** become per-log uuids, stable across runs: [`track_uuid`] (a SHA-256 of the log id
//! and the integer id, formatted as a uuid). A track's category is the most frequent `name` of its
//! boxes (the first seen on a tie). Every scene gets the ego track of annotations without one
//! (uuid `ego`, identity pose, AV2 ego size).
//!
//! **Confidence filter** ([`Filter::RefAv`], on by default): as RefAV, a track seen in one frame
//! whose score is at most 0.05, and a longer track whose lowest score is at most 0.005, are
//! dropped before mining.
//!
//! **Scores.** [`TrackedLog::scores`] holds each box's tracker score (1.0 for the ego), which the
//! predictions carry so the evaluation's per-prompt score thresholds work.

#![warn(missing_docs)]

pub mod build;
pub mod error;
pub mod filter;
pub mod frames;
pub mod input;

pub use build::{track_uuid, tracked_log, TrackedLog};
pub use error::TrackerError;
pub use filter::Filter;
pub use frames::Detections;
pub use input::TrackerPickle;
