//! `lane_direction(X, T, Rel)`: how X travels relative to the direction of the lane it is in
//! ("opposite" is driving against traffic).

use scenalog_facts::relation::RelationData;

use super::s;
use crate::cache::Extractor;
use crate::kinematics::wrap_angle;
use crate::map::geometry::{heading, nearest_on_polyline};
use crate::map::LaneGeom;
use crate::pairs::motion::{HEADINGS, SELF_MOVING_CATEGORIES};
use crate::query::Query;
use crate::rows::relation;
use crate::thresholds::{
    HEADING_OPPOSITE_MIN_DEG, HEADING_SAME_MAX_DEG, LANE_DIRECTION_MIN_SPEED_M_S,
};

/// The `Rel` value (its index in [`HEADINGS`]) for an angle (degrees, 0-180) between a direction
/// of travel and a lane's: "same", "perpendicular" or "opposite", with `heading_relative`'s
/// thresholds.
pub fn classify(angle_deg: f64) -> usize {
    if angle_deg <= HEADING_SAME_MAX_DEG {
        0
    } else if angle_deg >= HEADING_OPPOSITE_MIN_DEG {
        2
    } else {
        1
    }
}

/// The angle (degrees, 0-180) between `travel` (radians) and the direction of the lane `geom` at
/// the point of its centreline nearest `p`; `None` for a degenerate centreline.
fn angle_to_lane(geom: &LaneGeom, p: [f64; 2], travel: f64) -> Option<f64> {
    let (seg, _, _) = nearest_on_polyline(&geom.centerline, p)?;
    let lane = heading(geom.centerline[seg], geom.centerline[seg + 1]);
    Some(wrap_angle(travel - lane).abs().to_degrees())
}

/// `lane_direction(X, T, Rel)`: per box whose centre is in some lane and that has a direction of
/// travel (the velocity at [`LANE_DIRECTION_MIN_SPEED_M_S`] or more; slower, the box heading of an
/// object that moves by itself; a slow cone has none), the smallest angle to the direction of a
/// lane containing the centre, at the lane centreline's nearest point. Where lanes overlap (an
/// intersection) the best-matching one counts, so "opposite" means every lane there runs against
/// X; `in_lane`'s choice among them does not look at headings, so it is not used.
pub fn lane_direction(ex: &Extractor, q: &Query) -> RelationData {
    let (scene, kin, map) = (ex.scene(), ex.kinematics(), ex.map_index());
    let values: Vec<_> = HEADINGS.iter().map(|v| s(v)).collect();
    let mut rows = Vec::new();
    for x in q.tracks(scene, 0) {
        let Some(k) = kin.tracks.get(x.index()) else {
            continue;
        };
        let self_moving = SELF_MOVING_CATEGORIES.contains(&scene.track(x).category.as_str());
        for i in q.box_range(1, scene.num_frames(), &k.frames) {
            let travel = if k.speed[i] >= LANE_DIRECTION_MIN_SPEED_M_S {
                k.vel[i][1].atan2(k.vel[i][0])
            } else if self_moving {
                k.yaw[i]
            } else {
                continue;
            };
            let best = map
                .lanes_containing(k.center[i])
                .into_iter()
                .filter_map(|l| angle_to_lane(map.lanes.get(l)?, k.center[i], travel))
                .min_by(f64::total_cmp);
            let Some(angle) = best else {
                continue;
            };
            rows.push((x, k.frames[i], values[classify(angle)].clone()));
        }
    }
    relation(q, rows)
}
