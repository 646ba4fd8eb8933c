//! Reading an AV2 vector map (`map/log_map_archive_*.json`) into a [`VectorMap`].
//!
//! The file is deserialised into typed structs mirroring its layout; a malformed document yields
//! [`LoadError::MapJson`] naming the field path (e.g. `lane_segments.37979824.lane_type`).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use nalgebra::Point3;
use serde::Deserialize;

use crate::error::LoadError;
use crate::map::{DrivableArea, LaneId, LaneSegment, LaneType, PedestrianCrossing, VectorMap};

use super::arrow_file::{file_error, io_error};

/// The prefix of the vector map's file name in a log's `map/` directory.
pub const MAP_FILE_PREFIX: &str = "log_map_archive_";

#[derive(Deserialize)]
struct MapFile {
    lane_segments: HashMap<String, LaneJson>,
    pedestrian_crossings: HashMap<String, CrossingJson>,
    drivable_areas: HashMap<String, AreaJson>,
}

#[derive(Deserialize)]
struct PointJson {
    x: f64,
    y: f64,
    z: f64,
}

#[derive(Deserialize)]
struct LaneJson {
    id: i64,
    is_intersection: bool,
    lane_type: String,
    left_lane_boundary: Vec<PointJson>,
    right_lane_boundary: Vec<PointJson>,
    left_lane_mark_type: String,
    right_lane_mark_type: String,
    successors: Vec<i64>,
    predecessors: Vec<i64>,
    #[serde(default)]
    left_neighbor_id: Option<i64>,
    #[serde(default)]
    right_neighbor_id: Option<i64>,
}

#[derive(Deserialize)]
struct CrossingJson {
    id: i64,
    edge1: Vec<PointJson>,
    edge2: Vec<PointJson>,
}

#[derive(Deserialize)]
struct AreaJson {
    id: i64,
    area_boundary: Vec<PointJson>,
}

/// Finds the one `map/log_map_archive_*.json` of a log directory.
pub(crate) fn find_map_file(log_dir: &Path) -> Result<PathBuf, LoadError> {
    let map_dir = log_dir.join("map");
    let entries = match std::fs::read_dir(&map_dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(LoadError::NoMapFile {
                path: log_dir.to_path_buf(),
            })
        }
        Err(source) => return Err(io_error(&map_dir, source)),
    };
    let mut found: Option<PathBuf> = None;
    for entry in entries {
        let entry = entry.map_err(|source| io_error(&map_dir, source))?;
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if name.starts_with(MAP_FILE_PREFIX) && name.ends_with(".json") {
            if let Some(prev) = &found {
                let mut names = [
                    prev.file_name()
                        .map(|n| n.to_string_lossy().into_owned())
                        .unwrap_or_default(),
                    name.into_owned(),
                ];
                names.sort();
                let [first, second] = names;
                return Err(LoadError::SeveralMapFiles {
                    path: map_dir,
                    first,
                    second,
                });
            }
            found = Some(entry.path());
        }
    }
    found.ok_or(LoadError::NoMapFile {
        path: log_dir.to_path_buf(),
    })
}

/// The city code in a map file name: `log_map_archive_<log>____MIA_city_47894.json` → "MIA";
/// empty when the name does not follow that pattern.
pub fn city_from_map_name(name: &str) -> String {
    name.rsplit_once("____")
        .and_then(|(_, rest)| rest.split('_').next())
        .filter(|c| !c.is_empty() && c.chars().all(|ch| ch.is_ascii_alphanumeric()))
        .map(str::to_owned)
        .unwrap_or_default()
}

/// Reads and converts a vector map file.
pub(crate) fn read_map(path: &Path) -> Result<VectorMap, LoadError> {
    let bytes = scenalog_input::read_file_checking_ends(
        path,
        scenalog_input::MAP_LIMIT,
        &scenalog_input::ends::json_object_ends,
    )
    .map_err(|problem| file_error(path, problem))?;
    parse_map(path, &bytes)
}

/// Converts the bytes of a vector map file (named `path` in errors).
pub(crate) fn parse_map(path: &Path, bytes: &[u8]) -> Result<VectorMap, LoadError> {
    // Fast path without path tracking; on failure, parse again tracking the path for the message.
    let file: MapFile = match serde_json::from_slice(bytes) {
        Ok(f) => f,
        Err(_) => return Err(locate_json_error(path, bytes)),
    };
    let bad = |field: String, message: String| LoadError::MapJson {
        path: path.to_path_buf(),
        field,
        message,
    };
    let check_key = |section: &str, key: &str, id: i64| {
        if key.parse::<i64>().ok() == Some(id) {
            Ok(())
        } else {
            Err(bad(
                format!("{section}.{key}.id"),
                format!("id {id} differs from its key `{key}`; expected the key to be the id"),
            ))
        }
    };

    let mut lanes = Vec::with_capacity(file.lane_segments.len());
    for (key, l) in &file.lane_segments {
        check_key("lane_segments", key, l.id)?;
        let lane_type = LaneType::parse(&l.lane_type).ok_or_else(|| {
            bad(
                format!("lane_segments.{key}.lane_type"),
                format!(
                    "unknown lane type `{}`; expected \"VEHICLE\", \"BIKE\" or \"BUS\"",
                    l.lane_type
                ),
            )
        })?;
        lanes.push(LaneSegment {
            id: LaneId(l.id),
            lane_type,
            is_intersection: l.is_intersection,
            left_boundary: points(&l.left_lane_boundary),
            right_boundary: points(&l.right_lane_boundary),
            left_mark_type: l.left_lane_mark_type.clone(),
            right_mark_type: l.right_lane_mark_type.clone(),
            successors: l.successors.iter().map(|&i| LaneId(i)).collect(),
            predecessors: l.predecessors.iter().map(|&i| LaneId(i)).collect(),
            left_neighbor: l.left_neighbor_id.map(LaneId),
            right_neighbor: l.right_neighbor_id.map(LaneId),
        });
    }
    let mut crossings = Vec::with_capacity(file.pedestrian_crossings.len());
    for (key, c) in &file.pedestrian_crossings {
        check_key("pedestrian_crossings", key, c.id)?;
        crossings.push(PedestrianCrossing {
            id: c.id,
            edge1: points(&c.edge1),
            edge2: points(&c.edge2),
        });
    }
    let mut areas = Vec::with_capacity(file.drivable_areas.len());
    for (key, a) in &file.drivable_areas {
        check_key("drivable_areas", key, a.id)?;
        areas.push(DrivableArea {
            id: a.id,
            boundary: points(&a.area_boundary),
        });
    }
    Ok(VectorMap::new(lanes, crossings, areas))
}

/// The error of a map document that failed to parse, with the path of the offending field.
fn locate_json_error(path: &Path, bytes: &[u8]) -> LoadError {
    let mut de = serde_json::Deserializer::from_slice(bytes);
    let (field, message) = match serde_path_to_error::deserialize::<_, MapFile>(&mut de) {
        Err(e) => (e.path().to_string(), e.into_inner().to_string()),
        Ok(_) => match de.end() {
            Err(e) => (".".to_owned(), e.to_string()),
            Ok(()) => (".".to_owned(), "invalid JSON".to_owned()),
        },
    };
    LoadError::MapJson {
        path: path.to_path_buf(),
        field,
        message,
    }
}

fn points(ps: &[PointJson]) -> Vec<Point3<f64>> {
    ps.iter().map(|p| Point3::new(p.x, p.y, p.z)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn city_codes_from_file_names() {
        assert_eq!(
            city_from_map_name(
                "log_map_archive_3b3570b4-7b0b-3268-a571-b0889dbf40b6____MIA_city_47894.json"
            ),
            "MIA"
        );
        assert_eq!(
            city_from_map_name("log_map_archive_x____PIT_city_1.json"),
            "PIT"
        );
        assert_eq!(city_from_map_name("log_map_archive_x.json"), "");
    }

    #[test]
    fn wrong_type_names_the_field() {
        let text = br#"{"lane_segments": {"1": {"id": 1, "is_intersection": "no"}},
                        "pedestrian_crossings": {}, "drivable_areas": {}}"#;
        let err = parse_map(Path::new("m.json"), text).err();
        let msg = err.map(|e| e.to_string()).unwrap_or_default();
        assert!(msg.contains("lane_segments.1.is_intersection"), "{msg}");
        assert!(msg.starts_with("m.json: "), "{msg}");
    }

    #[test]
    fn trailing_garbage_is_an_error_on_the_whole_file() {
        let text = br#"{"lane_segments": {}, "pedestrian_crossings": {}, "drivable_areas": {}} x"#;
        let err = parse_map(Path::new("m.json"), text).err();
        let msg = err.map(|e| e.to_string()).unwrap_or_default();
        assert!(
            msg.starts_with("m.json: field `.`: trailing characters"),
            "{msg}"
        );
    }

    #[test]
    fn id_must_match_key_and_duplicate_free_map_builds() {
        let text = br#"{"lane_segments": {}, "pedestrian_crossings":
            {"7": {"id": 8, "edge1": [], "edge2": []}}, "drivable_areas": {}}"#;
        let msg = parse_map(Path::new("m.json"), text)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(msg.contains("pedestrian_crossings.7.id"), "{msg}");

        let ok = br#"{"lane_segments": {}, "pedestrian_crossings": {}, "drivable_areas":
            {"3": {"id": 3, "area_boundary": [{"x": 1, "y": 2, "z": 3}]}}}"#;
        let map = parse_map(Path::new("m.json"), ok).ok();
        assert_eq!(map.map(|m| m.drivable_areas[0].boundary.len()), Some(1));
    }
}
