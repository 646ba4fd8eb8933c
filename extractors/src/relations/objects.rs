//! Objects and time: `category`, `ego`, `present`, `frame_ns`, `seconds`; RefAV's order of
//! objects, `refav_order`.

use scenalog_facts::relation::RelationData;
use scenalog_facts::scene::{is_construction_category, is_vehicle_category, SUPER_CATEGORIES};
use scenalog_facts::{TrackBox, TrackId};

use super::s;
use crate::cache::Extractor;
use crate::query::Query;
use crate::rows::relation;

/// `category(X, C)`: each track's category, plus "VEHICLE" for vehicles, "CONSTRUCTION" for
/// road-works objects and "ANY" for all.
pub fn category(ex: &Extractor, q: &Query) -> RelationData {
    let scene = ex.scene();
    let (any, vehicle) = (s(SUPER_CATEGORIES[1]), s(SUPER_CATEGORIES[0]));
    let construction = s(SUPER_CATEGORIES[2]);
    let mut rows = Vec::new();
    for t in q.tracks(scene, 0) {
        let cat = &scene.track(t).category;
        rows.push((t, s(cat)));
        if is_vehicle_category(cat) {
            rows.push((t, vehicle.clone()));
        }
        if is_construction_category(cat) {
            rows.push((t, construction.clone()));
        }
        rows.push((t, any.clone()));
    }
    relation(q, rows)
}

/// `ego(X)`.
pub fn ego(ex: &Extractor, q: &Query) -> RelationData {
    let e = ex.scene().ego;
    let known = q.allows_track(0, e) && e.index() < ex.scene().tracks.len();
    relation(q, known.then_some((e,)))
}

/// `present(X, T)`: one tuple per annotated box.
pub fn present(ex: &Extractor, q: &Query) -> RelationData {
    let rows: Vec<_> = boxes(ex, q).map(|(t, b)| (t, b.frame)).collect();
    relation(q, rows)
}

/// Every box the query allows (tracks in column 0, times in column 1), with its track.
fn boxes<'e>(ex: &'e Extractor, q: &'e Query) -> impl Iterator<Item = (TrackId, &'e TrackBox)> {
    let scene = ex.scene();
    q.tracks(scene, 0).flat_map(move |t| {
        let boxes = &scene.track(t).boxes;
        let r = q.boxes_range(1, scene.num_frames(), boxes);
        boxes[r].iter().map(move |b| (t, b))
    })
}

/// `next_sample(X, T, T2)`: each box of X's track and the next one, whatever the rate and gaps.
pub fn next_sample(ex: &Extractor, q: &Query) -> RelationData {
    let scene = ex.scene();
    let mut rows = Vec::new();
    for t in q.tracks(scene, 0) {
        let boxes = &scene.track(t).boxes;
        for i in q.boxes_range(1, scene.num_frames(), boxes) {
            if let (Some(b), Some(next)) = (boxes.get(i), boxes.get(i + 1)) {
                rows.push((t, b.frame, next.frame));
            }
        }
    }
    relation(q, rows)
}

/// `frame_ns(T, Ns)`.
pub fn frame_ns(ex: &Extractor, q: &Query) -> RelationData {
    let tl = &ex.scene().timeline;
    let r = q.frames(0, tl.frame_count());
    relation(q, r.filter_map(|f| Some((f, tl.ns(f)?))))
}

/// `seconds(T, S)`.
pub fn seconds(ex: &Extractor, q: &Query) -> RelationData {
    let tl = &ex.scene().timeline;
    let frames = q
        .frames(0, tl.frame_count())
        .filter(|&f| tl.ns(f).is_some());
    relation(q, frames.map(|f| (f, tl.seconds(f).unwrap_or(0.0))))
}

/// `refav_order(X, Cat, R)`: see [`crate::refav::order`].
pub fn refav_order(ex: &Extractor, q: &Query) -> RelationData {
    let scene = ex.scene();
    let order = crate::refav::order(scene).into_iter();
    relation(
        q,
        order
            .filter(|&(t, _, _)| q.allows_track(0, t))
            .map(|(t, c, r)| (t, s(c), r)),
    )
}

/// `refav_color(X, C)`: the log's RefAV colour cache (`scenalog_facts::color`): each track it
/// holds with its colour, "none" for `null`; nothing without a cache; an unreadable cache is an
/// error naming the file.
pub fn refav_color(ex: &Extractor, q: &Query) -> Result<RelationData, crate::query::ExtractError> {
    use scenalog_facts::color::NO_COLOR;
    use scenalog_facts::ColorCache;
    let mut rows = Vec::new();
    match &ex.scene().color_cache {
        ColorCache::Absent => {}
        ColorCache::Read { colors, .. } => {
            for (&t, c) in colors {
                if q.allows_track(0, t) {
                    rows.push((t, s(c.as_deref().unwrap_or(NO_COLOR))));
                }
            }
        }
        ColorCache::Unreadable(message) => return Err(unreadable(q, message)),
    }
    Ok(relation(q, rows))
}

/// The error of a relation read from a log's file that cannot be read (`message` names it).
fn unreadable(q: &Query, message: &str) -> crate::query::ExtractError {
    crate::query::ExtractError::BadInput {
        relation: q.spec.name.into(),
        message: message.to_string(),
    }
}

/// `attribute(X, Name, Score)`: the rows of the log's attributes file
/// (`scenalog_facts::attributes`) and each colour of its RefAV colour cache with score 1;
/// nothing without either; an unreadable file is an error naming it.
pub fn attribute(ex: &Extractor, q: &Query) -> Result<RelationData, crate::query::ExtractError> {
    use scenalog_facts::{Attributes, ColorCache};
    let scene = ex.scene();
    let mut rows = Vec::new();
    match &scene.attributes {
        Attributes::Absent => {}
        Attributes::Read { rows: read, .. } => rows.extend(
            read.iter()
                .filter(|a| q.allows_track(0, a.track))
                .map(|a| (a.track, s(&a.name), a.score)),
        ),
        Attributes::Unreadable(message) => return Err(unreadable(q, message)),
    }
    match &scene.color_cache {
        ColorCache::Absent => {}
        ColorCache::Read { colors, .. } => rows.extend(
            colors
                .iter()
                .filter(|(&t, _)| q.allows_track(0, t))
                .filter_map(|(&t, c)| Some((t, s(c.as_deref()?), 1.0))),
        ),
        ColorCache::Unreadable(message) => return Err(unreadable(q, message)),
    }
    Ok(relation(q, rows))
}

/// `elevation(X, T, Z)`: the height of the bottom of X's box (its centre's city-frame z less half
/// its height), one tuple a box.
pub fn elevation(ex: &Extractor, q: &Query) -> RelationData {
    let bottom = |b: &TrackBox| b.city_center().z - b.size[2] / 2.0;
    let rows: Vec<_> = boxes(ex, q).map(|(t, b)| (t, b.frame, bottom(b))).collect();
    relation(q, rows)
}
