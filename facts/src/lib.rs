//! Scenalog's facts: the Scene model and the catalog of relations.
//!
//! Owns: reading one Argoverse 2 log directory (annotations and ego poses from Arrow IPC files with
//! LZ4, the vector map from JSON) into a typed [`Scene`]; interning and the frame timeline; the
//! catalog of relations the extractors provide ([`catalog`]).
//!
//! Does not own: computing relations from a scene (the `extractors` crate) or anything about rules.
//!
//! Entry point: [`load_scene`] reads a log directory; [`LoadError`] says what was wrong with it.

#![warn(missing_docs)]

pub mod attributes;
pub mod catalog;
pub mod color;
pub mod conventions;
pub mod error;
pub mod ids;
pub mod intern;
pub mod map;
pub mod read;
pub mod relation;
pub mod scene;
pub mod summary;
pub mod time;
pub mod units;

pub use attributes::Attributes;
pub use color::ColorCache;
pub use error::LoadError;
pub use intern::{Interner, Sym};
pub use map::{DrivableArea, PedestrianCrossing};
pub use read::{box_scores, load_scene};
pub use summary::SceneSummary;

pub use map::{LaneId, LaneSegment, LaneType, VectorMap};
pub use scene::{Frame, Pose, Scene, Track, TrackBox, TrackId};
pub use time::Timeline;
