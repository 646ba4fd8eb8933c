//! [`Extractor`]: the per-scene context of a run. Everything derived from the scene (kinematics,
//! the map index, lane assignment, events, stop signs) is computed lazily once, and every answered
//! request is kept (answering is in [`crate::extract`]), so a run computes each thing once. It is `Sync`: requests may be answered from
//! several threads; each cached value is computed by one of them and shared.

use std::any::{Any, TypeId};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use scenalog_facts::relation::{RelationData, Request};
use scenalog_facts::{Frame, Scene};

use crate::events::{self, Side};
use crate::kinematics::{self, Kinematics};
use crate::lanes::{assign_track_indices, LaneAssignment};
use crate::map::stop_signs::{self, StopSign};
use crate::map::MapIndex;

/// Lazily computed, shared per-scene data and the answers given so far.
pub struct Extractor<'s> {
    scene: &'s Scene,
    kin: OnceLock<Kinematics>,
    map: OnceLock<MapIndex>,
    lane_indices: OnceLock<Vec<Vec<Option<usize>>>>,
    lanes: OnceLock<LaneAssignment>,
    turning: OnceLock<Vec<Vec<(Frame, Side)>>>,
    refav_turning: OnceLock<Vec<Vec<(Frame, Side)>>>,
    refav_turning_filtered: OnceLock<Vec<Vec<(Frame, Side)>>>,
    lane_changes: OnceLock<Vec<Vec<(Frame, Side)>>>,
    stop_signs: OnceLock<Vec<StopSign>>,
    extra: Mutex<HashMap<TypeId, Arc<dyn Any + Send + Sync>>>,
    results: Mutex<HashMap<String, (Request, Arc<RelationData>)>>,
}

impl std::fmt::Debug for Extractor<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Extractor")
            .field("log_id", &self.scene.log_id)
            .finish_non_exhaustive()
    }
}

impl<'s> Extractor<'s> {
    /// A context for `scene`; nothing is computed yet.
    pub fn new(scene: &'s Scene) -> Extractor<'s> {
        Extractor {
            scene,
            kin: OnceLock::new(),
            map: OnceLock::new(),
            lane_indices: OnceLock::new(),
            lanes: OnceLock::new(),
            turning: OnceLock::new(),
            refav_turning: OnceLock::new(),
            refav_turning_filtered: OnceLock::new(),
            lane_changes: OnceLock::new(),
            stop_signs: OnceLock::new(),
            extra: Mutex::new(HashMap::new()),
            results: Mutex::new(HashMap::new()),
        }
    }

    /// The scene.
    pub fn scene(&self) -> &'s Scene {
        self.scene
    }

    /// Kinematics of every track.
    pub fn kinematics(&self) -> &Kinematics {
        self.kin.get_or_init(|| kinematics::compute(self.scene))
    }

    /// The map prepared for queries (R-trees, lane chains, road sides).
    pub fn map_index(&self) -> &MapIndex {
        self.map.get_or_init(|| MapIndex::new(&self.scene.map))
    }

    /// Per track, per box: the assigned lane's index in the map's lanes.
    pub fn lane_indices(&self) -> &[Vec<Option<usize>>] {
        self.lane_indices.get_or_init(|| {
            use rayon::prelude::*;
            let index = self.map_index();
            self.kinematics()
                .tracks
                .par_iter()
                .map(|t| assign_track_indices(index, t))
                .collect()
        })
    }

    /// Per track, per box: the assigned lane's id.
    pub fn lanes(&self) -> &LaneAssignment {
        self.lanes.get_or_init(|| {
            let index = self.map_index();
            LaneAssignment {
                lanes: self
                    .lane_indices()
                    .iter()
                    .map(|t| t.iter().map(|l| l.map(|k| index.lanes[k].id)).collect())
                    .collect(),
            }
        })
    }

    /// Per track: its turning frames, in frame order.
    pub fn turning(&self) -> &[Vec<(Frame, Side)>] {
        self.turning.get_or_init(|| {
            self.kinematics()
                .tracks
                .iter()
                .map(events::turning)
                .collect()
        })
    }

    /// Per track: its turning frames as RefAV's `turning` finds them ([`crate::refav`]).
    pub fn refav_turning(&self) -> &[Vec<(Frame, Side)>] {
        self.refav_turning.get_or_init(|| {
            self.scene
                .tracks
                .iter()
                .map(|t| crate::refav::turning(self.scene, t))
                .collect()
        })
    }

    /// Per track: its turning frames by RefAV's rule on a median-filtered yaw rate
    /// ([`crate::refav::turning_filtered`]).
    pub fn refav_turning_filtered(&self) -> &[Vec<(Frame, Side)>] {
        self.refav_turning_filtered.get_or_init(|| {
            self.scene
                .tracks
                .iter()
                .map(|t| crate::refav::turning_filtered(self.scene, t))
                .collect()
        })
    }

    /// Per track: its lane-change frames, in frame order.
    pub fn lane_changes(&self) -> &[Vec<(Frame, Side)>] {
        self.lane_changes.get_or_init(|| {
            let (kin, lanes, turning) = (self.kinematics(), self.lane_indices(), self.turning());
            let index = self.map_index();
            use rayon::prelude::*;
            kin.tracks
                .par_iter()
                .zip(lanes)
                .zip(turning)
                .map(|((t, l), tu)| events::lane_changes(&self.scene.map, index, t, l, tu))
                .collect()
        })
    }

    /// Computes the shared derived data (kinematics, map index, lanes, events) up front, each step
    /// parallel inside, so relations answered in parallel afterwards do not wait on one another.
    pub fn prepare(&self) {
        self.kinematics();
        self.map_index();
        self.lane_indices();
        self.lanes();
        self.lane_changes();
    }

    /// The stop signs with their lanes.
    pub fn stop_signs(&self) -> &[StopSign] {
        self.stop_signs
            .get_or_init(|| stop_signs::stop_signs(self.scene, self.kinematics(), self.map_index()))
    }

    /// A value of type `T` computed once per scene by `init` (keyed by the type), for data other
    /// modules derive and share, e.g. per-frame R-trees of object boxes.
    pub fn cached<T: Any + Send + Sync>(&self, init: impl FnOnce(&Self) -> T) -> Arc<T> {
        let key = TypeId::of::<T>();
        if let Some(v) = self.lock_extra().get(&key).cloned() {
            if let Ok(v) = v.downcast::<T>() {
                return v;
            }
        }
        // Computed outside the lock (init may ask for other cached values); if two threads race,
        // the first stored value wins and both return it.
        let value: Arc<dyn Any + Send + Sync> = Arc::new(init(self));
        let stored = self.lock_extra().entry(key).or_insert(value).clone();
        match stored.downcast::<T>() {
            Ok(v) => v,
            Err(_) => unreachable!("the entry for TypeId::of::<T>() always holds a T"),
        }
    }

    fn lock_extra(&self) -> std::sync::MutexGuard<'_, HashMap<TypeId, Arc<dyn Any + Send + Sync>>> {
        self.extra.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The answers kept so far, by request (its text), with the request.
    pub(crate) fn answers(
        &self,
    ) -> std::sync::MutexGuard<'_, HashMap<String, (Request, Arc<RelationData>)>> {
        self.results.lock().unwrap_or_else(|e| e.into_inner())
    }
}
