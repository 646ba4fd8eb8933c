//! The two ids every part of a scene is keyed by, in a module of their own so the scene, its
//! timeline and its colour cache all take them from below.

/// Compact id of a track inside one [`crate::Scene`]: the index into
/// [`crate::Scene::tracks`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct TrackId(pub u32);

impl TrackId {
    /// The index into [`crate::Scene::tracks`].
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A frame index of a log: 0..N over the annotation timestamps (10 Hz), in time order.
pub type Frame = u32;
