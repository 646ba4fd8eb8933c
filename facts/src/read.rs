//! Reading one Argoverse 2 log directory into a [`Scene`].
//!
//! A log directory holds:
//! - `annotations_with_ego.feather` (preferred when present; has one `EGO_VEHICLE` row per
//!   timestamp), `annotations.feather` (no ego rows) or RefAV's `sm_annotations.feather` (a
//!   tracker's output with a `score` column, read by [`box_scores`]): Arrow IPC files, one row
//!   per (track, timestamp) with the box in the ego frame;
//! - `city_SE3_egovehicle.feather`: the ego pose in the city frame at ~200 Hz;
//! - `map/log_map_archive_*.json`: the vector map; the city code is taken from its name.
//!
//! Semantics:
//! - frames are the sorted distinct annotation timestamps;
//! - every annotation timestamp must have an ego pose with exactly that timestamp;
//! - a box's city pose is `ego_pose(frame) * box_ego_pose`;
//! - when the annotations have no `EGO_VEHICLE` track (the plain variant), an ego track with uuid
//!   [`ADDED_EGO_UUID`] is added: category `EGO_VEHICLE`, size [`EGO_SIZE`], one box per frame,
//!   `num_interior_pts` 0;
//! - the ego's box is the car's body, not its rear axle (where the ego pose and the files' ego
//!   rows are): centred [`EGO_CENTRE_AHEAD_OF_AXLE_M`](crate::scene::EGO_CENTRE_AHEAD_OF_AXLE_M) ahead of the axle along its heading
//!   ([`ego_box_in_ego_frame`]), so it spans about −1.0 m to +3.9 m; a file's ego row at the axle
//!   (identity in the ego frame) is moved there too;
//! - tracks are sorted by uuid and `tracks[i].id == TrackId(i)`; boxes are sorted by frame;
//! - map ids pointing to lanes absent from the map are kept (dangling).
//!
//! Only the needed columns are decoded, rows are processed column-wise without per-row
//! allocation, and poses are matched to annotation timestamps by binary search.

mod arrow_file;
mod map_json;

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

use crate::error::LoadError;
use crate::scene::{
    ego_box_in_ego_frame, Frame, Pose, Scene, Track, TrackBox, TrackId, EGO_CATEGORY, EGO_SIZE,
};
use crate::time::Timeline;

use arrow_file::{any_floats, f64s, file_error, i64s, read_table, Kind, Strs, Table};
pub use map_json::{city_from_map_name, MAP_FILE_PREFIX};
use scenalog_input::FileProblem;

/// The annotations file with ego rows (preferred when both exist).
pub const ANNOTATIONS_WITH_EGO_FILE: &str = "annotations_with_ego.feather";
/// The plain annotations file (no ego rows).
pub const ANNOTATIONS_FILE: &str = "annotations.feather";
/// The ego pose file.
pub const EGO_POSES_FILE: &str = "city_SE3_egovehicle.feather";
/// The uuid of the ego track added to logs whose annotations have no `EGO_VEHICLE` track.
pub const ADDED_EGO_UUID: &str = "ego";

/// Quaternions shorter than this name no rotation and are rejected.
const MIN_QUATERNION_NORM: f64 = 1e-6;

const ANNOTATION_COLUMNS: &[(&str, Kind)] = &[
    ("timestamp_ns", Kind::Int64),
    ("track_uuid", Kind::Str),
    ("category", Kind::Str),
    ("length_m", Kind::Float64),
    ("width_m", Kind::Float64),
    ("height_m", Kind::Float64),
    ("qw", Kind::Float64),
    ("qx", Kind::Float64),
    ("qy", Kind::Float64),
    ("qz", Kind::Float64),
    ("tx_m", Kind::Float64),
    ("ty_m", Kind::Float64),
    ("tz_m", Kind::Float64),
    ("num_interior_pts", Kind::Int64),
];

const POSE_COLUMNS: &[(&str, Kind)] = &[
    ("timestamp_ns", Kind::Int64),
    ("qw", Kind::Float64),
    ("qx", Kind::Float64),
    ("qy", Kind::Float64),
    ("qz", Kind::Float64),
    ("tx_m", Kind::Float64),
    ("ty_m", Kind::Float64),
    ("tz_m", Kind::Float64),
];

/// Reads the log in `log_dir` (annotations, ego poses, vector map) into a [`Scene`].
///
/// See the module documentation for the files read and the semantics. Any problem with the input
/// is a [`LoadError`] naming the file; this never panics on input.
pub fn load_scene(log_dir: &Path) -> Result<Scene, LoadError> {
    match scenalog_input::directory(log_dir) {
        Ok(()) => {}
        Err(FileProblem::NotFound) => {
            return Err(LoadError::MissingFile {
                path: log_dir.to_path_buf(),
                expected: "an Argoverse 2 log directory",
            })
        }
        Err(problem) => return Err(file_error(log_dir, problem)),
    }
    let ann_path = annotations_path(log_dir)?;
    let pose_path = log_dir.join(EGO_POSES_FILE);
    let map_path = map_json::find_map_file(log_dir)?;

    let ann = read_table(&ann_path, ANNOTATION_COLUMNS)?;
    check_finite(&ann_path, &ann, ANNOTATION_COLUMNS)?;
    let mut stamps = Vec::with_capacity(ann.num_rows());
    for b in &ann.batches {
        stamps.extend_from_slice(i64s(b.column(0)));
    }
    let timeline = Timeline::new(stamps);

    let ego_poses = timeline.per_frame(&ego_poses_at(
        &pose_path,
        &ann_path,
        timeline.timestamps_ns(),
    )?);
    let tracks = build_tracks(&ann_path, &ann, &timeline, &ego_poses)?;
    let ego = tracks
        .iter()
        .find(|t| t.category == EGO_CATEGORY)
        .map(|t| t.id)
        .unwrap_or(TrackId(0));
    let track_by_uuid: std::collections::HashMap<String, TrackId> =
        tracks.iter().map(|t| (t.uuid.clone(), t.id)).collect();

    let map = map_json::read_map(&map_path)?;
    let city = map_path
        .file_name()
        .map(|n| city_from_map_name(&n.to_string_lossy()))
        .unwrap_or_default();

    let color_cache = crate::color::read_color_cache(log_dir, |u| track_by_uuid.get(u).copied());
    let attributes = crate::attributes::read_attributes(log_dir, |u| track_by_uuid.get(u).copied());
    Ok(Scene {
        log_id: log_id_of(log_dir),
        city,
        timeline,
        tracks,
        ego,
        ego_poses,
        map,
        track_by_uuid,
        color_cache,
        attributes,
    })
}

/// The ego pose at each of `stamps` (sorted, distinct) from `log_dir/city_SE3_egovehicle.feather`,
/// for scenes whose objects come from elsewhere (a tracker's output): a timestamp without a pose
/// is a [`LoadError::NoEgoPose`] naming `source` as where the timestamp came from.
pub fn ego_poses(log_dir: &Path, source: &Path, stamps: &[i64]) -> Result<Vec<Pose>, LoadError> {
    ego_poses_at(&log_dir.join(EGO_POSES_FILE), source, stamps)
}

/// The vector map of a log directory (`map/log_map_archive_*.json`) and its city code.
pub fn log_map(log_dir: &Path) -> Result<(crate::map::VectorMap, String), LoadError> {
    let map_path = map_json::find_map_file(log_dir)?;
    let map = map_json::read_map(&map_path)?;
    let city = map_path
        .file_name()
        .map(|n| city_from_map_name(&n.to_string_lossy()))
        .unwrap_or_default();
    Ok((map, city))
}

/// The ego track a scene without an `EGO_VEHICLE` track gets: uuid [`ADDED_EGO_UUID`], the car's
/// body in the ego frame ([`ego_box_in_ego_frame`]), size [`EGO_SIZE`], one box at each of
/// `frames` (the timeline's frames holding data; `ego_poses` is indexed by frame).
pub fn added_ego(ego_poses: &[Pose], frames: &[Frame]) -> (String, Vec<TrackBox>) {
    let b = added_ego_track(ego_poses, frames);
    (b.uuid.to_string(), b.boxes)
}

/// The log id: the directory's name (resolving `.` and the like).
fn log_id_of(log_dir: &Path) -> String {
    let name = |p: &Path| p.file_name().map(|n| n.to_string_lossy().into_owned());
    name(log_dir)
        .or_else(|| log_dir.canonicalize().ok().as_deref().and_then(name))
        .unwrap_or_default()
}

/// RefAV's per-log form of a tracker's output (`sm_annotations.feather`): the annotation
/// columns, a `score` column, and the ego as an `EGO_VEHICLE` track with uuid `ego`.
pub const REFAV_ANNOTATIONS_FILE: &str = "sm_annotations.feather";

/// The per-box confidence of a log whose annotations carry a `score` column (RefAV's per-log
/// form of a tracker's output, [`REFAV_ANNOTATIONS_FILE`]): `scores[track][box]`, aligned with
/// `scene.tracks[track].boxes[box]`; `None` when there is no such column (ground truth). A box
/// the file has no score for (the ego added to a plain log) scores 1.0; a score that is not a
/// finite number is an error naming the row.
pub fn box_scores(log_dir: &Path, scene: &Scene) -> Result<Option<Vec<Vec<f32>>>, LoadError> {
    const COLUMNS: &[(&str, Kind)] = &[
        ("timestamp_ns", Kind::Int64),
        ("track_uuid", Kind::Str),
        ("score", Kind::AnyFloat),
    ];
    let path = annotations_path(log_dir)?;
    let table = match read_table(&path, COLUMNS) {
        Ok(t) => t,
        Err(LoadError::MissingColumn {
            column: "score", ..
        }) => return Ok(None),
        Err(e) => return Err(e),
    };
    let mut by_box: HashMap<(&str, i64), f32> = HashMap::new();
    let mut first_row = 0;
    for b in &table.batches {
        let stamps = i64s(b.column(0));
        let uuids = Strs::of(b.column(1));
        let scores = any_floats(b.column(2));
        for (row, (&t, &score)) in stamps.iter().zip(&scores).enumerate() {
            if !score.is_finite() {
                return Err(LoadError::NonFinite {
                    path: path.clone(),
                    column: "score",
                    row: first_row + row,
                    value: score,
                });
            }
            by_box.insert((uuids.get(row), t), score as f32);
        }
        first_row += b.num_rows();
    }
    let timeline = &scene.timeline;
    Ok(Some(
        scene
            .tracks
            .iter()
            .map(|track| {
                track
                    .boxes
                    .iter()
                    .map(|b| {
                        timeline
                            .ns(b.frame)
                            .and_then(|t| by_box.get(&(track.uuid.as_str(), t)))
                            .copied()
                            .unwrap_or(1.0)
                    })
                    .collect()
            })
            .collect(),
    ))
}

/// The annotations file: the first of the three names that is there. Something there that is
/// not a readable regular file (a FIFO, a symlink loop, a directory that cannot be searched) is
/// reported as what it is, not as missing.
fn annotations_path(log_dir: &Path) -> Result<PathBuf, LoadError> {
    for name in [
        ANNOTATIONS_WITH_EGO_FILE,
        ANNOTATIONS_FILE,
        REFAV_ANNOTATIONS_FILE,
    ] {
        let p = log_dir.join(name);
        match scenalog_input::regular_file(&p) {
            Ok(_) => return Ok(p),
            Err(FileProblem::NotFound) => {}
            Err(problem) => return Err(file_error(&p, problem)),
        }
    }
    Err(LoadError::MissingFile {
        path: log_dir.join(ANNOTATIONS_FILE),
        expected: "annotations_with_ego.feather, annotations.feather or sm_annotations.feather in the log directory",
    })
}

/// Rejects NaN and infinities in every float column of `wanted`.
fn check_finite(
    path: &Path,
    table: &Table,
    wanted: &[(&'static str, Kind)],
) -> Result<(), LoadError> {
    let mut first_row = 0;
    for b in &table.batches {
        for (i, &(column, kind)) in wanted.iter().enumerate() {
            if kind != Kind::Float64 {
                continue;
            }
            let values = f64s(b.column(i));
            if let Some(row) = values.iter().position(|v| !v.is_finite()) {
                return Err(LoadError::NonFinite {
                    path: path.to_path_buf(),
                    column,
                    row: first_row + row,
                    value: values[row],
                });
            }
        }
        first_row += b.num_rows();
    }
    Ok(())
}

/// Builds a pose from a scalar-first quaternion and a translation, rejecting a zero quaternion.
fn checked_pose(path: &Path, row: usize, q: [f64; 4], t: [f64; 3]) -> Result<Pose, LoadError> {
    let q = Quaternion::new(q[0], q[1], q[2], q[3]);
    let norm = q.norm();
    if norm < MIN_QUATERNION_NORM {
        return Err(LoadError::BadQuaternion {
            path: path.to_path_buf(),
            row,
            norm,
        });
    }
    Ok(Isometry3::from_parts(
        Translation3::new(t[0], t[1], t[2]),
        UnitQuaternion::new_unchecked(q / norm),
    ))
}

/// The ego pose at each of `stamps` (sorted, distinct), from the pose file.
fn ego_poses_at(pose_path: &Path, ann_path: &Path, stamps: &[i64]) -> Result<Vec<Pose>, LoadError> {
    let table = read_table(pose_path, POSE_COLUMNS)?;
    // (timestamp, batch, row in batch, row in file), sorted by timestamp.
    let mut index: Vec<(i64, u32, u32, u32)> = Vec::with_capacity(table.num_rows());
    let mut first_row = 0usize;
    for (bi, b) in table.batches.iter().enumerate() {
        for (r, &ts) in i64s(b.column(0)).iter().enumerate() {
            index.push((ts, bi as u32, r as u32, (first_row + r) as u32));
        }
        first_row += b.num_rows();
    }
    index.sort_unstable();
    if let Some(w) = index.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(LoadError::DuplicatePoseTimestamp {
            path: pose_path.to_path_buf(),
            timestamp_ns: w[0].0,
            first_row: w[0].3 as usize,
            second_row: w[1].3 as usize,
        });
    }
    let mut poses = Vec::with_capacity(stamps.len());
    for &ts in stamps {
        let i = index
            .binary_search_by_key(&ts, |e| e.0)
            .map_err(|_| LoadError::NoEgoPose {
                path: pose_path.to_path_buf(),
                annotations: ann_path.to_path_buf(),
                timestamp_ns: ts,
            })?;
        let (_, bi, r, row) = index[i];
        let b = &table.batches[bi as usize];
        let r = r as usize;
        let mut v = [0.0; 7];
        for (c, slot) in v.iter_mut().enumerate() {
            let x = f64s(b.column(c + 1)).get(r).copied().unwrap_or(f64::NAN);
            if !x.is_finite() {
                return Err(LoadError::NonFinite {
                    path: pose_path.to_path_buf(),
                    column: POSE_COLUMNS[c + 1].0,
                    row: row as usize,
                    value: x,
                });
            }
            *slot = x;
        }
        poses.push(checked_pose(
            pose_path,
            row as usize,
            [v[0], v[1], v[2], v[3]],
            [v[4], v[5], v[6]],
        )?);
    }
    Ok(poses)
}

/// A fast non-cryptographic hasher (the Fx multiply-rotate scheme) for looking up track uuids,
/// once per annotation row; SipHash was a tenth of the load time.
#[derive(Default)]
struct UuidHasher(u64);

impl Hasher for UuidHasher {
    fn write(&mut self, bytes: &[u8]) {
        const K: u64 = 0x517c_c1b7_2722_0a95;
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            let mut w = [0u8; 8];
            w.copy_from_slice(c);
            self.0 = (self.0.rotate_left(5) ^ u64::from_le_bytes(w)).wrapping_mul(K);
        }
        for &b in chunks.remainder() {
            self.0 = (self.0.rotate_left(5) ^ u64::from(b)).wrapping_mul(K);
        }
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// A track while it is being assembled.
struct Building<'a> {
    uuid: &'a str,
    category: &'a str,
    first_row: usize,
    boxes: Vec<TrackBox>,
}

/// Groups annotation rows into tracks, adds the ego track if missing, sorts and numbers them.
fn build_tracks(
    path: &Path,
    ann: &Table,
    timeline: &Timeline,
    ego_poses: &[Pose],
) -> Result<Vec<Track>, LoadError> {
    let mut slot_of: HashMap<&str, usize, BuildHasherDefault<UuidHasher>> =
        HashMap::with_capacity_and_hasher(256, Default::default());
    let mut building: Vec<Building> = Vec::with_capacity(256);
    let mut first_row = 0usize;
    for b in &ann.batches {
        let ts = i64s(b.column(0));
        let uuid = Strs::of(b.column(1));
        let category = Strs::of(b.column(2));
        let f: Vec<&[f64]> = (3..13).map(|c| f64s(b.column(c))).collect();
        let pts = i64s(b.column(13));
        for r in 0..b.num_rows() {
            let row = first_row + r;
            let u = uuid.get(r);
            let c = category.get(r);
            let slot = *slot_of.entry(u).or_insert_with(|| {
                building.push(Building {
                    uuid: u,
                    category: c,
                    first_row: row,
                    boxes: Vec::new(),
                });
                building.len() - 1
            });
            let t = &mut building[slot];
            if t.category != c {
                return Err(LoadError::MixedCategory {
                    path: path.to_path_buf(),
                    track: u.to_owned(),
                    first: t.category.to_owned(),
                    first_row: t.first_row,
                    second: c.to_owned(),
                    second_row: row,
                });
            }
            // Every annotation timestamp is in the timeline, which was built from them.
            let frame = timeline.frame_of(ts[r]).unwrap_or(0);
            let ego = checked_pose(
                path,
                row,
                [f[3][r], f[4][r], f[5][r], f[6][r]],
                [f[7][r], f[8][r], f[9][r]],
            )?;
            let city = ego_poses[frame as usize] * ego;
            t.boxes.push(TrackBox {
                frame,
                ego,
                city,
                size: [f[0][r], f[1][r], f[2][r]],
                num_interior_pts: pts[r],
            });
        }
        first_row += b.num_rows();
    }

    let mut egos = building.iter().filter(|t| t.category == EGO_CATEGORY);
    if let (Some(a), Some(b)) = (egos.next(), egos.next()) {
        let mut pair = [a.uuid, b.uuid];
        pair.sort_unstable();
        return Err(LoadError::SeveralEgoTracks {
            path: path.to_path_buf(),
            first: pair[0].to_owned(),
            second: pair[1].to_owned(),
        });
    }
    if !building.iter().any(|t| t.category == EGO_CATEGORY) {
        if let Some(t) = building.iter().find(|t| t.uuid == ADDED_EGO_UUID) {
            return Err(LoadError::ReservedUuid {
                path: path.to_path_buf(),
                uuid: ADDED_EGO_UUID,
                category: t.category.to_owned(),
            });
        }
        building.push(added_ego_track(ego_poses, timeline.frames()));
    }

    // The file's ego rows are at the rear axle (identity in the ego frame): move each box to the
    // car's body, as the added ego's.
    for t in building.iter_mut().filter(|t| t.category == EGO_CATEGORY) {
        for b in &mut t.boxes {
            if b.ego.translation.vector.norm() < 1e-6 {
                b.ego *= ego_box_in_ego_frame();
                b.city *= ego_box_in_ego_frame();
            }
        }
    }
    // `building` is in the order of each track's first row (the added ego last): keep it.
    let mut building: Vec<(u32, Building)> = building
        .into_iter()
        .enumerate()
        .map(|(i, b)| (i as u32, b))
        .collect();
    building.sort_unstable_by(|a, b| a.1.uuid.cmp(b.1.uuid));
    let mut tracks = Vec::with_capacity(building.len());
    for (i, (file_order, mut t)) in building.into_iter().enumerate() {
        t.boxes.sort_unstable_by_key(|b| b.frame);
        if let Some(w) = t.boxes.windows(2).find(|w| w[0].frame == w[1].frame) {
            return Err(duplicate_row(path, ann, timeline, t.uuid, w[0].frame));
        }
        tracks.push(Track {
            id: TrackId(i as u32),
            uuid: t.uuid.to_owned(),
            category: t.category.to_owned(),
            boxes: t.boxes,
            file_order,
        });
    }
    Ok(tracks)
}

/// The ego track added to annotations without one: identity pose, AV2 ego size, a box at each
/// of `frames` (the frames holding data; `ego_poses` is indexed by frame).
fn added_ego_track(ego_poses: &[Pose], frames: &[Frame]) -> Building<'static> {
    let boxes = frames
        .iter()
        .filter_map(|&f| Some((f, ego_poses.get(f as usize)?)))
        .map(|(frame, pose)| TrackBox {
            frame,
            ego: ego_box_in_ego_frame(),
            city: pose * ego_box_in_ego_frame(),
            size: EGO_SIZE,
            num_interior_pts: 0,
        })
        .collect();
    Building {
        uuid: ADDED_EGO_UUID,
        category: EGO_CATEGORY,
        first_row: 0,
        boxes,
    }
}

/// The error for two rows of `uuid` at `frame`, with their row numbers (found by a rescan: this
/// is the error path only).
fn duplicate_row(
    path: &Path,
    ann: &Table,
    timeline: &Timeline,
    uuid: &str,
    frame: Frame,
) -> LoadError {
    let timestamp_ns = timeline.ns(frame).unwrap_or_default();
    let mut rows = Vec::with_capacity(2);
    let mut first_row = 0usize;
    for b in &ann.batches {
        let ts = i64s(b.column(0));
        let uuids = Strs::of(b.column(1));
        for (r, &t) in ts.iter().enumerate() {
            if t == timestamp_ns && uuids.get(r) == uuid && rows.len() < 2 {
                rows.push(first_row + r);
            }
        }
        first_row += b.num_rows();
    }
    LoadError::DuplicateRow {
        path: path.to_path_buf(),
        track: uuid.to_owned(),
        timestamp_ns,
        first_row: rows.first().copied().unwrap_or_default(),
        second_row: rows.get(1).copied().unwrap_or_default(),
    }
}
