//! Objects and time: `category`, `ego`, `present`, `frame_ns`, `seconds`; RefAV's order of
//! objects, `refav_order`.

use scenalog_facts::relation::{Column, RelationData};
use scenalog_facts::scene::{is_construction_category, is_vehicle_category, SUPER_CATEGORIES};

use super::s;
use crate::cache::Extractor;
use crate::query::Query;

/// `category(X, C)`: each track's category, plus "VEHICLE" for vehicles, "CONSTRUCTION" for
/// road-works objects and "ANY" for all.
pub fn category(ex: &Extractor, q: &Query) -> RelationData {
    let scene = ex.scene();
    let (any, vehicle) = (s(SUPER_CATEGORIES[1]), s(SUPER_CATEGORIES[0]));
    let construction = s(SUPER_CATEGORIES[2]);
    let (mut xs, mut cs) = (Vec::new(), Vec::new());
    for t in q.tracks(scene, 0) {
        let cat = &scene.track(t).category;
        xs.push(t);
        cs.push(s(cat));
        if is_vehicle_category(cat) {
            xs.push(t);
            cs.push(vehicle.clone());
        }
        if is_construction_category(cat) {
            xs.push(t);
            cs.push(construction.clone());
        }
        xs.push(t);
        cs.push(any.clone());
    }
    RelationData {
        name: q.spec.name.into(),
        columns: vec![Column::Track(xs), Column::Str(cs)],
    }
}

/// `ego(X)`.
pub fn ego(ex: &Extractor, q: &Query) -> RelationData {
    let e = ex.scene().ego;
    let xs = if q.allows_track(0, e) && e.index() < ex.scene().tracks.len() {
        vec![e]
    } else {
        Vec::new()
    };
    RelationData {
        name: q.spec.name.into(),
        columns: vec![Column::Track(xs)],
    }
}

/// `present(X, T)`: one tuple per annotated box.
pub fn present(ex: &Extractor, q: &Query) -> RelationData {
    let scene = ex.scene();
    let (mut xs, mut ts) = (Vec::new(), Vec::new());
    let r = q.frames(1, scene.num_frames());
    for t in q.tracks(scene, 0) {
        let boxes = &scene.track(t).boxes;
        let a = boxes.partition_point(|b| b.frame < r.start);
        let z = boxes.partition_point(|b| b.frame < r.end).max(a);
        for b in &boxes[a..z] {
            xs.push(t);
            ts.push(b.frame);
        }
    }
    RelationData {
        name: q.spec.name.into(),
        columns: vec![Column::Track(xs), Column::Time(ts)],
    }
}

/// `next_sample(X, T, T2)`: each box of X's track and the next one, whatever the rate and gaps.
pub fn next_sample(ex: &Extractor, q: &Query) -> RelationData {
    let scene = ex.scene();
    let (mut xs, mut ts, mut nexts) = (Vec::new(), Vec::new(), Vec::new());
    let r = q.frames(1, scene.num_frames());
    for t in q.tracks(scene, 0) {
        let boxes = &scene.track(t).boxes;
        let a = boxes.partition_point(|b| b.frame < r.start);
        let z = boxes.partition_point(|b| b.frame < r.end).max(a);
        for pair in boxes[a..boxes.len().min(z + 1)].windows(2) {
            if pair[0].frame >= r.end {
                break;
            }
            xs.push(t);
            ts.push(pair[0].frame);
            nexts.push(pair[1].frame);
        }
    }
    RelationData {
        name: q.spec.name.into(),
        columns: vec![Column::Track(xs), Column::Time(ts), Column::Time(nexts)],
    }
}

/// `frame_ns(T, Ns)`.
pub fn frame_ns(ex: &Extractor, q: &Query) -> RelationData {
    let tl = &ex.scene().timeline;
    let r = q.frames(0, tl.frame_count());
    let (frames, ns): (Vec<u32>, Vec<i64>) = r.filter_map(|f| Some((f, tl.ns(f)?))).unzip();
    RelationData {
        name: q.spec.name.into(),
        columns: vec![Column::Time(frames), Column::Int(ns)],
    }
}

/// `seconds(T, S)`.
pub fn seconds(ex: &Extractor, q: &Query) -> RelationData {
    let tl = &ex.scene().timeline;
    let frames: Vec<u32> = q
        .frames(0, tl.frame_count())
        .filter(|&f| tl.ns(f).is_some())
        .collect();
    let secs = frames
        .iter()
        .map(|&f| tl.seconds(f).unwrap_or(0.0))
        .collect();
    RelationData {
        name: q.spec.name.into(),
        columns: vec![Column::Time(frames), Column::Float(secs)],
    }
}

/// `refav_order(X, Cat, R)`: see [`crate::refav::order`].
pub fn refav_order(ex: &Extractor, q: &Query) -> RelationData {
    let scene = ex.scene();
    let (mut xs, mut cs, mut rs) = (Vec::new(), Vec::new(), Vec::new());
    for (t, c, r) in crate::refav::order(scene) {
        if q.allows_track(0, t) {
            xs.push(t);
            cs.push(s(c));
            rs.push(r);
        }
    }
    RelationData {
        name: q.spec.name.into(),
        columns: vec![Column::Track(xs), Column::Str(cs), Column::Int(rs)],
    }
}

/// `refav_color(X, C)`: the log's RefAV colour cache (`scenalog_facts::color`): each track it
/// holds with its colour, "none" for `null`; nothing without a cache; an unreadable cache is an
/// error naming the file.
pub fn refav_color(ex: &Extractor, q: &Query) -> Result<RelationData, crate::query::ExtractError> {
    use scenalog_facts::color::NO_COLOR;
    use scenalog_facts::ColorCache;
    let (mut xs, mut cs) = (Vec::new(), Vec::new());
    match &ex.scene().color_cache {
        ColorCache::Absent => {}
        ColorCache::Read { colors, .. } => {
            for (&t, c) in colors {
                if q.allows_track(0, t) {
                    xs.push(t);
                    cs.push(s(c.as_deref().unwrap_or(NO_COLOR)));
                }
            }
        }
        ColorCache::Unreadable(message) => {
            return Err(crate::query::ExtractError::BadInput {
                relation: q.spec.name.into(),
                message: message.clone(),
            })
        }
    }
    Ok(RelationData {
        name: q.spec.name.into(),
        columns: vec![Column::Track(xs), Column::Str(cs)],
    })
}
