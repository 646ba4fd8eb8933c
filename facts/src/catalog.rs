//! The catalog: every relation the extractors provide, as data (name, typed columns, one-line doc).
//!
//! The checker, the synthesis prompt and `scenalog catalog` all read this one table, so the
//! documentation an LLM sees is the one the checker enforces.

use crate::scene::{ALL_CATEGORIES, SUPER_CATEGORIES};
pub use crate::units::Unit;
use std::fmt;

/// The type of a relation column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ColType {
    /// An object of the log (the ego is one).
    Track,
    /// A moment of the log: stored as the frame of a 0.1 s grid (a 10 Hz log's frames are 0..N).
    Time,
    /// A lane segment id of the vector map.
    Lane,
    /// A string.
    Str,
    /// A floating-point number.
    Float,
    /// An integer.
    Int,
}

impl ColType {
    /// The type's name as written in the language and the catalog.
    pub fn as_str(self) -> &'static str {
        match self {
            ColType::Track => "track",
            ColType::Time => "time",
            ColType::Lane => "lane",
            ColType::Str => "str",
            ColType::Float => "float",
            ColType::Int => "int",
        }
    }

    /// Parses a type name ("track", "time", "lane", "str", "float", "int"; "number" is "float").
    pub fn parse(s: &str) -> Option<ColType> {
        Some(match s {
            "track" => ColType::Track,
            "time" => ColType::Time,
            "lane" => ColType::Lane,
            "str" | "symbol" | "string" => ColType::Str,
            "float" | "number" => ColType::Float,
            "int" => ColType::Int,
            _ => return None,
        })
    }

    /// Whether values of this type are numbers (int, float or time).
    pub fn is_numeric(self) -> bool {
        matches!(self, ColType::Float | ColType::Int | ColType::Time)
    }
}

impl fmt::Display for ColType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One column of a relation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ColumnSpec {
    /// The conventional variable name (e.g. "X", "T", "Dir").
    pub name: &'static str,
    /// The column's type.
    pub ty: ColType,
    /// For string columns with a closed set of values, the values; empty otherwise.
    pub values: &'static [&'static str],
    /// What a numeric column measures ([`Unit::None`] for the others).
    pub unit: Unit,
    /// For a distance column, the farthest it is produced: an object farther away has no tuple
    /// at all, so a lower bound on the column does not find it ([`PAIR_RANGE_M`],
    /// [`MAP_RANGE_M`]), in whole metres.
    pub range: Option<u32>,
}

/// Pair relations hold only for two objects whose ground rectangles are at most this far apart
/// (metres): their distance columns never exceed it.
pub const PAIR_RANGE_M: f64 = PAIR_RANGE as f64;

/// [`PAIR_RANGE_M`] in whole metres, as a column's [`ColumnSpec::range`] holds it.
pub const PAIR_RANGE: u32 = 50;

/// Map distances (`near_intersection`, `at_crosswalk`) are produced only up to this distance
/// (metres); a farther object has no tuple.
pub const MAP_RANGE_M: f64 = MAP_RANGE as f64;

/// [`MAP_RANGE_M`] in whole metres, as a column's [`ColumnSpec::range`] holds it.
pub const MAP_RANGE: u32 = 50;

/// The part of the catalog a relation belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Group {
    /// Objects and time.
    Objects,
    /// Kinematics of one object.
    Kinematics,
    /// Lanes and other map features.
    Map,
    /// Relations between two objects.
    Pairs,
    /// RefAV's definitions where they differ from Scenalog's, for programs imported with
    /// `scenalog import refav --semantics refav`.
    Refav,
}

impl Group {
    /// A heading for the group.
    pub fn title(self) -> &'static str {
        match self {
            Group::Objects => "Objects and time",
            Group::Kinematics => "Kinematics",
            Group::Map => "Map",
            Group::Pairs => "Pairs (Y within 50 m of X)",
            Group::Refav => "RefAV's definitions (what `scenalog import refav --semantics refav` targets; prefer the relations above)",
        }
    }
}

/// One relation of the catalog.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RelationSpec {
    /// The predicate name.
    pub name: &'static str,
    /// The columns, in order.
    pub columns: &'static [ColumnSpec],
    /// One line of documentation.
    pub doc: &'static str,
    /// Where it belongs.
    pub group: Group,
}

impl RelationSpec {
    /// Number of columns.
    pub fn arity(&self) -> usize {
        self.columns.len()
    }

    /// The column names: the columns' variable names (`X`, `T`, …), a repeated one made unique
    /// with `_2`, `_3` (`near`: `X`, `Y`, `T`, `D`). `scenalog facts --relation --json
    /// --columns` and the Python package's tables name the columns so.
    pub fn column_names(&self) -> Vec<String> {
        let mut names: Vec<String> = Vec::new();
        for c in self.columns {
            let mut name = c.name.to_string();
            let mut n = 1;
            while names.contains(&name) {
                n += 1;
                name = format!("{}_{n}", c.name);
            }
            names.push(name);
        }
        names
    }

    /// The column types, in order.
    pub fn types(&self) -> Vec<ColType> {
        self.columns.iter().map(|c| c.ty).collect()
    }

    /// The signature as written in docs, e.g. `near(X: track, Y: track, T: time, D: float)`.
    pub fn signature(&self) -> String {
        self.to_string()
    }

    /// The relation as a JSON object: `name`, `columns` (`name`, `type`, optional `values`,
    /// `unit` and `range`, the farthest a distance column is produced), `doc`, `group`.
    pub fn to_json(&self) -> serde_json::Value {
        let columns: Vec<serde_json::Value> = self
            .columns
            .iter()
            .map(|c| {
                let mut o = serde_json::json!({ "name": c.name, "type": c.ty.as_str() });
                if !c.values.is_empty() {
                    o["values"] = serde_json::json!(c.values);
                }
                if !c.unit.symbol().is_empty() {
                    o["unit"] = serde_json::json!(c.unit.symbol());
                }
                if let Some(r) = c.range {
                    o["range"] = serde_json::json!(r);
                }
                o
            })
            .collect();
        serde_json::json!({
            "name": self.name,
            "columns": columns,
            "doc": self.doc,
            "group": self.group.title(),
        })
    }
}

impl fmt::Display for RelationSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}(", self.name)?;
        for (i, c) in self.columns.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            write!(f, "{}: {}", c.name, c.ty)?;
            // A timestamp's nanoseconds are said in its doc: `int<ns>` is no column unit a
            // `.decl` takes (those are base units).
            if !matches!(
                c.unit,
                Unit::None | Unit::Count | Unit::Frame | Unit::Nanoseconds
            ) {
                write!(f, "<{}>", c.unit)?;
            }
        }
        f.write_str(")")
    }
}

const fn col(name: &'static str, ty: ColType) -> ColumnSpec {
    ColumnSpec {
        name,
        ty,
        values: &[],
        unit: match ty {
            ColType::Time => Unit::Frame,
            _ => Unit::None,
        },
        range: None,
    }
}

/// A float column measured in `unit`.
const fn qty(name: &'static str, unit: Unit) -> ColumnSpec {
    ColumnSpec {
        name,
        ty: ColType::Float,
        values: &[],
        unit,
        range: None,
    }
}

/// A distance column in metres produced only up to `range` metres.
const fn within(name: &'static str, range: u32) -> ColumnSpec {
    ColumnSpec {
        name,
        ty: ColType::Float,
        values: &[],
        unit: Unit::Metre,
        range: Some(range),
    }
}

/// An integer column measured in `unit`.
const fn int_col(name: &'static str, unit: Unit) -> ColumnSpec {
    ColumnSpec {
        name,
        ty: ColType::Int,
        values: &[],
        unit,
        range: None,
    }
}

const fn enum_col(name: &'static str, values: &'static [&'static str]) -> ColumnSpec {
    ColumnSpec {
        name,
        ty: ColType::Str,
        values,
        unit: Unit::None,
        range: None,
    }
}

const X: ColumnSpec = col("X", ColType::Track);
const Y: ColumnSpec = col("Y", ColType::Track);
const T: ColumnSpec = col("T", ColType::Time);
/// The columns of `crossing_detail` and `refav_crossing`.
const CROSSING_DETAIL_COLUMNS: &[ColumnSpec] = &[
    X,
    Y,
    T,
    enum_col("Dir", DIRECTIONS),
    enum_col("Sense", SENSES),
    qty("Reach", Unit::Metre),
    qty("Off", Unit::Metre),
];
/// The columns of `direction` and `refav_direction`.
const DIRECTION_COLUMNS: &[ColumnSpec] = &[
    X,
    Y,
    T,
    enum_col("Dir", DIRECTIONS),
    within("Dist", PAIR_RANGE),
    qty("Lat", Unit::Metre),
];
const L: ColumnSpec = col("L", ColType::Lane);

/// Directions relative to an object's own frame.
pub const DIRECTIONS: &[&str] = &["forward", "backward", "left", "right"];
/// Turn and lane-change directions.
pub const SIDES: &[&str] = &["left", "right"];
/// Relative headings.
pub const HEADINGS: &[&str] = &["same", "perpendicular", "opposite"];
/// Lane types.
pub const LANE_TYPES: &[&str] = &["VEHICLE", "BIKE", "BUS"];
/// Road sides.
pub const ROAD_SIDES: &[&str] = &["same", "opposite"];
/// Which way a lane segment takes its traffic (`lane_turn`).
pub const LANE_TURNS: &[&str] = &["left", "right", "straight"];
/// The paint of a lane boundary, as AV2's map files name it (`over_marking`).
pub const MARK_TYPES: &[&str] = &[
    "DASH_SOLID_YELLOW",
    "DASH_SOLID_WHITE",
    "DASHED_WHITE",
    "DASHED_YELLOW",
    "DOUBLE_SOLID_YELLOW",
    "DOUBLE_SOLID_WHITE",
    "DOUBLE_DASH_YELLOW",
    "DOUBLE_DASH_WHITE",
    "SOLID_YELLOW",
    "SOLID_WHITE",
    "SOLID_DASH_WHITE",
    "SOLID_DASH_YELLOW",
    "SOLID_BLUE",
    "NONE",
    "UNKNOWN",
];
/// The sense in which an object crosses another's midplane, about it seen from above.
pub const SENSES: &[&str] = &["clockwise", "counterclockwise"];

/// The values of `refav_color`'s colour column: RefAV's colours and "none".
pub const COLOR_VALUES: &[&str] = &["white", "silver", "black", "red", "yellow", "blue", "none"];

const CATEGORY_COUNT: usize = ALL_CATEGORIES.len() + SUPER_CATEGORIES.len();

const CATEGORY_ARRAY: [&str; CATEGORY_COUNT] = {
    let mut out = [""; CATEGORY_COUNT];
    let mut i = 0;
    while i < ALL_CATEGORIES.len() {
        out[i] = ALL_CATEGORIES[i];
        i += 1;
    }
    let mut j = 0;
    while j < SUPER_CATEGORIES.len() {
        out[i + j] = SUPER_CATEGORIES[j];
        j += 1;
    }
    out
};

/// The values of `category`'s second column: every AV2 category (`scene::ALL_CATEGORIES`) and
/// the super-categories (`scene::SUPER_CATEGORIES`), in that order.
pub const CATEGORY_VALUES: &[&str] = &CATEGORY_ARRAY;

/// A value people (and language models) write for a closed string column that the data spells
/// otherwise or does not have: the checker's hint for it names what is closest.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ValueAlias {
    /// The closed set of values this alias is about (one of the catalog's value lists).
    pub domain: &'static [&'static str],
    /// What was written, upper case for categories (compared ignoring case).
    pub said: &'static str,
    /// The closest values of the domain, best first (the first is the suggested replacement).
    pub closest: &'static [&'static str],
    /// Why: how AV2 names it, or that AV2 has no such class.
    pub note: &'static str,
}

const fn alias(
    domain: &'static [&'static str],
    said: &'static str,
    closest: &'static [&'static str],
    note: &'static str,
) -> ValueAlias {
    ValueAlias {
        domain,
        said,
        closest,
        note,
    }
}

/// Common names for values of closed columns that the data spells otherwise or lacks (AV2's
/// taxonomy as its annotation guide describes it).
pub const VALUE_ALIASES: &[ValueAlias] = &[
    alias(CATEGORY_VALUES, "CAR", &["REGULAR_VEHICLE"], "AV2 calls cars, vans, SUVs and pick-ups REGULAR_VEHICLE"),
    alias(CATEGORY_VALUES, "EGO", &["EGO_VEHICLE"], "the ego vehicle's category is EGO_VEHICLE (or use `ego(X)`)"),
    alias(CATEGORY_VALUES, "EMERGENCY_VEHICLE", &["REGULAR_VEHICLE", "LARGE_VEHICLE"], "AV2 has no emergency-vehicle class: police cars are REGULAR_VEHICLE, fire engines and most ambulances LARGE_VEHICLE; say in a comment that the program approximates"),
    alias(CATEGORY_VALUES, "AMBULANCE", &["LARGE_VEHICLE", "REGULAR_VEHICLE"], "AV2 has no ambulance class (emergency vehicles are annotated by body type)"),
    alias(CATEGORY_VALUES, "POLICE_CAR", &["REGULAR_VEHICLE"], "AV2 has no police class (emergency vehicles are annotated by body type)"),
    alias(CATEGORY_VALUES, "FIRE_TRUCK", &["LARGE_VEHICLE"], "AV2 has no fire-engine class (emergency vehicles are annotated by body type)"),
    alias(CATEGORY_VALUES, "VAN", &["REGULAR_VEHICLE"], "AV2 counts vans as REGULAR_VEHICLE"),
    alias(CATEGORY_VALUES, "SUV", &["REGULAR_VEHICLE"], "AV2 counts SUVs as REGULAR_VEHICLE"),
    alias(CATEGORY_VALUES, "PICKUP_TRUCK", &["REGULAR_VEHICLE"], "AV2 counts pick-up trucks as REGULAR_VEHICLE"),
    alias(CATEGORY_VALUES, "PERSON", &["PEDESTRIAN"], "AV2 calls people on foot PEDESTRIAN"),
    alias(CATEGORY_VALUES, "CYCLIST", &["BICYCLIST"], "AV2 calls the rider BICYCLIST and the bicycle BICYCLE"),
    alias(CATEGORY_VALUES, "BIKE", &["BICYCLE"], "AV2 calls a bicycle BICYCLE (its rider BICYCLIST)"),
    alias(CATEGORY_VALUES, "MOTORBIKE", &["MOTORCYCLE"], "AV2 calls it MOTORCYCLE (its rider MOTORCYCLIST)"),
    alias(CATEGORY_VALUES, "TRAILER", &["VEHICULAR_TRAILER"], "AV2 calls a towed trailer VEHICULAR_TRAILER"),
    alias(CATEGORY_VALUES, "SEMI_TRUCK", &["TRUCK_CAB", "TRUCK"], "AV2 annotates a semi's tractor as TRUCK_CAB and its trailer as VEHICULAR_TRAILER"),
    alias(CATEGORY_VALUES, "TRAFFIC_LIGHT", &["TRAFFIC_LIGHT_TRAILER"], "AV2 has no traffic-light objects (TRAFFIC_LIGHT_TRAILER is a mobile signal on a trailer) and the catalog has no signal state"),
    alias(CATEGORY_VALUES, "TRAFFIC_CONE", &["CONSTRUCTION_CONE"], "AV2 calls it CONSTRUCTION_CONE"),
    alias(CATEGORY_VALUES, "CONE", &["CONSTRUCTION_CONE"], "AV2 calls it CONSTRUCTION_CONE"),
    alias(CATEGORY_VALUES, "BARREL", &["CONSTRUCTION_BARREL"], "AV2 calls it CONSTRUCTION_BARREL"),
    alias(CATEGORY_VALUES, "SCOOTER", &["WHEELED_DEVICE", "WHEELED_RIDER"], "AV2 calls scooters and skateboards WHEELED_DEVICE and their riders WHEELED_RIDER"),
    alias(CATEGORY_VALUES, "CHILD", &["PEDESTRIAN"], "AV2 does not tell children from adults: PEDESTRIAN"),
    alias(CATEGORY_VALUES, "CAT", &["ANIMAL"], "AV2 has DOG and ANIMAL for all other animals"),
    alias(CATEGORY_VALUES, "OBJECT", &["ANY"], "every object is in the super-category ANY"),
    alias(CATEGORY_VALUES, "CONSTRUCTION_SIGN", &["CONSTRUCTION", "SIGN"], "AV2 has no construction-sign class: CONSTRUCTION is every road-works object, SIGN any sign"),
    alias(CATEGORY_VALUES, "CONSTRUCTION_OBJECT", &["CONSTRUCTION"], "the super-category of road-works objects is CONSTRUCTION"),
    alias(CATEGORY_VALUES, "BARRIER", &["CONSTRUCTION_BARREL", "BOLLARD"], "AV2 has no barrier class: CONSTRUCTION_BARREL, BOLLARD or the super-category CONSTRUCTION"),
    alias(DIRECTIONS, "front", &["forward"], "directions are forward, backward, left, right"),
    alias(DIRECTIONS, "ahead", &["forward"], "directions are forward, backward, left, right"),
    alias(DIRECTIONS, "behind", &["backward"], "directions are forward, backward, left, right"),
    alias(DIRECTIONS, "back", &["backward"], "directions are forward, backward, left, right"),
    alias(HEADINGS, "oncoming", &["opposite"], "relative headings are same, perpendicular, opposite"),
    alias(HEADINGS, "parallel", &["same"], "relative headings are same, perpendicular, opposite"),
    alias(HEADINGS, "crossing", &["perpendicular"], "relative headings are same, perpendicular, opposite"),
    alias(HEADINGS, "against", &["opposite"], "relative headings (and lane directions) are same, perpendicular, opposite: against traffic is opposite"),
    alias(HEADINGS, "wrong_way", &["opposite"], "relative headings (and lane directions) are same, perpendicular, opposite: the wrong way is opposite"),
];

/// The alias entry for a value written in a closed column with these values, if there is one
/// (compared ignoring ASCII case).
pub fn value_alias(domain: &[&str], said: &str) -> Option<&'static ValueAlias> {
    VALUE_ALIASES
        .iter()
        .find(|a| a.domain == domain && a.said.eq_ignore_ascii_case(said))
}

const CATALOG: &[RelationSpec] = &[
    // Objects and time
    RelationSpec {
        name: "category",
        columns: &[X, enum_col("C", CATEGORY_VALUES)],
        doc: "X's AV2 category, e.g. \"REGULAR_VEHICLE\", \"PEDESTRIAN\", \"EGO_VEHICLE\"; also the super-categories \"VEHICLE\", \"ANY\" and \"CONSTRUCTION\" (cones, barrels, message-board and traffic-light trailers, mobile crossing signs)",
        group: Group::Objects,
    },
    RelationSpec {
        name: "ego",
        columns: &[X],
        doc: "X is the ego vehicle",
        group: Group::Objects,
    },
    RelationSpec {
        name: "present",
        columns: &[X, T],
        doc: "X is annotated at T (a sample of its track)",
        group: Group::Objects,
    },
    RelationSpec {
        name: "next_sample",
        columns: &[X, T, col("T2", ColType::Time)],
        doc: "T2 is X's next sample after T: the next moment its track has a box (0.1 s later at 10 Hz, 0.5 s at 2 Hz, later across a gap); \"the next moment\" whatever the rate",
        group: Group::Objects,
    },
    RelationSpec {
        name: "frame_ns",
        columns: &[T, int_col("Ns", Unit::Nanoseconds)],
        doc: "T's timestamp in nanoseconds",
        group: Group::Objects,
    },
    RelationSpec {
        name: "seconds",
        columns: &[T, qty("S", Unit::SecondsFromStart)],
        doc: "T's time in seconds from the log's start",
        group: Group::Objects,
    },
    RelationSpec {
        name: "attribute",
        columns: &[X, col("Name", ColType::Str), qty("Score", Unit::Count)],
        doc: "a model looking at camera images said X is Name (any text, e.g. \"ambulance\", \"construction worker\", \"police\") with confidence Score in [0, 1]: read from the log's `attributes.csv` (columns track_uuid, name, score), and the colours of RefAV's colour cache with Score 1; empty for a log with neither (what only a camera shows is not in the boxes and the map), which `mine` says",
        group: Group::Objects,
    },
    // Kinematics
    RelationSpec {
        name: "speed",
        columns: &[X, T, qty("V", Unit::MetrePerSecond)],
        doc: "X's speed in m/s (city frame, smoothed); the concepts stopped, moving and fast are the prelude's `stopped`, `moving`, `fast`",
        group: Group::Kinematics,
    },
    RelationSpec {
        name: "forward_speed",
        columns: &[X, T, qty("V", Unit::MetrePerSecond)],
        doc: "X's signed speed along its heading in m/s (smoothed velocity on X's box's forward axis): negative when X moves backwards; the prelude's `reversing`",
        group: Group::Kinematics,
    },
    RelationSpec {
        name: "accel",
        columns: &[X, T, qty("A", Unit::MetrePerSecond2)],
        doc: "X's forward acceleration in m/s² in its own frame; the concepts are the prelude's `accelerating`, `braking`, `braking_hard`",
        group: Group::Kinematics,
    },
    RelationSpec {
        name: "lat_accel",
        columns: &[X, T, qty("A", Unit::MetrePerSecond2)],
        doc: "X's lateral acceleration in m/s² in its own frame, + is to the left",
        group: Group::Kinematics,
    },
    RelationSpec {
        name: "yaw_rate",
        columns: &[X, T, qty("W", Unit::DegreePerSecond)],
        doc: "X's yaw rate in deg/s, + is counter-clockwise (left), unsmoothed",
        group: Group::Kinematics,
    },
    RelationSpec {
        name: "elevation",
        columns: &[X, T, qty("Z", Unit::Metre)],
        doc: "the height in m of the bottom of X's box at T in the city frame, about the ground X stands on (the ego's box is centred at its rear axle's height, so its Z is some 0.35 m below its road): \"uphill from\" Y is a larger Z than Y's at the same T, by 2 m or more for a slope rather than noise",
        group: Group::Kinematics,
    },
    RelationSpec {
        name: "total_turn",
        columns: &[X, T, qty("A", Unit::Degree)],
        doc: "how far X's heading has turned by T since X's first box, in deg, + counter-clockwise (left), unwrapped (a U-turn adds about 180, a full circle 360): the turn between two moments T1 and T2 is A2 - A1; the prelude's `u_turn`",
        group: Group::Kinematics,
    },
    RelationSpec {
        name: "stationary",
        columns: &[X],
        doc: "X barely moves over its whole track (parked, not merely stopped): its smoothed positions fit in a box of diagonal < 3 m",
        group: Group::Kinematics,
    },
    RelationSpec {
        name: "turning",
        columns: &[X, T, enum_col("Dir", SIDES)],
        doc: "X is turning \"left\" or \"right\" at T (a run of same-sign yaw rate turning more than 45° in all)",
        group: Group::Kinematics,
    },
    RelationSpec {
        name: "lane_change",
        columns: &[X, T, enum_col("Dir", SIDES)],
        doc: "X is changing lanes to the \"left\" or \"right\" neighbour lane at T (not while turning)",
        group: Group::Kinematics,
    },
    // Map
    RelationSpec {
        name: "in_lane",
        columns: &[X, T, L],
        doc: "X's centre is in lane segment L at T (one lane per object and time)",
        group: Group::Map,
    },
    RelationSpec {
        name: "lane_type",
        columns: &[L, enum_col("Ty", LANE_TYPES)],
        doc: "lane L is a \"VEHICLE\", \"BIKE\" or \"BUS\" lane",
        group: Group::Map,
    },
    RelationSpec {
        name: "intersection_lane",
        columns: &[L],
        doc: "lane L lies in an intersection",
        group: Group::Map,
    },
    RelationSpec {
        name: "lane_successor",
        columns: &[L, col("L2", ColType::Lane)],
        doc: "lane L2 continues lane L",
        group: Group::Map,
    },
    RelationSpec {
        name: "lane_neighbor",
        columns: &[L, col("L2", ColType::Lane), enum_col("Side", SIDES)],
        doc: "lane L2 is L's neighbour on the \"left\" or \"right\"",
        group: Group::Map,
    },
    RelationSpec {
        name: "lane_turn",
        columns: &[L, enum_col("Dir", LANE_TURNS), qty("A", Unit::Degree)],
        doc: "lane segment L takes its traffic \"left\" or \"right\" (its centre line's heading changes by more than 45° from its start to its end; A is the change, + left) or \"straight\"; turns happen on intersection lanes, and the lane before one whose successors all turn one way is a turn lane (the prelude's `turn_lane`)",
        group: Group::Map,
    },
    RelationSpec {
        name: "road_lanes",
        columns: &[L, int_col("Same", Unit::Count), int_col("Opposite", Unit::Count)],
        doc: "the road at lane L has Same lanes in L's direction (L and the lanes beside it running its way, counted across the road from the map's geometry) and Opposite lanes of the other direction beside them; Opposite 0 is a one-way road or a carriageway with a median before the other direction (the map links no lane across a median), and lanes the map file lacks are not counted",
        group: Group::Map,
    },
    RelationSpec {
        name: "on_road",
        columns: &[X, T],
        doc: "X is in some lane at T",
        group: Group::Map,
    },
    RelationSpec {
        name: "in_drivable_area",
        columns: &[X, T],
        doc: "X's centre is inside the drivable area at T",
        group: Group::Map,
    },
    RelationSpec {
        name: "on_intersection",
        columns: &[X, T],
        doc: "X's centre is on an intersection lane at T",
        group: Group::Map,
    },
    RelationSpec {
        name: "near_intersection",
        columns: &[X, T, within("D", MAP_RANGE)],
        doc: "distance in m from X's centre to the nearest intersection lane at T, 0 inside",
        group: Group::Map,
    },
    RelationSpec {
        name: "at_crosswalk",
        columns: &[X, T, within("D", MAP_RANGE)],
        doc: "distance in m from X's box to the nearest pedestrian crossing at T, 0 when overlapping",
        group: Group::Map,
    },
    RelationSpec {
        name: "lane_direction",
        columns: &[X, T, enum_col("Rel", HEADINGS)],
        doc: "X travels in the \"same\" direction as the lane its centre is in at T (<= 45°), \"perpendicular\" or \"opposite\" (>= 135°: against traffic); where lanes overlap, the best-matching one; along its velocity at >= 1 m/s, else its box",
        group: Group::Map,
    },
    RelationSpec {
        name: "at_stop_sign",
        columns: &[X, col("S", ColType::Track), T],
        doc: "X is in stop sign S's lane, within 10 m before it and facing it, at T",
        group: Group::Map,
    },
    RelationSpec {
        name: "lane_offset",
        columns: &[X, T, qty("Off", Unit::Metre), qty("W", Unit::Metre)],
        doc: "X's centre lies Off m to the left (+) or right (-) of its lane's centre line at T (the lane of `in_lane`), in a lane W m wide there: |Off| near W / 2 is at the lane's edge",
        group: Group::Map,
    },
    RelationSpec {
        name: "over_marking",
        columns: &[X, T, enum_col("Side", SIDES), enum_col("Mark", MARK_TYPES), qty("D", Unit::Metre)],
        doc: "X's box reaches D m (> 0) past the \"left\" or \"right\" boundary of its lane at T, painted Mark (\"DASHED_WHITE\" between lanes of one direction, \"DOUBLE_SOLID_YELLOW\" or \"SOLID_YELLOW\" the centre line, \"SOLID_WHITE\" an edge line, \"NONE\" unpainted, as in intersections): a box over a line, not its centre (that is a lane change)",
        group: Group::Map,
    },
    RelationSpec {
        name: "road_edge",
        columns: &[X, T, within("D", MAP_RANGE)],
        doc: "X's box is D m from the nearest edge of the drivable area at T (a kerb, a median's side or where the paved road ends; 0 over the edge): on the road (`in_drivable_area`) D is how far from the kerb, off it how far from the road",
        group: Group::Map,
    },
    // Pairs
    RelationSpec {
        name: "near",
        columns: &[X, Y, T, within("D", PAIR_RANGE)],
        doc: "D is the distance in m between X's and Y's ground rectangles at T (0 if they overlap)",
        group: Group::Pairs,
    },
    RelationSpec {
        name: "direction",
        columns: DIRECTION_COLUMNS,
        doc: "Y's centre lies \"forward\", \"backward\", \"left\" or \"right\" of X's box in X's frame (a diagonal Y holds in two directions, e.g. forward and left); Dist box-to-box distance, Lat >= 0 how far Y's centre is outside X's sides (forward/backward) or ends (left/right), 0 when within",
        group: Group::Pairs,
    },
    RelationSpec {
        name: "heading_relative",
        columns: &[X, Y, T, enum_col("Rel", HEADINGS)],
        doc: "X's and Y's headings are the \"same\" (<= 45°), \"perpendicular\" or \"opposite\" (>= 135°)",
        group: Group::Pairs,
    },
    RelationSpec {
        name: "facing",
        columns: &[X, Y, T],
        doc: "Y is within 22.5° of X's forward axis at T",
        group: Group::Pairs,
    },
    RelationSpec {
        name: "heading_toward",
        columns: &[X, Y, T],
        doc: "X's velocity points within 22.5° of Y and X closes on Y at >= 0.5 m/s at T",
        group: Group::Pairs,
    },
    RelationSpec {
        name: "crossing",
        columns: &[X, Y, T, enum_col("Dir", DIRECTIONS)],
        doc: "Y crosses the half-plane extending 10 m from X's Dir side at T",
        group: Group::Pairs,
    },
    RelationSpec {
        name: "crossing_detail",
        columns: CROSSING_DETAIL_COLUMNS,
        doc: "Y crosses X's Dir half-midplane at T, as crossing but with its extents as columns: Sense \"clockwise\" or \"counterclockwise\" about X seen from above (on X's left, clockwise is back to front; \"overtaking\" is the prelude's `overtaking`), Reach how far beyond X's Dir side Y crossed (m, up to 30), Off Y's distance from the midplane at T (m, up to 15); crossing is Reach <= 10, Off <= 5",
        group: Group::Pairs,
    },
    RelationSpec {
        name: "same_lane",
        columns: &[X, Y, T],
        doc: "Y is in X's lane as a driver sees it (the straight chain of predecessors and successors) at T",
        group: Group::Pairs,
    },
    RelationSpec {
        name: "following",
        columns: &[X, Y, T],
        doc: "X follows lead Y at T: same lane (or Y in a successor), Y 0-25 m ahead, |lateral| < 5 m, headings within 60° (every such lead, not only the nearest)",
        group: Group::Pairs,
    },
    RelationSpec {
        name: "towing",
        columns: &[X, Y, T],
        doc: "vehicle X tows trailer Y at T: Y is a \"VEHICULAR_TRAILER\" behind X, rectangles <= 3 m apart, Y's centre <= 2 m outside X's sides, headings within 60° (a trailer parked right behind a vehicle holds too)",
        group: Group::Pairs,
    },
    RelationSpec {
        name: "in_between",
        columns: &[X, Y, col("Z", ColType::Track), T],
        doc: "X is between Y and Z at T: both within 5 m of X (box to box) and X's centre within 2 m of the segment joining their centres, strictly inside it; holds for (Y, Z) and (Z, Y)",
        group: Group::Pairs,
    },
    RelationSpec {
        name: "road_side",
        columns: &[X, Y, T, enum_col("Side", ROAD_SIDES)],
        doc: "Y is on the \"same\" or \"opposite\" side of the road as X at T",
        group: Group::Pairs,
    },
    RelationSpec {
        name: "refav_turning",
        columns: &[X, T, enum_col("Dir", SIDES)],
        doc: "RefAV's definition of `turning`: X is turning \"left\" or \"right\" at T by RefAV's rule (runs of same-sign unfiltered yaw rate, each including the sample that ends it, turning more than 45° in all), so a one-frame sign flip splits a turn",
        group: Group::Refav,
    },
    RelationSpec {
        name: "refav_turning_filtered",
        columns: &[X, T, enum_col("Dir", SIDES)],
        doc: "`refav_turning` on the yaw rate median-filtered over 3 samples: RefAV's rule without its spike defect (a one-frame heading spike no longer splits a turn)",
        group: Group::Refav,
    },
    RelationSpec {
        name: "refav_direction",
        columns: DIRECTION_COLUMNS,
        doc: "RefAV's definition of `direction` (its has_objects_in_relative_direction): as `direction`, but the ego is where RefAV places it: its position and box at the rear axle (1.44 m behind its body's centre), and as X a fixed box from 3.86 m to 1.02 m ahead of the axle (RefAV's back-edge sign slip) and 1 m either side",
        group: Group::Refav,
    },
    RelationSpec {
        name: "refav_direction_corrected",
        columns: DIRECTION_COLUMNS,
        doc: "`refav_direction` with the ego's back edge where RefAV means it: as X, its fixed box runs from 1.02 m behind the rear axle to 3.86 m ahead (RefAV's sign slip fixed)",
        group: Group::Refav,
    },
    RelationSpec {
        name: "refav_near",
        columns: &[X, Y, T, within("D", PAIR_RANGE)],
        doc: "RefAV's definition of `near` (the distance of its near_objects): as `near`, but the ego's ground rectangle is where RefAV places it, centred on the rear axle (1.44 m behind its body's centre)",
        group: Group::Refav,
    },
    RelationSpec {
        name: "refav_crossing",
        columns: CROSSING_DETAIL_COLUMNS,
        doc: "RefAV's definition of `crossing` (its being_crossed_by(X, Y, direction=Dir, in_direction=Sense) with forward_thresh >= Reach and lateral_thresh > Off): Y's median-filtered centre passes one of X's side lines extended in direction Dir (Reach m beyond half X's length) moving across faster than 0.2 m/s; T is in the span around it while Y keeps moving across that fast, Off the farthest Y has got past X's midplane on the far side by T (the near side unbounded); RefAV's direction overwrite is the importer's, with `refav_crossing_event` and `refav_order`",
        group: Group::Refav,
    },
    RelationSpec {
        name: "refav_crossing_event",
        columns: &[X, Y, T, enum_col("Dir", DIRECTIONS), qty("Reach", Unit::Metre)],
        doc: "a crossing RefAV's being_crossed_by(X, Y, direction=Dir) finds, whatever its sense and span: Y's median-filtered centre passes one of X's side lines extended in direction Dir between the frame before T and T, Reach m beyond half X's length, moving across faster than 0.2 m/s (after its first one RefAV overwrites its direction argument)",
        group: Group::Refav,
    },
    RelationSpec {
        name: "refav_crosswalk",
        columns: &[X, T, int_col("C", Unit::None), within("D", MAP_RANGE)],
        doc: "RefAV's definition of `at_crosswalk` (its at_pedestrian_crossing): X's box as RefAV has it (the ego's at its rear axle) touches pedestrian crossing C (its map id) dilated by D m with mitred corners (the polygon's edges moved out by D), 0 when they overlap",
        group: Group::Refav,
    },
    RelationSpec {
        name: "refav_lane_change",
        columns: &[X, T, enum_col("Dir", SIDES)],
        doc: "RefAV's definition of `lane_change` (its changing_lanes): X's lane by RefAV's lane buckets becomes its previous lane's \"left\" or \"right\" neighbour by AV2's links (across a centre line too) while X moves sideways at 0.1 m/s or more in the city frame, spanning the frames around it over which X keeps moving across its lane that way; RefAV's turning frames removed",
        group: Group::Refav,
    },
    RelationSpec {
        name: "refav_on_intersection",
        columns: &[X, T],
        doc: "RefAV's definition of `on_intersection`: the lane RefAV's lane buckets assign X at T (its median-filtered centre, the ego's at its rear axle) is an intersection lane",
        group: Group::Refav,
    },
    RelationSpec {
        name: "refav_color",
        columns: &[X, enum_col("C", COLOR_VALUES)],
        doc: "X's colour in RefAV's colour cache of the log (`cache/color_cache.json`, SigLIP2 over camera crops, computed offline by RefAV), \"none\" where the cache holds none; no rows for a log without a cache or a track the cache lacks (RefAV's is_color keeps those)",
        group: Group::Refav,
    },
    RelationSpec {
        name: "refav_order",
        columns: &[X, enum_col("Cat", CATEGORY_VALUES), int_col("R", Unit::Count)],
        doc: "X is the R-th (0 first) of the objects RefAV's get_objects_of_category(Cat) returns, for Cat X's category, \"VEHICLE\" (a vehicle) and \"ANY\": the annotation file's order of first rows, for \"VEHICLE\" category by category (RefAV's loops over candidates follow it)",
        group: Group::Refav,
    },
];

/// Every relation of the catalog, grouped and in documentation order.
pub fn catalog() -> &'static [RelationSpec] {
    CATALOG
}

/// The relation with this name, if the catalog has one.
pub fn relation(name: &str) -> Option<&'static RelationSpec> {
    CATALOG.iter().find(|r| r.name == name)
}

/// The catalog as plain text: a header with the column types, then the relations by group, each
/// as its signature, its doc, and the allowed values of any closed string column.
pub fn render_text() -> String {
    render_text_of(|_| true)
}

/// What descriptions ask for that no relation can hold: the catalog's last line.
pub const NOT_IN_THE_DATA: &str = "\nNot in the data: traffic-light state (red, green, yellow), parking lots and parking spaces, and attributes only a camera sees (an ambulance, a police car, a construction worker), which only `attribute` holds, and only for a log that carries a camera model's `attributes.csv` (empty otherwise). A program asked for one writes what the data holds and says in a `//` comment that it approximates.\n";

/// The relations written from descriptions, as text: every group but RefAV's definitions
/// ([`Group::Refav`]), which only `scenalog import refav --semantics refav` targets, so a model
/// writing a program is shown one definition of turning, direction and crossing.
pub fn render_rules_text() -> String {
    render_text_of(|r| r.group != Group::Refav)
}

/// The relations `keep` accepts, as [`render_text`] writes them.
fn render_text_of(keep: impl Fn(&RelationSpec) -> bool) -> String {
    let kept: Vec<&RelationSpec> = CATALOG.iter().filter(|r| keep(r)).collect();
    let mut out = format!(
        "{} relations. Column types: track (an object; the ego is one), time (a moment of the \
         log), lane (lane segment id), str, float, int; a float's unit follows its type \
         (`float<m/s>`).\n\n",
        kept.len()
    );
    let mut group = None;
    for r in kept {
        if group != Some(r.group) {
            if group.is_some() {
                out.push('\n');
            }
            out.push_str(r.group.title());
            out.push('\n');
            group = Some(r.group);
        }
        out.push_str(&format!("  {}\n      {}\n", r, r.doc));
        for c in r.columns.iter().filter(|c| !c.values.is_empty()) {
            let values: Vec<String> = c.values.iter().map(|v| format!("{v:?}")).collect();
            out.push_str(&format!(
                "      {} is one of {}\n",
                c.name,
                values.join(", ")
            ));
        }
        for c in r.columns.iter() {
            if let Some(range) = c.range {
                out.push_str(&format!(
                    "      {} only up to {range} m (a farther one has no tuple): \"farther than K\" is \"not within K\", a negation, not {} > K alone\n",
                    c.name, c.name
                ));
            }
        }
    }
    out.push_str(NOT_IN_THE_DATA);
    out
}

/// The catalog as a JSON array of relation objects (see [`RelationSpec::to_json`]).
pub fn render_json() -> serde_json::Value {
    serde_json::Value::Array(CATALOG.iter().map(RelationSpec::to_json).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn category_values_are_the_av2_categories_and_the_super_categories() {
        let want: Vec<&str> = ALL_CATEGORIES
            .iter()
            .chain(SUPER_CATEGORIES)
            .copied()
            .collect();
        assert_eq!(CATEGORY_VALUES, &want[..]);
        assert!(CATEGORY_VALUES.contains(&"EGO_VEHICLE") && CATEGORY_VALUES.contains(&"ANY"));
    }

    #[test]
    fn every_alias_is_outside_its_domain_and_points_into_it() {
        for a in VALUE_ALIASES {
            assert!(
                !a.domain.iter().any(|v| v.eq_ignore_ascii_case(a.said)),
                "{} is a value, not an alias",
                a.said
            );
            assert!(!a.closest.is_empty(), "{} has no closest value", a.said);
            for c in a.closest {
                assert!(a.domain.contains(c), "{}: {c} is not a value", a.said);
            }
        }
        assert_eq!(
            value_alias(CATEGORY_VALUES, "car").map(|a| a.closest[0]),
            Some("REGULAR_VEHICLE")
        );
        assert_eq!(value_alias(DIRECTIONS, "car"), None);
    }

    #[test]
    fn color_values_are_refav_colours_and_none() {
        let mut want: Vec<&str> = crate::color::REFAV_COLORS.to_vec();
        want.push(crate::color::NO_COLOR);
        assert_eq!(COLOR_VALUES, &want[..]);
    }

    #[test]
    fn every_number_has_a_unit_and_every_time_is_a_frame() {
        for r in catalog() {
            for c in r.columns {
                match c.ty {
                    // A plain number (a model's score) is a count's measure, no dimension.
                    ColType::Float => assert!(
                        c.unit == Unit::Count
                            || c.unit
                                .measure()
                                .is_some_and(|m| m.dims != crate::units::Dims::NONE),
                        "{}'s {} has no unit",
                        r.name,
                        c.name
                    ),
                    ColType::Time => assert_eq!(c.unit, Unit::Frame, "{}", r.name),
                    ColType::Int => {}
                    _ => assert_eq!(c.unit, Unit::None, "{}'s {}", r.name, c.name),
                }
            }
        }
        let speed = relation("speed").map(|r| r.columns[2].unit);
        assert_eq!(speed, Some(Unit::MetrePerSecond));
        assert_eq!(
            relation("yaw_rate").map(|r| r.columns[2].unit),
            Some(Unit::DegreePerSecond)
        );
        assert_eq!(
            relation("refav_order").map(|r| r.columns[2].unit),
            Some(Unit::Count)
        );
    }

    #[test]
    fn names_are_unique_and_lookup_works() {
        let mut names: Vec<_> = catalog().iter().map(|r| r.name).collect();
        names.sort_unstable();
        let n = names.len();
        names.dedup();
        assert_eq!(n, names.len());
        assert_eq!(relation("near").map(|r| r.arity()), Some(4));
        assert_eq!(
            relation("direction").map(|r| r.signature()),
            Some(
                "direction(X: track, Y: track, T: time, Dir: str, Dist: float<m>, Lat: float<m>)"
                    .into()
            )
        );
        assert!(relation("nope").is_none());
    }

    #[test]
    fn catalog_has_every_relation_of_the_design() {
        // The 32 relations of the original catalog, crossing_detail (crossing with its
        // extents and sense as columns, for RefAV's being_crossed_by arguments), and the
        // concepts of issue #14: lane_direction, towing, in_between; RefAV's definitions for
        // imported programs and the relations its defects need (issue #30); next_sample (the
        // next moment of a track whatever its rate, issue #39).
        const RELATIONS: usize = 58;
        assert_eq!(catalog().len(), RELATIONS);
        for name in [
            "crossing_detail",
            "lane_direction",
            "towing",
            "in_between",
            "refav_turning",
            "refav_direction",
            "refav_crossing",
            "refav_direction_corrected",
            "refav_crossing_event",
            "refav_order",
            "refav_crosswalk",
            "refav_turning_filtered",
            "refav_lane_change",
            "refav_on_intersection",
            "refav_color",
            "refav_near",
        ] {
            assert!(relation(name).is_some(), "{name}");
        }
        let json = render_json();
        assert_eq!(json.as_array().map(|a| a.len()), Some(RELATIONS));
        let text = render_text();
        assert!(text.starts_with(&format!("{RELATIONS} relations.")));
        assert!(text.contains("at_stop_sign(X: track, S: track, T: time)"));
        assert!(
            text.contains("      Dir is one of \"left\", \"right\"\n"),
            "{text}"
        );
    }
}
