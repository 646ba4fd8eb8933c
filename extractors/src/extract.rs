//! The entry points: answering a [`Request`] for any catalog relation, all relations of a scene,
//! and many logs in parallel.

use scenalog_facts::catalog;
use scenalog_facts::relation::{RelationData, Request};
use scenalog_facts::Scene;

use crate::cache::Extractor;
use crate::query::{ExtractError, Query};
use crate::relations::{between, lane_direction, map, motion, objects, towing};

/// Computes the tuples of `query`'s relation (unfiltered, unsorted), then filters and sorts them.
pub(crate) fn provide(ex: &Extractor, q: &Query) -> Result<RelationData, ExtractError> {
    let data = match q.spec.name {
        "category" => objects::category(ex, q),
        "ego" => objects::ego(ex, q),
        "present" => objects::present(ex, q),
        "next_sample" => objects::next_sample(ex, q),
        "frame_ns" => objects::frame_ns(ex, q),
        "seconds" => objects::seconds(ex, q),
        "speed" => motion::per_box(ex, q, |k| &k.speed),
        "accel" => motion::per_box(ex, q, |k| &k.accel),
        "lat_accel" => motion::per_box(ex, q, |k| &k.lat_accel),
        "yaw_rate" => motion::per_box(ex, q, |k| &k.yaw_rate),
        "stationary" => motion::stationary(ex, q),
        "turning" => motion::events(ex, q, ex.turning()),
        "refav_turning" => motion::events(ex, q, ex.refav_turning()),
        "refav_turning_filtered" => motion::events(ex, q, ex.refav_turning_filtered()),
        "refav_crossing" => crate::pairs::refav::refav_crossing(ex.scene(), q),
        "refav_crossing_event" => crate::pairs::refav::refav_crossing_event(ex.scene(), q),
        "refav_order" => objects::refav_order(ex, q),
        "refav_color" => objects::refav_color(ex, q)?,
        "refav_crosswalk" => map::refav_crosswalk(ex, q),
        "refav_lane_change" => crate::refav_lanes::refav_lane_change(ex, q),
        "refav_on_intersection" => crate::refav_lanes::refav_on_intersection(ex, q),
        "lane_change" => motion::events(ex, q, ex.lane_changes()),
        "in_lane" => map::in_lane(ex, q),
        "lane_type" => map::lane_type(ex, q),
        "intersection_lane" => map::intersection_lane(ex, q),
        "lane_successor" => map::lane_successor(ex, q),
        "lane_neighbor" => map::lane_neighbor(ex, q),
        "on_road" => map::on_road(ex, q),
        "in_drivable_area" => {
            let index = ex.map_index();
            map::centre_test(ex, q, |c| index.in_drivable_area(c))
        }
        "on_intersection" => {
            let index = ex.map_index();
            map::centre_test(ex, q, |c| index.in_intersection(c))
        }
        "near_intersection" => map::near_intersection(ex, q),
        "at_crosswalk" => map::at_crosswalk(ex, q),
        "at_stop_sign" => map::at_stop_sign(ex, q),
        "lane_direction" => lane_direction::lane_direction(ex, q),
        "towing" => towing::towing(ex, q),
        "in_between" => between::in_between(ex, q),
        other => match crate::pairs::provide(ex, q) {
            Some(data) => data,
            None => return Err(ExtractError::NotProvided(other.to_string())),
        },
    };
    // A computation stopped by its budget returns what it had: an error, never that.
    if let Some(e) = q.spent.error(q.spec.name, &q.budget) {
        return Err(e);
    }
    if data.len() > q.budget.max_tuples {
        return Err(ExtractError::TooManyTuples {
            relation: q.spec.name.to_string(),
            limit: q.budget.max_tuples,
        });
    }
    Ok(q.finish(ex.scene(), data))
}

/// The relation `req` asks for over `scene`: only tuples satisfying every constraint, sorted.
/// (One-off; use an [`Extractor`] to share work between requests on one scene.)
pub fn extract(scene: &Scene, req: &Request) -> Result<RelationData, ExtractError> {
    Extractor::new(scene).extract_uncached(req)
}

/// Every relation of the catalog the extractors provide, in catalog order (relations in parallel;
/// the output does not depend on the thread count).
pub fn extract_all(scene: &Scene) -> Vec<RelationData> {
    extract_all_with(&Extractor::new(scene))
}

/// [`extract_all`] with an existing context.
pub fn extract_all_with(ex: &Extractor) -> Vec<RelationData> {
    use rayon::prelude::*;
    ex.prepare();
    catalog::catalog()
        .par_iter()
        .filter_map(|spec| ex.extract_uncached(&Request::all(spec.name)).ok())
        .collect()
}

/// Answers the same requests on many logs in parallel: per scene, the answers in request order.
pub fn extract_logs(
    scenes: &[Scene],
    requests: &[Request],
) -> Vec<Result<Vec<RelationData>, ExtractError>> {
    use rayon::prelude::*;
    scenes
        .par_iter()
        .map(|scene| {
            let ex = Extractor::new(scene);
            requests.iter().map(|r| ex.extract_uncached(r)).collect()
        })
        .collect()
}
