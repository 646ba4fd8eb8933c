//! A summary of a [`Scene`] (what `scenalog facts LOG_DIR` prints), as data, text and JSON.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use crate::map::LaneId;
use crate::scene::Scene;

/// Counts describing one loaded log.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneSummary {
    /// The log id.
    pub log_id: String,
    /// The city code ("" when unknown).
    pub city: String,
    /// Number of annotation timestamps (frames holding data).
    pub timestamps: usize,
    /// The last frame on the 0.1 s grid (`timestamps - 1` for a 10 Hz log, more for a slower one).
    pub last_frame: u32,
    /// First annotation timestamp, ns (0 for an empty log).
    pub first_timestamp_ns: i64,
    /// Seconds from the first to the last annotation timestamp.
    pub duration_s: f64,
    /// Boxes over all tracks, the ego's included.
    pub boxes: usize,
    /// Tracks, the ego included.
    pub tracks: usize,
    /// The ego track's uuid.
    pub ego_uuid: String,
    /// Tracks per category, sorted by category.
    pub tracks_by_category: BTreeMap<String, usize>,
    /// Lane segments in the map.
    pub lane_segments: usize,
    /// Lane segments per lane type ("VEHICLE", "BIKE", "BUS"), sorted.
    pub lane_segments_by_type: BTreeMap<String, usize>,
    /// Lane segments in an intersection.
    pub intersection_lane_segments: usize,
    /// Distinct lane ids referenced by successors, predecessors or neighbours but absent from the map.
    pub dangling_lane_ids: usize,
    /// Pedestrian crossings.
    pub pedestrian_crossings: usize,
    /// Drivable areas.
    pub drivable_areas: usize,
}

impl SceneSummary {
    /// Summarises a scene.
    pub fn of(scene: &Scene) -> Self {
        let ts = scene.timeline.timestamps_ns();
        let first = ts.first().copied().unwrap_or_default();
        let last = ts.last().copied().unwrap_or_default();
        let lanes = &scene.map.lanes;
        let mut by_type = BTreeMap::new();
        for l in lanes {
            *by_type.entry(l.lane_type.as_str().to_owned()).or_insert(0) += 1;
        }
        let mut dangling: BTreeSet<LaneId> = BTreeSet::new();
        for l in lanes {
            let refs = l
                .successors
                .iter()
                .chain(&l.predecessors)
                .chain(&l.left_neighbor)
                .chain(&l.right_neighbor);
            dangling.extend(refs.filter(|&&id| scene.map.lane(id).is_none()));
        }
        SceneSummary {
            log_id: scene.log_id.clone(),
            city: scene.city.clone(),
            timestamps: ts.len(),
            last_frame: scene.timeline.frames().last().copied().unwrap_or(0),
            first_timestamp_ns: first,
            duration_s: (last - first) as f64 * 1e-9,
            boxes: scene.num_boxes(),
            tracks: scene.tracks.len(),
            ego_uuid: scene
                .tracks
                .get(scene.ego.index())
                .map(|t| t.uuid.clone())
                .unwrap_or_default(),
            tracks_by_category: scene.tracks_by_category(),
            lane_segments: lanes.len(),
            lane_segments_by_type: by_type,
            intersection_lane_segments: lanes.iter().filter(|l| l.is_intersection).count(),
            dangling_lane_ids: dangling.len(),
            pedestrian_crossings: scene.map.crossings.len(),
            drivable_areas: scene.map.drivable_areas.len(),
        }
    }

    /// The summary as one JSON object; keys are the field names.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "log_id": self.log_id,
            "city": self.city,
            "timestamps": self.timestamps,
            "last_frame": self.last_frame,
            "first_timestamp_ns": self.first_timestamp_ns,
            "duration_s": self.duration_s,
            "boxes": self.boxes,
            "tracks": self.tracks,
            "ego_uuid": self.ego_uuid,
            "tracks_by_category": self.tracks_by_category,
            "lane_segments": self.lane_segments,
            "lane_segments_by_type": self.lane_segments_by_type,
            "intersection_lane_segments": self.intersection_lane_segments,
            "dangling_lane_ids": self.dangling_lane_ids,
            "pedestrian_crossings": self.pedestrian_crossings,
            "drivable_areas": self.drivable_areas,
        })
    }

    /// The summary as text for people, several lines ending in a newline.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        let city = if self.city.is_empty() {
            "unknown"
        } else {
            &self.city
        };
        // Writing to a String cannot fail.
        let _ = writeln!(s, "log {} (city {city})", self.log_id);
        let _ = writeln!(
            s,
            "  timestamps  {} over {:.2} s (10 Hz frames 0..{})",
            self.timestamps, self.duration_s, self.last_frame
        );
        let _ = writeln!(s, "  boxes       {}", self.boxes);
        let _ = writeln!(s, "  tracks      {} (ego {})", self.tracks, self.ego_uuid);
        let width = self
            .tracks_by_category
            .keys()
            .map(String::len)
            .max()
            .unwrap_or(0);
        for (cat, n) in &self.tracks_by_category {
            let _ = writeln!(s, "    {cat:<width$}  {n:>4}");
        }
        let types: Vec<String> = self
            .lane_segments_by_type
            .iter()
            .map(|(t, n)| format!("{n} {t}"))
            .collect();
        let _ = writeln!(
            s,
            "  lane segments {} ({}; {} in intersections; {} dangling ids)",
            self.lane_segments,
            types.join(", "),
            self.intersection_lane_segments,
            self.dangling_lane_ids
        );
        let _ = writeln!(s, "  pedestrian crossings {}", self.pedestrian_crossings);
        let _ = writeln!(s, "  drivable areas {}", self.drivable_areas);
        s
    }
}
