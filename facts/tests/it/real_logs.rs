//! Loading the three real Argoverse 2 logs in `tests/data/av2/logs/` and checking figures anyone
//! can verify from the files.
//!
//! Every expected figure below was computed independently of this crate with python3, pyarrow 26
//! and numpy 2.4 over the same files. The script is `facts/tests/verify_figures.py`; run
//! `python3 facts/tests/verify_figures.py` from the repository root to print the figures again.
//! It counts rows as `len(table)`, timestamps as `table.timestamp_ns.nunique()`, tracks per
//! category as `table.groupby('category').track_uuid.nunique()`, map features as
//! `len(json[section])`, lanes by `lane_type` and `is_intersection`, dangling ids as the distinct
//! successor, predecessor and neighbour ids that are not lane keys, and one box's city pose as
//! `R(q_ego) @ t_box + t_ego` with the ego pose row of the same timestamp.

use std::collections::BTreeMap;

use nalgebra::{Point3, Vector3};
use scenalog_facts::read::ADDED_EGO_UUID;
use scenalog_facts::scene::{yaw_of, EGO_CATEGORY, EGO_SIZE};
use scenalog_facts::{load_scene, LaneId, LaneType, Scene, SceneSummary};

fn load(id: &str) -> Scene {
    match load_scene(&crate::log_dir(id)) {
        Ok(s) => s,
        Err(e) => panic!("loading {id}: {e}"),
    }
}

/// The figures of one log, as pyarrow/json computed them.
struct Expected {
    id: &'static str,
    city: &'static str,
    rows: usize,
    timestamps: usize,
    first_ns: i64,
    last_ns: i64,
    ego_uuid: &'static str,
    ego_in_file: bool,
    by_category: &'static [(&'static str, usize)],
    lanes: usize,
    lanes_by_type: &'static [(LaneType, usize)],
    intersection_lanes: usize,
    dangling: usize,
    a_dangling_id: i64,
    crossings: usize,
    drivable_areas: usize,
    /// Ego translation in the city frame at the first annotation timestamp.
    ego_t0: [f64; 3],
    /// The first track by uuid (ego excluded), its number of boxes, and its first box's city
    /// centre and city yaw (radians).
    first_track: (&'static str, &'static str, usize, [f64; 3], f64),
}

const LOGS: &[Expected] = &[
    Expected {
        id: "3b3570b4-7b0b-3268-a571-b0889dbf40b6",
        city: "MIA",
        rows: 13_820,
        timestamps: 157,
        first_ns: 315_971_916_960_141_000,
        last_ns: 315_971_932_559_986_000,
        ego_uuid: "9d57813a-2d04-40e6-9694-20dfa13295dc",
        ego_in_file: true,
        by_category: &[
            ("BICYCLE", 6),
            ("BOLLARD", 3),
            ("BOX_TRUCK", 1),
            ("CONSTRUCTION_CONE", 1),
            ("EGO_VEHICLE", 1),
            ("LARGE_VEHICLE", 1),
            ("MOTORCYCLE", 2),
            ("PEDESTRIAN", 12),
            ("REGULAR_VEHICLE", 84),
            ("TRUCK", 2),
            ("WHEELED_DEVICE", 7),
        ],
        lanes: 150,
        lanes_by_type: &[(LaneType::Vehicle, 150)],
        intersection_lanes: 48,
        dangling: 22,
        a_dangling_id: 37_981_105,
        crossings: 6,
        drivable_areas: 5,
        ego_t0: [743.9777930173304, 2231.5482569447154, -22.927443244886017],
        first_track: (
            "037ce8e5-b14f-47fe-a042-97499a39bae5",
            "TRUCK",
            157,
            [735.01807843309, 2253.114142224683, -21.89821341314947],
            2.4548460008622532,
        ),
    },
    Expected {
        id: "3bffdcff-c3a7-38b6-a0f2-64196d130958",
        city: "PIT",
        rows: 12_342,
        timestamps: 156,
        first_ns: 315_975_581_059_920_000,
        last_ns: 315_975_596_559_887_000,
        ego_uuid: "27c6325e-81c4-458a-8e45-628550c80da3",
        ego_in_file: true,
        by_category: &[
            ("BOLLARD", 4),
            ("BOX_TRUCK", 1),
            ("CONSTRUCTION_CONE", 2),
            ("EGO_VEHICLE", 1),
            ("LARGE_VEHICLE", 4),
            ("PEDESTRIAN", 2),
            ("REGULAR_VEHICLE", 98),
            ("SIGN", 1),
            ("TRUCK", 2),
            ("TRUCK_CAB", 1),
        ],
        lanes: 211,
        lanes_by_type: &[
            (LaneType::Vehicle, 173),
            (LaneType::Bike, 37),
            (LaneType::Bus, 1),
        ],
        intersection_lanes: 67,
        dangling: 26,
        a_dangling_id: 56_224_784,
        crossings: 14,
        drivable_areas: 15,
        ego_t0: [5007.495261617844, 2466.341663597744, 60.39003904278181],
        first_track: (
            "01f2525d-c1c4-4178-a423-a826c6304fd2",
            "BOLLARD",
            146,
            [5020.464757497925, 2489.339653773142, 61.57618532344195],
            -1.2944497051741508,
        ),
    },
    Expected {
        id: "adcf7d18-0510-35b0-a2fa-b4cea13a6d76",
        city: "PIT",
        rows: 12_078,
        timestamps: 156,
        first_ns: 315_973_157_959_879_000,
        last_ns: 315_973_173_459_753_000,
        ego_uuid: ADDED_EGO_UUID,
        ego_in_file: false,
        // The file's own tracks; the added ego track is the one EGO_VEHICLE.
        by_category: &[
            ("BICYCLE", 1),
            ("BOLLARD", 41),
            ("BOX_TRUCK", 2),
            ("BUS", 3),
            ("CONSTRUCTION_CONE", 6),
            ("EGO_VEHICLE", 1),
            ("LARGE_VEHICLE", 1),
            ("PEDESTRIAN", 38),
            ("REGULAR_VEHICLE", 47),
            ("SIGN", 6),
            ("TRUCK", 1),
        ],
        lanes: 199,
        lanes_by_type: &[
            (LaneType::Vehicle, 166),
            (LaneType::Bike, 19),
            (LaneType::Bus, 14),
        ],
        intersection_lanes: 61,
        dangling: 40,
        a_dangling_id: 42_806_887,
        crossings: 11,
        drivable_areas: 8,
        ego_t0: [1468.8715400961275, 211.51179261099088, 13.137160248434473],
        first_track: (
            "05b99369-a556-4ed0-8ff9-43328e6be1a4",
            "PEDESTRIAN",
            107,
            [1506.9359657554085, 269.95990433001634, 13.090007454380025],
            -2.2395969911420766,
        ),
    },
];

#[test]
fn counts_match_the_files() {
    for e in LOGS {
        let s = load(e.id);
        assert_eq!(s.log_id, e.id);
        assert_eq!(s.city, e.city, "{}", e.id);
        assert_eq!(s.num_frames(), e.timestamps, "{}", e.id);
        assert_eq!(s.timeline.ns(0), Some(e.first_ns), "{}", e.id);
        assert_eq!(
            s.timeline.ns(e.timestamps as u32 - 1),
            Some(e.last_ns),
            "{}",
            e.id
        );
        assert_eq!(s.ego_poses.len(), e.timestamps, "{}", e.id);
        // Rows of the file = boxes, plus one box per timestamp when the ego track was added.
        let added = if e.ego_in_file { 0 } else { e.timestamps };
        assert_eq!(s.num_boxes(), e.rows + added, "{}", e.id);
        let want: BTreeMap<String, usize> = e
            .by_category
            .iter()
            .map(|&(c, n)| (c.to_owned(), n))
            .collect();
        assert_eq!(s.tracks_by_category(), want, "{}", e.id);
        assert_eq!(s.tracks.len(), want.values().sum::<usize>(), "{}", e.id);

        assert_eq!(s.map.lanes.len(), e.lanes, "{}", e.id);
        for &(ty, n) in e.lanes_by_type {
            let got = s.map.lanes.iter().filter(|l| l.lane_type == ty).count();
            assert_eq!(got, n, "{} {:?}", e.id, ty);
        }
        let inter = s.map.lanes.iter().filter(|l| l.is_intersection).count();
        assert_eq!(inter, e.intersection_lanes, "{}", e.id);
        assert_eq!(s.map.crossings.len(), e.crossings, "{}", e.id);
        assert_eq!(s.map.drivable_areas.len(), e.drivable_areas, "{}", e.id);

        let summary = SceneSummary::of(&s);
        assert_eq!(summary.dangling_lane_ids, e.dangling, "{}", e.id);
        assert_eq!(summary.timestamps, e.timestamps);
        assert_eq!(summary.lane_segments, e.lanes);
        assert_eq!(summary.ego_uuid, e.ego_uuid);
    }
}

#[test]
fn tracks_are_numbered_sorted_and_consistent() {
    for e in LOGS {
        let s = load(e.id);
        for (i, t) in s.tracks.iter().enumerate() {
            assert_eq!(t.id.index(), i);
            assert_eq!(s.track_by_uuid(&t.uuid).map(|x| x.id), Some(t.id));
            assert!(t.boxes.windows(2).all(|w| w[0].frame < w[1].frame));
            assert!(t.boxes.iter().all(|b| (b.frame as usize) < s.num_frames()));
        }
        assert!(s.tracks.windows(2).all(|w| w[0].uuid < w[1].uuid));
        assert_eq!(s.track_by_uuid.len(), s.tracks.len());
        let ego = s.track(s.ego);
        assert_eq!(ego.uuid, e.ego_uuid);
        assert_eq!(ego.category, EGO_CATEGORY);
        assert!(s.track_by_uuid("no-such-uuid").is_none());

        let (uuid, cat, n, centre, yaw) = e.first_track;
        let first = s
            .tracks
            .iter()
            .find(|t| t.id != s.ego)
            .unwrap_or_else(|| panic!("{}: no track", e.id));
        assert_eq!((first.uuid.as_str(), first.category.as_str()), (uuid, cat));
        assert_eq!(first.boxes.len(), n, "{}", e.id);
        let b = &first.boxes[0];
        let c = b.city_center();
        for k in 0..3 {
            assert!(
                (c[k] - centre[k]).abs() < 1e-9,
                "{} centre {c} vs {centre:?}",
                e.id
            );
        }
        assert!((b.city_yaw() - yaw).abs() < 1e-9, "{} yaw", e.id);

        let t0 = s.ego_poses[0].translation.vector;
        for k in 0..3 {
            assert!((t0[k] - e.ego_t0[k]).abs() < 1e-9, "{} ego t0", e.id);
        }
    }
}

#[test]
fn ego_track_has_one_box_per_timestamp_at_the_ego_pose() {
    for e in LOGS {
        let s = load(e.id);
        let ego = s.track(s.ego);
        assert_eq!(ego.boxes.len(), s.num_frames(), "{}", e.id);
        for (f, b) in ego.boxes.iter().enumerate() {
            assert_eq!(b.frame as usize, f);
            assert_eq!(b.size, EGO_SIZE);
            // The box is the car's body: its centre 1.4385 m ahead of the rear axle (the ego
            // pose), so it spans -1.0 m to +3.877 m along the heading.
            let ahead = EGO_SIZE[0] / 2.0 - 1.0;
            assert!((b.ego.translation.vector - Vector3::new(ahead, 0.0, 0.0)).norm() < 1e-12);
            assert!(b.ego.rotation.angle() < 1e-12);
            let want = s.ego_poses[f] * Point3::new(ahead, 0.0, 0.0);
            let d = b.city.translation.vector - want.coords;
            assert!(d.norm() < 1e-9);
            assert!(b.city.rotation.angle_to(&s.ego_poses[f].rotation) < 1e-12);
        }
        // In the with-ego logs the ego rows come from the file with one LiDAR point count; the added
        // ego track has 0.
        let pts: i64 = ego.boxes.iter().map(|b| b.num_interior_pts).sum();
        if e.ego_in_file {
            assert_eq!(pts, e.timestamps as i64, "{}", e.id);
        } else {
            assert_eq!(pts, 0);
        }
    }
}

#[test]
fn ego_city_ego_round_trip_is_exact() {
    for e in LOGS {
        let s = load(e.id);
        let mut checked = 0;
        for t in &s.tracks {
            for b in &t.boxes {
                let p = Point3::from(b.ego.translation.vector);
                let city = s
                    .ego_to_city(b.frame, &p)
                    .unwrap_or_else(|| panic!("frame"));
                // The city pose of the box is ego_pose * box pose: same centre.
                assert!((city - b.city_center()).norm() < 1e-9);
                let back = s
                    .city_to_ego(b.frame, &city)
                    .unwrap_or_else(|| panic!("frame"));
                assert!(
                    (back - p).norm() < 1e-9,
                    "{}: {p} -> {city} -> {back}",
                    e.id
                );
                // Heading composes too: city yaw = ego-vehicle yaw + box yaw (mod 2π), on flat ground.
                let ego_yaw = yaw_of(&s.ego_poses[b.frame as usize].rotation);
                let diff = (b.city_yaw() - ego_yaw - b.ego_yaw()).rem_euclid(std::f64::consts::TAU);
                let diff = diff.min(std::f64::consts::TAU - diff);
                assert!(diff < 0.05, "{}: yaw mismatch {diff}", e.id);
                checked += 1;
            }
        }
        assert_eq!(checked, s.num_boxes());
        assert!(s
            .ego_to_city(s.num_frames() as u32, &Point3::origin())
            .is_none());
    }
}

#[test]
fn dangling_lane_ids_answer_none() {
    for e in LOGS {
        let s = load(e.id);
        let id = LaneId(e.a_dangling_id);
        assert!(s.map.lane(id).is_none(), "{}", e.id);
        assert!(s.map.lane_index(id).is_none());
        let referenced = s.map.lanes.iter().any(|l| {
            l.successors.contains(&id)
                || l.predecessors.contains(&id)
                || l.left_neighbor == Some(id)
                || l.right_neighbor == Some(id)
        });
        assert!(
            referenced,
            "{}: {id:?} should be referenced by some lane",
            e.id
        );
        // Every lane in the file answers Some.
        for l in &s.map.lanes {
            assert_eq!(s.map.lane(l.id).map(|x| x.id), Some(l.id));
        }
    }
}

#[test]
fn first_lane_of_the_map_is_read_field_by_field() {
    // lane_segments["37979824"] of 3b3570b4's map, as printed by `json.load`.
    let s = load("3b3570b4-7b0b-3268-a571-b0889dbf40b6");
    let l = s
        .map
        .lane(LaneId(37_979_824))
        .unwrap_or_else(|| panic!("lane 37979824"));
    assert_eq!(l.lane_type, LaneType::Vehicle);
    assert!(!l.is_intersection);
    assert_eq!(
        l.left_boundary,
        vec![
            Point3::new(742.88, 2200.44, -23.36),
            Point3::new(743.07, 2193.39, -23.37)
        ]
    );
    assert_eq!(
        l.right_boundary,
        vec![
            Point3::new(739.5, 2200.35, -23.45),
            Point3::new(739.69, 2193.29, -23.46)
        ]
    );
    assert_eq!(l.left_mark_type, "SOLID_YELLOW");
    assert_eq!(l.right_mark_type, "DASHED_WHITE");
    assert_eq!(l.successors, vec![LaneId(37_996_592), LaneId(37_996_593)]);
    assert!(l.predecessors.is_empty());
    assert_eq!(l.right_neighbor, Some(LaneId(37_992_207)));
    assert_eq!(l.left_neighbor, Some(LaneId(37_985_322)));
    assert!(s.map.lanes.windows(2).all(|w| w[0].id < w[1].id));
}

#[test]
fn log_id_comes_from_a_relative_dot_path_too() {
    let dir = crate::log_dir("3b3570b4-7b0b-3268-a571-b0889dbf40b6").join(".");
    let s = load_scene(&dir).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.log_id, "3b3570b4-7b0b-3268-a571-b0889dbf40b6");
}
