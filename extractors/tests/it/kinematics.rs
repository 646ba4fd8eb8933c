//! Kinematics and lane assignment on synthetic scenes whose answer is known by construction.

use scenalog_extractors::kinematics::compute;
use scenalog_extractors::lanes::assign;
use scenalog_facts::LaneId;
use scenalog_testkit::{straight, SceneBuilder, Waypoint};
use std::f64::consts::FRAC_PI_2;

/// A car turning left 90° at 10 m/s on a circle of radius 20 m (frames 10..), straight before.
fn left_turn() -> Vec<Waypoint> {
    let v = 10.0;
    let r = 20.0;
    let mut way = straight(0, 10, -10.0, 0.0, 0.0, v);
    let w = v / r; // rad/s
    let turn_frames = ((FRAC_PI_2 / w) / 0.1).round() as u32; // 31
    for k in 0..=turn_frames {
        let a = (w * 0.1 * k as f64).min(FRAC_PI_2);
        way.push((10 + k, r * a.sin(), r - r * a.cos(), a));
    }
    let end = 10 + turn_frames;
    for k in 1..15 {
        way.push((end + k, r, r + v * 0.1 * k as f64, FRAC_PI_2));
    }
    way
}

#[test]
fn straight_car_has_constant_speed_and_no_acceleration() {
    let scene = SceneBuilder::new(40)
        .track(
            "car",
            "REGULAR_VEHICLE",
            [4.5, 1.8, 1.5],
            straight(0, 40, 0.0, 0.0, 0.3, 12.0),
        )
        .build();
    let kin = compute(&scene);
    let k = &kin.tracks[scene.track_by_uuid["car"].index()];
    assert_eq!(k.frames.len(), 40);
    for i in 0..40 {
        assert!((k.speed[i] - 12.0).abs() < 1e-6, "speed {}", k.speed[i]);
        assert!(k.accel[i].abs() < 1e-6 && k.lat_accel[i].abs() < 1e-6);
        assert!(k.yaw_rate[i].abs() < 1e-9);
    }
    assert!(!k.stationary);
}

#[test]
fn braking_car_has_negative_forward_acceleration() {
    // x = 10 t - 1.5 t^2 (decelerating at 3 m/s^2) over 3 s, heading +y.
    let way: Vec<Waypoint> = (0..30)
        .map(|f| {
            let t = f as f64 * 0.1;
            (f, 5.0, 10.0 * t - 1.5 * t * t, FRAC_PI_2)
        })
        .collect();
    let scene = SceneBuilder::new(30)
        .track("car", "REGULAR_VEHICLE", [4.5, 1.8, 1.5], way)
        .build();
    let kin = compute(&scene);
    let k = &kin.tracks[scene.track_by_uuid["car"].index()];
    for i in 3..27 {
        assert!(
            (k.accel[i] + 3.0).abs() < 1e-6,
            "accel {} at {i}",
            k.accel[i]
        );
        assert!(k.lat_accel[i].abs() < 1e-6);
    }
}

#[test]
fn left_turn_has_positive_yaw_rate_and_lateral_acceleration() {
    let way = left_turn();
    let n = way.len();
    let scene = SceneBuilder::new(n)
        .track("car", "REGULAR_VEHICLE", [4.5, 1.8, 1.5], way)
        .build();
    let kin = compute(&scene);
    let k = &kin.tracks[scene.track_by_uuid["car"].index()];
    // Mid-turn: yaw rate v / r = 0.5 rad/s = 28.6 deg/s; lateral acceleration v^2 / r = 5 m/s^2.
    let mid = 25;
    assert!(
        (k.yaw_rate[mid] - 0.5f64.to_degrees()).abs() < 0.5,
        "{}",
        k.yaw_rate[mid]
    );
    assert!((k.lat_accel[mid] - 5.0).abs() < 0.5, "{}", k.lat_accel[mid]);
    assert!((k.speed[mid] - 10.0).abs() < 0.2, "{}", k.speed[mid]);
}

#[test]
fn missing_frames_use_real_time_steps() {
    // Frames 0, 1, 3, 4, 7: a car at 5 m/s along x.
    let way: Vec<Waypoint> = [0u32, 1, 3, 4, 7]
        .iter()
        .map(|&f| (f, 0.5 * f as f64, 0.0, 0.0))
        .collect();
    let scene = SceneBuilder::new(8)
        .track("car", "REGULAR_VEHICLE", [4.5, 1.8, 1.5], way)
        .build();
    let kin = compute(&scene);
    let k = &kin.tracks[scene.track_by_uuid["car"].index()];
    for s in &k.speed {
        assert!((s - 5.0).abs() < 1e-9, "{s}");
    }
}

#[test]
fn parked_car_is_stationary_and_stopped_car_is_not() {
    // Parked: jitters within 0.3 m for 5 s. Stopped at a light: drives 20 m, waits 3 s, drives on.
    let parked: Vec<Waypoint> = (0..50)
        .map(|f| (f, 3.0 + 0.1 * ((f % 3) as f64), 4.0, 0.0))
        .collect();
    let mut stopped = straight(0, 15, 0.0, -4.0, 0.0, 10.0);
    let stop_x = 10.0 * 1.4;
    stopped.extend((15..35).map(|f| (f, stop_x, -4.0, 0.0)));
    stopped.extend(
        straight(35, 50, stop_x, -4.0, 0.0, 10.0)
            .into_iter()
            .skip(1),
    );
    let scene = SceneBuilder::new(50)
        .track("parked", "REGULAR_VEHICLE", [4.5, 1.8, 1.5], parked)
        .track("stopped", "REGULAR_VEHICLE", [4.5, 1.8, 1.5], stopped)
        .build();
    let kin = compute(&scene);
    let p = &kin.tracks[scene.track_by_uuid["parked"].index()];
    let s = &kin.tracks[scene.track_by_uuid["stopped"].index()];
    assert!(p.stationary);
    assert!(!s.stationary);
    assert!(s.speed[25] < 0.5, "{}", s.speed[25]);
}

#[test]
fn lane_assignment_keeps_a_lane_and_leaves_the_road() {
    // Two lanes along +x: 1 (y 0..3.5), 2 (y 3.5..7); overlapping lane 3 over 1 for x 20..40.
    let scene = SceneBuilder::new(60)
        .straight_lane(1, 0.0, 50.0, 0.0, 3.5)
        .straight_lane(2, 0.0, 50.0, 3.5, 7.0)
        .straight_lane(3, 20.0, 40.0, 0.0, 3.5)
        .track(
            "car",
            "REGULAR_VEHICLE",
            [4.5, 1.8, 1.5],
            straight(0, 60, 1.0, 1.7, 0.0, 10.0),
        )
        .build();
    let kin = compute(&scene);
    let la = assign(&scene, &kin);
    let car = scene.track_by_uuid["car"].index();
    let lanes = &la.lanes[car];
    assert_eq!(lanes.len(), 60);
    // Lane 1 from start until x = 50 (frame 49), never the overlapping lane 3; then off the map.
    for (f, l) in lanes.iter().enumerate() {
        let x = 1.0 + f as f64;
        if x < 50.0 {
            assert_eq!(*l, Some(LaneId(1)), "frame {f}");
        } else if x > 50.0 {
            assert_eq!(*l, None, "frame {f}");
        }
    }
}

#[test]
fn lane_assignment_ties_follow_the_turn_direction() {
    // Straight lane 1 along +x and left-turn lane 2 (quarter circle of radius 10 about (0, 10))
    // overlap where both start. Two short tracks stay in the overlap: one yawing left, one straight.
    let arc = |r: f64| -> Vec<[f64; 2]> {
        (0..=9)
            .map(|k| {
                let a = FRAC_PI_2 * k as f64 / 9.0;
                [r * a.sin(), 10.0 - r * a.cos()]
            })
            .collect()
    };
    let scene = SceneBuilder::new(4)
        .straight_lane(1, 0.0, 20.0, -1.75, 1.75)
        .lane(2, &arc(8.25), &arc(11.75), &[], None, None, true)
        .track(
            "turner",
            "REGULAR_VEHICLE",
            [4.5, 1.8, 1.5],
            (0..4)
                .map(|f| (f, 0.5 + 0.3 * f as f64, 0.0, 0.1 * f as f64))
                .collect(),
        )
        .track(
            "straight",
            "REGULAR_VEHICLE",
            [4.5, 1.8, 1.5],
            (0..4)
                .map(|f| (f, 0.5 + 0.3 * f as f64, 0.0, 0.0))
                .collect(),
        )
        .build();
    let kin = compute(&scene);
    let la = assign(&scene, &kin);
    let turner = &la.lanes[scene.track_by_uuid["turner"].index()];
    let straight_car = &la.lanes[scene.track_by_uuid["straight"].index()];
    assert!(turner.iter().all(|l| *l == Some(LaneId(2))), "{turner:?}");
    assert!(
        straight_car.iter().all(|l| *l == Some(LaneId(1))),
        "{straight_car:?}"
    );
}
