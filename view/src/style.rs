//! Colours and sizes of the pictures: one place, so every picture looks the same.

/// Canvas background (off-road).
pub const BACKGROUND: &str = "#f3f1ea";
/// Drivable area fill.
pub const DRIVABLE: &str = "#d4d4d4";
/// Vehicle lane fill.
pub const VEHICLE_LANE: &str = "#bcbcbc";
/// Bike lane fill.
pub const BIKE_LANE: &str = "#8fcf8f";
/// Bus lane fill.
pub const BUS_LANE: &str = "#e9a9a0";
/// Lane boundary stroke.
pub const LANE_EDGE: &str = "#fafafa";
/// Pedestrian crossing fill (stripes are drawn over it).
pub const CROSSING: &str = "#ffffff";
/// Pedestrian crossing stripes and outline.
pub const CROSSING_EDGE: &str = "#7a7a7a";
/// The referred object's fill.
pub const REFERRED: &str = "#e6007e";
/// Related objects' outline and the link to them.
pub const RELATED: &str = "#00b3c7";
/// The ego's fill.
pub const EGO: &str = "#222222";
/// A fact that holds.
pub const FACT: &str = "#1565c0";
/// A fact that fails (why-not).
pub const FAILED: &str = "#d50000";
/// Text.
pub const TEXT: &str = "#111111";
/// Secondary text (the point of view, a count of lines left out).
pub const MUTED: &str = "#555555";
/// The side panel's background.
pub const PANEL: &str = "#ffffff";
/// The line between the map and the side panel.
pub const PANEL_EDGE: &str = "#9e9e9e";
/// Font family (the embedded DejaVu Sans).
pub const FONT: &str = "DejaVu Sans";

/// The fill colour of an object of this AV2 category.
pub fn category_colour(category: &str) -> &'static str {
    match category {
        "EGO_VEHICLE" => EGO,
        "BUS" | "ARTICULATED_BUS" | "SCHOOL_BUS" => "#7b4fb0",
        "REGULAR_VEHICLE" | "LARGE_VEHICLE" | "TRUCK" | "BOX_TRUCK" | "TRUCK_CAB"
        | "VEHICULAR_TRAILER" | "RAILED_VEHICLE" => "#3f6fbf",
        "PEDESTRIAN" | "OFFICIAL_SIGNALER" | "STROLLER" | "WHEELCHAIR" => "#1e9e50",
        "DOG" | "ANIMAL" => "#6b8e23",
        "BICYCLE" | "BICYCLIST" | "MOTORCYCLE" | "MOTORCYCLIST" | "WHEELED_RIDER"
        | "WHEELED_DEVICE" => "#e08a00",
        "STOP_SIGN" => "#c62828",
        _ => "#8a8a8a",
    }
}

/// The legend's groups: a colour and what it stands for.
pub const LEGEND: &[(&str, &str)] = &[
    (REFERRED, "referred"),
    (EGO, "ego"),
    ("#3f6fbf", "vehicle"),
    ("#7b4fb0", "bus"),
    ("#1e9e50", "pedestrian"),
    ("#e08a00", "cyclist"),
    ("#8a8a8a", "other"),
];
