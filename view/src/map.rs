//! The map under a picture: the drivable area, the lanes (vehicle lanes grey, bike and bus
//! lanes in their own colours, the same in and out of intersections, as the legend shows them),
//! and the pedestrian crossings, striped. Says which kinds it drew, so the legend lists those.

use scenalog_facts::map::LaneType;
use scenalog_facts::scene::Scene;

use crate::label::{bounds, overlaps, Rect};
use crate::style;
use crate::svg::{path_data, Svg};
use crate::view::View;

/// Which kinds of map feature a picture shows (the legend lists those).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MapKinds {
    /// Some vehicle lane is in view.
    pub vehicle_lane: bool,
    /// Some bike lane is in view.
    pub bike_lane: bool,
    /// Some bus lane is in view.
    pub bus_lane: bool,
    /// Some pedestrian crossing is in view.
    pub crossing: bool,
}

/// The zebra pattern of pedestrian crossings (also the legend's swatch).
pub const ZEBRA: &str = r##"<defs><pattern id="zebra" width="6" height="6" patternUnits="userSpaceOnUse" patternTransform="rotate(45)"><rect width="3" height="6" fill="#9a9a9a"/></pattern></defs>
"##;

/// The pixels of a polygon when some of it is inside `area` (its bounding rectangle meets it).
fn in_area(view: &View, area: &Rect, pts: &[[f64; 2]]) -> Option<Vec<[f64; 2]>> {
    if !view.touches(pts, 0.0) {
        return None;
    }
    let px: Vec<[f64; 2]> = pts.iter().map(|q| view.px(*q)).collect();
    overlaps(&bounds(&px), area).then_some(px)
}

/// Draws the drivable areas, lanes and pedestrian crossings that reach into `area` (the map's
/// rectangle, pixels); returns which kinds it drew.
pub fn draw_map(svg: &mut Svg, view: &View, scene: &Scene, area: &Rect) -> MapKinds {
    let mut kinds = MapKinds::default();
    svg.rect(
        area[0],
        area[1],
        area[2] - area[0],
        area[3] - area[1],
        &format!(r#"fill="{}""#, style::BACKGROUND),
    );
    svg.raw(ZEBRA);
    let mut d = String::new();
    for a in &scene.map.drivable_areas {
        let pts: Vec<[f64; 2]> = a.boundary.iter().map(|p| [p.x, p.y]).collect();
        if let Some(px) = in_area(view, area, &pts) {
            d.push_str(&path_data(&px, true));
        }
    }
    svg.path(&d, &format!(r#"fill="{}""#, style::DRIVABLE));
    // Vehicle lanes first, bike and bus lanes over them. Intersection lanes overlap each other:
    // vehicle ones are drawn translucent so the overlaps show; bike and bus ones keep their
    // colour (the legend's), outlined dashed to say they are in an intersection.
    for (kind, colour) in [
        (LaneType::Vehicle, style::VEHICLE_LANE),
        (LaneType::Bus, style::BUS_LANE),
        (LaneType::Bike, style::BIKE_LANE),
    ] {
        for intersection in [false, true] {
            let mut d = String::new();
            for l in &scene.map.lanes {
                if l.lane_type != kind || l.is_intersection != intersection {
                    continue;
                }
                if let Some(px) = in_area(view, area, &l.polygon_xy()) {
                    d.push_str(&path_data(&px, true));
                }
            }
            if d.is_empty() {
                continue;
            }
            match kind {
                LaneType::Vehicle => kinds.vehicle_lane = true,
                LaneType::Bus => kinds.bus_lane = true,
                LaneType::Bike => kinds.bike_lane = true,
            }
            let style = match (kind, intersection) {
                (LaneType::Vehicle, true) => format!(
                    r#"fill="{colour}" fill-opacity="0.45" stroke="{}" stroke-width="0.8""#,
                    style::LANE_EDGE
                ),
                (_, true) => format!(
                    r#"fill="{colour}" stroke="{}" stroke-width="0.8" stroke-dasharray="4 3""#,
                    style::LANE_EDGE
                ),
                _ => format!(
                    r#"fill="{colour}" stroke="{}" stroke-width="0.8""#,
                    style::LANE_EDGE
                ),
            };
            svg.path(&d, &style);
        }
    }
    let mut d = String::new();
    for c in &scene.map.crossings {
        if let Some(px) = in_area(view, area, &c.polygon_xy()) {
            d.push_str(&path_data(&px, true));
        }
    }
    if !d.is_empty() {
        kinds.crossing = true;
        svg.path(&d, &format!(r#"fill="{}" stroke="none""#, style::CROSSING));
        svg.path(
            &d,
            &format!(
                r#"fill="url(#zebra)" stroke="{}" stroke-width="1""#,
                style::CROSSING_EDGE
            ),
        );
    }
    kinds
}
