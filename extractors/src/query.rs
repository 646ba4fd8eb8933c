//! A checked request: the relation's catalog entry, the constraints validated against its column
//! types, the tracks each track column may take (pushdown), and the final filter every result
//! passes, so a result never holds a tuple that breaks a constraint.

use std::cmp::Ordering;
use std::sync::Arc;

use crate::budget::{Budget, Spent};
pub use crate::error::ExtractError;

use scenalog_facts::catalog::{self, ColType, RelationSpec};
use scenalog_facts::relation::{Column, Constraint, RelationData, Request, Value};
use scenalog_facts::scene::is_vehicle_category;
use scenalog_facts::{Frame, Scene, TrackId};

/// Whether `category` (a track's AV2 category) matches a category constraint (an AV2 category or
/// the super-categories "VEHICLE", "CONSTRUCTION" and "ANY").
pub fn category_matches(category: &str, wanted: &str) -> bool {
    wanted == "ANY"
        || category == wanted
        || (wanted == "VEHICLE" && is_vehicle_category(category))
        || (wanted == "CONSTRUCTION" && scenalog_facts::scene::is_construction_category(category))
}

/// A validated request, with the tracks each track column may take.
#[derive(Debug, Clone)]
pub struct Query<'r> {
    /// The request.
    pub req: &'r Request,
    /// The relation's catalog entry.
    pub spec: &'static RelationSpec,
    /// Per column: for track columns with a category, equality or one-of constraint, which tracks (by
    /// `TrackId::index()`) may appear; `None` for any.
    allowed: Vec<Option<Vec<bool>>>,
    /// The (X, Y, T) triples a [`Constraint::Triples`] on column 0 demands (the smallest such
    /// list when there are several; every one is applied by [`Query::finish`]).
    demanded: Option<&'r [(TrackId, TrackId, Frame)]>,
    /// The limits the relation is computed under.
    pub budget: Budget,
    /// What the computation has used of the budget (shared by its threads).
    pub(crate) spent: Arc<Spent>,
}

/// Membership over the scene's `n` tracks (by [`TrackId::index`]) of `tracks`.
fn track_set(n: usize, tracks: impl IntoIterator<Item = TrackId>) -> Vec<bool> {
    let mut set = vec![false; n];
    for t in tracks {
        if let Some(s) = set.get_mut(t.index()) {
            *s = true;
        }
    }
    set
}

/// Whether `t` is in a [`track_set`].
fn in_set(set: &[bool], t: TrackId) -> bool {
    set.get(t.index()).copied().unwrap_or(false)
}

/// Narrows a column's allowed tracks (all `n` when none were set yet) to those `keep` accepts.
fn restrict(allowed: &mut Option<Vec<bool>>, n: usize, keep: impl Fn(TrackId) -> bool) {
    let mask = allowed.get_or_insert_with(|| vec![true; n]);
    for (i, m) in mask.iter_mut().enumerate() {
        *m = *m && keep(TrackId(i as u32));
    }
}

fn constraint_fits(c: &Constraint, ty: ColType) -> bool {
    match c {
        Constraint::Category(_) => ty == ColType::Track,
        Constraint::Eq(v) => value_fits(v, ty),
        Constraint::OneOf(vs) => vs.iter().all(|v| value_fits(v, ty)),
        // The next two columns' types are checked by `Query::new`.
        Constraint::Triples(_) => ty == ColType::Track,
        Constraint::Lt(_) | Constraint::Le(_) | Constraint::Gt(_) | Constraint::Ge(_) => {
            ty.is_numeric()
        }
    }
}

/// Whether value `v` may be compared with a column of type `ty` (numbers with numbers).
fn value_fits(v: &Value, ty: ColType) -> bool {
    matches!(
        (v, ty),
        (Value::Track(_), ColType::Track)
            | (Value::Time(_), ColType::Time)
            | (Value::Lane(_), ColType::Lane)
            | (Value::Str(_), ColType::Str)
            | (Value::Float(_), ColType::Float)
            | (Value::Int(_), ColType::Int)
            | (Value::Int(_), ColType::Float)
            | (Value::Float(_), ColType::Int)
            | (Value::Int(_), ColType::Time)
    )
}

impl<'r> Query<'r> {
    /// Validates `req` against the catalog and works out the allowed tracks per track column.
    pub fn new(scene: &Scene, req: &'r Request) -> Result<Query<'r>, ExtractError> {
        let spec = catalog::relation(&req.name)
            .ok_or_else(|| ExtractError::UnknownRelation(req.name.clone()))?;
        let mut allowed: Vec<Option<Vec<bool>>> = vec![None; spec.arity()];
        for (col, c) in &req.constraints {
            let Some(cs) = spec.columns.get(*col) else {
                return Err(ExtractError::NoSuchColumn {
                    relation: req.name.clone(),
                    arity: spec.arity(),
                    column: *col,
                });
            };
            let triple_cols = |col: usize| {
                spec.columns.get(col + 1).map(|c| c.ty) == Some(ColType::Track)
                    && spec.columns.get(col + 2).map(|c| c.ty) == Some(ColType::Time)
            };
            let unsorted = |c: &Constraint| match c {
                Constraint::Triples(ts) => ts.windows(2).any(|w| w[0] >= w[1]),
                _ => false,
            };
            if !constraint_fits(c, cs.ty)
                || (matches!(c, Constraint::Triples(_)) && !triple_cols(*col))
                || unsorted(c)
            {
                return Err(ExtractError::BadConstraint {
                    relation: req.name.clone(),
                    column: *col,
                    ty: cs.ty,
                    constraint: format!("{c:?}"),
                });
            }
            let keep: Option<Box<dyn Fn(TrackId) -> bool>> = match c {
                Constraint::Category(cat) => {
                    let cat = cat.clone();
                    Some(Box::new(move |t| {
                        category_matches(&scene.track(t).category, &cat)
                    }))
                }
                Constraint::Eq(Value::Track(x)) => {
                    let x = *x;
                    Some(Box::new(move |t| t == x))
                }
                Constraint::OneOf(vs) => {
                    let set = track_set(
                        scene.tracks.len(),
                        vs.iter().filter_map(|v| match v {
                            Value::Track(t) => Some(*t),
                            _ => None,
                        }),
                    );
                    Some(Box::new(move |t| in_set(&set, t)))
                }
                _ => None,
            };
            if let Some(keep) = keep {
                restrict(&mut allowed[*col], scene.tracks.len(), keep);
            }
            if let Constraint::Triples(ts) = c {
                // X and Y may only be the tracks the triples name.
                let n = scene.tracks.len();
                let xs = track_set(n, ts.iter().map(|t| t.0));
                let ys = track_set(n, ts.iter().map(|t| t.1));
                restrict(&mut allowed[*col], n, |t| in_set(&xs, t));
                restrict(&mut allowed[*col + 1], n, |t| in_set(&ys, t));
            }
        }
        let demanded = req
            .constraints
            .iter()
            .filter_map(|(c, k)| match k {
                Constraint::Triples(ts) if *c == 0 => Some(&ts[..]),
                _ => None,
            })
            .min_by_key(|ts| ts.len());
        Ok(Query {
            req,
            spec,
            allowed,
            demanded,
            budget: Budget::UNLIMITED,
            spent: Arc::default(),
        })
    }

    /// The (X, Y, T) triples of columns 0, 1, 2 that a [`Constraint::Triples`] demands, sorted
    /// and distinct; `None` when no such constraint is given (any triple may be asked for).
    pub fn demanded(&self) -> Option<&'r [(TrackId, TrackId, Frame)]> {
        self.demanded
    }

    /// Whether track `t` may appear in column `col`.
    pub fn allows_track(&self, col: usize, t: TrackId) -> bool {
        match self.allowed.get(col) {
            Some(Some(mask)) => mask.get(t.index()).copied().unwrap_or(false),
            _ => true,
        }
    }

    /// The tracks of `scene` that may appear in column `col`, in id order.
    pub fn tracks(&self, scene: &Scene, col: usize) -> impl Iterator<Item = TrackId> + '_ {
        let n = scene.tracks.len();
        (0..n as u32)
            .map(TrackId)
            .filter(move |&t| self.allows_track(col, t))
    }

    /// The tightest upper bound the constraints put on numeric column `col` (`Lt`/`Le`/`Eq`).
    pub fn upper_bound(&self, col: usize) -> Option<f64> {
        self.req
            .constraints
            .iter()
            .filter(|(c, _)| *c == col)
            .filter_map(|(_, c)| match c {
                Constraint::Lt(v) | Constraint::Le(v) => Some(*v),
                Constraint::Eq(Value::Float(v)) => Some(*v),
                Constraint::Eq(Value::Int(v)) => Some(*v as f64),
                _ => None,
            })
            .reduce(f64::min)
    }

    /// The frames the constraints on time column `col` allow (`Eq`, `Lt`, `Le`, `Gt`, `Ge`), as a
    /// range within `0..num_frames` (empty when no frame can satisfy them).
    pub fn frames(&self, col: usize, num_frames: usize) -> std::ops::Range<Frame> {
        let (mut lo, mut hi) = (0.0_f64, num_frames as f64);
        for (c, k) in &self.req.constraints {
            if let Constraint::Triples(ts) = k {
                // The frames of the demanded triples, when their time column is `col`.
                if *c + 2 == col {
                    let a = ts
                        .iter()
                        .map(|t| t.2)
                        .min()
                        .map_or(f64::INFINITY, f64::from);
                    let b = ts
                        .iter()
                        .map(|t| t.2)
                        .max()
                        .map_or(f64::NEG_INFINITY, f64::from);
                    lo = lo.max(a);
                    hi = hi.min(b + 1.0);
                }
                continue;
            }
            if *c != col {
                continue;
            }
            match k {
                Constraint::Eq(Value::Time(t)) => {
                    lo = lo.max(f64::from(*t));
                    hi = hi.min(f64::from(*t) + 1.0);
                }
                Constraint::Eq(Value::Int(t)) => {
                    lo = lo.max(*t as f64);
                    hi = hi.min(*t as f64 + 1.0);
                }
                Constraint::OneOf(vs) => {
                    // The smallest range holding every listed frame; `finish` drops the rest.
                    let ts = vs.iter().filter_map(|v| match v {
                        Value::Time(t) => Some(f64::from(*t)),
                        Value::Int(t) => Some(*t as f64),
                        _ => None,
                    });
                    let (a, b) = ts.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
                        (a.min(t), b.max(t))
                    });
                    lo = lo.max(a);
                    hi = hi.min(b + 1.0);
                }
                Constraint::Triples(_) => {}
                Constraint::Lt(v) => hi = hi.min(v.ceil()),
                Constraint::Le(v) => hi = hi.min(v.floor() + 1.0),
                Constraint::Gt(v) => lo = lo.max(v.floor() + 1.0),
                Constraint::Ge(v) => lo = lo.max(v.ceil()),
                _ => {}
            }
        }
        if lo.is_nan() || hi.is_nan() || hi <= lo {
            return 0..0;
        }
        let lo = lo.clamp(0.0, num_frames as f64) as Frame;
        let hi = hi.clamp(0.0, num_frames as f64) as Frame;
        lo..hi.max(lo)
    }

    /// The indices of a track's boxes (given their sorted frames) whose frame the constraints on
    /// time column `col` allow.
    pub fn box_range(
        &self,
        col: usize,
        num_frames: usize,
        frames: &[Frame],
    ) -> std::ops::Range<usize> {
        self.range_by(col, num_frames, frames, |&f| f)
    }

    /// [`Query::box_range`] over a track's boxes themselves (sorted by frame).
    pub fn boxes_range(
        &self,
        col: usize,
        num_frames: usize,
        boxes: &[scenalog_facts::TrackBox],
    ) -> std::ops::Range<usize> {
        self.range_by(col, num_frames, boxes, |b| b.frame)
    }

    /// The indices of `items` (sorted by `frame`) whose frame the constraints on time column
    /// `col` allow.
    fn range_by<T>(
        &self,
        col: usize,
        num_frames: usize,
        items: &[T],
        frame: impl Fn(&T) -> Frame,
    ) -> std::ops::Range<usize> {
        let r = self.frames(col, num_frames);
        let a = items.partition_point(|x| frame(x) < r.start);
        let b = items.partition_point(|x| frame(x) < r.end);
        a..b.max(a)
    }

    /// The string column `col` is fixed to, if an `Eq` constraint fixes it.
    pub fn fixed_str(&self, col: usize) -> Option<&str> {
        self.req.constraints.iter().find_map(|(c, k)| match k {
            Constraint::Eq(Value::Str(s)) if *c == col => Some(&**s),
            _ => None,
        })
    }

    /// Which rows of `data` satisfy every constraint of the request (column by column).
    fn rows_ok(&self, scene: &Scene, data: &RelationData) -> Vec<bool> {
        let n = data.len();
        let mut ok = vec![true; n];
        for (col, c) in &self.req.constraints {
            let Some(column) = data.columns.get(*col) else {
                return vec![false; n];
            };
            if let Constraint::Triples(ts) = c {
                let cols = (column, data.columns.get(col + 1), data.columns.get(col + 2));
                let (Column::Track(xs), Some(Column::Track(ys)), Some(Column::Time(fs))) = cols
                else {
                    return vec![false; n];
                };
                for (i, o) in ok.iter_mut().enumerate() {
                    *o = *o && ts.binary_search(&(xs[i], ys[i], fs[i])).is_ok();
                }
                continue;
            }
            match (column, c, self.allowed.get(*col)) {
                // Track constraints were turned into a mask over tracks up front.
                (
                    Column::Track(v),
                    Constraint::Category(_)
                    | Constraint::Eq(Value::Track(_))
                    | Constraint::OneOf(_),
                    Some(Some(mask)),
                ) => {
                    for (o, t) in ok.iter_mut().zip(v) {
                        *o = *o && mask.get(t.index()).copied().unwrap_or(false);
                    }
                }
                (Column::Float(v), Constraint::Lt(b), _) => {
                    ok.iter_mut().zip(v).for_each(|(o, x)| *o = *o && *x < *b)
                }
                (Column::Float(v), Constraint::Le(b), _) => {
                    ok.iter_mut().zip(v).for_each(|(o, x)| *o = *o && *x <= *b)
                }
                (Column::Float(v), Constraint::Gt(b), _) => {
                    ok.iter_mut().zip(v).for_each(|(o, x)| *o = *o && *x > *b)
                }
                (Column::Float(v), Constraint::Ge(b), _) => {
                    ok.iter_mut().zip(v).for_each(|(o, x)| *o = *o && *x >= *b)
                }
                (Column::Time(v), Constraint::OneOf(vs), _) => {
                    let mut set: Vec<Frame> = vs
                        .iter()
                        .filter_map(|x| match x {
                            Value::Time(t) => Some(*t),
                            Value::Int(t) => Frame::try_from(*t).ok(),
                            _ => None,
                        })
                        .collect();
                    set.sort_unstable();
                    for (o, t) in ok.iter_mut().zip(v) {
                        *o = *o && set.binary_search(t).is_ok();
                    }
                }
                (Column::Str(v), Constraint::Eq(Value::Str(w)), _) => ok
                    .iter_mut()
                    .zip(v)
                    .for_each(|(o, x)| *o = *o && **x == **w),
                _ => {
                    for (i, o) in ok.iter_mut().enumerate() {
                        *o = *o && column.get(i).is_some_and(|v| satisfies(scene, &v, c));
                    }
                }
            }
        }
        ok
    }

    /// Drops the rows that break a constraint and sorts the rest (lexicographically by column).
    pub fn finish(&self, scene: &Scene, mut data: RelationData) -> RelationData {
        let n = data.len();
        let mut keep: Vec<usize> = if self.req.constraints.is_empty() {
            (0..n).collect()
        } else {
            let ok = self.rows_ok(scene, &data);
            (0..n).filter(|&i| ok[i]).collect()
        };
        let (keys, packed_all) = sort_keys(&data);
        let sorted = keep.windows(2).all(|w| {
            keys[w[0]] < keys[w[1]]
                || (keys[w[0]] == keys[w[1]]
                    && !packed_all
                    && compare_rows(&data, w[0], w[1]) == Ordering::Less)
        });
        if sorted {
            // Already strictly increasing: nothing to sort or drop.
            if keep.len() == n {
                return data;
            }
        } else {
            keep.sort_unstable_by(|&a, &b| {
                keys[a].cmp(&keys[b]).then_with(|| {
                    if packed_all {
                        Ordering::Equal
                    } else {
                        compare_rows(&data, a, b)
                    }
                })
            });
            keep.dedup_by(|a, b| {
                keys[*a] == keys[*b]
                    && (packed_all || compare_rows(&data, *a, *b) == Ordering::Equal)
            });
        }
        data.columns = data.columns.iter().map(|c| take(c, &keep)).collect();
        data
    }
}

/// Whether value `v` satisfies constraint `c`.
pub fn satisfies(scene: &Scene, v: &Value, c: &Constraint) -> bool {
    let num = |v: &Value| match v {
        Value::Float(x) => Some(*x),
        Value::Int(x) => Some(*x as f64),
        Value::Time(x) => Some(*x as f64),
        _ => None,
    };
    match c {
        Constraint::Category(cat) => match v {
            Value::Track(t) => scene
                .tracks
                .get(t.index())
                .is_some_and(|tr| category_matches(&tr.category, cat)),
            _ => false,
        },
        Constraint::Eq(w) => match (num(v), num(w)) {
            (Some(a), Some(b)) => a == b,
            _ => v == w,
        },
        Constraint::OneOf(ws) => ws
            .iter()
            .any(|w| satisfies(scene, v, &Constraint::Eq(w.clone()))),
        // One value can only be checked against the triples' first column (X).
        Constraint::Triples(ts) => match v {
            Value::Track(t) => ts.iter().any(|x| x.0 == *t),
            _ => false,
        },
        Constraint::Lt(b) => num(v).is_some_and(|a| a < *b),
        Constraint::Le(b) => num(v).is_some_and(|a| a <= *b),
        Constraint::Gt(b) => num(v).is_some_and(|a| a > *b),
        Constraint::Ge(b) => num(v).is_some_and(|a| a >= *b),
    }
}

/// String columns with more distinct values than this are not packed into sort keys.
const STR_RANK_MAX: usize = 256;

/// An order-preserving 64-bit image of an f64 under `total_cmp`.
fn float_key(x: f64) -> u64 {
    let bits = x.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | (1 << 63)
    }
}

/// Per row, a 128-bit key that orders rows like [`compare_rows`] on the leading columns that fit
/// (tracks and times 32 bits, strings by rank 32 bits, lanes, ints and floats 64 bits), and
/// whether every column fit (then equal keys mean equal rows).
fn sort_keys(data: &RelationData) -> (Vec<u128>, bool) {
    let n = data.len();
    let mut keys = vec![0u128; n];
    let mut used = 0u32;
    for c in &data.columns {
        let width = match c {
            Column::Track(_) | Column::Time(_) | Column::Str(_) => 32,
            Column::Lane(_) | Column::Int(_) | Column::Float(_) => 64,
        };
        if used + width > 128 {
            return (keys, false);
        }
        used += width;
        let shift = 128 - used;
        match c {
            Column::Track(v) => {
                for (k, t) in keys.iter_mut().zip(v) {
                    *k |= u128::from(t.0) << shift;
                }
            }
            Column::Time(v) => {
                for (k, t) in keys.iter_mut().zip(v) {
                    *k |= u128::from(*t) << shift;
                }
            }
            Column::Lane(v) => {
                for (k, l) in keys.iter_mut().zip(v) {
                    *k |= u128::from((l.0 as u64) ^ (1 << 63)) << shift;
                }
            }
            Column::Int(v) => {
                for (k, x) in keys.iter_mut().zip(v) {
                    *k |= u128::from((*x as u64) ^ (1 << 63)) << shift;
                }
            }
            Column::Float(v) => {
                for (k, x) in keys.iter_mut().zip(v) {
                    *k |= u128::from(float_key(*x)) << shift;
                }
            }
            Column::Str(v) => {
                // Rank among the distinct values (closed columns hold a handful).
                let mut distinct: Vec<&std::sync::Arc<str>> = Vec::new();
                for x in v {
                    let seen = distinct.iter().any(|d: &&std::sync::Arc<str>| {
                        std::sync::Arc::ptr_eq(d, x) || d.as_ref() == x.as_ref()
                    });
                    if !seen {
                        if distinct.len() == STR_RANK_MAX {
                            // An open string column: order by the leading columns only.
                            return (keys, false);
                        }
                        distinct.push(x);
                    }
                }
                distinct.sort();
                for (k, x) in keys.iter_mut().zip(v) {
                    let rank = distinct.binary_search(&x).unwrap_or(0) as u128;
                    *k |= rank << shift;
                }
            }
        }
    }
    (keys, true)
}

fn compare_rows(data: &RelationData, a: usize, b: usize) -> Ordering {
    for c in &data.columns {
        let o = match c {
            Column::Track(v) => v[a].cmp(&v[b]),
            Column::Time(v) => v[a].cmp(&v[b]),
            Column::Lane(v) => v[a].cmp(&v[b]),
            Column::Str(v) => v[a].cmp(&v[b]),
            Column::Float(v) => v[a].total_cmp(&v[b]),
            Column::Int(v) => v[a].cmp(&v[b]),
        };
        if o != Ordering::Equal {
            return o;
        }
    }
    Ordering::Equal
}

fn take(c: &Column, idx: &[usize]) -> Column {
    match c {
        Column::Track(v) => Column::Track(idx.iter().map(|&i| v[i]).collect()),
        Column::Time(v) => Column::Time(idx.iter().map(|&i| v[i]).collect()),
        Column::Lane(v) => Column::Lane(idx.iter().map(|&i| v[i]).collect()),
        Column::Str(v) => Column::Str(idx.iter().map(|&i| v[i].clone()).collect()),
        Column::Float(v) => Column::Float(idx.iter().map(|&i| v[i]).collect()),
        Column::Int(v) => Column::Int(idx.iter().map(|&i| v[i]).collect()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scenalog_facts::LaneId;
    use std::sync::Arc;

    fn rows(d: &RelationData) -> Vec<Vec<Value>> {
        (0..d.len()).filter_map(|i| d.row(i)).collect()
    }

    #[test]
    fn finish_sorts_like_a_row_comparison_and_drops_duplicates() {
        let scene = scenalog_testkit::SceneBuilder::new(3).build();
        let strs: Vec<Arc<str>> = ["b", "a", "c"].iter().map(|s| Arc::from(*s)).collect();
        // Pseudo-random rows with negative numbers, repeated keys and duplicates.
        let mut state = 12345u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as i64
        };
        let n = 500;
        let (mut lanes, mut ints, mut ss, mut fs, mut ts) =
            (vec![], vec![], vec![], vec![], vec![]);
        for _ in 0..n {
            lanes.push(LaneId(next() % 5 - 2));
            ints.push(next() % 3 - 1);
            ss.push(strs[(next() % 3) as usize].clone());
            fs.push(((next() % 7) - 3) as f64 * 0.5);
            ts.push((next() % 4) as u32);
        }
        for columns in [
            vec![
                Column::Lane(lanes.clone()),
                Column::Int(ints.clone()),
                Column::Str(ss.clone()),
                Column::Float(fs.clone()),
            ],
            vec![
                Column::Time(ts.clone()),
                Column::Str(ss.clone()),
                Column::Int(ints.clone()),
            ],
            vec![
                Column::Float(fs.clone()),
                Column::Lane(lanes.clone()),
                Column::Time(ts.clone()),
                Column::Int(ints.clone()),
            ],
        ] {
            let data = RelationData {
                name: "x".into(),
                columns,
            };
            let req = Request::all("present");
            let q = Query::new(&scene, &req).expect("query");
            let got = rows(&q.finish(&scene, data.clone()));
            let mut idx: Vec<usize> = (0..n).collect();
            idx.sort_by(|&a, &b| compare_rows(&data, a, b));
            idx.dedup_by(|a, b| compare_rows(&data, *a, *b) == Ordering::Equal);
            let want: Vec<Vec<Value>> = idx.iter().filter_map(|&i| data.row(i)).collect();
            assert_eq!(got, want);
            assert!(got.len() < n);
        }
    }
}
