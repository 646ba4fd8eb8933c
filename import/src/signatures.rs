//! RefAV's atomic functions as data: each one's parameters in Python order, with defaults, and
//! what kind of scenario operation it is. Argument binding follows Python's rules against these
//! signatures, so a call RefAV itself would reject (an unknown keyword, a missing argument) is
//! rejected here too, with RefAV's own wording.

/// A parameter's default value, as RefAV's signature declares it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Default {
    /// No default: the argument is required.
    Required,
    /// A number (`np.inf` is `f64::INFINITY`).
    Num(f64),
    /// A string.
    Str(&'static str),
    /// `None`.
    None,
    /// `False` / `True`.
    Bool(bool),
}

/// What a function does to scenarios.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Makes a scenario from the log (`get_objects_of_category`).
    Source,
    /// Keeps a subset of one scenario's (track, timestamp) pairs (RefAV's `@composable`).
    Filter,
    /// Relates a scenario's tracks to candidates (RefAV's `@composable_relational`, and
    /// `get_objects_in_relative_direction`).
    Relational,
    /// Combines a list of scenarios (`scenario_and`, `scenario_or`).
    Combine,
    /// Wraps another function (`scenario_not`, `reverse_relationship`).
    Wrapper,
    /// Writes the result (`output_scenario`).
    Output,
}

/// One RefAV function.
#[derive(Debug, Clone, Copy)]
pub struct Signature {
    /// The Python name.
    pub name: &'static str,
    /// Parameters in order, with defaults.
    pub params: &'static [(&'static str, Default)],
    /// Whether it accepts any further keyword arguments (`**kwargs`).
    pub var_kwargs: bool,
    /// What it does.
    pub kind: Kind,
}

use self::Default::{Bool, None as NoneD, Num, Required as R, Str};

const INF: f64 = f64::INFINITY;

/// Every RefAV function the importer knows, with RefAV's signatures (CainanD/RefAV at 5c5be64,
/// `refAV/atomic_functions.py`).
pub const SIGNATURES: &[Signature] = &[
    Signature {
        name: "get_objects_of_category",
        params: &[("log_dir", R), ("category", R)],
        var_kwargs: false,
        kind: Kind::Source,
    },
    Signature {
        name: "is_category",
        params: &[("track_candidates", R), ("log_dir", R), ("category", R)],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "turning",
        params: &[
            ("track_candidates", R),
            ("log_dir", R),
            ("direction", NoneD),
        ],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "changing_lanes",
        params: &[
            ("track_candidates", R),
            ("log_dir", R),
            ("direction", NoneD),
        ],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "has_lateral_acceleration",
        params: &[
            ("track_candidates", R),
            ("log_dir", R),
            ("min_accel", Num(-INF)),
            ("max_accel", Num(INF)),
        ],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "accelerating",
        params: &[
            ("track_candidates", R),
            ("log_dir", R),
            ("min_accel", Num(0.65)),
            ("max_accel", Num(INF)),
        ],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "has_velocity",
        params: &[
            ("track_candidates", R),
            ("log_dir", R),
            ("min_velocity", Num(0.5)),
            ("max_velocity", Num(INF)),
        ],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "at_pedestrian_crossing",
        params: &[
            ("track_candidates", R),
            ("log_dir", R),
            ("within_distance", Num(1.0)),
        ],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "is_color",
        params: &[("track_candidates", R), ("log_dir", R), ("color", R)],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "on_lane_type",
        params: &[("track_uuid", R), ("log_dir", R), ("lane_type", R)],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "near_intersection",
        params: &[("track_uuid", R), ("log_dir", R), ("threshold", Num(5.0))],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "on_intersection",
        params: &[("track_candidates", R), ("log_dir", R)],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "stationary",
        params: &[("track_candidates", R), ("log_dir", R)],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "at_stop_sign",
        params: &[
            ("track_candidates", R),
            ("log_dir", R),
            ("forward_thresh", Num(10.0)),
        ],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "in_drivable_area",
        params: &[("track_candidates", R), ("log_dir", R)],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "on_road",
        params: &[("track_candidates", R), ("log_dir", R)],
        var_kwargs: false,
        kind: Kind::Filter,
    },
    Signature {
        name: "has_objects_in_relative_direction",
        params: &[
            ("track_candidates", R),
            ("related_candidates", R),
            ("log_dir", R),
            ("direction", R),
            ("min_number", Num(1.0)),
            ("max_number", Num(INF)),
            ("within_distance", Num(50.0)),
            ("lateral_thresh", Num(INF)),
        ],
        var_kwargs: false,
        kind: Kind::Relational,
    },
    Signature {
        name: "get_objects_in_relative_direction",
        params: &[
            ("track_candidates", R),
            ("related_candidates", R),
            ("log_dir", R),
            ("direction", R),
            ("min_number", Num(0.0)),
            ("max_number", Num(INF)),
            ("within_distance", Num(50.0)),
            ("lateral_thresh", Num(INF)),
        ],
        var_kwargs: false,
        kind: Kind::Relational,
    },
    Signature {
        name: "facing_toward",
        params: &[
            ("track_candidates", R),
            ("related_candidates", R),
            ("log_dir", R),
            ("within_angle", Num(22.5)),
            ("max_distance", Num(50.0)),
        ],
        var_kwargs: false,
        kind: Kind::Relational,
    },
    Signature {
        name: "heading_toward",
        params: &[
            ("track_candidates", R),
            ("related_candidates", R),
            ("log_dir", R),
            ("angle_threshold", Num(22.5)),
            ("minimum_speed", Num(0.5)),
            ("max_distance", Num(INF)),
        ],
        var_kwargs: false,
        kind: Kind::Relational,
    },
    Signature {
        name: "being_crossed_by",
        params: &[
            ("track_candidates", R),
            ("related_candidates", R),
            ("log_dir", R),
            ("direction", Str("forward")),
            ("in_direction", Str("either")),
            ("forward_thresh", Num(10.0)),
            ("lateral_thresh", Num(5.0)),
        ],
        var_kwargs: false,
        kind: Kind::Relational,
    },
    Signature {
        name: "near_objects",
        params: &[
            ("track_uuid", R),
            ("candidate_uuids", R),
            ("log_dir", R),
            ("distance_thresh", Num(10.0)),
            ("min_objects", Num(1.0)),
            ("include_self", Bool(false)),
        ],
        var_kwargs: false,
        kind: Kind::Relational,
    },
    Signature {
        name: "following",
        params: &[
            ("track_candidates", R),
            ("related_candidates", R),
            ("log_dir", R),
        ],
        var_kwargs: false,
        kind: Kind::Relational,
    },
    Signature {
        name: "heading_in_relative_direction_to",
        params: &[
            ("track_candidates", R),
            ("related_candidates", R),
            ("log_dir", R),
            ("direction", R),
        ],
        var_kwargs: false,
        kind: Kind::Relational,
    },
    Signature {
        name: "in_same_lane",
        params: &[
            ("track_candidates", R),
            ("related_candidates", R),
            ("log_dir", R),
        ],
        var_kwargs: false,
        kind: Kind::Relational,
    },
    Signature {
        name: "on_relative_side_of_road",
        params: &[
            ("track_candidates", R),
            ("related_candidates", R),
            ("log_dir", R),
            ("side", R),
        ],
        var_kwargs: false,
        kind: Kind::Relational,
    },
    Signature {
        name: "scenario_and",
        params: &[("scenario_dicts", R)],
        var_kwargs: false,
        kind: Kind::Combine,
    },
    Signature {
        name: "scenario_or",
        params: &[("scenario_dicts", R)],
        var_kwargs: false,
        kind: Kind::Combine,
    },
    Signature {
        name: "reverse_relationship",
        params: &[("func", R)],
        var_kwargs: false,
        kind: Kind::Wrapper,
    },
    Signature {
        name: "scenario_not",
        params: &[("func", R)],
        var_kwargs: false,
        kind: Kind::Wrapper,
    },
    Signature {
        name: "output_scenario",
        params: &[
            ("scenario", R),
            ("description", R),
            ("log_dir", R),
            ("output_dir", R),
            ("visualize", Bool(false)),
        ],
        var_kwargs: true,
        kind: Kind::Output,
    },
];

/// The function whose keyword marks a program written against RefAV's first API:
/// `accelerating(track_candidates, log_dir, thresh=0)` (its prompt of March 2025, e.g.
/// CainanD/RefAV 05a681c), which the code the 262 programs came with (d61b714) still accepted as
/// `min_accel=thresh, max_accel=inf`, and 5c5be64 rejects (`TypeError`).
pub const FIRST_API_FUNCTION: &str = "accelerating";

/// The first API's keyword of [`FIRST_API_FUNCTION`].
pub const FIRST_API_KEYWORD: &str = "thresh";

/// RefAV functions that exist but read data Scenalog does not have (camera images).
pub const UNSUPPORTED: &[(&str, &str)] =
    &[("within_camera_view", "needs camera calibration and images")];

/// The signature of a RefAV function, if it is one.
pub fn lookup(name: &str) -> Option<&'static Signature> {
    SIGNATURES.iter().find(|s| s.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_log_dir_is_where_refav_has_it() {
        for (i, s) in SIGNATURES.iter().enumerate() {
            assert!(
                SIGNATURES[i + 1..].iter().all(|o| o.name != s.name),
                "{} twice",
                s.name
            );
            let log_dir = s.params.iter().position(|p| p.0 == "log_dir");
            match s.kind {
                Kind::Source => assert_eq!(log_dir, Some(0)),
                Kind::Filter => assert_eq!(log_dir, Some(1), "{}", s.name),
                Kind::Relational => assert_eq!(log_dir, Some(2), "{}", s.name),
                Kind::Output => assert_eq!(log_dir, Some(2)),
                Kind::Combine | Kind::Wrapper => assert_eq!(log_dir, None),
            }
        }
        assert!(lookup("being_crossed_by").is_some());
        assert!(lookup("on_road_lane").is_none());
    }
}
