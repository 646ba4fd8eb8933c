//! One log's detections as a [`Scene`] (the coordinate convention is in the crate documentation).

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use scenalog_facts::scene::EGO_CATEGORY;
use scenalog_facts::{Frame, Pose, Scene, Timeline, Track, TrackBox, TrackId};
use sha2::{Digest, Sha256};

use crate::error::TrackerError;
use crate::filter::{kept_tracks, Filter};
use crate::frames::Detections;

/// A log's tracker output as a scene, with each box's score.
#[derive(Debug, Clone)]
pub struct TrackedLog {
    /// The scene (tracks sorted by uuid, the ego among them).
    pub scene: Scene,
    /// `scores[track][i]` is the score of `scene.tracks[track].boxes[i]` (1.0 for the ego).
    pub scores: Vec<Vec<f32>>,
    /// The integer tracker id of each track (`None` for the ego).
    pub tracker_ids: Vec<Option<i64>>,
}

impl TrackedLog {
    /// The score of `track`'s box at `frame`, if it has one there.
    pub fn score(&self, track: TrackId, frame: Frame) -> Option<f32> {
        let t = self.scene.tracks.get(track.index())?;
        let i = t.boxes.binary_search_by_key(&frame, |b| b.frame).ok()?;
        self.scores.get(track.index())?.get(i).copied()
    }
}

/// The stable uuid of tracker track `track_id` of log `log_id`: the first 16 bytes of
/// SHA-256(`log_id` `/` `track_id`), formatted 8-4-4-4-12 in lower-case hex.
pub fn track_uuid(log_id: &str, track_id: i64) -> String {
    let h = Sha256::digest(format!("{log_id}/{track_id}").as_bytes());
    let x: String = h[..16].iter().map(|b| format!("{b:02x}")).collect();
    format!(
        "{}-{}-{}-{}-{}",
        &x[..8],
        &x[8..12],
        &x[12..16],
        &x[16..20],
        &x[20..32]
    )
}

/// A box given in the city frame (`centre`, `yaw`), in the ego frame of `ego` and back (see the
/// crate documentation): (ego-frame pose, city-frame pose). The ego-frame rotation is about the
/// ego's z axis, by the angle `θ` whose city pose has exactly the given yaw: `yaw_of(R·Rz(θ)) = ψ`.
pub fn city_box_to_ego(ego: &Pose, centre: [f64; 3], yaw: f64) -> (Pose, Pose) {
    let c = nalgebra::Point3::new(centre[0], centre[1], centre[2]);
    let e = ego.inverse_transform_point(&c);
    // The city x axis of R·Rz(θ) is R·(cos θ, sin θ, 0); its heading is ψ when its component
    // across ψ vanishes, a·cos θ + b·sin θ = 0, and its component along ψ is positive.
    let r = ego.rotation.to_rotation_matrix();
    let m = r.matrix();
    let (sp, cp) = yaw.sin_cos();
    let a = m[(1, 0)] * cp - m[(0, 0)] * sp;
    let b = m[(1, 1)] * cp - m[(0, 1)] * sp;
    let mut theta = (-a).atan2(b);
    let (st, ct) = theta.sin_cos();
    let along = (m[(0, 0)] * ct + m[(0, 1)] * st) * cp + (m[(1, 0)] * ct + m[(1, 1)] * st) * sp;
    if along < 0.0 {
        theta += std::f64::consts::PI;
    }
    let rot = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), theta);
    let in_ego = Isometry3::from_parts(Translation3::new(e.x, e.y, e.z), rot);
    (in_ego, ego * in_ego)
}

/// A track before numbering: uuid, category, tracker id (`None` for the ego), scored boxes.
type Assembled = (String, String, Option<i64>, Vec<(TrackBox, f32)>);

/// Builds the scene of `log_id` from its detections (frames in any order, one per timestamp)
/// and the ego poses and map of `log_dir` (the log's directory in the AV2 split). `file` names
/// the tracker file in errors.
pub fn tracked_log(
    log_id: &str,
    frames: &[Detections],
    log_dir: &Path,
    filter: Filter,
    file: &str,
) -> Result<TrackedLog, TrackerError> {
    let stamps: Vec<i64> = frames.iter().map(|f| f.timestamp_ns).collect();
    let timeline = Timeline::new(stamps.clone());
    if timeline.len() != frames.len() {
        return Err(TrackerError::log(
            file,
            log_id,
            "two frames have the same timestamp_ns",
        ));
    }
    if frames.is_empty() {
        return Err(TrackerError::log(file, log_id, "no frames"));
    }
    let ego_poses = timeline.per_frame(
        &scenalog_facts::read::ego_poses(log_dir, Path::new(file), timeline.timestamps_ns())
            .map_err(|e| TrackerError::log(file, log_id, format!("ego poses: {e}")))?,
    );
    let (map, city) = scenalog_facts::read::log_map(log_dir)
        .map_err(|e| TrackerError::log(file, log_id, format!("map: {e}")))?;
    let kept = kept_tracks(frames, filter);

    struct Building {
        names: BTreeMap<String, (usize, usize)>,
        boxes: Vec<(TrackBox, f32)>,
    }
    let mut by_id: HashMap<i64, Building> = HashMap::new();
    for f in frames {
        // Frames were timestamped by the timeline itself.
        let frame = timeline.frame_of(f.timestamp_ns).unwrap_or(0);
        let Some(&ego) = ego_poses.get(frame as usize) else {
            continue;
        };
        for i in 0..f.len() {
            let id = f.track_id[i];
            if !kept.contains(&id) {
                continue;
            }
            let (in_ego, city) = city_box_to_ego(&ego, f.translation_m[i], f.yaw[i]);
            let b = by_id.entry(id).or_insert_with(|| Building {
                names: BTreeMap::new(),
                boxes: Vec::new(),
            });
            let order = b.names.len();
            b.names.entry(f.name[i].clone()).or_insert((0, order)).0 += 1;
            b.boxes.push((
                TrackBox {
                    frame,
                    ego: in_ego,
                    city,
                    size: f.size[i],
                    num_interior_pts: 0,
                },
                f.score[i],
            ));
        }
    }
    let mut tracks: Vec<Assembled> = by_id
        .into_iter()
        .map(|(id, mut b)| {
            let category = b
                .names
                .iter()
                .max_by(|x, y| x.1 .0.cmp(&y.1 .0).then(y.1 .1.cmp(&x.1 .1)))
                .map(|(n, _)| n.clone())
                .unwrap_or_default();
            b.boxes.sort_by_key(|(bx, _)| bx.frame);
            (track_uuid(log_id, id), category, Some(id), b.boxes)
        })
        .collect();
    let (ego_uuid, ego_boxes) = scenalog_facts::read::added_ego(&ego_poses, timeline.frames());
    tracks.push((
        ego_uuid,
        EGO_CATEGORY.to_string(),
        None,
        ego_boxes.into_iter().map(|b| (b, 1.0)).collect(),
    ));
    // The "file order" (RefAV's order of objects, `Track::file_order`): a tracker file has no
    // annotation rows, so tracks are ordered by their first frame, then tracker id; the added
    // ego last.
    let mut first: Vec<(u32, i64, usize)> = tracks
        .iter()
        .enumerate()
        .map(|(i, t)| match t.2 {
            Some(id) => (t.3.first().map_or(u32::MAX, |b| b.0.frame), id, i),
            None => (u32::MAX, i64::MAX, i),
        })
        .collect();
    first.sort_unstable();
    let mut file_order = vec![0u32; tracks.len()];
    for (rank, &(_, _, i)) in first.iter().enumerate() {
        file_order[i] = rank as u32;
    }
    let mut tracks: Vec<(u32, Assembled)> = file_order.into_iter().zip(tracks).collect();
    tracks.sort_by(|a, b| a.1 .0.cmp(&b.1 .0));

    let mut out_tracks = Vec::with_capacity(tracks.len());
    let mut scores = Vec::with_capacity(tracks.len());
    let mut tracker_ids = Vec::with_capacity(tracks.len());
    let mut ego = TrackId(0);
    for (i, (file_order, (uuid, category, id, boxes))) in tracks.into_iter().enumerate() {
        if category == EGO_CATEGORY {
            ego = TrackId(i as u32);
        }
        let (b, s): (Vec<TrackBox>, Vec<f32>) = boxes.into_iter().unzip();
        out_tracks.push(Track {
            id: TrackId(i as u32),
            uuid,
            category,
            boxes: b,
            file_order,
        });
        scores.push(s);
        tracker_ids.push(id);
    }
    let track_by_uuid = out_tracks.iter().map(|t| (t.uuid.clone(), t.id)).collect();
    Ok(TrackedLog {
        scene: Scene {
            log_id: log_id.to_string(),
            city,
            timeline,
            tracks: out_tracks,
            ego,
            ego_poses,
            map,
            track_by_uuid,
            // RefAV's colour cache is per tracker log (keyed by its own uuids); not read.
            color_cache: scenalog_facts::ColorCache::Absent,
            // Keyed by the log's uuids too: a tracker's tracks are not the annotations'.
            attributes: scenalog_facts::Attributes::Absent,
        },
        scores,
        tracker_ids,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_city_box_keeps_its_yaw_under_a_tilted_ego() {
        use scenalog_facts::scene::yaw_of;
        let ego = Isometry3::from_parts(
            Translation3::new(100.0, -40.0, 3.0),
            UnitQuaternion::from_euler_angles(0.03, -0.05, 2.0),
        );
        for psi in [-3.0, -1.2, 0.0, 0.4, 1.9, 3.1] {
            let (in_ego, city) = city_box_to_ego(&ego, [105.0, -38.0, 3.5], psi);
            let d = (yaw_of(&city.rotation) - psi + std::f64::consts::PI)
                .rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            assert!(d.abs() < 1e-12, "{psi}: {d}");
            let (roll, pitch, _) = in_ego.rotation.euler_angles();
            assert!(roll.abs() < 1e-12 && pitch.abs() < 1e-12);
            assert!((city.translation.vector - Vector3::new(105.0, -38.0, 3.5)).norm() < 1e-9);
        }
    }

    #[test]
    fn uuids_are_stable_and_distinct() {
        let a = track_uuid("3b3570b4-7b0b-3268-a571-b0889dbf40b6", 7);
        assert_eq!(a, track_uuid("3b3570b4-7b0b-3268-a571-b0889dbf40b6", 7));
        assert_ne!(a, track_uuid("3b3570b4-7b0b-3268-a571-b0889dbf40b6", 8));
        assert_ne!(a, track_uuid("3bffdcff-c3a7-38b6-a0f2-64196d130958", 7));
        assert_eq!(a.len(), 36);
        assert_eq!(a.matches('-').count(), 4);
    }
}
