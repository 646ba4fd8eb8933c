//! Properties a person can confirm on the three real Argoverse 2 logs in `tests/data/av2/logs/`.
//! Run with `--nocapture` to see the per-relation counts.

use scenalog_extractors::{extract_all, Extractor};
use scenalog_facts::relation::{Column, Request};
use scenalog_testkit::sample_scenes as scenes;

/// Winding number of a closed polygon around `p` (an implementation independent of the crate's).
fn winding(poly: &[[f64; 2]], p: [f64; 2]) -> i32 {
    let mut w = 0;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let side = (b[0] - a[0]) * (p[1] - a[1]) - (p[0] - a[0]) * (b[1] - a[1]);
        if a[1] <= p[1] {
            if b[1] > p[1] && side > 0.0 {
                w += 1;
            }
        } else if b[1] <= p[1] && side < 0.0 {
            w -= 1;
        }
    }
    w
}

#[test]
fn ego_speed_matches_its_pose_track() {
    for scene in scenes() {
        let ex = Extractor::new(scene);
        let kin = &ex.kinematics().tracks[scene.ego.index()];
        let ts = scene.timeline.timestamps_ns();
        let n = ts.len();
        assert_eq!(
            kin.frames.len(),
            n,
            "{}: ego present at every frame",
            scene.log_id
        );
        let mut worst: f64 = 0.0;
        // Reference: displacement of the raw ego poses over ±5 frames (1 s) divided by the time.
        for f in 5..n - 5 {
            let (a, b) = (&scene.ego_poses[f - 5], &scene.ego_poses[f + 5]);
            let d = (b.translation.vector - a.translation.vector).xy().norm();
            let reference = d / ((ts[f + 5] - ts[f - 5]) as f64 * 1e-9);
            worst = worst.max((kin.speed[f] - reference).abs());
        }
        let max_speed = kin.speed.iter().cloned().fold(0.0, f64::max);
        println!(
            "{}: ego max speed {max_speed:.2} m/s, worst gap to pose track {worst:.3} m/s",
            scene.log_id
        );
        assert!(
            worst < 0.5,
            "{}: ego speed differs from its pose track by {worst} m/s",
            scene.log_id
        );
    }
}

#[test]
fn every_in_lane_centre_lies_in_its_lane() {
    for scene in scenes() {
        let ex = Extractor::new(scene);
        let data = ex.extract(&Request::all("in_lane")).unwrap();
        let (Column::Track(xs), Column::Time(ts), Column::Lane(ls)) =
            (&data.columns[0], &data.columns[1], &data.columns[2])
        else {
            panic!("in_lane columns")
        };
        assert!(!xs.is_empty(), "{}: some object is in a lane", scene.log_id);
        for i in 0..xs.len() {
            let b = scene.track(xs[i]).box_at(ts[i]).expect("box at frame");
            let c = b.city_center();
            let lane = scene.map.lane(ls[i]).expect("lane in map");
            assert_ne!(
                winding(&lane.polygon_xy(), [c.x, c.y]),
                0,
                "{}: {i}",
                scene.log_id
            );
        }
        println!("{}: {} in_lane tuples checked", scene.log_id, xs.len());
    }
}

#[test]
fn relation_counts_are_stable_and_plausible() {
    for (k, scene) in scenes().iter().enumerate() {
        let all = extract_all(scene);
        if k == 0 {
            // Same answer on one thread as on the default pool.
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .expect("pool");
            let again = pool.install(|| extract_all(scene));
            assert_eq!(all, again, "{}: deterministic", scene.log_id);
        }
        let count = |name: &str| all.iter().find(|r| r.name == name).map(|r| r.len());
        println!(
            "{} ({} tracks, {} boxes, {} frames, {} lanes):",
            scene.log_id,
            scene.tracks.len(),
            scene.num_boxes(),
            scene.num_frames(),
            scene.map.lanes.len()
        );
        for r in &all {
            println!("  {:<18} {:>7}", r.name, r.len());
        }
        let boxes = scene.num_boxes();
        assert_eq!(count("present"), Some(boxes));
        assert_eq!(count("speed"), Some(boxes));
        assert_eq!(count("yaw_rate"), Some(boxes));
        assert_eq!(count("frame_ns"), Some(scene.num_frames()));
        assert_eq!(count("ego"), Some(1));
        assert!(count("category").unwrap() >= 2 * scene.tracks.len());
        let in_lane = count("in_lane").unwrap();
        assert!(
            in_lane > boxes / 10 && in_lane < boxes,
            "in_lane {in_lane} of {boxes}"
        );
        assert_eq!(count("on_road"), Some(in_lane));
        let in_da = count("in_drivable_area").unwrap();
        assert!(in_da >= in_lane / 2 && in_da <= boxes);
        assert_eq!(count("lane_type"), Some(scene.map.lanes.len()));
        let stationary = count("stationary").unwrap();
        assert!(stationary > 0 && stationary < scene.tracks.len());
        assert!(count("lane_successor").unwrap() > 0);
        assert!(count("near_intersection").unwrap() > 0);
    }
}

#[test]
fn map_distances_match_brute_force() {
    use scenalog_extractors::map::geometry::{box_corners, Polygon};
    for scene in scenes() {
        let ex = Extractor::new(scene);
        let inter: Vec<Polygon> = scene
            .map
            .lanes
            .iter()
            .filter(|l| l.is_intersection)
            .map(|l| Polygon::new(l.polygon_xy()))
            .collect();
        let crossings: Vec<Polygon> = scene
            .map
            .crossings
            .iter()
            .map(|c| Polygon::new(c.polygon_xy()))
            .collect();
        for (name, polys, boxes) in [
            ("near_intersection", &inter, false),
            ("at_crosswalk", &crossings, true),
        ] {
            let data = ex.extract(&Request::all(name)).unwrap();
            let (Column::Track(xs), Column::Time(ts), Column::Float(ds)) =
                (&data.columns[0], &data.columns[1], &data.columns[2])
            else {
                panic!("{name} columns")
            };
            assert!(!xs.is_empty());
            for i in (0..xs.len()).step_by(13) {
                let b = scene.track(xs[i]).box_at(ts[i]).expect("box");
                let c = b.city_center();
                let brute = if boxes {
                    let shape = Polygon::new(
                        box_corners([c.x, c.y], b.city_yaw(), b.size[0], b.size[1]).to_vec(),
                    );
                    polys
                        .iter()
                        .map(|p| p.distance_to_polygon(&shape))
                        .fold(f64::INFINITY, f64::min)
                } else {
                    polys
                        .iter()
                        .map(|p| p.distance_to_point([c.x, c.y]))
                        .fold(f64::INFINITY, f64::min)
                };
                assert!(
                    (brute - ds[i]).abs() < 1e-9,
                    "{}: {name} row {i}: {} vs brute force {brute}",
                    scene.log_id,
                    ds[i]
                );
            }
        }
    }
}

#[test]
fn a_narrower_request_is_answered_from_a_kept_broader_one_as_if_extracted() {
    use scenalog_facts::relation::{Constraint, Value};
    for scene in scenes() {
        let every = |n: usize| -> std::sync::Arc<[Value]> {
            (0..scene.tracks.len())
                .step_by(n)
                .map(|i| Value::Track(scenalog_facts::TrackId(i as u32)))
                .collect()
        };
        for (name, broad, narrow) in [
            // speed under 0.5 m/s, then also for every third track.
            (
                "speed",
                vec![(2, Constraint::Lt(0.5))],
                vec![(2, Constraint::Lt(0.5)), (0, Constraint::OneOf(every(3)))],
            ),
            // A tighter bound and a subset of the tracks.
            (
                "speed",
                vec![(2, Constraint::Le(0.5)), (0, Constraint::OneOf(every(3)))],
                vec![(0, Constraint::OneOf(every(6))), (2, Constraint::Lt(0.3))],
            ),
            // Pedestrians in the drivable area, then every third track of them.
            (
                "in_drivable_area",
                vec![(0, Constraint::Category("PEDESTRIAN".into()))],
                vec![
                    (0, Constraint::Category("PEDESTRIAN".into())),
                    (0, Constraint::OneOf(every(3))),
                ],
            ),
        ] {
            let request = |constraints| Request {
                name: name.into(),
                constraints,
            };
            let shared = Extractor::new(scene);
            let whole = shared.extract(&request(broad)).expect("extracts");
            let served = shared.extract(&request(narrow.clone())).expect("extracts");
            let fresh = Extractor::new(scene)
                .extract(&request(narrow))
                .expect("extracts");
            assert_eq!(*served, *fresh, "{name} on {}", scene.log_id);
            assert!(whole.len() >= served.len());
            assert!(name != "speed" || !served.is_empty(), "{}", scene.log_id);
        }
    }
}
