//! The conventions: how the phrases of descriptions are written with the catalog and the
//! prelude. One table, from which the synthesis prompt's conventions are generated; tests check
//! that every idiom checks and that the library programs named for a convention follow it.
//!
//! The concepts themselves ("stopped", "near", "a group", …) and their thresholds are not here:
//! they are relations of the prelude (`rules/prelude.dl`), defined once, and the prompt lists
//! them from there. A convention only says how to use them and how to write what is not a
//! concept.

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

/// Every convention, in the order the prompt lists them.
pub const CONVENTIONS: &[Convention] = &[
    Convention {
        phrase: "an object's kind",
        idiom: "`category(X, \"PEDESTRIAN\")`; \"vehicle\" is `category(X, \"VEHICLE\")` (every vehicle category, the ego included); \"car\" is \"REGULAR_VEHICLE\"; \"bicycle\" is \"BICYCLE\" (every bicycle, ridden or not: a ridden one also has a \"BICYCLIST\" box for its rider, so never add \"BICYCLIST\" to a bicycle); \"bicyclist\" or \"cyclist\" is \"BICYCLIST\"; the ego vehicle is `ego(X)`. AV2 has no emergency-vehicle, police or traffic-light class",
        example: "referred(X, T) :- category(X, \"REGULAR_VEHICLE\"), present(X, T).",
        library: &[("stopped_car", "category(V, \"REGULAR_VEHICLE\")")],
    },
    Convention {
        phrase: "concepts: stopped, moving, fast, accelerating, braking, reversing, a U-turn or three-point turn, near, at a crosswalk or an intersection, off the road, approaching, the lead vehicle, waiting, waiting to turn, overtaking, cutting in, against traffic, a group, a construction zone",
        idiom: "use the prelude relation listed under Concepts (`stopped(X, T)`, `nearby(X, Y, T)`, `group_size(P, T, N)`, …): it is already defined, so never define it again or re-derive it from the catalog. Parked vehicles are stopped; \"stopped but not parked\" adds `!parked(X)`; an object of any kind that stays put over its whole track is `stationary(X)`. A number the description gives is written with the catalog relation itself: \"within 5 m\" is `near(X, Y, T, D), D <= 5 m`",
        example: "referred(X, T) :- category(X, \"REGULAR_VEHICLE\"), stopped(X, T).",
        library: &[("stopped_car", "stopped(V, T)")],
    },
    Convention {
        phrase: "in front of, behind, beside",
        idiom: "`direction(X, Y, T, \"forward\", Dist, Lat)`: Y's centre is ahead of X's front. A diagonal Y holds in two directions (ahead and to the left is both \"forward\" and \"left\"). `Lat` is unsigned: how far Y's centre lies beyond X's sides (0 when within them), so \"directly in front\" adds `Lat < 1 m`; within a distance: `Dist < 25 m`",
        example: "referred(X, T) :- ego(E), direction(E, X, T, \"forward\", Dist, Lat), Dist < 25 m, Lat < 1 m.",
        library: &[],
    },
    Convention {
        phrase: "no reference object (\"within 5 m to the right\", \"ahead\", \"behind\")",
        idiom: "a position or distance with no object to measure from is measured from the ego vehicle: `ego(E), direction(E, X, T, \"right\", D, _), D <= 5 m`; the ego is then the related object",
        example: "referred(X, T) :- category(X, \"PEDESTRIAN\"), ego(E), direction(E, X, T, \"right\", D, _), D <= 5 m.",
        library: &[("pedestrian_within_5_meters_to_the_right", "ego(E), direction(E, P, T, \"right\"")],
    },
    Convention {
        phrase: "two subjects (\"bicycle and vehicle …\", \"a bus and a pedestrian\")",
        idiom: "both are what the description is about: one `referred` rule per subject, each with the whole condition; when the description relates them, each is the other's related object",
        example: "pair(B, V, T) :- category(B, \"BICYCLE\"), category(V, \"VEHICLE\"), nearby(B, V, T).\nreferred(B, T) :- pair(B, _, T).\nreferred(V, T) :- pair(_, V, T).\nrelated(B, V, T) :- pair(B, V, T).\nrelated(V, B, T) :- pair(B, V, T).",
        library: &[("bicycle_and_vehicle_near_each_other", "referred(V, T) :- pair(_, V, T).")],
    },
    Convention {
        phrase: "turning, changing lanes",
        idiom: "`turning(X, T, \"left\")`; `lane_change(X, T, \"right\")`",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), turning(X, T, \"left\").",
        library: &[],
    },
    Convention {
        phrase: "following, same lane, crossing in front",
        idiom: "`following(X, Y, T)` (every lead within 25 m, not only the nearest; the nearest is the prelude's `lead(X, Y, T)`), `same_lane(X, Y, T)`, `crossing(X, Y, T, \"forward\")` (Y crosses in front of X)",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), following(X, Y, T), category(Y, \"BUS\").",
        library: &[],
    },
    Convention {
        phrase: "between",
        idiom: "`in_between(X, Y, Z, T)`: X between Y and Z (both within 5 m, X within 2 m of the line joining them); it holds for (Y, Z) and (Z, Y), so put the same conditions on both; \"vehicles on both sides\" of X is `direction(X, Y, T, \"left\", _, _), direction(X, Z, T, \"right\", _, _)`",
        example: "referred(P, T) :- category(P, \"PEDESTRIAN\"), in_between(P, A, B, T), category(A, \"VEHICLE\"), category(B, \"VEHICLE\").",
        library: &[("pedestrian_walking_between_two_stopped_vehicles", "in_between(P, A, B, T)")],
    },
    Convention {
        phrase: "oncoming",
        idiom: "oncoming traffic or an oncoming vehicle: `heading_relative(X, Y, T, \"opposite\")` with Y ahead, `direction(X, Y, T, \"forward\", _, _)`; the oncoming side of the road: `road_side(X, Y, T, \"opposite\")`; driving against traffic is the prelude's `against_traffic(X, T)`",
        example: "referred(Y, T) :- ego(E), heading_relative(E, Y, T, \"opposite\"), direction(E, Y, T, \"forward\", _, _).",
        library: &[("vehicle_driving_against_traffic", "against_traffic(V, T)")],
    },
    Convention {
        phrase: "swerving",
        idiom: "a sudden sideways move that is neither a turn nor a lane change: `lat_accel(X, T, A), A >= 2 m/s2` (left; `A <= -2 m/s2` right), `speed(X, T, V), V > 3 m/s`, `!turning(X, T, _), !lane_change(X, T, _)`",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), lat_accel(X, T, A), A <= -2 m/s2, speed(X, T, V), V > 3 m/s, !turning(X, T, _), !lane_change(X, T, _).",
        library: &[("passenger_vehicle_swerving_left", "A >= 2.0 m/s2")],
    },
    Convention {
        phrase: "towing, with a trailer",
        idiom: "`towing(X, Y, T)`: X pulls trailer Y (a semi is a \"TRUCK_CAB\" and a \"VEHICULAR_TRAILER\", two objects); without a trailer: `!towing(X, _, T)`",
        example: "referred(X, T) :- category(X, \"TRUCK_CAB\"), present(X, T), !towing(X, _, T).",
        library: &[("truck_cab_towing_a_trailer", "towing(C, _, T)")],
    },
    Convention {
        phrase: "construction objects, a construction zone",
        idiom: "road-works objects: `category(X, \"CONSTRUCTION\")` (cones, barrels, message-board and traffic-light trailers, mobile crossing signs; AV2 has no construction-sign class); a zone is the prelude's `construction_zone(C, T)` (a cluster of at least three), \"near a construction zone\" is within a distance of one of its objects",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), near(X, C, T, D), D < 10 m, construction_zone(C, T).",
        library: &[("construction_zone", "construction_zone(C, T)")],
    },
    Convention {
        phrase: "numbers and time",
        idiom: "write every number with its unit: `50 km/h`, `3 m`, `2 m/s2`, `0.3 rad/s`, `90 deg`, `2 s`, `500 ms` (a bare number is read in the column's unit, with a warning). A time is a moment of the log, whatever the tracker's rate: `T2 - T1` is a duration, `T + 1 s` one second later (`T + 1` is an error) and X's next moment `next_sample(X, T, T2)`; never count samples to measure a duration",
        example: "referred(X, T2) :- turning(X, T1, \"left\"), turning(X, T2, \"left\"), T2 > T1, T2 - T1 <= 2 s.",
        library: &[],
    },
    Convention {
        phrase: "for at least 2 s",
        idiom: "it holds at every sample from 2 s before T to T: `p(X, T), T0 = T - 2 s, p(X, T0), N = count : { p(X, U), U >= T0, U <= T }, M = count : { present(X, W), W >= T0, W <= T }, N = M` (the same at any tracker rate; the prelude's `against_traffic` is written so)",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), stopped(X, T), T0 = T - 2 s, stopped(X, T0), N = count : { stopped(X, U), U >= T0, U <= T }, M = count : { present(X, W), W >= T0, W <= T }, N = M.",
        library: &[],
    },
    Convention {
        phrase: "A then B, after A, before B",
        idiom: "join the two moments and order them: `a(X, T1), b(X, T2), T2 > T1, T2 - T1 <= 3 s` (B within 3 s after A); \"after stopping\" is `stopped(X, T1), T > T1`",
        example: "referred(X, T2) :- stopped(X, T1), accelerating(X, T2), T2 > T1, T2 - T1 <= 3 s.",
        library: &[],
    },
    Convention {
        phrase: "a person waiting",
        idiom: "the prelude's `waiting(P, T)` is a person stopped at a crosswalk, an intersection or a stop sign; waiting beside a bus (for it) is `stopped(P, T)` within 3 m of it: `stopped(P, T), near(P, B, T, D), D <= 3 m, category(B, \"BUS\")`; \"at the kerb\" is `stopped(P, T), on_sidewalk(P, T), at_road_edge(P, T)` (off the road, within 1 m of its edge)",
        example: "referred(P, T) :- category(P, \"PEDESTRIAN\"), stopped(P, T), near(P, B, T, D), D <= 3 m, category(B, \"BUS\").",
        library: &[],
    },
    Convention {
        phrase: "a traffic light, a parking lot, what only a camera sees",
        idiom: "not in the data (the catalog says so too): no traffic-light state, no parking lots or spaces, no attribute only a camera sees (an ambulance, a police car, a construction worker) except through `attribute(X, Name, Score)`, which is empty unless a log carries a camera model's attributes file: write the body type (`category`) and, when the description names such a thing, say in a comment that `attribute(X, \"ambulance\", S), S >= 0.5` would say it where the logs carry attributes. Write what the data holds and say in a `//` comment that it approximates: \"stopped at a red light\" is `waiting(X, T), at_an_intersection(X, T)`, \"through a yellow light\" `moving(X, T), on_intersection(X, T)`, \"in a parking lot\" `on_sidewalk(X, T)` or beside `parked` vehicles",
        example: "referred(X, T) :- category(X, \"VEHICLE\"), waiting(X, T), at_an_intersection(X, T).",
        library: &[],
    },
    Convention {
        phrase: "something the catalog cannot express",
        idiom: "write the closest program you can and say in a `//` comment what it approximates and why; use only catalog relations, the prelude's concepts, categories and your own helpers, never invented ones",
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
    fn no_convention_writes_a_concept_threshold_of_its_own() {
        // The concepts' thresholds are the prelude's (rules/prelude.dl); a convention that
        // restated one would be a second definition.
        for c in CONVENTIONS {
            for restated in [
                "V < 0.5",
                "A <= -1",
                "A <= -3",
                "A >= 0.65",
                "D < 10",
                "D < 1",
            ] {
                assert!(!c.idiom.contains(restated), "{}: {restated}", c.phrase);
            }
        }
        let text = render_text();
        assert_eq!(text.lines().count(), CONVENTIONS.len());
        assert!(text.starts_with("- An object's kind: "), "{text}");
    }
}
