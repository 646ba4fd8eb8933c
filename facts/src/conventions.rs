//! The conventions: how the phrases of descriptions are written with the catalog, with the
//! thresholds the scenario library uses. One table, from which the synthesis prompt's
//! conventions are generated; tests check that every idiom checks and that the library programs
//! named for a convention use its threshold.

/// One convention.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Convention {
    /// The phrases of descriptions it covers.
    pub phrase: &'static str,
    /// How to write it (Scenalog fragments and a short explanation), one line.
    pub idiom: &'static str,
    /// A complete rule using the idiom, which must check clean.
    pub example: &'static str,
    /// Library programs (file stems) that embody the convention, each with a fragment its text
    /// must contain.
    pub library: &'static [(&'static str, &'static str)],
}

/// Speed below which an object is stopped, m/s (parked objects included).
pub const STOPPED_SPEED: f64 = 0.5;
/// Forward acceleration at or below which an object is braking, m/s².
pub const BRAKING_ACCEL: f64 = -1.0;
/// Forward acceleration at or below which an object is braking hard (or heavily), m/s².
pub const HARD_BRAKING_ACCEL: f64 = -3.0;

/// Every convention, in the order the prompt lists them.
pub const CONVENTIONS: &[Convention] = &[
    Convention {
        phrase: "an object's kind",
        idiom: "`category(X, \"PEDESTRIAN\")`; \"vehicle\" is `category(X, \"VEHICLE\")` (every vehicle category, the ego included); \"car\" is \"REGULAR_VEHICLE\"; the ego vehicle is `ego(X)`. AV2 has no emergency-vehicle, police or traffic-light class",
        example: "referred(X, T) :- category(X, \"REGULAR_VEHICLE\"), present(X, T).",
        library: &[("stopped_car", "category(V, \"REGULAR_VEHICLE\")")],
    },
    Convention {
        phrase: "stopped",
        idiom: "`speed(X, T, V), V < 0.5`: parked objects are stopped too (the library and the benchmark count them); \"stopped but not parked\" adds `!stationary(X)`; parked for the whole log is `stationary(X)`",
        example: "referred(X, T) :- category(X, \"REGULAR_VEHICLE\"), speed(X, T, V), V < 0.5.",
        library: &[("stopped_car", "S < 0.5"), ("parked_vehicle", "stationary(")],
    },
    Convention {
        phrase: "moving, fast",
        idiom: "moving: `speed(X, T, V), V > 0.5`; fast: `V > 10`",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), speed(X, T, V), V > 10.0.",
        library: &[],
    },
    Convention {
        phrase: "accelerating",
        idiom: "`accel(X, T, A), A >= 0.65` (`A >= 1` when it must be unmistakable)",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), accel(X, T, A), A >= 0.65.",
        library: &[("accelerating_truck", "A >= 1.0")],
    },
    Convention {
        phrase: "braking",
        idiom: "`accel(X, T, A), A <= -1`; braking hard, heavily or sharply: `A <= -3`",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), accel(X, T, A), A <= -3.0.",
        library: &[
            ("braking_vehicle", "A <= -1.0"),
            ("vehicle_braking_heavily", "A <= -3.0"),
            ("motorcyclist_braking_hard", "A <= -3.0"),
        ],
    },
    Convention {
        phrase: "turning, changing lanes",
        idiom: "`turning(X, T, \"left\")`; `lane_change(X, T, \"right\")`",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), turning(X, T, \"left\").",
        library: &[],
    },
    Convention {
        phrase: "near, close to, next to",
        idiom: "`near(X, Y, T, D), D < 10` (`D < 5` for \"very close\"); X != Y",
        example: "referred(X, T) :- category(X, \"PEDESTRIAN\"), near(X, Y, T, D), D < 10.0, category(Y, \"BUS\").",
        library: &[],
    },
    Convention {
        phrase: "in front of, behind, beside",
        idiom: "`direction(X, Y, T, \"forward\", Dist, Lat)`: Y's centre is ahead of X's front. A diagonal Y holds in two directions (ahead and to the left is both \"forward\" and \"left\"). `Lat` is unsigned: how far Y's centre lies beyond X's sides (0 when within them), so \"directly in front\" adds `Lat < 1`; within a distance: `Dist < 25`",
        example: "referred(X, T) :- ego(E), direction(E, X, T, \"forward\", Dist, Lat), Dist < 25.0, Lat < 1.0.",
        library: &[],
    },
    Convention {
        phrase: "following, same lane, crossing in front",
        idiom: "`following(X, Y, T)` (every lead within 25 m, not only the nearest), `same_lane(X, Y, T)`, `crossing(X, Y, T, \"forward\")` (Y crosses in front of X). The direct lead: `between(X, Y, T) :- following(X, Z, T), following(Z, Y, T).` then `lead(X, Y, T) :- following(X, Y, T), !between(X, Y, T).`",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), following(X, Y, T), category(Y, \"BUS\").",
        library: &[],
    },
    Convention {
        phrase: "at an intersection, a crosswalk",
        idiom: "`on_intersection(X, T)`; near one: `near_intersection(X, T, D), D < 10`; at a crosswalk: `at_crosswalk(X, T, D), D < 1`",
        example: "referred(X, T) :- category(X, \"PEDESTRIAN\"), at_crosswalk(X, T, D), D < 1.0.",
        library: &[],
    },
    Convention {
        phrase: "approaching a place or an object",
        idiom: "a place along one's path: its distance shrinks, at least 1 m within the next second: `near_intersection(X, T, D), D > 0, D <= 30, T2 = T + 10, near_intersection(X, T2, D2), D2 <= D - 1` (the same with `at_crosswalk`); a stop sign: `at_stop_sign(X, S, T)` while moving; an object ahead: `heading_toward(X, Y, T)` (X's velocity points at Y and it closes in)",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), near_intersection(X, T, D), D > 0.0, D <= 30.0, T2 = T + 10, near_intersection(X, T2, D2), D2 <= D - 1.0.",
        library: &[("vehicle_approaching_intersection", "D2 <= D - 1.0")],
    },
    Convention {
        phrase: "between",
        idiom: "`in_between(X, Y, Z, T)`: X between Y and Z (both within 5 m, X within 2 m of the line joining them); it holds for (Y, Z) and (Z, Y), so put the same conditions on both; \"vehicles on both sides\" of X is `direction(X, Y, T, \"left\", _, _), direction(X, Z, T, \"right\", _, _)`",
        example: "referred(P, T) :- category(P, \"PEDESTRIAN\"), in_between(P, A, B, T), category(A, \"VEHICLE\"), category(B, \"VEHICLE\").",
        library: &[("pedestrian_walking_between_two_stopped_vehicles", "in_between(P, A, B, T)")],
    },
    Convention {
        phrase: "against traffic, wrong way, oncoming",
        idiom: "driving against traffic (wrong way): `lane_direction(X, T, \"opposite\")` (X travels against its own lane) with `speed(X, T, V), V > 1` and `!on_intersection(X, T)` (lanes of every direction overlap there), for at least 2 s in a row (a second in the oncoming lane is a turn cutting across it); oncoming traffic or an oncoming vehicle: `heading_relative(X, Y, T, \"opposite\")` with Y ahead, `direction(X, Y, T, \"forward\", _, _)`; the oncoming side of the road: `road_side(X, Y, T, \"opposite\")`",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), speed(X, T, V), V > 1.0, lane_direction(X, T, \"opposite\"), !on_intersection(X, T).",
        library: &[("vehicle_driving_against_traffic", "lane_direction(V, T, \"opposite\"), !on_intersection(V, T)")],
    },
    Convention {
        phrase: "swerving",
        idiom: "a sudden sideways move that is neither a turn nor a lane change: `lat_accel(X, T, A), A >= 2` (left; `A <= -2` right), `speed(X, T, V), V > 3`, `!turning(X, T, _), !lane_change(X, T, _)`",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), lat_accel(X, T, A), A <= -2.0, speed(X, T, V), V > 3.0, !turning(X, T, _), !lane_change(X, T, _).",
        library: &[("passenger_vehicle_swerving_left", "A >= 2.0")],
    },
    Convention {
        phrase: "towing, with a trailer",
        idiom: "`towing(X, Y, T)`: X pulls trailer Y (a semi is a \"TRUCK_CAB\" and a \"VEHICULAR_TRAILER\", two objects); without a trailer: `!towing(X, _, T)`",
        example: "referred(X, T) :- category(X, \"TRUCK_CAB\"), present(X, T), !towing(X, _, T).",
        library: &[("truck_cab_towing_a_trailer", "towing(C, _, T)")],
    },
    Convention {
        phrase: "construction objects, a construction zone",
        idiom: "road-works objects: `category(X, \"CONSTRUCTION\")` (cones, barrels, message-board and traffic-light trailers, mobile crossing signs; AV2 has no construction-sign class); a zone is a cluster: link objects within 10 m and close the links by recursion, then count, as for a group",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), near(X, C, T, D), D < 10.0, category(C, \"CONSTRUCTION\").",
        library: &[("construction_zone", "category(C, \"CONSTRUCTION\")")],
    },
    Convention {
        phrase: "a group of N people",
        idiom: "a group is connected, not a neighbour count: `link(P, Q, T)` for pedestrians within 2 m, `grouped(P, Q, T) :- link(P, Q, T).` `grouped(P, R, T) :- grouped(P, Q, T), link(Q, R, T).` then `N = count : { grouped(P, Q, T) }` is P's group size (P included)",
        example: "link(P, Q, T) :- category(P, \"PEDESTRIAN\"), category(Q, \"PEDESTRIAN\"), P != Q, near(P, Q, T, D), D <= 2.0.\ngrouped(P, Q, T) :- link(P, Q, T).\ngrouped(P, R, T) :- grouped(P, Q, T), link(Q, R, T).\nreferred(P, T) :- grouped(P, _, T), N = count : { grouped(P, Q, T) }, N >= 3.",
        library: &[("group_of_three_people", "grouped(P, R, T) :- grouped(P, Q, T), link(Q, R, T).")],
    },
    Convention {
        phrase: "time: frames",
        idiom: "times are frames at 10 Hz: `T + 10` is one second later, 2 s is 20 frames; compare times with integers, never floats (`seconds(T, S)` gives seconds)",
        example: "referred(X, T2) :- turning(X, T1, \"left\"), turning(X, T2, \"left\"), T2 > T1, T2 - T1 <= 20.",
        library: &[],
    },
    Convention {
        phrase: "for at least 2 s",
        idiom: "count the frames of the last 2 s: `N = count : { stopped(X, T2), T2 > T - 20, T2 <= T }, N >= 20` (every frame of the window holds)",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), present(X, T), N = count : { speed(X, T2, V), V < 0.5, T2 > T - 20, T2 <= T }, N >= 20.",
        library: &[],
    },
    Convention {
        phrase: "A then B, after A, before B",
        idiom: "join the two moments and order them: `a(X, T1), b(X, T2), T2 > T1, T2 - T1 <= 30` (B within 3 s after A); \"after stopping\" is `stopped(X, T1), T > T1`",
        example: "referred(X, T2) :- speed(X, T1, V), V < 0.5, accel(X, T2, A), A >= 1.0, T2 > T1, T2 - T1 <= 30.",
        library: &[],
    },
    Convention {
        phrase: "something the catalog cannot express",
        idiom: "write the closest program you can and say in a `//` comment what it approximates and why; use only catalog relations, categories and your own helpers, never invented ones",
        example: "referred(X, T) :- category(X, \"LARGE_VEHICLE\"), present(X, T).",
        library: &[],
    },
];

/// The conventions as the prompt lists them: one `- phrase: idiom` line each.
pub fn render_text() -> String {
    CONVENTIONS
        .iter()
        .map(|c| format!("- {}: {}.\n", capitalised(c.phrase), c.idiom))
        .collect()
}

fn capitalised(s: &str) -> String {
    let mut cs = s.chars();
    match cs.next() {
        Some(c) => c.to_uppercase().chain(cs).collect(),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thresholds_named_here_are_the_ones_the_idioms_use() {
        let stopped = CONVENTIONS.iter().find(|c| c.phrase == "stopped");
        assert!(stopped.is_some_and(|c| c.idiom.contains(&format!("V < {STOPPED_SPEED}"))));
        assert!(stopped.is_some_and(|c| !c.idiom.contains("(not parked)")));
        let braking = CONVENTIONS.iter().find(|c| c.phrase == "braking");
        let hard = format!("A <= {}", HARD_BRAKING_ACCEL as i64);
        let plain = format!("A <= {}", BRAKING_ACCEL as i64);
        assert!(braking.is_some_and(|c| c.idiom.contains(&hard) && c.idiom.contains(&plain)));
        let text = render_text();
        assert_eq!(text.lines().count(), CONVENTIONS.len());
        assert!(text.starts_with("- An object's kind: "), "{text}");
    }
}
