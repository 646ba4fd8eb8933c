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
        idiom: "`on_intersection(X, T)`; approaching one: `near_intersection(X, T, D), D < 10`; at a crosswalk: `at_crosswalk(X, T, D), D < 1`",
        example: "referred(X, T) :- category(X, \"PEDESTRIAN\"), at_crosswalk(X, T, D), D < 1.0.",
        library: &[],
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
