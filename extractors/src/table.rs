//! The relation table: every catalog relation the extractors provide, with how it is computed.
//! One row per relation; the catalog (`scenalog_facts::catalog`) says what the relation is, this
//! table says which function computes it, and a test holds the two to the same names.
//!
//! Adding a relation: its spec in the catalog, its function in [`crate::relations`] (one object at
//! a time, from the per-scene [`Extractor`]) or [`crate::pairs`] (pairs of objects, through the
//! per-frame R-tree), one row here, and its tests.

use scenalog_facts::relation::{RelationData, Request};

use crate::cache::Extractor;
use crate::pairs::{self, PairContext};
use crate::query::{ExtractError, Query};
use crate::refav_lanes;
use crate::relations::{between, lane_direction, map, motion, objects, road, towing};

/// How a relation's tuples are computed: unfiltered and unsorted; the caller applies the request's
/// constraints and sorts ([`Query::finish`]).
#[derive(Clone, Copy)]
pub(crate) enum Compute {
    /// From the per-scene context: one object, the map or the timeline at a time.
    Scene(fn(&Extractor, &Query) -> RelationData),
    /// As [`Compute::Scene`], for a relation that can fail on its input (a file it reads).
    Fallible(fn(&Extractor, &Query) -> Result<RelationData, ExtractError>),
    /// Pairs of objects at one frame, from the pair context ([`PairContext`]).
    Pairs(fn(&PairContext, &Query) -> RelationData),
}

/// Every relation the extractors provide and how, in no particular order.
const RELATIONS: &[(&str, Compute)] = &[
    // Objects and time.
    ("category", Compute::Scene(objects::category)),
    ("ego", Compute::Scene(objects::ego)),
    ("present", Compute::Scene(objects::present)),
    ("next_sample", Compute::Scene(objects::next_sample)),
    ("frame_ns", Compute::Scene(objects::frame_ns)),
    ("seconds", Compute::Scene(objects::seconds)),
    ("refav_order", Compute::Scene(objects::refav_order)),
    ("elevation", Compute::Scene(objects::elevation)),
    ("refav_color", Compute::Fallible(objects::refav_color)),
    ("attribute", Compute::Fallible(objects::attribute)),
    // Kinematics and events.
    (
        "speed",
        Compute::Scene(|ex, q| motion::per_box(ex, q, |k| &k.speed)),
    ),
    (
        "accel",
        Compute::Scene(|ex, q| motion::per_box(ex, q, |k| &k.accel)),
    ),
    (
        "lat_accel",
        Compute::Scene(|ex, q| motion::per_box(ex, q, |k| &k.lat_accel)),
    ),
    (
        "yaw_rate",
        Compute::Scene(|ex, q| motion::per_box(ex, q, |k| &k.yaw_rate)),
    ),
    ("forward_speed", Compute::Scene(motion::forward_speed)),
    ("total_turn", Compute::Scene(motion::total_turn)),
    ("stationary", Compute::Scene(motion::stationary)),
    (
        "turning",
        Compute::Scene(|ex, q| motion::events(ex, q, ex.turning())),
    ),
    (
        "refav_turning",
        Compute::Scene(|ex, q| motion::events(ex, q, ex.refav_turning())),
    ),
    (
        "refav_turning_filtered",
        Compute::Scene(|ex, q| motion::events(ex, q, ex.refav_turning_filtered())),
    ),
    (
        "lane_change",
        Compute::Scene(|ex, q| motion::events(ex, q, ex.lane_changes())),
    ),
    (
        "refav_lane_change",
        Compute::Scene(refav_lanes::refav_lane_change),
    ),
    (
        "refav_on_intersection",
        Compute::Scene(refav_lanes::refav_on_intersection),
    ),
    // The map.
    ("in_lane", Compute::Scene(map::in_lane)),
    ("lane_type", Compute::Scene(map::lane_type)),
    ("intersection_lane", Compute::Scene(map::intersection_lane)),
    ("lane_successor", Compute::Scene(map::lane_successor)),
    ("lane_neighbor", Compute::Scene(map::lane_neighbor)),
    ("lane_turn", Compute::Scene(road::lane_turn)),
    ("road_lanes", Compute::Scene(road::road_lanes)),
    ("on_road", Compute::Scene(map::on_road)),
    (
        "in_drivable_area",
        Compute::Scene(|ex, q| {
            let index = ex.map_index();
            map::centre_test(ex, q, |c| index.in_drivable_area(c))
        }),
    ),
    (
        "on_intersection",
        Compute::Scene(|ex, q| {
            let index = ex.map_index();
            map::centre_test(ex, q, |c| index.in_intersection(c))
        }),
    ),
    ("near_intersection", Compute::Scene(map::near_intersection)),
    ("at_crosswalk", Compute::Scene(map::at_crosswalk)),
    ("refav_crosswalk", Compute::Scene(map::refav_crosswalk)),
    ("at_stop_sign", Compute::Scene(map::at_stop_sign)),
    ("lane_offset", Compute::Scene(road::lane_offset)),
    ("over_marking", Compute::Scene(road::over_marking)),
    ("road_edge", Compute::Scene(road::road_edge)),
    (
        "lane_direction",
        Compute::Scene(lane_direction::lane_direction),
    ),
    // Several objects, found through the per-frame R-tree.
    ("towing", Compute::Scene(towing::towing)),
    ("in_between", Compute::Scene(between::in_between)),
    (
        "refav_crossing",
        Compute::Scene(|ex, q| pairs::refav::refav_crossing(ex.scene(), q)),
    ),
    (
        "refav_crossing_event",
        Compute::Scene(|ex, q| pairs::refav::refav_crossing_event(ex.scene(), q)),
    ),
    // Pairs of objects at one frame.
    ("near", Compute::Pairs(pairs::spatial::near)),
    ("direction", Compute::Pairs(pairs::spatial::direction)),
    ("facing", Compute::Pairs(pairs::spatial::facing)),
    (
        "heading_relative",
        Compute::Pairs(pairs::motion::heading_relative),
    ),
    (
        "heading_toward",
        Compute::Pairs(pairs::motion::heading_toward),
    ),
    ("crossing", Compute::Pairs(pairs::motion::crossing)),
    (
        "crossing_detail",
        Compute::Pairs(pairs::motion::crossing_detail),
    ),
    ("same_lane", Compute::Pairs(pairs::lanes::same_lane)),
    ("following", Compute::Pairs(pairs::lanes::following)),
    ("road_side", Compute::Pairs(pairs::lanes::road_side)),
    (
        "refav_direction",
        Compute::Pairs(pairs::refav::refav_direction),
    ),
    (
        "refav_direction_corrected",
        Compute::Pairs(pairs::refav::refav_direction_corrected),
    ),
    ("refav_near", Compute::Pairs(pairs::refav::refav_near)),
];

/// How the relation `name` is computed, if the extractors provide it.
pub(crate) fn compute(name: &str) -> Option<Compute> {
    RELATIONS.iter().find(|(n, _)| *n == name).map(|(_, c)| *c)
}

/// The names of every relation the extractors provide, in table order.
pub fn provided() -> impl Iterator<Item = &'static str> {
    RELATIONS.iter().map(|(n, _)| *n)
}

/// The names of the pair relations (computed from a [`PairContext`]), in table order.
pub fn pair_relations() -> Vec<&'static str> {
    RELATIONS
        .iter()
        .filter(|(_, c)| matches!(c, Compute::Pairs(_)))
        .map(|(n, _)| *n)
        .collect()
}

/// The tuples of `q`'s relation (unfiltered, unsorted) computed with the extractor's shared data;
/// `None` for a relation the table does not hold.
pub(crate) fn tuples(ex: &Extractor, q: &Query) -> Option<Result<RelationData, ExtractError>> {
    Some(match compute(q.spec.name)? {
        Compute::Scene(f) => Ok(f(ex, q)),
        Compute::Fallible(f) => f(ex, q),
        Compute::Pairs(f) => {
            let index = pairs::pair_index(ex);
            let ctx = PairContext::of(ex, &index);
            Ok(f(&ctx, q))
        }
    })
}

/// `req` answered by the pair relation it names, from an explicit context: only tuples satisfying
/// every constraint, rows sorted; an error for a relation that is not a pair relation or a
/// constraint that does not fit its column.
pub fn pair_relation(ctx: &PairContext, req: &Request) -> Result<RelationData, ExtractError> {
    let q = Query::new(ctx.scene, req)?;
    let Some(Compute::Pairs(f)) = compute(&req.name) else {
        return Err(ExtractError::NotProvided(format!(
            "{} (not a pair relation)",
            req.name
        )));
    };
    let data = f(ctx, &q);
    Ok(q.finish(ctx.scene, data))
}

#[cfg(test)]
mod tests {
    use super::*;
    use scenalog_facts::catalog::catalog;

    #[test]
    fn the_table_provides_exactly_the_catalog_relations() {
        let mut table: Vec<&str> = provided().collect();
        table.sort_unstable();
        let before = table.len();
        table.dedup();
        assert_eq!(table.len(), before, "a relation is in the table twice");
        let mut names: Vec<&str> = catalog().iter().map(|s| s.name).collect();
        names.sort_unstable();
        assert_eq!(table, names);
    }
}
