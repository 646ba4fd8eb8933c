//! The scenario library (`rules/library/*.dl`) on synthetic *fact scenes*: every program that
//! `library.rs` and `real_logs.rs` do not already test, with at least one case that stages what
//! the program's description means (and must be found exactly) and near-misses that violate one
//! condition of the description (and must find nothing, or less).
//!
//! The scenes are written with the harness of `fact_scene/mod.rs`.
//!
//! The facts are written from the descriptions and the catalog's documentation, not from the
//! rules, so a rule that does not mean its description fails its test.

use crate::fact_scene;

use fact_scene::*;
use scenalog_facts::relation::{Constraint, Request, Value};
use scenalog_facts::TrackId;

#[test]
fn harness_completes_facts_as_the_extractors_do_and_applies_constraints() {
    let f = Facts::parse(
        r#"category(0, "EGO_VEHICLE"). category(1, "PEDESTRIAN").
           near(0, 1, 3, 2.5). speed(1, 3, 1.0). speed(1, 4, 0.2)."#,
    );
    let t = |n| Value::Track(TrackId(n));
    let mut cats: Vec<(u32, String)> = provided(&f, &Request::all("category"))
        .iter()
        .map(|r| match &r[1] {
            Value::Str(c) => (track(&r[0]), c.to_string()),
            other => panic!("not a string: {other:?}"),
        })
        .collect();
    cats.sort();
    let want: Vec<(u32, String)> = [
        (0, "ANY"),
        (0, "EGO_VEHICLE"),
        (0, "VEHICLE"),
        (1, "ANY"),
        (1, "PEDESTRIAN"),
    ]
    .iter()
    .map(|&(x, c)| (x, c.to_string()))
    .collect();
    assert_eq!(cats, want);
    assert_eq!(provided(&f, &Request::all("ego")), vec![vec![t(0)]]);
    let near = provided(&f, &Request::all("near"));
    assert_eq!(near.len(), 2, "{near:?}");
    assert!(near.contains(&vec![t(1), t(0), Value::Time(3), Value::Float(2.5)]));
    // Constraints are applied: a pedestrian's speed >= 0.5, and no vehicle has a speed.
    let walking = Request {
        name: "speed".into(),
        constraints: vec![
            (0, Constraint::Category("PEDESTRIAN".into())),
            (2, Constraint::Ge(0.5)),
        ],
    };
    assert_eq!(
        provided(&f, &walking),
        vec![vec![t(1), Value::Time(3), Value::Float(1.0)]]
    );
    let vehicles = Request {
        name: "speed".into(),
        constraints: vec![(0, Constraint::Category("VEHICLE".into()))],
    };
    assert!(provided(&f, &vehicles).is_empty());
    // A relation the scene does not mention is empty, with the catalog's columns.
    let lanes = f
        .provide(&Request::all("in_lane"))
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(lanes.is_empty());
    assert_eq!(lanes.columns.len(), 3);
}

#[test]
#[should_panic(expected = "has no category fact")]
fn harness_refuses_a_track_without_a_category() {
    Facts::parse(r#"category(1, "BUS"). near(1, 2, 0, 1.0)."#);
}

// ---- accelerating / braking -------------------------------------------------------------------

#[test]
fn accelerating_truck() {
    let name = "accelerating_truck";
    // A box truck accelerating at 1.5 m/s² at frame 10, coasting at frame 11; a car
    // accelerating hard.
    let base = r#"
        category(1, "BOX_TRUCK"). accel(1, 10, 1.5). accel(1, 11, 0.2).
        category(2, "REGULAR_VEHICLE"). accel(2, 10, 3.0).
    "#;
    finds(name, base, &[(1, 10)], &[]);
    // A tractor unit and a plain truck are trucks too.
    finds(name, &swap(base, "BOX_TRUCK", "TRUCK_CAB"), &[(1, 10)], &[]);
    finds(name, &swap(base, "BOX_TRUCK", "TRUCK"), &[(1, 10)], &[]);
    // Pulling away gently still counts: `accelerating` is 0.65 m/s² or more, the threshold
    // included.
    finds(
        name,
        &swap(base, "accel(1, 10, 1.5)", "accel(1, 10, 0.7)"),
        &[(1, 10)],
        &[],
    );
    finds(
        name,
        &swap(base, "accel(1, 10, 1.5)", "accel(1, 10, 0.65)"),
        &[(1, 10)],
        &[],
    );
    // Just below it (0.6 m/s²): holding speed on a slope, not accelerating.
    nothing(name, &swap(base, "accel(1, 10, 1.5)", "accel(1, 10, 0.6)"));
    // Decelerating is not accelerating.
    nothing(name, &swap(base, "accel(1, 10, 1.5)", "accel(1, 10, -1.5)"));
}

#[test]
fn accelerating_vehicle_changing_lanes_right() {
    let name = "accelerating_vehicle_changing_lanes_right";
    // A car changing lanes to the right at frames 20-21 while accelerating at 1.2 m/s²
    // (frame 20) and cruising (frame 21).
    let base = r#"
        category(1, "REGULAR_VEHICLE").
        lane_change(1, 20, "right"). lane_change(1, 21, "right").
        accel(1, 20, 1.2). accel(1, 21, 0.0).
    "#;
    finds(name, base, &[(1, 20)], &[]);
    // The same manoeuvre to the left.
    nothing(
        name,
        &swap(
            base,
            "\"right\"). lane_change(1, 21, \"right\")",
            "\"left\"). lane_change(1, 21, \"left\")",
        ),
    );
    // Accelerating, but not changing lanes at that frame.
    nothing(name, &swap(base, "lane_change(1, 20, \"right\").", ""));
    // A pedestrian "changing lanes" is not a vehicle.
    nothing(name, &swap(base, "REGULAR_VEHICLE", "PEDESTRIAN"));
}

#[test]
fn braking_vehicle() {
    let name = "braking_vehicle";
    // A bus braking at -1.5 m/s² at frame 5; the ego braking as hard, a vehicle too (the
    // description does not leave it out).
    let base = r#"
        category(0, "EGO_VEHICLE"). accel(0, 5, -1.5).
        category(1, "BUS"). accel(1, 5, -1.5). accel(1, 6, -0.3).
    "#;
    finds(name, base, &[(0, 5), (1, 5)], &[]);
    // Decelerating gently (-0.9 m/s²) is not reliably braking.
    finds(
        name,
        &swap(base, "accel(1, 5, -1.5)", "accel(1, 5, -0.9)"),
        &[(0, 5)],
        &[],
    );
    // Accelerating is not braking.
    finds(
        name,
        &swap(base, "accel(1, 5, -1.5)", "accel(1, 5, 1.5)"),
        &[(0, 5)],
        &[],
    );
    // A braking cyclist is not a vehicle.
    finds(
        name,
        &swap(base, "\"BUS\"", "\"BICYCLIST\""),
        &[(0, 5)],
        &[],
    );
}

#[test]
fn high_lateral_acceleration() {
    let name = "high_lateral_acceleration";
    // A car swerving: +2.5 m/s² (left) at frame 3, -2.2 m/s² (right) at frame 4, 1.0 at 5.
    let base = r#"
        category(1, "REGULAR_VEHICLE").
        lat_accel(1, 3, 2.5). lat_accel(1, 4, -2.2). lat_accel(1, 5, 1.0).
    "#;
    finds(name, base, &[(1, 3), (1, 4)], &[]);
    // Just under 2 m/s² either way.
    nothing(
        name,
        &swap(
            &swap(base, "lat_accel(1, 3, 2.5)", "lat_accel(1, 3, 1.9)"),
            "lat_accel(1, 4, -2.2)",
            "lat_accel(1, 4, -1.9)",
        ),
    );
}

#[test]
fn vehicle_accelerating_more_than_two_meters_per_second() {
    let name = "vehicle_accelerating_more_than_two_meters_per_second";
    // A motorcycle at 2.3 m/s² (frame 1) and exactly 2 (frame 2); a pedestrian at 3.
    let base = r#"
        category(1, "MOTORCYCLE"). accel(1, 1, 2.3). accel(1, 2, 2.0).
        category(2, "PEDESTRIAN"). accel(2, 1, 3.0).
    "#;
    finds(name, base, &[(1, 1)], &[]);
    // 1.9 m/s²: not more than two.
    nothing(name, &swap(base, "accel(1, 1, 2.3)", "accel(1, 1, 1.9)"));
}

#[test]
fn vehicle_accelerating_on_intersection() {
    let name = "vehicle_accelerating_on_intersection";
    // A car accelerating at 1.5 m/s² at frames 7 (on the intersection) and 8 (past it).
    let base = r#"
        category(1, "REGULAR_VEHICLE").
        accel(1, 7, 1.5). accel(1, 8, 1.5). on_intersection(1, 7).
    "#;
    finds(name, base, &[(1, 7)], &[]);
    // On the intersection but merely cruising.
    nothing(name, &swap(base, "accel(1, 7, 1.5)", "accel(1, 7, 0.5)"));
    // Accelerating, but the intersection is never reached.
    nothing(name, &swap(base, "on_intersection(1, 7).", ""));
}

#[test]
fn vehicle_braking_heavily() {
    let name = "vehicle_braking_heavily";
    // A truck at -3.5 m/s² (frame 2) and -2 m/s² (frame 3).
    let base = r#"
        category(1, "TRUCK"). accel(1, 2, -3.5). accel(1, 3, -2.0).
    "#;
    finds(name, base, &[(1, 2)], &[]);
    // -2.9 m/s² is braking but not heavily.
    nothing(name, &swap(base, "-3.5", "-2.9"));
    // A dog stopping short is not a vehicle.
    nothing(name, &swap(base, "TRUCK", "DOG"));
}

#[test]
fn vehicle_braking_at_pedestrian_crossing() {
    let name = "vehicle_braking_at_pedestrian_crossing";
    // A car braking at -2 m/s² with its box 0.5 m from a crosswalk at frame 4; braking as
    // hard far from any crosswalk at frame 9.
    let base = r#"
        category(1, "REGULAR_VEHICLE").
        accel(1, 4, -2.0). at_crosswalk(1, 4, 0.5).
        accel(1, 9, -2.0). at_crosswalk(1, 9, 25.0).
    "#;
    finds(name, base, &[(1, 4)], &[]);
    // On the crosswalk, and exactly 1 m from it (`at_a_crosswalk` includes 1 m).
    for d in ["0.0", "1.0"] {
        let on = swap(
            base,
            "at_crosswalk(1, 4, 0.5)",
            &format!("at_crosswalk(1, 4, {d})"),
        );
        finds(name, &on, &[(1, 4)], &[]);
    }
    // At the crosswalk but not braking: coasting (-0.5) or just under braking (-0.9 m/s²).
    nothing(name, &swap(base, "accel(1, 4, -2.0)", "accel(1, 4, -0.5)"));
    nothing(name, &swap(base, "accel(1, 4, -2.0)", "accel(1, 4, -0.9)"));
    // Braking 1.5 m from the crosswalk: short of it, not at it.
    nothing(
        name,
        &swap(base, "at_crosswalk(1, 4, 0.5)", "at_crosswalk(1, 4, 1.5)"),
    );
    // A bicyclist braking there is not a vehicle.
    nothing(name, &swap(base, "REGULAR_VEHICLE", "BICYCLIST"));
}

// ---- lane changes -----------------------------------------------------------------------------

#[test]
fn bicyclist_changing_lanes_to_the_right() {
    let name = "bicyclist_changing_lanes_to_the_right";
    // A bicyclist moving right at frames 30-31.
    let base = r#"
        category(1, "BICYCLIST"). lane_change(1, 30, "right"). lane_change(1, 31, "right").
    "#;
    finds(name, base, &[(1, 30), (1, 31)], &[]);
    // To the left instead.
    nothing(name, &base.replace("\"right\"", "\"left\""));
    // A car changing lanes right is not a bicyclist.
    nothing(name, &swap(base, "BICYCLIST", "REGULAR_VEHICLE"));
}

#[test]
fn box_truck_changing_lanes_to_the_left() {
    let name = "box_truck_changing_lanes_to_the_left";
    // A box truck moving left at frame 12.
    let base = r#"category(1, "BOX_TRUCK"). lane_change(1, 12, "left")."#;
    finds(name, base, &[(1, 12)], &[]);
    // To the right instead.
    nothing(name, &swap(base, "\"left\"", "\"right\""));
    // A semi's tractor is not a box truck.
    nothing(name, &swap(base, "BOX_TRUCK", "TRUCK_CAB"));
}

#[test]
fn bus_changing_lanes() {
    let name = "bus_changing_lanes";
    // A bus moving left at frame 3, an articulated bus right at frame 8, a school bus left
    // at frame 9.
    let base = r#"
        category(1, "BUS"). lane_change(1, 3, "left").
        category(2, "ARTICULATED_BUS"). lane_change(2, 8, "right").
        category(3, "SCHOOL_BUS"). lane_change(3, 9, "left").
    "#;
    finds(name, base, &[(1, 3), (2, 8), (3, 9)], &[]);
    // A truck changing lanes is not a bus.
    finds(
        name,
        &swap(base, "ARTICULATED_BUS", "TRUCK"),
        &[(1, 3), (3, 9)],
        &[],
    );
}

#[test]
fn vehicle_changing_lanes_to_the_right() {
    let name = "vehicle_changing_lanes_to_the_right";
    // A car moving right at frame 40, the ego (a vehicle too) moving right at frame 40 as well.
    let base = r#"
        category(0, "EGO_VEHICLE"). lane_change(0, 40, "right").
        category(1, "REGULAR_VEHICLE"). lane_change(1, 40, "right").
    "#;
    finds(name, base, &[(0, 40), (1, 40)], &[]);
    // The car moving left instead.
    finds(
        name,
        &swap(
            base,
            "lane_change(1, 40, \"right\")",
            "lane_change(1, 40, \"left\")",
        ),
        &[(0, 40)],
        &[],
    );
}

#[test]
fn vehicle_changing_lanes_on_intersection() {
    let name = "vehicle_changing_lanes_on_intersection";
    // A car changing lanes left at frames 5 (on the intersection) and 6 (past it).
    let base = r#"
        category(1, "REGULAR_VEHICLE"). lane_change(1, 5, "left"). lane_change(1, 6, "left").
        on_intersection(1, 5).
    "#;
    finds(name, base, &[(1, 5)], &[]);
    // Either direction counts.
    finds(name, &base.replace("\"left\"", "\"right\""), &[(1, 5)], &[]);
    // On the intersection, staying in lane.
    nothing(name, &swap(base, "lane_change(1, 5, \"left\").", ""));
}

#[test]
fn left_lane_change_while_there_is_a_vehicle_to_the_left() {
    let name = "left_lane_change_while_there_is_a_vehicle_to_the_left";
    // Car 1 changes lanes left at frame 10 with car 2 on its left, 1.5 m from its box and
    // overlapping its length (Lat 0).
    let base = r#"
        category(1, "REGULAR_VEHICLE"). category(2, "REGULAR_VEHICLE").
        lane_change(1, 10, "left").
        direction(1, 2, 10, "left", 1.5, 0.0).
    "#;
    finds(name, base, &[(1, 10)], &[(1, 2, 10)]);
    // The other car is on its right.
    nothing(name, &swap(base, "\"left\", 1.5", "\"right\", 1.5"));
    // Changing lanes right, away from it.
    nothing(
        name,
        &swap(
            base,
            "lane_change(1, 10, \"left\")",
            "lane_change(1, 10, \"right\")",
        ),
    );
    // The left neighbour is a pedestrian on the sidewalk, not a vehicle.
    nothing(
        name,
        &swap(
            base,
            "category(2, \"REGULAR_VEHICLE\")",
            "category(2, \"PEDESTRIAN\")",
        ),
    );
    // Far to the left (8 m): the gap is free.
    nothing(name, &swap(base, "1.5, 0.0", "8.0, 0.0"));
}

// ---- speed, stopped vs parked -----------------------------------------------------------------

#[test]
fn vehicle_moving_at_crawling_speed() {
    let name = "vehicle_moving_at_crawling_speed";
    // A car at 1.5 m/s (frame 1), 0.2 m/s (frame 2, stopped) and 8 m/s (frame 3).
    let base = r#"
        category(1, "REGULAR_VEHICLE"). speed(1, 1, 1.5). speed(1, 2, 0.2). speed(1, 3, 8.0).
        category(2, "PEDESTRIAN"). speed(2, 1, 1.5).
    "#;
    finds(name, base, &[(1, 1)], &[]);
    // Just above walking pace.
    nothing(name, &swap(base, "speed(1, 1, 1.5)", "speed(1, 1, 3.1)"));
}

#[test]
fn regular_vehicles_that_are_stopped_or_nearly_stopped() {
    let name = "regular_vehicles_that_are_stopped_or_nearly_stopped";
    // A car stopped at a light (0 m/s, frame 1), creeping (0.8 m/s, frame 2), moving off
    // (4 m/s, frame 3); its track moves overall, so it is not parked.
    let base = r#"
        category(1, "REGULAR_VEHICLE"). speed(1, 1, 0.0). speed(1, 2, 0.8). speed(1, 3, 4.0).
    "#;
    finds(name, base, &[(1, 1), (1, 2)], &[]);
    // 1.2 m/s is not nearly stopped.
    finds(
        name,
        &swap(base, "speed(1, 2, 0.8)", "speed(1, 2, 1.2)"),
        &[(1, 1)],
        &[],
    );
    // A stopped bus is not a regular vehicle.
    nothing(name, &swap(base, "REGULAR_VEHICLE", "BUS"));
    // A parked car is stopped too (the prelude's `stopped`): the description does not leave
    // parked cars out.
    finds(
        name,
        &format!("{base} stationary(1)."),
        &[(1, 1), (1, 2)],
        &[],
    );
}

#[test]
fn object_that_has_not_moved() {
    let name = "object_that_has_not_moved";
    // A parked car and a bollard that never move, a pedestrian who walks away; all present
    // at frames 0-1.
    let base = r#"
        category(1, "REGULAR_VEHICLE"). stationary(1). present(1, 0). present(1, 1).
        category(2, "BOLLARD"). stationary(2). present(2, 0). present(2, 1).
        category(3, "PEDESTRIAN"). present(3, 0). present(3, 1).
    "#;
    finds(name, base, &[(1, 0), (1, 1), (2, 0), (2, 1)], &[]);
    // The car drives off at some point: its track is not stationary.
    finds(
        name,
        &swap(base, "stationary(1).", ""),
        &[(2, 0), (2, 1)],
        &[],
    );
}

#[test]
fn vehicle_stopped_at_intersection() {
    let name = "vehicle_stopped_at_intersection";
    // A car waiting on an intersection at 0.2 m/s over frames 0-30, on the intersection at
    // frames 10 and 20; it drives away later, so it is not parked.
    let mut base = String::from(
        r#"category(1, "REGULAR_VEHICLE"). on_intersection(1, 10). on_intersection(1, 20)."#,
    );
    for f in 0..=30 {
        base.push_str(&format!(" speed(1, {f}, 0.2)."));
    }
    finds(name, &base, &[(1, 10), (1, 20)], &[]);
    // `stopped` is the frame's own speed below 0.5 m/s: creeping at 0.6 m/s at frame 25 does
    // not undo frame 20, while 0.5 m/s at frame 20 itself is not stopped, 0.45 is.
    finds(
        name,
        &swap(&base, "speed(1, 25, 0.2)", "speed(1, 25, 0.6)"),
        &[(1, 10), (1, 20)],
        &[],
    );
    finds(
        name,
        &swap(&base, "speed(1, 20, 0.2)", "speed(1, 20, 0.5)"),
        &[(1, 10)],
        &[],
    );
    finds(
        name,
        &swap(&base, "speed(1, 20, 0.2)", "speed(1, 20, 0.45)"),
        &[(1, 10), (1, 20)],
        &[],
    );
    // Parked on the intersection (stationary over its whole track): parked is stopped too.
    finds(
        name,
        &format!("{base} stationary(1)."),
        &[(1, 10), (1, 20)],
        &[],
    );
    // Stopped, but not on an intersection.
    let off = swap(
        &swap(&base, "on_intersection(1, 10).", ""),
        "on_intersection(1, 20).",
        "",
    );
    nothing(name, &off);
    // At frame 5 it waits at the stop line: in lane 7, which leads into intersection lane 8,
    // 3 m from the intersection.
    let line = format!(
        "{off} in_lane(1, 5, 7). lane_successor(7, 8). intersection_lane(8). \
         near_intersection(1, 5, 3.0)."
    );
    finds(name, &line, &[(1, 5)], &[]);
    // 5 m from it is still at it; 6 m is short of it.
    let at = |d: &str| swap(&line, "near_intersection(1, 5, 3.0)", d);
    finds(name, &at("near_intersection(1, 5, 5.0)"), &[(1, 5)], &[]);
    nothing(name, &at("near_intersection(1, 5, 6.0)"));
    // 3 m from an intersection its lane does not lead into (a side street's, across a median).
    nothing(name, &swap(&line, "intersection_lane(8).", ""));
    // A pedestrian standing there is not a vehicle.
    nothing(name, &swap(&base, "REGULAR_VEHICLE", "PEDESTRIAN"));
}

// ---- turns ------------------------------------------------------------------------------------

#[test]
fn passenger_vehicle_turning_left_at_intersection() {
    let name = "passenger_vehicle_turning_left_at_intersection";
    // A car turning left at frames 20-21, on the intersection at both.
    let base = r#"
        category(1, "REGULAR_VEHICLE").
        turning(1, 20, "left"). turning(1, 21, "left").
        on_intersection(1, 20). on_intersection(1, 21).
    "#;
    finds(name, base, &[(1, 20), (1, 21)], &[]);
    // Turning right instead.
    nothing(name, &base.replace("\"left\"", "\"right\""));
    // Turning left into a driveway, off any intersection.
    nothing(
        name,
        &base.replace("on_intersection(1, 20). on_intersection(1, 21).", ""),
    );
    // A bus is not a passenger vehicle.
    nothing(name, &swap(base, "REGULAR_VEHICLE", "BUS"));
}

#[test]
fn vehicle_making_a_right_turn() {
    let name = "vehicle_making_a_right_turn";
    // A truck turning right at frame 15; the ego (a vehicle too) turning right at the same time.
    let base = r#"
        category(0, "EGO_VEHICLE"). turning(0, 15, "right").
        category(1, "TRUCK"). turning(1, 15, "right").
    "#;
    finds(name, base, &[(0, 15), (1, 15)], &[]);
    // The truck turns left.
    finds(
        name,
        &swap(
            base,
            "turning(1, 15, \"right\")",
            "turning(1, 15, \"left\")",
        ),
        &[(0, 15)],
        &[],
    );
    // A cyclist turning right is not a vehicle.
    finds(name, &swap(base, "TRUCK", "BICYCLIST"), &[(0, 15)], &[]);
}

#[test]
fn vehicle_turning_right_at_stop_sign() {
    let name = "vehicle_turning_right_at_stop_sign";
    // A car at stop sign 9 at frames 10-12, then turning right at frames 40 and 62 (50
    // frames, 5 s, after it last was at the sign) and 63 (51 frames after).
    let base = r#"
        category(1, "REGULAR_VEHICLE"). category(9, "STOP_SIGN").
        at_stop_sign(1, 9, 10). at_stop_sign(1, 9, 11). at_stop_sign(1, 9, 12).
        turning(1, 40, "right"). turning(1, 62, "right"). turning(1, 63, "right").
    "#;
    finds(name, base, &[(1, 40), (1, 62)], &[(1, 9, 40), (1, 9, 62)]);
    // Turning left after the stop sign.
    nothing(name, &base.replace("\"right\"", "\"left\""));
    // Turning right before ever reaching the stop sign (frames 1-3), no sign after.
    let before = r#"
        category(1, "REGULAR_VEHICLE"). category(9, "STOP_SIGN").
        turning(1, 1, "right"). turning(1, 2, "right"). turning(1, 3, "right").
        at_stop_sign(1, 9, 10).
    "#;
    nothing(name, before);
    // A bicyclist at the sign and turning is not a vehicle.
    nothing(name, &swap(base, "REGULAR_VEHICLE", "BICYCLIST"));
}

#[test]
fn vehicle_turning_right_with_pedestrian_in_front() {
    let name = "vehicle_turning_right_with_pedestrian_in_front";
    // A car turning right at frame 8 with a pedestrian 6 m ahead, 1 m outside its side.
    let base = r#"
        category(1, "REGULAR_VEHICLE"). category(2, "PEDESTRIAN").
        turning(1, 8, "right").
        direction(1, 2, 8, "forward", 6.0, 1.0).
    "#;
    finds(name, base, &[(1, 8)], &[(1, 2, 8)]);
    // The pedestrian is behind the car.
    nothing(name, &swap(base, "\"forward\"", "\"backward\""));
    // Too far ahead (12 m).
    nothing(name, &swap(base, "6.0, 1.0", "12.0, 1.0"));
    // Ahead but well off the car's path (4 m outside its side).
    nothing(name, &swap(base, "6.0, 1.0", "6.0, 4.0"));
    // The car is turning left.
    nothing(name, &swap(base, "\"right\"", "\"left\""));
    // A traffic cone in front is not a pedestrian.
    nothing(
        name,
        &swap(
            base,
            "category(2, \"PEDESTRIAN\")",
            "category(2, \"CONSTRUCTION_CONE\")",
        ),
    );
}

#[test]
fn vehicle_turning_left_while_pedestrian_crosses_at_crosswalk() {
    let name = "vehicle_turning_left_while_pedestrian_crosses_at_crosswalk";
    // A car turning left at frame 30 while a pedestrian on a crosswalk (box overlapping it)
    // crosses in front of it.
    let base = r#"
        category(1, "REGULAR_VEHICLE"). category(2, "PEDESTRIAN").
        turning(1, 30, "left").
        crossing(1, 2, 30, "forward").
        at_crosswalk(2, 30, 0.0).
    "#;
    finds(name, base, &[(1, 30)], &[(1, 2, 30)]);
    // The pedestrian crosses 4 m away from any crosswalk (jaywalking).
    nothing(
        name,
        &swap(base, "at_crosswalk(2, 30, 0.0)", "at_crosswalk(2, 30, 4.0)"),
    );
    // The car turns right.
    nothing(name, &swap(base, "\"left\"", "\"right\""));
    // The pedestrian passes behind the car, not in front of it.
    nothing(name, &swap(base, "\"forward\"", "\"backward\""));
    // A cyclist on the crosswalk is not a pedestrian.
    nothing(
        name,
        &swap(
            base,
            "category(2, \"PEDESTRIAN\")",
            "category(2, \"BICYCLIST\")",
        ),
    );
}

// ---- intersections ----------------------------------------------------------------------------

#[test]
fn any_object_within_5_meters_of_an_intersection() {
    let name = "any_object_within_5_meters_of_an_intersection";
    // A pedestrian 4 m from an intersection (frame 1), a car on it (frame 1), a cone 7 m away;
    // the ego, an object too, on it as well.
    let base = r#"
        category(0, "EGO_VEHICLE"). near_intersection(0, 1, 0.0).
        category(1, "PEDESTRIAN"). near_intersection(1, 1, 4.0).
        category(2, "REGULAR_VEHICLE"). near_intersection(2, 1, 0.0).
        category(3, "CONSTRUCTION_CONE"). near_intersection(3, 1, 7.0).
    "#;
    finds(name, base, &[(0, 1), (1, 1), (2, 1)], &[]);
    // The pedestrian 5.5 m away.
    finds(
        name,
        &swap(
            base,
            "near_intersection(1, 1, 4.0)",
            "near_intersection(1, 1, 5.5)",
        ),
        &[(0, 1), (2, 1)],
        &[],
    );
}

#[test]
fn bicycle_on_intersection() {
    let name = "bicycle_on_intersection";
    // A ridden bicycle on an intersection at frame 4: the BICYCLE box (2) and its rider's
    // BICYCLIST box (1); a car too. The bicycle is the BICYCLE, never its rider.
    let base = r#"
        category(1, "BICYCLIST"). on_intersection(1, 4).
        category(2, "BICYCLE"). on_intersection(2, 4).
        category(3, "REGULAR_VEHICLE"). on_intersection(3, 4).
    "#;
    finds(name, base, &[(2, 4)], &[]);
    // The bicycle waits before the intersection while its rider leans onto it: nothing.
    nothing(name, &swap(base, "on_intersection(2, 4).", ""));
    // A motorcycle is not a bicycle.
    nothing(name, &swap(base, "\"BICYCLE\"", "\"MOTORCYCLE\""));
}

#[test]
fn school_bus_on_intersection() {
    let name = "school_bus_on_intersection";
    // A school bus on an intersection at frame 2 (not at frame 3); a city bus on it.
    let base = r#"
        category(1, "SCHOOL_BUS"). on_intersection(1, 2). present(1, 3).
        category(2, "BUS"). on_intersection(2, 2).
    "#;
    finds(name, base, &[(1, 2)], &[]);
    // The school bus waits before the intersection.
    nothing(name, &swap(base, "on_intersection(1, 2).", ""));
}

// ---- stop signs -------------------------------------------------------------------------------

#[test]
fn active_vehicle_at_stop_sign() {
    let name = "active_vehicle_at_stop_sign";
    // A car in stop sign 9's lane, facing it, at frames 3-4; it drives on later.
    let base = r#"
        category(1, "REGULAR_VEHICLE"). category(9, "STOP_SIGN").
        at_stop_sign(1, 9, 3). at_stop_sign(1, 9, 4).
    "#;
    finds(name, base, &[(1, 3), (1, 4)], &[(1, 9, 3), (1, 9, 4)]);
    // A car parked at the sign for the whole log is not active.
    nothing(name, &format!("{base} stationary(1)."));
    // A bicyclist at the sign is not a vehicle.
    nothing(name, &swap(base, "REGULAR_VEHICLE", "BICYCLIST"));
}

#[test]
fn pedestrian_near_stop_sign() {
    let name = "pedestrian_near_stop_sign";
    // A pedestrian 8 m from a stop sign's box at frame 6 (`nearby`: 10 m at most), 12 m at
    // frame 7.
    let base = r#"
        category(1, "PEDESTRIAN"). category(9, "STOP_SIGN").
        near(1, 9, 6, 8.0). near(1, 9, 7, 12.0).
    "#;
    finds(name, base, &[(1, 6)], &[(1, 9, 6)]);
    // Exactly 10 m away at frame 7 is near too.
    finds(
        name,
        &swap(base, "near(1, 9, 7, 12.0)", "near(1, 9, 7, 10.0)"),
        &[(1, 6), (1, 7)],
        &[(1, 9, 6), (1, 9, 7)],
    );
    // 10.5 m away at frame 6 too.
    nothing(
        name,
        &swap(base, "near(1, 9, 6, 8.0)", "near(1, 9, 6, 10.5)"),
    );
    // Next to a sign that is not a stop sign.
    nothing(name, &swap(base, "STOP_SIGN", "SIGN"));
}

#[test]
fn vehicle_stopped_at_a_stop_sign() {
    let name = "vehicle_stopped_at_a_stop_sign";
    // A car at stop sign 9 at frames 10-12: arriving (3 m/s), stopped (0.1 m/s), leaving
    // (0.6 m/s).
    let base = r#"
        category(1, "REGULAR_VEHICLE"). category(9, "STOP_SIGN").
        at_stop_sign(1, 9, 10). at_stop_sign(1, 9, 11). at_stop_sign(1, 9, 12).
        speed(1, 10, 3.0). speed(1, 11, 0.1). speed(1, 12, 0.6).
    "#;
    finds(name, base, &[(1, 11)], &[(1, 9, 11)]);
    // Stopped at frame 11 but elsewhere, not at the sign.
    nothing(name, &swap(base, "at_stop_sign(1, 9, 11).", ""));
    // Rolling through at 0.6 m/s.
    nothing(name, &swap(base, "speed(1, 11, 0.1)", "speed(1, 11, 0.6)"));
}

// ---- lanes ------------------------------------------------------------------------------------

#[test]
fn bicyclist_riding_in_vehicle_lane() {
    let name = "bicyclist_riding_in_vehicle_lane";
    // Lane 100 is a vehicle lane, lane 200 a bike lane. A bicyclist rides at 4 m/s in lane
    // 100 at frame 1 and in lane 200 at frame 2.
    let base = r#"
        lane_type(100, "VEHICLE"). lane_type(200, "BIKE").
        category(1, "BICYCLIST").
        in_lane(1, 1, 100). speed(1, 1, 4.0).
        in_lane(1, 2, 200). speed(1, 2, 4.0).
    "#;
    finds(name, base, &[(1, 1)], &[]);
    // Standing with the bike (0.2 m/s) in the vehicle lane: not riding.
    nothing(name, &swap(base, "speed(1, 1, 4.0)", "speed(1, 1, 0.2)"));
    // A car in the vehicle lane is not a bicyclist.
    nothing(name, &swap(base, "BICYCLIST", "REGULAR_VEHICLE"));
}

#[test]
fn stationary_vehicle_blocking_bike_lane() {
    let name = "stationary_vehicle_blocking_bike_lane";
    // A delivery truck standing (0.1 m/s) in bike lane 200 at frame 5, driving (6 m/s) in
    // it at frame 6; a car standing in vehicle lane 100 at frame 5.
    let base = r#"
        lane_type(100, "VEHICLE"). lane_type(200, "BIKE").
        category(1, "BOX_TRUCK"). in_lane(1, 5, 200). speed(1, 5, 0.1).
        in_lane(1, 6, 200). speed(1, 6, 6.0).
        category(2, "REGULAR_VEHICLE"). in_lane(2, 5, 100). speed(2, 5, 0.0).
    "#;
    finds(name, base, &[(1, 5)], &[]);
    // Moving slowly (0.6 m/s) through the bike lane is not standing in it.
    nothing(name, &swap(base, "speed(1, 5, 0.1)", "speed(1, 5, 0.6)"));
    // A bicyclist standing in the bike lane is not a vehicle blocking it.
    nothing(name, &swap(base, "BOX_TRUCK", "BICYCLIST"));
}

#[test]
fn car_driving_in_bus_lane() {
    let name = "car_driving_in_bus_lane";
    // A car at 8 m/s in bus lane 300 at frame 1, in vehicle lane 100 at frame 2.
    let base = r#"
        lane_type(100, "VEHICLE"). lane_type(300, "BUS").
        category(1, "REGULAR_VEHICLE").
        in_lane(1, 1, 300). speed(1, 1, 8.0). in_lane(1, 2, 100). speed(1, 2, 8.0).
    "#;
    finds(name, base, &[(1, 1)], &[]);
    // Parked in the bus lane (0 m/s): not driving.
    nothing(name, &swap(base, "speed(1, 1, 8.0)", "speed(1, 1, 0.0)"));
    // A bus in the bus lane is not a car.
    nothing(name, &swap(base, "REGULAR_VEHICLE", "BUS"));
}

#[test]
fn bus_in_bus_lane() {
    let name = "bus_in_bus_lane";
    // A city bus in bus lane 300 at frame 1 and vehicle lane 100 at frame 2; a car in the bus
    // lane at frame 1. (Like most of the library's bus programs, this one means the BUS
    // category only; `bus_changing_lanes` and `bus_with_another_bus_in_its_lane` also count
    // articulated and school buses.)
    let base = r#"
        lane_type(100, "VEHICLE"). lane_type(300, "BUS").
        category(1, "BUS"). in_lane(1, 1, 300). in_lane(1, 2, 100).
        category(2, "REGULAR_VEHICLE"). in_lane(2, 1, 300).
    "#;
    finds(name, base, &[(1, 1)], &[]);
    // The bus lane is a bike lane instead.
    nothing(
        name,
        &swap(base, "lane_type(300, \"BUS\")", "lane_type(300, \"BIKE\")"),
    );
    // The bus is in no lane at frame 1 (in a depot).
    nothing(name, &swap(base, "in_lane(1, 1, 300).", ""));
}

#[test]
fn bus_with_another_bus_in_its_lane() {
    let name = "bus_with_another_bus_in_its_lane";
    // A bus and an articulated bus in the same lane at frame 3 (each in the other's).
    let base = r#"
        category(1, "BUS"). category(2, "ARTICULATED_BUS").
        same_lane(1, 2, 3). same_lane(2, 1, 3).
    "#;
    finds(name, base, &[(1, 3), (2, 3)], &[(1, 2, 3), (2, 1, 3)]);
    // The other is a truck.
    nothing(name, &swap(base, "ARTICULATED_BUS", "TRUCK"));
    // One bus alone: `same_lane` of a bus with itself is not another bus.
    nothing(name, r#"category(1, "BUS"). same_lane(1, 1, 3)."#);
}

#[test]
fn truck_sharing_a_lane_with_another_truck() {
    let name = "truck_sharing_a_lane_with_another_truck";
    // A box truck and a tractor unit in one lane at frame 3.
    let base = r#"
        category(1, "BOX_TRUCK"). category(2, "TRUCK_CAB").
        same_lane(1, 2, 3). same_lane(2, 1, 3).
    "#;
    finds(name, base, &[(1, 3), (2, 3)], &[(1, 2, 3), (2, 1, 3)]);
    // The other is a bus.
    nothing(name, &swap(base, "TRUCK_CAB", "BUS"));
    // A truck alone.
    nothing(name, r#"category(1, "TRUCK"). same_lane(1, 1, 3)."#);
}

// ---- directions around the ego ----------------------------------------------------------------

#[test]
fn bus_within_5_meters_to_either_side_of_ego_vehicle() {
    let name = "bus_within_5_meters_to_either_side_of_ego_vehicle";
    // At frame 2 a bus 3 m to the ego's left and another 4 m to its right.
    let base = r#"
        category(0, "EGO_VEHICLE"). category(1, "BUS"). category(2, "BUS").
        direction(0, 1, 2, "left", 3.0, 0.0).
        direction(0, 2, 2, "right", 4.0, 1.0).
    "#;
    finds(name, base, &[(1, 2), (2, 2)], &[(1, 0, 2), (2, 0, 2)]);
    // The right bus 6 m away.
    finds(
        name,
        &swap(base, "\"right\", 4.0", "\"right\", 6.0"),
        &[(1, 2)],
        &[(1, 0, 2)],
    );
    // The left bus is ahead instead, 3 m from the ego's front.
    finds(
        name,
        &swap(base, "\"left\", 3.0", "\"forward\", 3.0"),
        &[(2, 2)],
        &[(2, 0, 2)],
    );
    // A truck beside the ego is not a bus.
    finds(
        name,
        &swap(base, "category(1, \"BUS\")", "category(1, \"TRUCK\")"),
        &[(2, 2)],
        &[(2, 0, 2)],
    );
}

#[test]
fn motorcycle_or_pedestrian_within_5_meters_to_the_right_of_the_ego_vehicle() {
    let name = "motorcycle_or_pedestrian_within_5_meters_to_the_right_of_the_ego_vehicle";
    // At frame 1, a motorcycle 4 m and a pedestrian 2 m to the ego's right.
    let base = r#"
        category(0, "EGO_VEHICLE"). category(1, "MOTORCYCLE"). category(2, "PEDESTRIAN").
        direction(0, 1, 1, "right", 4.0, 0.0).
        direction(0, 2, 1, "right", 2.0, 3.0).
    "#;
    finds(name, base, &[(1, 1), (2, 1)], &[(1, 0, 1), (2, 0, 1)]);
    // The motorcycle 5.5 m away.
    finds(
        name,
        &swap(base, "4.0, 0.0", "5.5, 0.0"),
        &[(2, 1)],
        &[(2, 0, 1)],
    );
    // The pedestrian on the ego's left.
    finds(
        name,
        &swap(base, "\"right\", 2.0", "\"left\", 2.0"),
        &[(1, 1)],
        &[(1, 0, 1)],
    );
    // A bicyclist is neither.
    finds(
        name,
        &swap(
            base,
            "category(2, \"PEDESTRIAN\")",
            "category(2, \"BICYCLIST\")",
        ),
        &[(1, 1)],
        &[(1, 0, 1)],
    );
}

#[test]
fn moving_bicycle_directly_to_the_left_of_the_ego_vehicle() {
    let name = "moving_bicycle_directly_to_the_left_of_the_ego_vehicle";
    // At frame 3 a bicycle (1) ridden at 5 m/s 1.5 m to the ego's left, alongside it (its
    // centre between the ego's ends, Lat 0); its rider is the BICYCLIST box 2 beside it.
    let base = r#"
        category(0, "EGO_VEHICLE"). category(1, "BICYCLE"). category(2, "BICYCLIST").
        direction(0, 1, 3, "left", 1.5, 0.0). speed(1, 3, 5.0).
        direction(0, 2, 3, "left", 1.6, 0.0). speed(2, 3, 5.0).
    "#;
    finds(name, base, &[(1, 3)], &[(1, 0, 3)]);
    // Left of the ego but 2 m past its front end: not directly beside it.
    nothing(
        name,
        &base
            .replace("1.5, 0.0", "1.5, 2.0")
            .replace("1.6, 0.0", "1.6, 2.0"),
    );
    // The bicycle pushed at 0.5 m/s is moving (the threshold included); at 0.45 m/s, or
    // parked (0 m/s), it is not, whatever the rider's box does.
    let pushed = |v: &str| swap(base, "speed(1, 3, 5.0)", &format!("speed(1, 3, {v})"));
    finds(name, &pushed("0.5"), &[(1, 3)], &[(1, 0, 3)]);
    nothing(name, &pushed("0.45"));
    nothing(name, &pushed("0.0"));
    // On the ego's right.
    nothing(name, &base.replace("\"left\"", "\"right\""));
    // A moving bicyclist with no BICYCLE box is not a bicycle.
    nothing(
        name,
        &swap(base, "direction(0, 1, 3, \"left\", 1.5, 0.0).", ""),
    );
}

#[test]
fn moving_pedestrian_within_3_meters_to_the_left_of_ego_vehicle() {
    let name = "moving_pedestrian_within_3_meters_to_the_left_of_ego_vehicle";
    // At frame 4 a pedestrian walking (1.4 m/s) 2 m to the ego's left.
    let base = r#"
        category(0, "EGO_VEHICLE"). category(1, "PEDESTRIAN").
        direction(0, 1, 4, "left", 2.0, 1.0). speed(1, 4, 1.4).
    "#;
    finds(name, base, &[(1, 4)], &[(1, 0, 4)]);
    // 3.5 m away.
    nothing(name, &swap(base, "2.0, 1.0", "3.5, 1.0"));
    // Standing still (0.1 m/s).
    nothing(name, &swap(base, "speed(1, 4, 1.4)", "speed(1, 4, 0.1)"));
    // On the right.
    nothing(name, &swap(base, "\"left\"", "\"right\""));
}

#[test]
fn semi_truck_within_30_meters_ahead_of_ego_vehicle() {
    let name = "semi_truck_within_30_meters_ahead_of_ego_vehicle";
    // At frame 5 a tractor unit 20 m ahead of the ego in its lane (Lat 0).
    let base = r#"
        category(0, "EGO_VEHICLE"). category(1, "TRUCK_CAB").
        direction(0, 1, 5, "forward", 20.0, 0.0).
    "#;
    finds(name, base, &[(1, 5)], &[(1, 0, 5)]);
    // 31 m ahead.
    nothing(name, &swap(base, "20.0, 0.0", "31.0, 0.0"));
    // 20 m behind.
    nothing(name, &swap(base, "\"forward\"", "\"backward\""));
    // A box truck is not a semi.
    nothing(name, &swap(base, "TRUCK_CAB", "BOX_TRUCK"));
}

#[test]
fn vehicle_facing_the_ego_vehicle() {
    let name = "vehicle_facing_the_ego_vehicle";
    // At frame 6 an oncoming car 20 m away with the ego on its forward axis.
    let base = r#"
        category(0, "EGO_VEHICLE"). category(1, "REGULAR_VEHICLE").
        facing(1, 0, 6). heading_relative(1, 0, 6, "opposite"). near(1, 0, 6, 20.0).
    "#;
    finds(name, base, &[(1, 6)], &[(1, 0, 6)]);
    // Oncoming but pointed past the ego (the ego off its forward axis).
    nothing(name, &swap(base, "facing(1, 0, 6).", ""));
    // Facing the ego from 35 m.
    nothing(
        name,
        &swap(base, "near(1, 0, 6, 20.0)", "near(1, 0, 6, 35.0)"),
    );
    // A pedestrian facing the ego is not a vehicle.
    nothing(name, &swap(base, "REGULAR_VEHICLE", "PEDESTRIAN"));
}

#[test]
fn ego_with_vehicles_on_both_sides() {
    let name = "ego_with_vehicles_on_both_sides";
    // At frame 7 a car 1 m to the ego's left and a bus 2 m to its right.
    let base = r#"
        category(0, "EGO_VEHICLE"). category(1, "REGULAR_VEHICLE"). category(2, "BUS").
        direction(0, 1, 7, "left", 1.0, 0.0).
        direction(0, 2, 7, "right", 2.0, 0.0).
    "#;
    finds(name, base, &[(0, 7)], &[(0, 1, 7), (0, 2, 7)]);
    // The bus is a lane and more away (3.5 m).
    nothing(name, &swap(base, "\"right\", 2.0", "\"right\", 3.5"));
    // Both vehicles on the left.
    nothing(name, &swap(base, "\"right\", 2.0", "\"left\", 2.0"));
    // A pedestrian on the right is not a vehicle.
    nothing(
        name,
        &swap(base, "category(2, \"BUS\")", "category(2, \"PEDESTRIAN\")"),
    );
}

#[test]
fn two_active_vehicles_behind_ego() {
    let name = "two_active_vehicles_behind_ego";
    // At frame 8 two driving cars behind the ego, 5 m and 12 m from its box.
    let base = r#"
        category(0, "EGO_VEHICLE"). category(1, "REGULAR_VEHICLE"). category(2, "REGULAR_VEHICLE").
        direction(0, 1, 8, "backward", 5.0, 0.0).
        direction(0, 2, 8, "backward", 12.0, 0.0).
    "#;
    finds(name, base, &[(1, 8), (2, 8)], &[(1, 0, 8), (2, 0, 8)]);
    // The second 16 m behind: only one within 15 m.
    nothing(name, &swap(base, "12.0", "16.0"));
    // The second is parked for the whole log: not active.
    nothing(name, &format!("{base} stationary(2)."));
    // The second is ahead of the ego.
    nothing(name, &swap(base, "\"backward\", 12.0", "\"forward\", 12.0"));
}

#[test]
fn pedestrians_over_30_meters_away() {
    let name = "pedestrians_over_30_meters_away";
    // At frame 9 a pedestrian 35 m from the ego, another 10 m from it, and a third 70 m away
    // (beyond the 50 m of pair relations, so no `near` tuple at all).
    let base = r#"
        category(0, "EGO_VEHICLE"). present(0, 9).
        category(1, "PEDESTRIAN"). present(1, 9). near(0, 1, 9, 35.0).
        category(2, "PEDESTRIAN"). present(2, 9). near(0, 2, 9, 10.0).
        category(3, "PEDESTRIAN"). present(3, 9).
    "#;
    finds(name, base, &[(1, 9), (3, 9)], &[]);
    // The first at 29 m.
    finds(name, &swap(base, "35.0", "29.0"), &[(3, 9)], &[]);
    // Exactly 30 m is not over 30.
    finds(name, &swap(base, "35.0", "30.0"), &[(3, 9)], &[]);
    // Cars far away are not pedestrians.
    let cars = base.replace("\"PEDESTRIAN\"", "\"REGULAR_VEHICLE\"");
    nothing(name, &cars);
}

#[test]
fn group_of_pedestrians_ahead_of_the_ego_vehicle() {
    let name = "group_of_pedestrians_ahead_of_the_ego_vehicle";
    // At frame 10 three pedestrians 15-17 m ahead of the ego, within 5 m of its path, in one
    // group: 1-2 and 2-3 are 1 m apart, 1-3 2.2 m (chained, not each within 2 m of both).
    let base = r#"
        category(0, "EGO_VEHICLE").
        category(1, "PEDESTRIAN"). category(2, "PEDESTRIAN"). category(3, "PEDESTRIAN").
        direction(0, 1, 10, "forward", 15.0, 3.0).
        direction(0, 2, 10, "forward", 16.0, 4.0).
        direction(0, 3, 10, "forward", 17.0, 4.5).
        near(1, 2, 10, 1.0). near(2, 3, 10, 1.0). near(1, 3, 10, 2.2).
    "#;
    let all = [
        (1, 2, 10),
        (1, 3, 10),
        (2, 1, 10),
        (2, 3, 10),
        (3, 1, 10),
        (3, 2, 10),
    ];
    finds(name, base, &[(1, 10), (2, 10), (3, 10)], &all);
    // Three pedestrians ahead, but spread out (2-3 2.1 m apart): a pair and one alone.
    nothing(
        name,
        &swap(base, "near(2, 3, 10, 1.0)", "near(2, 3, 10, 2.1)"),
    );
    // The third stands 5.5 m off the ego's path, still in the group: the two ahead are
    // found, with the whole group related.
    finds(
        name,
        &swap(base, "17.0, 4.5", "17.0, 5.5"),
        &[(1, 10), (2, 10)],
        &[(1, 2, 10), (1, 3, 10), (2, 1, 10), (2, 3, 10)],
    );
    // The group is behind the ego.
    nothing(name, &base.replace("\"forward\"", "\"backward\""));
    // The third is a dog: two pedestrians are not a group.
    nothing(
        name,
        &swap(base, "category(3, \"PEDESTRIAN\")", "category(3, \"DOG\")"),
    );
}

#[test]
fn multiple_motorcycles_ahead_of_the_ego_vehicle() {
    let name = "multiple_motorcycles_ahead_of_the_ego_vehicle";
    // At frame 11 two motorcycles ahead of the ego (10 m and 40 m).
    let base = r#"
        category(0, "EGO_VEHICLE"). category(1, "MOTORCYCLE"). category(2, "MOTORCYCLE").
        direction(0, 1, 11, "forward", 10.0, 0.0).
        direction(0, 2, 11, "forward", 40.0, 2.0).
    "#;
    finds(name, base, &[(1, 11), (2, 11)], &[]);
    // The second behind the ego.
    nothing(name, &swap(base, "\"forward\", 40.0", "\"backward\", 40.0"));
    // The second is a bicycle.
    nothing(
        name,
        &swap(
            base,
            "category(2, \"MOTORCYCLE\")",
            "category(2, \"BICYCLE\")",
        ),
    );
}

#[test]
fn multiple_pedestrians_near_a_vehicle() {
    let name = "multiple_pedestrians_near_a_vehicle";
    // At frame 12 two pedestrians 1 m and 8 m from a parked car's box (`nearby`: 10 m at most).
    let base = r#"
        category(1, "REGULAR_VEHICLE"). category(2, "PEDESTRIAN"). category(3, "PEDESTRIAN").
        near(1, 2, 12, 1.0). near(1, 3, 12, 8.0). near(2, 3, 12, 7.5).
    "#;
    finds(name, base, &[(1, 12)], &[(1, 2, 12), (1, 3, 12)]);
    // The second exactly 10 m away is near too.
    finds(
        name,
        &swap(base, "near(1, 3, 12, 8.0)", "near(1, 3, 12, 10.0)"),
        &[(1, 12)],
        &[(1, 2, 12), (1, 3, 12)],
    );
    // The second 10.5 m away: one pedestrian is not multiple.
    nothing(
        name,
        &swap(base, "near(1, 3, 12, 8.0)", "near(1, 3, 12, 10.5)"),
    );
    // The "vehicle" is a bollard.
    nothing(name, &swap(base, "REGULAR_VEHICLE", "BOLLARD"));
}

#[test]
fn multiple_pedestrians_crossing_ahead() {
    let name = "multiple_pedestrians_crossing_ahead";
    // At frame 13 two pedestrians crossing in front of the ego.
    let base = r#"
        category(0, "EGO_VEHICLE"). category(1, "PEDESTRIAN"). category(2, "PEDESTRIAN").
        crossing(0, 1, 13, "forward"). crossing(0, 2, 13, "forward").
    "#;
    finds(name, base, &[(1, 13), (2, 13)], &[]);
    // The second crosses behind the ego.
    nothing(
        name,
        &swap(
            base,
            "crossing(0, 2, 13, \"forward\")",
            "crossing(0, 2, 13, \"backward\")",
        ),
    );
    // The second crosses a frame later: never two at once.
    nothing(
        name,
        &swap(base, "crossing(0, 2, 13,", "crossing(0, 2, 14,"),
    );
    // Two pedestrians crossing in front of another car, not the ego.
    let other = r#"
        category(0, "EGO_VEHICLE"). category(5, "REGULAR_VEHICLE").
        category(1, "PEDESTRIAN"). category(2, "PEDESTRIAN").
        crossing(5, 1, 13, "forward"). crossing(5, 2, 13, "forward").
    "#;
    nothing(name, other);
}

// ---- crosswalks, crossings, jaywalking --------------------------------------------------------

#[test]
fn pedestrian_crossing_in_front_of_vehicle_at_crosswalk() {
    let name = "pedestrian_crossing_in_front_of_vehicle_at_crosswalk";
    // At frame 14 a pedestrian on a crosswalk (0.5 m from it) crosses a car's front.
    let base = r#"
        category(1, "REGULAR_VEHICLE"). category(2, "PEDESTRIAN").
        crossing(1, 2, 14, "forward"). at_crosswalk(2, 14, 0.5).
    "#;
    finds(name, base, &[(2, 14)], &[(2, 1, 14)]);
    // Crossing 3 m from any crosswalk.
    nothing(
        name,
        &swap(base, "at_crosswalk(2, 14, 0.5)", "at_crosswalk(2, 14, 3.0)"),
    );
    // Walking past the car's side, not its front.
    nothing(name, &swap(base, "\"forward\"", "\"left\""));
    // Crossing in front of a bollard, not a vehicle.
    nothing(name, &swap(base, "REGULAR_VEHICLE", "BOLLARD"));
    // A bicyclist on the crosswalk is not a pedestrian.
    nothing(
        name,
        &swap(
            base,
            "category(2, \"PEDESTRIAN\")",
            "category(2, \"BICYCLIST\")",
        ),
    );
}

#[test]
fn ego_vehicle_approaching_pedestrian_at_crosswalk() {
    let name = "ego_vehicle_approaching_pedestrian_at_crosswalk";
    // At frame 15 the ego heads toward a pedestrian standing on a crosswalk 20 m away.
    let base = r#"
        category(0, "EGO_VEHICLE"). category(1, "PEDESTRIAN").
        at_crosswalk(1, 15, 0.0). heading_toward(0, 1, 15). near(0, 1, 15, 20.0).
    "#;
    finds(name, base, &[(0, 15)], &[(0, 1, 15)]);
    // The ego drives away from (or past) the pedestrian.
    nothing(name, &swap(base, "heading_toward(0, 1, 15).", ""));
    // 35 m away.
    nothing(name, &swap(base, "20.0", "35.0"));
    // The pedestrian is 3 m from the crosswalk.
    nothing(
        name,
        &swap(base, "at_crosswalk(1, 15, 0.0)", "at_crosswalk(1, 15, 3.0)"),
    );
    // Another car, not the ego, approaches the pedestrian.
    let other = r#"
        category(0, "EGO_VEHICLE"). category(5, "REGULAR_VEHICLE"). category(1, "PEDESTRIAN").
        at_crosswalk(1, 15, 0.0). heading_toward(5, 1, 15). near(5, 1, 15, 20.0).
    "#;
    nothing(name, other);
}

#[test]
fn vehicle_approaching_pedestrians_waiting_at_a_crosswalk() {
    let name = "vehicle_approaching_pedestrians_waiting_at_a_crosswalk";
    // At frame 16 a car heads toward a pedestrian standing (0.1 m/s) 1 m from a crosswalk,
    // 25 m away.
    let base = r#"
        category(1, "REGULAR_VEHICLE"). category(2, "PEDESTRIAN").
        at_crosswalk(2, 16, 1.0). speed(2, 16, 0.1).
        heading_toward(1, 2, 16). near(1, 2, 16, 25.0).
    "#;
    finds(name, base, &[(1, 16)], &[(1, 2, 16)]);
    // The pedestrian is walking (1.3 m/s): crossing, not waiting.
    nothing(name, &swap(base, "speed(2, 16, 0.1)", "speed(2, 16, 1.3)"));
    // Standing 5 m from the crosswalk.
    nothing(
        name,
        &swap(base, "at_crosswalk(2, 16, 1.0)", "at_crosswalk(2, 16, 5.0)"),
    );
    // The car is not heading toward the pedestrian.
    nothing(name, &swap(base, "heading_toward(1, 2, 16).", ""));
    // 40 m away.
    nothing(name, &swap(base, "25.0", "40.0"));
}

#[test]
fn pedestrians_using_designated_crossing() {
    let name = "pedestrians_using_designated_crossing";
    // At frame 17 a pedestrian walking (1.2 m/s) on a crosswalk (box overlapping it).
    let base = r#"
        category(1, "PEDESTRIAN"). at_crosswalk(1, 17, 0.0). speed(1, 17, 1.2).
    "#;
    finds(name, base, &[(1, 17)], &[]);
    // Stepping onto it, 0.5 m and 1 m from it: `at_a_crosswalk` (1 m at most).
    for d in ["0.5", "1.0"] {
        let at = swap(
            base,
            "at_crosswalk(1, 17, 0.0)",
            &format!("at_crosswalk(1, 17, {d})"),
        );
        finds(name, &at, &[(1, 17)], &[]);
    }
    // Walking along the kerb 1.5 m from the crosswalk.
    nothing(
        name,
        &swap(base, "at_crosswalk(1, 17, 0.0)", "at_crosswalk(1, 17, 1.5)"),
    );
    // Standing on it (0.1 m/s).
    nothing(name, &swap(base, "speed(1, 17, 1.2)", "speed(1, 17, 0.1)"));
    // A bicyclist riding over the crosswalk is not a pedestrian.
    nothing(name, &swap(base, "PEDESTRIAN", "BICYCLIST"));
}

#[test]
fn jaywalking_pedestrian() {
    let name = "jaywalking_pedestrian";
    // A pedestrian on the road 8 m from the nearest crosswalk at frame 1; another on a road
    // of a map with no crosswalk at all at frame 1.
    let base = r#"
        category(1, "PEDESTRIAN"). on_road(1, 1). at_crosswalk(1, 1, 8.0).
        category(2, "PEDESTRIAN"). on_road(2, 1).
    "#;
    finds(name, base, &[(1, 1), (2, 1)], &[]);
    // The first is on the crosswalk.
    finds(
        name,
        &swap(base, "at_crosswalk(1, 1, 8.0)", "at_crosswalk(1, 1, 0.0)"),
        &[(2, 1)],
        &[],
    );
    // The second is on the sidewalk, not the road.
    finds(name, &swap(base, "on_road(2, 1).", ""), &[(1, 1)], &[]);
    // A car on the road is not a pedestrian.
    finds(
        name,
        &swap(
            base,
            "category(2, \"PEDESTRIAN\")",
            "category(2, \"REGULAR_VEHICLE\")",
        ),
        &[(1, 1)],
        &[],
    );
}

#[test]
fn pedestrian_on_intersection_not_using_a_crosswalk() {
    let name = "pedestrian_on_intersection_not_using_a_crosswalk";
    // At frame 2 a pedestrian in the middle of an intersection, 6 m from any crosswalk.
    let base = r#"
        category(1, "PEDESTRIAN"). on_intersection(1, 2). at_crosswalk(1, 2, 6.0).
    "#;
    finds(name, base, &[(1, 2)], &[]);
    // On the intersection's crosswalk.
    nothing(
        name,
        &swap(base, "at_crosswalk(1, 2, 6.0)", "at_crosswalk(1, 2, 0.0)"),
    );
    // Off the intersection.
    nothing(name, &swap(base, "on_intersection(1, 2).", ""));
}

#[test]
fn vehicle_crossed_by_pedestrian() {
    let name = "vehicle_crossed_by_pedestrian";
    // At frame 3 a pedestrian crosses in front of a bus.
    let base = r#"
        category(1, "BUS"). category(2, "PEDESTRIAN"). crossing(1, 2, 3, "forward").
    "#;
    finds(name, base, &[(1, 3)], &[(1, 2, 3)]);
    // Walking past the bus's side.
    nothing(name, &swap(base, "\"forward\"", "\"right\""));
    // A dog crossing is not a pedestrian.
    nothing(name, &swap(base, "PEDESTRIAN", "DOG"));
}

// ---- following and chains of following ---------------------------------------------------------

#[test]
fn bicycle_following_closely_behind_a_vehicle() {
    let name = "bicycle_following_closely_behind_a_vehicle";
    // At frame 6 a bicycle (1) follows a car, 3 m behind its box; its rider's BICYCLIST box (3)
    // follows the car too.
    let base = r#"
        category(1, "BICYCLE"). category(2, "REGULAR_VEHICLE"). category(3, "BICYCLIST").
        following(1, 2, 6). near(1, 2, 6, 3.0).
        following(3, 2, 6). near(3, 2, 6, 3.2).
    "#;
    finds(name, base, &[(1, 6)], &[(1, 2, 6)]);
    // 6 m behind: not closely.
    nothing(
        name,
        &swap(base, "near(1, 2, 6, 3.0)", "near(1, 2, 6, 6.0)"),
    );
    // The car follows the bicycle instead.
    nothing(
        name,
        &swap(base, "following(1, 2, 6)", "following(2, 1, 6)"),
    );
    // Following a pedestrian, not a vehicle.
    nothing(name, &swap(base, "REGULAR_VEHICLE", "PEDESTRIAN"));
    // The rider alone (no BICYCLE box) is not a bicycle.
    nothing(
        name,
        &swap(
            base,
            "category(1, \"BICYCLE\")",
            "category(1, \"BICYCLIST\")",
        ),
    );
}

#[test]
fn car_following_closely_behind_bicyclist() {
    let name = "car_following_closely_behind_bicyclist";
    // At frame 7 a car follows a bicyclist, 2 m behind.
    let base = r#"
        category(1, "REGULAR_VEHICLE"). category(2, "BICYCLIST").
        following(1, 2, 7). near(1, 2, 7, 2.0).
    "#;
    finds(name, base, &[(1, 7)], &[(1, 2, 7)]);
    // 7 m behind.
    nothing(name, &swap(base, "2.0", "7.0"));
    // The bicyclist follows the car.
    nothing(
        name,
        &swap(base, "following(1, 2, 7)", "following(2, 1, 7)"),
    );
    // A bus is not a car.
    nothing(name, &swap(base, "REGULAR_VEHICLE", "BUS"));
}

/// A queue in one lane at `frame`: cars `1..=n` at about 7 m spacing, car `i + 1` in front of
/// car `i` when `ahead` (the ego, track 0, at the back), behind it otherwise (the ego at the
/// front). As the catalog documents it, `following(X, Y, T)` holds for every lead up to 25 m
/// ahead, so each car follows the next three in front of it, not only the nearest.
fn queue(n: u32, ahead: bool, frame: u32) -> String {
    let mut out = String::from(r#"category(0, "EGO_VEHICLE")."#);
    for i in 1..=n {
        out.push_str(&format!(r#" category({i}, "REGULAR_VEHICLE")."#));
    }
    for i in 0..=n {
        for j in i + 1..=n.min(i + 3) {
            let (x, y) = if ahead { (i, j) } else { (j, i) };
            out.push_str(&format!(" following({x}, {y}, {frame})."));
        }
    }
    out
}

#[test]
fn the_active_vehicle_in_front_of_the_vehicle_ahead() {
    let name = "the_active_vehicle_in_front_of_the_vehicle_ahead";
    // Car 2 is in front of the ego's lead (car 1); cars 3 and 4 are further ahead.
    let base = queue(4, true, 8);
    finds(name, &base, &[(2, 8)], &[]);
    // Car 2 is parked for the whole log: not active (and car 3 is not in front of the
    // vehicle ahead either).
    nothing(name, &format!("{base} stationary(2)."));
    // Only the ego's lead: nothing in front of it.
    nothing(name, &queue(1, true, 8));
}

#[test]
fn two_cars_back_from_the_ego_vehicle() {
    let name = "two_cars_back_from_the_ego_vehicle";
    // Cars 1-4 queue behind the ego at frame 9: car 2 is two cars back.
    let base = queue(4, false, 9);
    finds(name, &base, &[(2, 9)], &[(2, 0, 9)]);
    // Only one car behind the ego.
    nothing(name, &queue(1, false, 9));
    // The queue is ahead of the ego: nobody is behind it.
    nothing(name, &queue(4, true, 9));
    // The second car back is a bicyclist.
    nothing(
        name,
        &swap(
            &base,
            "category(2, \"REGULAR_VEHICLE\")",
            "category(2, \"BICYCLIST\")",
        ),
    );
}

#[test]
fn ego_vehicle_two_cars_ahead_of_another_vehicle() {
    let name = "ego_vehicle_two_cars_ahead_of_another_vehicle";
    // Cars 1-4 queue behind the ego at frame 10: the ego is two cars ahead of car 2 (only).
    let base = queue(4, false, 10);
    finds(name, &base, &[(0, 10)], &[(0, 2, 10)]);
    // One car behind only: the ego is one car ahead of it.
    nothing(name, &queue(1, false, 10));
    // The second car back is a bicyclist, not a vehicle.
    nothing(
        name,
        &swap(
            &base,
            "category(2, \"REGULAR_VEHICLE\")",
            "category(2, \"BICYCLIST\")",
        ),
    );
    // The ego follows the queue: it is behind, not ahead.
    nothing(name, &queue(4, true, 10));
}

#[test]
fn vehicle_two_cars_ahead_is_braking() {
    let name = "vehicle_two_cars_ahead_is_braking";
    // The second car ahead of the ego brakes at -2 m/s².
    let q = queue(4, true, 11);
    let base = format!("{q} accel(2, 11, -2.0). accel(1, 11, 0.0).");
    finds(name, &base, &[(2, 11)], &[]);
    // It merely eases off (-0.5 m/s²).
    nothing(
        name,
        &swap(&base, "accel(2, 11, -2.0)", "accel(2, 11, -0.5)"),
    );
    // Only the car directly ahead brakes.
    nothing(name, &format!("{q} accel(1, 11, -2.0)."));
    // Only the third car ahead brakes (the ego and car 1 follow it too, within 25 m).
    nothing(name, &format!("{q} accel(3, 11, -2.0)."));
}

#[test]
fn vehicle_two_cars_ahead_is_changing_lanes() {
    let name = "vehicle_two_cars_ahead_is_changing_lanes";
    // The second car ahead of the ego moves left at frame 12.
    let q = queue(4, true, 12);
    let base = format!("{q} lane_change(2, 12, \"left\").");
    finds(name, &base, &[(2, 12)], &[]);
    // To the right counts as well.
    finds(
        name,
        &base.replace("\"left\"", "\"right\""),
        &[(2, 12)],
        &[],
    );
    // The car directly ahead changes lanes.
    nothing(name, &swap(&base, "lane_change(2,", "lane_change(1,"));
    // The third car ahead changes lanes.
    nothing(name, &swap(&base, "lane_change(2,", "lane_change(3,"));
}

#[test]
fn vehicle_two_vehicles_ahead_is_turning() {
    let name = "vehicle_two_vehicles_ahead_is_turning";
    // The second car ahead of the ego turns right at frame 13.
    let base = format!("{} turning(2, 13, \"right\").", queue(4, true, 13));
    finds(name, &base, &[(2, 13)], &[]);
    // Turning left counts as well.
    finds(
        name,
        &base.replace("\"right\"", "\"left\""),
        &[(2, 13)],
        &[],
    );
    // The car directly ahead turns.
    nothing(name, &swap(&base, "turning(2,", "turning(1,"));
    // The third and fourth cars ahead turn.
    nothing(
        name,
        &swap(
            &base,
            "turning(2, 13, \"right\").",
            "turning(3, 13, \"right\"). turning(4, 13, \"right\").",
        ),
    );
    // The second car turns at another frame than the one it is two ahead.
    nothing(name, &swap(&base, "turning(2, 13,", "turning(2, 14,"));
}

#[test]
fn vehicle_two_cars_ahead_is_being_crossed_by_a_pedestrian() {
    let name = "vehicle_two_cars_ahead_is_being_crossed_by_a_pedestrian";
    // At frame 5 a pedestrian (track 9) crosses the front of the second car ahead of the ego.
    let q = queue(4, true, 5);
    let base = format!(r#"{q} category(9, "PEDESTRIAN"). crossing(2, 9, 5, "forward")."#);
    finds(name, &base, &[(2, 5)], &[(2, 9, 5)]);
    // The pedestrian crosses car 1, the car directly ahead.
    nothing(name, &swap(&base, "crossing(2, 9, 5,", "crossing(1, 9, 5,"));
    // The pedestrian crosses the third car ahead.
    nothing(name, &swap(&base, "crossing(2, 9, 5,", "crossing(3, 9, 5,"));
    // Only one car ahead of the ego, crossed.
    nothing(
        name,
        &format!(
            r#"{} category(9, "PEDESTRIAN"). crossing(1, 9, 5, "forward")."#,
            queue(1, true, 5)
        ),
    );
    // A cone "crossing" is not a pedestrian.
    nothing(
        name,
        &swap(
            &base,
            "category(9, \"PEDESTRIAN\")",
            "category(9, \"CONSTRUCTION_CONE\")",
        ),
    );
}

#[test]
fn the_vehicle_behind_another_vehicle_being_crossed_by_a_jaywalking_pedestrian() {
    let name = "the_vehicle_behind_another_vehicle_being_crossed_by_a_jaywalking_pedestrian";
    // At frame 4 cars 1-4 queue behind the ego (track 0, which leads the queue) and a
    // pedestrian (track 9) on the road 10 m from any crosswalk crosses car 1's front: car 2
    // is the vehicle behind it (cars 3 and 4 follow car 1 too, but further back).
    let q = queue(4, false, 4);
    let jaywalker = r#"category(9, "PEDESTRIAN"). on_road(9, 4). at_crosswalk(9, 4, 10.0)."#;
    let base = format!(r#"{q} {jaywalker} crossing(1, 9, 4, "forward")."#);
    finds(name, &base, &[(2, 4)], &[(2, 1, 4)]);
    // The pedestrian uses a crosswalk.
    nothing(
        name,
        &swap(&base, "at_crosswalk(9, 4, 10.0)", "at_crosswalk(9, 4, 0.0)"),
    );
    // The pedestrian crosses behind car 1 (between it and car 2), not its front.
    nothing(name, &swap(&base, "\"forward\"", "\"backward\""));
    // The last car of the queue is crossed: nobody is behind it.
    nothing(
        name,
        &format!(r#"{q} {jaywalker} crossing(4, 9, 4, "forward")."#),
    );
}

// ---- against traffic, approaching, passing, overtaking --------------------------------------

#[test]
fn bicycle_traveling_against_traffic() {
    let name = "bicycle_traveling_against_traffic";
    // A bicycle (1) ridden at 4 m/s against its lane for 2 s (frames 10-30, 21 samples), its
    // rider's BICYCLIST box (3) with it. At frame 14 a car drives at 10 m/s on the same side
    // of the road, 15 m away, heading the opposite way: the traffic it rides against.
    let car = r#"
        category(2, "REGULAR_VEHICLE"). speed(2, 14, 10.0).
        road_side(2, 1, 14, "same"). heading_relative(2, 1, 14, "opposite").
        near(2, 1, 14, 15.0).
    "#;
    let scene = |frames: std::ops::Range<u32>, speed: f64| {
        let bike = wrong_way(1, "BICYCLE", frames.clone(), speed);
        let rider = wrong_way(3, "BICYCLIST", frames, speed);
        format!("{bike} {rider} {car}")
    };
    let base = scene(10..31, 4.0);
    let all: Vec<(u32, u32)> = (10..31).map(|f| (1, f)).collect();
    finds(name, &base, &all, &[(1, 2, 14)]);
    // 1.9 s against the lane (20 samples) is a bicycle cutting across it, not riding against
    // traffic.
    nothing(name, &scene(10..30, 4.0));
    // Riding with the traffic (its lane's direction, the car's too); walking the bike at 1 m/s.
    nothing(name, &base.replace("\"opposite\")", "\"same\")"));
    nothing(name, &scene(10..31, 1.0));
    // The rider alone (no BICYCLE box) is not a bicycle.
    nothing(
        name,
        &swap(
            &base,
            "category(1, \"BICYCLE\")",
            "category(1, \"BICYCLIST\")",
        ),
    );
    // Vehicles not met head-on on its side are not related: heading the same way, on the other
    // side of the road, 35 m away, or stopped (0.2 m/s).
    for (from, to) in [
        (
            "heading_relative(2, 1, 14, \"opposite\")",
            "heading_relative(2, 1, 14, \"same\")",
        ),
        (
            "road_side(2, 1, 14, \"same\")",
            "road_side(2, 1, 14, \"opposite\")",
        ),
        ("near(2, 1, 14, 15.0)", "near(2, 1, 14, 35.0)"),
        ("speed(2, 14, 10.0)", "speed(2, 14, 0.2)"),
    ] {
        finds(name, &swap(&base, from, to), &all, &[]);
    }
}

#[test]
fn ego_vehicle_approaching_stopped_truck() {
    let name = "ego_vehicle_approaching_stopped_truck";
    // At frame 15 the ego heads toward a box truck stopped in traffic (0.2 m/s, it drives
    // on later), 20 m away.
    let base = r#"
        category(0, "EGO_VEHICLE"). category(1, "BOX_TRUCK").
        speed(1, 15, 0.2). heading_toward(0, 1, 15). near(0, 1, 15, 20.0).
    "#;
    finds(name, base, &[(0, 15)], &[(0, 1, 15)]);
    // The truck is parked for the whole log: a parked truck is stopped too.
    finds(
        name,
        &format!("{base} stationary(1)."),
        &[(0, 15)],
        &[(0, 1, 15)],
    );
    // `stopped` is below 0.5 m/s: 0.45 is, 0.5 and 3 m/s are not.
    let at = |v: &str| swap(base, "speed(1, 15, 0.2)", &format!("speed(1, 15, {v})"));
    finds(name, &at("0.45"), &[(0, 15)], &[(0, 1, 15)]);
    nothing(name, &at("0.5"));
    nothing(name, &at("3.0"));
    // The ego is not heading toward it.
    nothing(name, &swap(base, "heading_toward(0, 1, 15).", ""));
    // 30 m away is still approaching; 40 m is not.
    finds(name, &swap(base, "20.0", "30.0"), &[(0, 15)], &[(0, 1, 15)]);
    nothing(name, &swap(base, "20.0", "40.0"));
    // A stopped bus is not a truck.
    nothing(name, &swap(base, "BOX_TRUCK", "BUS"));
}

#[test]
fn ego_vehicle_passing_parked_bus() {
    let name = "ego_vehicle_passing_parked_bus";
    // At frame 16 the ego drives at 8 m/s beside a parked bus, 2 m to its left and
    // overlapping its length.
    let base = r#"
        category(0, "EGO_VEHICLE"). category(1, "BUS"). stationary(1).
        speed(0, 16, 8.0). direction(0, 1, 16, "left", 2.0, 0.0).
    "#;
    finds(name, base, &[(0, 16)], &[(0, 1, 16)]);
    // On the right counts too.
    finds(
        name,
        &swap(base, "\"left\"", "\"right\""),
        &[(0, 16)],
        &[(0, 1, 16)],
    );
    // The ego is stopped beside the bus.
    nothing(name, &swap(base, "speed(0, 16, 8.0)", "speed(0, 16, 0.1)"));
    // The bus drives (not stationary over its track).
    nothing(name, &swap(base, "stationary(1).", ""));
    // The bus is still ahead-left, 3 m beyond the ego's front: not yet alongside.
    nothing(name, &swap(base, "2.0, 0.0", "2.0, 3.0"));
    // 7 m to the side.
    nothing(name, &swap(base, "2.0, 0.0", "7.0, 0.0"));
}

/// Track 1 (a `slow` m/s vehicle of `cat1`) has its `side` half-midplane crossed by track 2
/// (`fast` m/s, `cat2`) at frame 17, the two heading `rel`-ly.
fn crossing_pair(cat1: &str, cat2: &str, side: &str, rel: &str, slow: f64, fast: f64) -> String {
    format!(
        r#"
        category(1, "{cat1}"). category(2, "{cat2}").
        speed(1, 17, {slow:.1}). speed(2, 17, {fast:.1}).
        crossing(1, 2, 17, "{side}"). heading_relative(1, 2, 17, "{rel}").
    "#
    )
}

#[test]
fn motorcycle_overtaking_a_vehicle() {
    let name = "motorcycle_overtaking_a_vehicle";
    let scene =
        |side, rel, car, moto| crossing_pair("REGULAR_VEHICLE", "MOTORCYCLE", side, rel, car, moto);
    // A motorcycle at 14 m/s passes a car at 8 m/s, both heading the same way, crossing the
    // car's left half-midplane; or its right one.
    finds(
        name,
        &scene("left", "same", 8.0, 14.0),
        &[(2, 17)],
        &[(2, 1, 17)],
    );
    finds(
        name,
        &scene("right", "same", 8.0, 14.0),
        &[(2, 17)],
        &[(2, 1, 17)],
    );
    // Any vehicle can be overtaken: a bus, or another motorcycle.
    let bus = crossing_pair("BUS", "MOTORCYCLE", "left", "same", 8.0, 14.0);
    finds(name, &bus, &[(2, 17)], &[(2, 1, 17)]);
    let moto = crossing_pair("MOTORCYCLE", "MOTORCYCLE", "left", "same", 8.0, 14.0);
    finds(name, &moto, &[(2, 17)], &[(2, 1, 17)]);
    // An oncoming motorcycle passes the car on its left: passing, not overtaking.
    nothing(name, &scene("left", "opposite", 8.0, 14.0));
    // The car overtakes a slower motorcycle (6 m/s against 12): the motorcycle is overtaken.
    nothing(name, &scene("left", "same", 12.0, 6.0));
    // The motorcycle crosses in front of the car.
    nothing(name, &scene("forward", "perpendicular", 8.0, 14.0));
    // A parked motorcycle is passed by the car's swept plane: nothing overtakes.
    nothing(
        name,
        &format!("{} stationary(2).", scene("left", "same", 8.0, 14.0)),
    );
}

#[test]
fn vehicle_being_overtaken_on_the_left() {
    let name = "vehicle_being_overtaken_on_the_left";
    let scene =
        |side, rel, v, w| crossing_pair("REGULAR_VEHICLE", "REGULAR_VEHICLE", side, rel, v, w);
    // A car at 8 m/s is passed on its left by a car at 14 m/s going the same way.
    finds(
        name,
        &scene("left", "same", 8.0, 14.0),
        &[(1, 17)],
        &[(1, 2, 17)],
    );
    // Passed on the right instead.
    nothing(name, &scene("right", "same", 8.0, 14.0));
    // Oncoming traffic on its left: not overtaking it.
    nothing(name, &scene("left", "opposite", 8.0, 14.0));
    // It is the faster one (14 m/s against 8), passing the other: it overtakes.
    nothing(name, &scene("left", "same", 14.0, 8.0));
    // A parked car is not being overtaken, it is passed.
    nothing(
        name,
        &format!("{} stationary(1).", scene("left", "same", 0.0, 14.0)),
    );
}

#[test]
fn vehicle_being_overtaken_on_the_right() {
    let name = "vehicle_being_overtaken_on_the_right";
    let scene = |side, rel, v, w| crossing_pair("BUS", "REGULAR_VEHICLE", side, rel, v, w);
    // A bus at 6 m/s is passed on its right by a car at 12 m/s going the same way.
    finds(
        name,
        &scene("right", "same", 6.0, 12.0),
        &[(1, 17)],
        &[(1, 2, 17)],
    );
    // Passed on the left instead.
    nothing(name, &scene("left", "same", 6.0, 12.0));
    // A car driving the other way past its right (a one-way street's wrong-way driver).
    nothing(name, &scene("right", "opposite", 6.0, 12.0));
    // The bus is the faster one, passing the car on its left.
    nothing(name, &scene("right", "same", 12.0, 6.0));
}

#[test]
fn vehicle_starts_to_change_lanes_then_goes_back() {
    let name = "vehicle_starts_to_change_lanes_then_goes_back";
    // A car at 8 m/s pushes left at frame 10 (+1.5 m/s²) and right at frame 25 (-1.5 m/s²),
    // 1.5 s later, and never changes lanes: referred from frame 10 to frame 25.
    let base = r#"
        category(1, "REGULAR_VEHICLE").
        speed(1, 10, 8.0). lat_accel(1, 10, 1.5).
        speed(1, 25, 8.0). lat_accel(1, 25, -1.5).
        present(1, 5). present(1, 10). present(1, 18). present(1, 25). present(1, 30).
    "#;
    finds(name, base, &[(1, 10), (1, 18), (1, 25)], &[]);
    // The same pushes around a completed lane change (the crossing between them).
    nothing(name, &format!("{base} lane_change(1, 18, \"left\")."));
    // The push back comes 3.5 s later: more than 3 s.
    nothing(
        name,
        &swap(
            &swap(
                base,
                "speed(1, 25, 8.0). lat_accel(1, 25, -1.5).",
                "speed(1, 45, 8.0). lat_accel(1, 45, -1.5).",
            ),
            "present(1, 30).",
            "present(1, 45).",
        ),
    );
    // No push back: -0.9 m/s² is below the threshold.
    nothing(
        name,
        &swap(base, "lat_accel(1, 25, -1.5)", "lat_accel(1, 25, -0.9)"),
    );
    // A pedestrian stepping sideways is not a vehicle.
    nothing(name, &swap(base, "REGULAR_VEHICLE", "PEDESTRIAN"));
    // Creeping at 2 m/s: not moving along a lane.
    nothing(name, &swap(base, "speed(1, 10, 8.0)", "speed(1, 10, 2.0)"));
}

// ---- concepts of issue #14 --------------------------------------------------------------------

#[test]
fn group_of_three_people() {
    let name = "group_of_three_people";
    // Three pedestrians in a line 1.5 m apart at frame 5: one group of three, though 1 and 3
    // are 3 m apart (a neighbour count within 2 m would give 1 and 3 only one neighbour).
    let base = r#"
        category(1, "PEDESTRIAN"). category(2, "PEDESTRIAN"). category(3, "PEDESTRIAN").
        near(1, 2, 5, 1.5). near(2, 3, 5, 1.5). near(1, 3, 5, 3.0).
    "#;
    finds(
        name,
        base,
        &[(1, 5), (2, 5), (3, 5)],
        &[
            (1, 2, 5),
            (1, 3, 5),
            (2, 1, 5),
            (2, 3, 5),
            (3, 1, 5),
            (3, 2, 5),
        ],
    );
    // The chain broken (2 and 3 are 2.1 m apart): a pair and a lone pedestrian.
    nothing(
        name,
        &swap(base, "near(2, 3, 5, 1.5)", "near(2, 3, 5, 2.1)"),
    );
    // A fourth pedestrian joins the chain: a group of four, not three.
    nothing(
        name,
        &format!(r#"{base} category(4, "PEDESTRIAN"). near(3, 4, 5, 1.0)."#),
    );
    // A car in the chain's place does not link pedestrians.
    nothing(
        name,
        &swap(
            base,
            "category(2, \"PEDESTRIAN\")",
            "category(2, \"REGULAR_VEHICLE\")",
        ),
    );
    // Two groups of three at one frame are found apart (4-5-6 is 10 m from 1-2-3).
    let two = format!(
        r#"{base} category(4, "PEDESTRIAN"). category(5, "PEDESTRIAN"). category(6, "PEDESTRIAN").
        near(4, 5, 5, 1.0). near(5, 6, 5, 1.0). near(3, 4, 5, 10.0)."#
    );
    let found = run(name, &two);
    assert_eq!(found.referred.len(), 6, "{found:?}");
    assert!(!found.related.contains(&(3, 4, 5)));
}

#[test]
fn construction_zone() {
    let name = "construction_zone";
    // A cone, a barrel and a message-board trailer 8 m apart in a row at frame 2: one zone.
    let base = r#"
        category(1, "CONSTRUCTION_CONE"). category(2, "CONSTRUCTION_BARREL").
        category(3, "MESSAGE_BOARD_TRAILER").
        near(1, 2, 2, 8.0). near(2, 3, 2, 8.0). near(1, 3, 2, 16.0).
    "#;
    finds(name, base, &[(1, 2), (2, 2), (3, 2)], &[]);
    // 10.5 m between the barrel and the trailer (> 10): two objects are no zone.
    nothing(
        name,
        &swap(base, "near(2, 3, 2, 8.0)", "near(2, 3, 2, 10.5)"),
    );
    // A plain sign is not a road-works object.
    nothing(name, &swap(base, "\"MESSAGE_BOARD_TRAILER\"", "\"SIGN\""));
}

#[test]
fn passenger_vehicle_swerving_left() {
    let name = "passenger_vehicle_swerving_left";
    // A car at 12 m/s pushed 2.5 m/s² to the left at frame 30, neither turning nor changing lanes.
    let base = r#"
        category(1, "REGULAR_VEHICLE"). lat_accel(1, 30, 2.5). speed(1, 30, 12.0).
    "#;
    finds(name, base, &[(1, 30)], &[]);
    // To the right (+ is left).
    nothing(
        name,
        &swap(base, "lat_accel(1, 30, 2.5)", "lat_accel(1, 30, -2.5)"),
    );
    // Just under 2 m/s².
    nothing(
        name,
        &swap(base, "lat_accel(1, 30, 2.5)", "lat_accel(1, 30, 1.9)"),
    );
    // Turning left at that frame: a turn, not a swerve; changing lanes: a lane change.
    nothing(name, &format!(r#"{base} turning(1, 30, "left")."#));
    nothing(name, &format!(r#"{base} lane_change(1, 30, "left")."#));
    // Creeping at 2 m/s.
    nothing(name, &swap(base, "speed(1, 30, 12.0)", "speed(1, 30, 2.0)"));
}

#[test]
fn truck_cab_towing_a_trailer() {
    let name = "truck_cab_towing_a_trailer";
    let base = r#"
        category(1, "TRUCK_CAB"). category(2, "VEHICULAR_TRAILER"). towing(1, 2, 7).
    "#;
    finds(name, base, &[(1, 7)], &[(1, 2, 7)]);
    // A box truck towing a trailer is not a truck cab.
    nothing(name, &swap(base, "TRUCK_CAB", "BOX_TRUCK"));
    // A truck cab alone.
    nothing(
        name,
        r#"category(1, "TRUCK_CAB"). category(2, "VEHICULAR_TRAILER")."#,
    );
}

/// Track `id` of `category` present at `frames`, driving at `speed` against its lane
/// (`lane_direction` "opposite") at each.
fn wrong_way(id: u32, category: &str, frames: impl IntoIterator<Item = u32>, speed: f64) -> String {
    let mut s = format!("category({id}, \"{category}\").");
    for f in frames {
        s.push_str(&format!(
            " present({id}, {f}). speed({id}, {f}, {speed:.1}). \
             lane_direction({id}, {f}, \"opposite\")."
        ));
    }
    s
}

#[test]
fn vehicle_driving_against_traffic() {
    let name = "vehicle_driving_against_traffic";
    // A car driving the wrong way down a street for 2.4 s (frames 10-34) at 8 m/s: every frame.
    let base = wrong_way(1, "REGULAR_VEHICLE", 10..35, 8.0);
    let all: Vec<(u32, u32)> = (10..35).map(|f| (1, f)).collect();
    finds(name, &base, &all, &[]);
    // Exactly 2 s (frames 10-30, 21 samples) is enough; 1.9 s (20 samples) is a car cutting
    // the oncoming lane (a left turn into a driveway, nosing out of a side road), not
    // wrong-way driving.
    let two: Vec<(u32, u32)> = (10..31).map(|f| (1, f)).collect();
    finds(
        name,
        &wrong_way(1, "REGULAR_VEHICLE", 10..31, 8.0),
        &two,
        &[],
    );
    nothing(name, &wrong_way(1, "REGULAR_VEHICLE", 10..30, 8.0));
    // The samples are counted, not assumed 10 a second: a track annotated at 5 Hz (every
    // other frame) over 2 s is found at its samples, over 1.8 s is not.
    let half: Vec<(u32, u32)> = (10..31).step_by(2).map(|f| (1, f)).collect();
    let five_hz = |to: u32| wrong_way(1, "REGULAR_VEHICLE", (10..to).step_by(2), 8.0);
    finds(name, &five_hz(31), &half, &[]);
    nothing(name, &five_hz(29));
    // A sample it is present at but not against its lane (between lanes at frame 20) splits
    // the 2.4 s into two stretches too short.
    nothing(
        name,
        &swap(&base, "lane_direction(1, 20, \"opposite\").", ""),
    );
    // On an intersection, lanes of several directions overlap: frames there do not count, so
    // 2.4 s with an intersection crossed in the middle is two stretches too short.
    nothing(
        name,
        &format!("{base} on_intersection(1, 20). on_intersection(1, 21)."),
    );
    // The same stretch with the intersection at its start still leaves 2.2 s off it.
    let off: Vec<(u32, u32)> = (12..35).map(|f| (1, f)).collect();
    finds(
        name,
        &format!("{base} on_intersection(1, 10). on_intersection(1, 11)."),
        &off,
        &[],
    );
    // With traffic; crossing the lane; parked facing the wrong way (0.2 m/s); rolling at
    // 1 m/s (`wrong_way` is faster than 1 m/s).
    nothing(name, &base.replace("\"opposite\"", "\"same\""));
    nothing(name, &base.replace("\"opposite\"", "\"perpendicular\""));
    nothing(name, &wrong_way(1, "REGULAR_VEHICLE", 10..35, 0.2));
    nothing(name, &wrong_way(1, "REGULAR_VEHICLE", 10..35, 1.0));
    // A pedestrian walking against the lane is not a vehicle.
    nothing(name, &wrong_way(1, "PEDESTRIAN", 10..35, 1.5));
}

#[test]
fn vehicle_approaching_intersection() {
    let name = "vehicle_approaching_intersection";
    // 20 m from an intersection at frame 0 and 12 m one second later.
    let base = r#"
        category(1, "BUS"). near_intersection(1, 0, 20.0). near_intersection(1, 10, 12.0).
    "#;
    finds(name, base, &[(1, 0)], &[]);
    // Only 0.5 m closer (< 1 m): waiting, not approaching.
    nothing(
        name,
        &swap(
            base,
            "near_intersection(1, 10, 12.0)",
            "near_intersection(1, 10, 19.5)",
        ),
    );
    // Driving away.
    nothing(
        name,
        &swap(
            base,
            "near_intersection(1, 10, 12.0)",
            "near_intersection(1, 10, 28.0)",
        ),
    );
    // Already on it (distance 0).
    nothing(
        name,
        &swap(
            base,
            "near_intersection(1, 0, 20.0)",
            "near_intersection(1, 0, 0.0)",
        ),
    );
    // 35 m away (> 30).
    nothing(
        name,
        &swap(
            &swap(
                base,
                "near_intersection(1, 0, 20.0)",
                "near_intersection(1, 0, 35.0)",
            ),
            "near_intersection(1, 10, 12.0)",
            "near_intersection(1, 10, 27.0)",
        ),
    );
}

#[test]
fn pedestrian_walking_between_two_stopped_vehicles() {
    let name = "pedestrian_walking_between_two_stopped_vehicles";
    let base = r#"
        category(1, "PEDESTRIAN"). speed(1, 3, 1.2).
        category(2, "REGULAR_VEHICLE"). speed(2, 3, 0.0).
        category(3, "BOX_TRUCK"). speed(3, 3, 0.1).
        in_between(1, 2, 3, 3). in_between(1, 3, 2, 3).
    "#;
    finds(name, base, &[(1, 3)], &[(1, 2, 3), (1, 3, 3)]);
    // One of the vehicles moving.
    nothing(name, &swap(base, "speed(3, 3, 0.1)", "speed(3, 3, 4.0)"));
    // The pedestrian standing still.
    nothing(name, &swap(base, "speed(1, 3, 1.2)", "speed(1, 3, 0.3)"));
    // Between a car and a cone, not two vehicles.
    nothing(name, &swap(base, "\"BOX_TRUCK\"", "\"CONSTRUCTION_CONE\""));
}

// ---- vehicle reversing -----------------------------------------------------------------------

/// A car (track 1) moving backwards at 2 m/s along its heading from frame 0 to `last`, present
/// from 0 to 30.
fn reversing_scene(last: u32, v: f64) -> String {
    let mut s = String::from("category(1, \"REGULAR_VEHICLE\").\n");
    for t in 0..=30 {
        s.push_str(&format!("present(1, {t}).\n"));
        let fs = if t <= last { v } else { 3.0 };
        s.push_str(&format!("forward_speed(1, {t}, {fs}).\n"));
    }
    s
}

#[test]
fn a_car_backing_up_for_two_seconds_is_reversing_throughout() {
    let frames: Vec<(u32, u32)> = (0..=20).map(|t| (1, t)).collect();
    finds(
        "vehicle_reversing",
        &reversing_scene(20, -2.0),
        &frames,
        &[],
    );
}

#[test]
fn backing_for_less_than_a_second_or_forwards_or_parked_is_not_reversing() {
    // Half a second backwards: a shove or a settling box, not reversing.
    nothing("vehicle_reversing", &reversing_scene(5, -2.0));
    // Two seconds at 0.3 m/s backwards: below the threshold.
    nothing("vehicle_reversing", &reversing_scene(20, -0.3));
    // Forwards.
    nothing("vehicle_reversing", &reversing_scene(20, 2.0));
    // A parked car whose box drifts backwards.
    let parked = format!("{}stationary(1).\n", reversing_scene(20, -2.0));
    nothing("vehicle_reversing", &parked);
}

// ---- U-turn and three-point turn ---------------------------------------------------------------

/// A car (track 1) present and moving at 5 m/s over `frames` frames whose heading turns by
/// `turn` degrees at a steady rate from frame 30 over `over` frames; `back`, the frames at which
/// it moves backwards at 2 m/s instead.
fn turn_scene(frames: u32, turn: f64, over: u32, back: std::ops::Range<u32>) -> String {
    let mut s = String::from("category(1, \"REGULAR_VEHICLE\").\n");
    for t in 0..frames {
        let a = turn * f64::from(t.saturating_sub(30).min(over)) / f64::from(over);
        let fs = if back.contains(&t) { -2.0 } else { 5.0 };
        s.push_str(&format!(
            "present(1, {t}). speed(1, {t}, {}). forward_speed(1, {t}, {fs}). total_turn(1, {t}, {a}).\n",
            f64::abs(fs)
        ));
    }
    s
}

#[test]
fn a_half_circle_in_four_seconds_is_a_u_turn_during_the_turn() {
    // 180 degrees over frames 30..70 (4.5 degrees a frame): the turn past its first and before its
    // last 15 degrees is frames 34..=66.
    let frames: Vec<(u32, u32)> = (34..=66).map(|t| (1, t)).collect();
    finds(
        "vehicle_making_a_u_turn",
        &turn_scene(100, 180.0, 40, 0..0),
        &frames,
        &[],
    );
    // Turning right instead of left: the same.
    finds(
        "vehicle_making_a_u_turn",
        &turn_scene(100, -180.0, 40, 0..0),
        &frames,
        &[],
    );
}

#[test]
fn a_left_turn_or_a_slow_circle_or_a_parked_car_is_not_a_u_turn() {
    nothing("vehicle_making_a_u_turn", &turn_scene(100, 90.0, 40, 0..0));
    // 180 degrees over 30 s: a long curve, never 150 degrees within 20 s.
    nothing(
        "vehicle_making_a_u_turn",
        &turn_scene(340, 180.0, 300, 0..0),
    );
    let parked = format!("{}stationary(1).\n", turn_scene(100, 180.0, 40, 0..0));
    nothing("vehicle_making_a_u_turn", &parked);
}

#[test]
fn a_u_turn_with_reversing_in_it_is_a_three_point_turn() {
    // The same half circle over 8 s (frames 30..110), backing up over frames 60..80 (2 s).
    let scene = turn_scene(140, 180.0, 80, 60..80);
    let u_turn = run("vehicle_making_a_u_turn", &scene);
    assert!(!u_turn.referred.is_empty());
    finds(
        "vehicle_making_a_three_point_turn",
        &scene,
        &u_turn.referred.iter().copied().collect::<Vec<_>>(),
        &[],
    );
    // The same U-turn driven forwards throughout is not one.
    nothing(
        "vehicle_making_a_three_point_turn",
        &turn_scene(140, 180.0, 80, 0..0),
    );
}

// ---- cut-in, waiting to turn -------------------------------------------------------------------

/// The ego (track 0) and a car (track 1), both present over 60 frames, 10 m apart; the car
/// changes lanes at frame 10 and the ego follows it from frame `from` to `to`.
fn cut_in_scene(from: u32, to: u32, gap: f64) -> String {
    let mut s = String::from("category(0, \"EGO_VEHICLE\"). category(1, \"REGULAR_VEHICLE\").\n");
    for t in 0..60 {
        s.push_str(&format!(
            "present(0, {t}). present(1, {t}). near(0, 1, {t}, {gap}).\n"
        ));
        if (from..to).contains(&t) {
            s.push_str(&format!("following(0, 1, {t}).\n"));
        }
    }
    s.push_str("lane_change(1, 10, \"left\").\n");
    s
}

#[test]
fn a_car_changing_lanes_into_the_ego_s_lead_cuts_in() {
    finds(
        "vehicle_cutting_in_front_of_the_ego_vehicle",
        &cut_in_scene(20, 60, 10.0),
        &[(1, 10)],
        &[(1, 0, 10)],
    );
}

#[test]
fn an_old_lead_a_late_lead_or_a_far_one_does_not_cut_in() {
    let name = "vehicle_cutting_in_front_of_the_ego_vehicle";
    // Already the ego's lead before the lane change.
    nothing(name, &cut_in_scene(0, 60, 10.0));
    // The lead only 5 s after the lane change.
    nothing(name, &cut_in_scene(60 - 1, 60, 10.0));
    // 30 m ahead: merging far in front, not cutting in.
    nothing(name, &cut_in_scene(20, 60, 30.0));
}

/// A car (track 1) stopped on an intersection over frames 0..=20 (2 s), then moving at 5 m/s
/// until frame 199; it turns `dir` over frames `turn`.
fn waiting_scene(dir: &str, turn: std::ops::Range<u32>) -> String {
    let mut s = String::from("category(1, \"REGULAR_VEHICLE\").\n");
    for t in 0..200 {
        let v = if t <= 20 { 0.0 } else { 5.0 };
        s.push_str(&format!(
            "present(1, {t}). speed(1, {t}, {v}). on_intersection(1, {t}).\n"
        ));
        if turn.contains(&t) {
            s.push_str(&format!("turning(1, {t}, \"{dir}\").\n"));
        }
    }
    s
}

#[test]
fn a_car_stopped_at_an_intersection_before_turning_left_waits_to_turn() {
    // Turning left from frame 25 (2.5 s): all of the stop is waiting to turn left.
    let frames: Vec<(u32, u32)> = (0..=20).map(|t| (1, t)).collect();
    finds(
        "vehicle_waiting_to_turn_left",
        &waiting_scene("left", 25..35),
        &frames,
        &[],
    );
    // Turning left from frame 115: only the stop's moments within 10 s before it, 15..=20.
    let late: Vec<(u32, u32)> = (15..=20).map(|t| (1, t)).collect();
    finds(
        "vehicle_waiting_to_turn_left",
        &waiting_scene("left", 115..125),
        &late,
        &[],
    );
    // Turning right, turning left 15 s later, or not turning: not waiting to turn left.
    nothing(
        "vehicle_waiting_to_turn_left",
        &waiting_scene("right", 25..35),
    );
    nothing(
        "vehicle_waiting_to_turn_left",
        &waiting_scene("left", 170..180),
    );
    nothing("vehicle_waiting_to_turn_left", &waiting_scene("left", 0..0));
}

// ---- uphill ------------------------------------------------------------------------------------

#[test]
fn a_car_two_metres_or_more_above_the_ego_is_uphill() {
    let scene = "category(0, \"EGO_VEHICLE\"). category(1, \"REGULAR_VEHICLE\"). category(2, \"REGULAR_VEHICLE\"). category(3, \"PEDESTRIAN\").\n\
                 elevation(0, 5, 10.0). elevation(1, 5, 12.5). elevation(2, 5, 11.5). elevation(3, 5, 14.0).\n\
                 elevation(0, 6, 10.0). elevation(1, 6, 11.0).";
    // Car 1 is 2.5 m above at 5 and 1 m at 6; car 2 only 1.5 m; the pedestrian is no vehicle.
    finds("vehicle_uphill_from_the_ego_vehicle", scene, &[(1, 5)], &[]);
}

// ---- the road's structure ----------------------------------------------------------------------

#[test]
fn a_bus_over_a_line_with_a_lane_beyond_it_spills_over_the_dividing_line() {
    let name = "bus_spilling_over_the_lane_dividing_line";
    let base = "category(1, \"BUS\"). in_lane(1, 5, 7). lane_neighbor(7, 8, \"left\").\n\
                over_marking(1, 5, \"left\", \"SOLID_WHITE\", 0.5).";
    finds(name, base, &[(1, 5)], &[]);
    // The same paint with no lane beyond it is the road's edge line.
    nothing(name, &swap(base, "lane_neighbor(7, 8, \"left\").", ""));
    // A dashed line divides lanes whatever the map links.
    let dashed = swap(
        &swap(base, "lane_neighbor(7, 8, \"left\").", ""),
        "SOLID_WHITE",
        "DASHED_WHITE",
    );
    finds(name, &dashed, &[(1, 5)], &[]);
    // Only 0.2 m over; unpainted; while changing lanes; not a bus.
    nothing(name, &swap(base, "0.5)", "0.2)"));
    nothing(name, &swap(&dashed, "DASHED_WHITE", "NONE"));
    nothing(name, &format!("{base} lane_change(1, 5, \"left\")."));
    nothing(name, &swap(base, "\"BUS\"", "\"REGULAR_VEHICLE\""));
}

#[test]
fn a_vehicle_moving_in_a_lane_turning_right_off_the_intersection_is_in_a_slip_lane() {
    let name = "vehicle_turning_right_in_a_slip_lane";
    let base = "category(1, \"REGULAR_VEHICLE\"). in_lane(1, 5, 7). speed(1, 5, 5.0).\n\
                lane_turn(7, \"right\", -80.0).";
    finds(name, base, &[(1, 5)], &[]);
    // A right turn through the intersection, a lane bending left, a stopped car.
    nothing(name, &format!("{base} intersection_lane(7)."));
    nothing(name, &swap(base, "\"right\", -80.0", "\"left\", 80.0"));
    nothing(name, &swap(base, "5.0)", "0.1)"));
}

#[test]
fn a_vehicle_leaving_a_left_turn_lane_on_a_straight_lane_goes_straight_from_it() {
    let name = "vehicle_going_straight_from_a_turn_lane";
    let base = "category(1, \"REGULAR_VEHICLE\"). in_lane(1, 5, 7). lane_successor(7, 8).\n\
                lane_turn(8, \"left\", 85.0). in_lane(1, 20, 9). intersection_lane(9).\n\
                lane_turn(9, \"straight\", 2.0). intersection_lane(8).";
    finds(name, base, &[(1, 20)], &[]);
    // Lane 7 also leads straight on: no turn lane.
    nothing(name, &format!("{base} lane_successor(7, 9)."));
    // It turned left on the way (a left turn, then a second junction crossed straight on).
    nothing(name, &format!("{base} turning(1, 12, \"left\")."));
    finds(
        name,
        &format!("{base} turning(1, 30, \"left\")."),
        &[(1, 20)],
        &[],
    );
    // On the straight lane 12 s later; the lane it reaches turns too.
    nothing(name, &swap(base, "in_lane(1, 20, 9)", "in_lane(1, 125, 9)"));
    nothing(
        name,
        &swap(
            base,
            "lane_turn(9, \"straight\", 2.0)",
            "lane_turn(9, \"left\", 90.0)",
        ),
    );
}

#[test]
fn a_pedestrian_standing_off_the_road_within_a_metre_of_its_edge_is_at_the_curb() {
    let name = "pedestrian_standing_at_the_curb";
    let base =
        "category(1, \"PEDESTRIAN\"). present(1, 5). speed(1, 5, 0.1). road_edge(1, 5, 0.6).";
    finds(name, base, &[(1, 5)], &[]);
    // In the road; 1.5 m back on the pavement; walking.
    nothing(name, &format!("{base} in_drivable_area(1, 5)."));
    nothing(name, &swap(base, "0.6)", "1.5)"));
    nothing(name, &swap(base, "0.1)", "1.2)"));
}

#[test]
fn a_vehicle_in_a_lane_with_no_lane_the_other_way_beside_it_is_on_a_one_way_road() {
    let name = "vehicle_on_a_one_way_road";
    let base = "category(1, \"REGULAR_VEHICLE\"). speed(1, 5, 8.0). in_lane(1, 5, 7).\n\
                road_lanes(7, 2, 0).";
    finds(name, base, &[(1, 5)], &[]);
    nothing(
        name,
        &swap(base, "road_lanes(7, 2, 0)", "road_lanes(7, 2, 1)"),
    );
    nothing(name, &format!("{base} on_intersection(1, 5)."));
    nothing(name, &swap(base, "8.0)", "0.1)"));
}
