//! Pairwise relations between objects: `near`, `direction`, `facing` ([`spatial`]),
//! `heading_relative`, `heading_toward`, `crossing` ([`motion`]), `same_lane`, `following`,
//! `road_side` ([`lanes`]); RefAV's definitions where they differ: `refav_direction`
//! ([`refav`]).
//!
//! Every pair relation holds only for two different objects present at the same frame whose
//! ground rectangles are at most [`PAIR_MAX_DISTANCE_M`] apart (`near`'s distance). Candidates come
//! from a per-frame `rstar` R-tree over the boxes' bounding boxes ([`index::PairIndex`]); the exact
//! distance is `parry2d`'s rectangle distance ([`index::box_distance`]).
//!
//! Geometry conventions: relations about boxes (`near`, `direction`, `facing`) use the raw
//! annotated box (centre and heading); relations about motion (`heading_relative`,
//! `heading_toward`, `crossing`, `following`) use the smoothed positions and velocities of
//! [`Kinematics`], in X's frame (X's smoothed position, X's box heading).
//!
//! Pushdown: a request's constraints restrict the work, not only the output. `Category` and
//! `Eq(Track)` on X or Y restrict the tracks visited (a small Y set is looked up directly instead of
//! through the R-tree), `Eq`/`Lt`/`Le`/`Gt`/`Ge` on T restrict the frames, an upper bound on a
//! distance column shrinks the search radius, a fixed string (direction, heading, side) skips
//! the other values, and `Triples` (a tuple-level demand, [`Query::demanded`]) looks up exactly
//! the demanded pairs at the demanded frames. Every result then passes [`Query::finish`] (all
//! constraints, sorted rows).
//!
//! API: build a [`PairContext`] (the relation table builds one from an [`Extractor`]) and ask
//! [`crate::pair_relation`]`(&ctx, &request)`; the relation functions are the crate's own, listed
//! in [`crate::table`].

pub mod index;
pub mod lanes;
pub mod motion;
pub mod refav;
pub mod spatial;

use std::ops::Range;
use std::sync::Arc;

use scenalog_facts::{Frame, Scene, TrackId};

use crate::cache::Extractor;
use crate::kinematics::Kinematics;
use crate::lanes::LaneAssignment;
use crate::map::MapIndex;
use crate::query::Query;
use crate::thresholds::PAIR_MAX_DISTANCE_M;

pub use index::{box_distance, FrameBoxes, ObjBox, PairIndex, PairList, PairRow, Region};

/// Everything the pair relations read: the scene, its kinematics, lane assignment, prepared map
/// and per-frame box index. Plain references, so it is `Sync` and cheap to build per request.
#[derive(Debug, Clone, Copy)]
pub struct PairContext<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// Kinematics of every track.
    pub kin: &'a Kinematics,
    /// Lane of every track box.
    pub lanes: &'a LaneAssignment,
    /// The map prepared for queries (lane chains, road sides).
    pub map: &'a MapIndex,
    /// Object boxes per frame in R-trees.
    pub index: &'a PairIndex,
}

impl<'a> PairContext<'a> {
    /// A context from its parts.
    pub fn new(
        scene: &'a Scene,
        kin: &'a Kinematics,
        lanes: &'a LaneAssignment,
        map: &'a MapIndex,
        index: &'a PairIndex,
    ) -> PairContext<'a> {
        PairContext {
            scene,
            kin,
            lanes,
            map,
            index,
        }
    }

    /// The context of an extractor's scene, with its box index (e.g. [`pair_index`]`(ex)`).
    pub fn of(ex: &'a Extractor, index: &'a PairIndex) -> PairContext<'a> {
        PairContext::new(
            ex.scene(),
            ex.kinematics(),
            ex.lanes(),
            ex.map_index(),
            index,
        )
    }

    /// The map lane index of track `t`'s box `k`, if it is in a lane.
    pub fn lane_index(&self, t: TrackId, k: usize) -> Option<usize> {
        let lanes = self.index.lane_indices(self.lanes, &self.scene.map);
        lanes
            .get(t.index())?
            .get(k)
            .copied()
            .flatten()
            .map(|i| i as usize)
    }
}

/// The per-frame box index of the extractor's scene, built once and shared (through
/// [`Extractor::cached`]).
pub fn pair_index(ex: &Extractor) -> Arc<PairIndex> {
    ex.cached(|ex| PairIndex::new(ex.scene()))
}

/// The frames a query's constraints on column `col` (a time column) allow, as a range clamped to
/// the log's frames.
pub(crate) fn frame_range(q: &Query, col: usize, num_frames: usize) -> Range<Frame> {
    q.frames(col, num_frames)
}

/// The search radius for a relation whose distance column is `col` (if any): the request's upper
/// bound on it, never above [`PAIR_MAX_DISTANCE_M`].
pub(crate) fn radius(q: &Query, col: Option<usize>) -> f64 {
    col.and_then(|c| q.upper_bound(c))
        .map_or(PAIR_MAX_DISTANCE_M, |b| b.min(PAIR_MAX_DISTANCE_M))
}

/// Candidate pairs visited between two checks of the budget's clock and count.
const BUDGET_STRIDE: usize = 256;

/// Y sets at most this large are looked up directly per X instead of through the R-tree.
const DIRECT_LOOKUP_MAX: usize = 16;

/// The distance between the two boxes of a visited pair, computed when first asked for (most
/// relations test their own condition first) and shared through the pair list.
#[derive(Debug)]
pub struct PairDistance<'b> {
    row: &'b PairRow,
    x: &'b ObjBox,
    y: &'b ObjBox,
    radius: f64,
}

impl PairDistance<'_> {
    /// The ground-rectangle distance ([`box_distance`]).
    pub fn value(&self) -> f64 {
        self.row.distance(self.x, self.y)
    }

    /// Whether the boxes are within the search radius. Cheap when the centres already are (the
    /// rectangle distance never exceeds the centre distance).
    pub fn within(&self) -> bool {
        self.row.centres <= self.radius || self.value() <= self.radius
    }
}

/// A row's sort key: `(X, Y, T, rank)`, where `rank` orders the row's string value by its text
/// ([`text_ranks`]; 0 when there is none). Keys are unique within a relation, and rows sorted by
/// them are in [`Query::finish`]'s order, so its sort only confirms it.
pub(crate) type RowKey = (TrackId, TrackId, Frame, u8);

fn packed(k: RowKey) -> u128 {
    (u128::from(k.0 .0) << 96)
        | (u128::from(k.1 .0) << 64)
        | (u128::from(k.2) << 32)
        | u128::from(k.3)
}

/// Calls `f(frame, x, y, distance, out)` for every pair of different boxes at a frame the query
/// allows, X allowed in column 0, Y in column 1, whose rectangles may be at most `radius` apart;
/// `f` must check [`PairDistance::within`] (or the value) itself. X tracks in parallel;
/// pairs are visited in (X, Y, T) order and the rows come back sorted by `key` (so `f` should push
/// several rows of one pair in key order): deterministic.
pub(crate) fn for_each_pair<T: Send>(
    ctx: &PairContext,
    q: &Query,
    radius: f64,
    key: impl Fn(&T) -> RowKey + Sync,
    f: impl Fn(Frame, &ObjBox, &ObjBox, &PairDistance, &mut Vec<T>) + Sync,
) -> Vec<T> {
    for_each_pair_searching(ctx, q, (radius, radius), None, key, f)
}

/// [`for_each_pair`], visiting only the pairs whose centres are at most `search` plus both half
/// diagonals apart (`search` at most `radius`; [`PairDistance::within`] still tests `radius`):
/// for a relation whose own condition bounds the distance more tightly than `radius` does, so a
/// dense log looks at fewer candidates per box.
/// When `region` is given, the R-tree is asked for the boxes meeting `region(x)` instead
/// ([`PairIndex::rows_in`]); it must hold every Y the relation can accept.
pub(crate) fn for_each_pair_searching<T: Send>(
    ctx: &PairContext,
    q: &Query,
    (radius, search): (f64, f64),
    region: Option<&Region<'_>>,
    key: impl Fn(&T) -> RowKey + Sync,
    f: impl Fn(Frame, &ObjBox, &ObjBox, &PairDistance, &mut Vec<T>) + Sync,
) -> Vec<T> {
    let frames = frame_range(q, 2, ctx.index.num_frames());
    let search = search.min(radius);
    let visit = Visit {
        frames,
        radius,
        search,
        at_frames: true,
        region,
    };
    visit_pairs(ctx, q, visit, key, f)
}

/// How [`visit_pairs`] looks for candidates.
struct Visit<'r> {
    /// The frames visited.
    frames: Range<Frame>,
    /// What [`PairDistance::within`] tests.
    radius: f64,
    /// The candidate search radius (centre distance less both half diagonals).
    search: f64,
    /// Whether a tuple-level demand fixes the frames too, not only the pairs.
    at_frames: bool,
    /// Where Y may be around X's box, if the relation knows.
    region: Option<&'r Region<'r>>,
}

/// Most rows the scene's cached list of every pair ([`PairIndex::all_pairs`]) may hold, whatever
/// the budget: 4 M rows of 32 bytes (128 MB). A denser log visits its pairs per X track instead.
pub const ALL_PAIRS_MAX_ROWS: usize = 4_000_000;

/// Where a query's candidate pairs come from.
enum PairSource<'c> {
    /// The scene's cached list of every pair within [`PAIR_MAX_DISTANCE_M`].
    Cached(&'c PairList),
    /// Computed per X track as it is visited and dropped after (never the whole list at once):
    /// the X tracks, and the Y tracks to look up directly when they are few.
    PerX {
        xs: Vec<TrackId>,
        direct: Option<Vec<TrackId>>,
    },
    /// A tuple-level demand ([`Query::demanded`]), per X track (ascending): the demanded
    /// (Y, frame) pairs, looked up box by box; with `at_frames` false, each demanded (X, Y) pair
    /// at every frame of the range instead.
    Demanded {
        per_x: Vec<(TrackId, Vec<(TrackId, Frame)>)>,
        at_frames: bool,
    },
}

/// A tuple-level demand's triples grouped by X (they are sorted, so X ascending, each X's
/// (Y, frame) pairs sorted), keeping the tracks the query allows.
fn demanded_per_x(
    q: &Query,
    triples: &[(TrackId, TrackId, Frame)],
) -> Vec<(TrackId, Vec<(TrackId, Frame)>)> {
    let mut per_x: Vec<(TrackId, Vec<(TrackId, Frame)>)> = Vec::new();
    for &(x, y, f) in triples {
        if !q.allows_track(0, x) || !q.allows_track(1, y) {
            continue;
        }
        match per_x.last_mut() {
            Some((lx, at)) if *lx == x => at.push((y, f)),
            _ => per_x.push((x, vec![(y, f)])),
        }
    }
    per_x
}

/// The pairs a query may need: the scene's cached list of every pair within
/// [`PAIR_MAX_DISTANCE_M`] when it exists or the query is unrestricted (the full relation needs it
/// anyway) and the list fits its cap (the request's tuple budget, at most
/// [`ALL_PAIRS_MAX_ROWS`]); else the pairs of the query's tracks, frames and radius, per X track
/// (pushdown, and memory bounded by one X's pairs a thread).
fn pair_source<'c>(
    ctx: &'c PairContext,
    q: &Query,
    frames: &Range<Frame>,
    at_frames: bool,
) -> PairSource<'c> {
    if let Some(triples) = q.demanded() {
        return PairSource::Demanded {
            per_x: demanded_per_x(q, triples),
            at_frames,
        };
    }
    if let Some(all) = ctx.index.all_pairs_if_built() {
        return PairSource::Cached(all);
    }
    let n = ctx.scene.tracks.len();
    let xs: Vec<TrackId> = q.tracks(ctx.scene, 0).collect();
    let ys: Vec<TrackId> = q.tracks(ctx.scene, 1).collect();
    let whole = frames.start == 0 && frames.end as usize >= ctx.index.num_frames();
    if xs.len() == n && ys.len() == n && whole && !ctx.index.all_pairs_too_large() {
        let cap = q.budget.max_tuples.min(ALL_PAIRS_MAX_ROWS);
        if let Some(all) = ctx.index.all_pairs(ctx.kin, cap) {
            return PairSource::Cached(all);
        }
    }
    let direct = (ys.len() <= DIRECT_LOOKUP_MAX).then_some(ys);
    PairSource::PerX { xs, direct }
}

/// [`for_each_pair`] over the given frames, whatever the query's time constraints: a tuple-level
/// demand ([`Query::demanded`]) restricts the (X, Y) pairs visited, not their frames (for
/// relations that follow a pair over time, like `crossing`).
pub(crate) fn for_each_pair_in<T: Send>(
    ctx: &PairContext,
    q: &Query,
    frames: Range<Frame>,
    radius: f64,
    key: impl Fn(&T) -> RowKey + Sync,
    f: impl Fn(Frame, &ObjBox, &ObjBox, &PairDistance, &mut Vec<T>) + Sync,
) -> Vec<T> {
    let visit = Visit {
        frames,
        radius,
        search: radius,
        at_frames: false,
        region: None,
    };
    visit_pairs(ctx, q, visit, key, f)
}

/// The pair visit of [`for_each_pair_searching`] and [`for_each_pair_in`], as `visit` says.
fn visit_pairs<T: Send>(
    ctx: &PairContext,
    q: &Query,
    visit: Visit<'_>,
    key: impl Fn(&T) -> RowKey + Sync,
    f: impl Fn(Frame, &ObjBox, &ObjBox, &PairDistance, &mut Vec<T>) + Sync,
) -> Vec<T> {
    use rayon::prelude::*;
    let Visit {
        frames,
        radius,
        search,
        at_frames,
        region,
    } = visit;
    if radius.is_nan() || radius < 0.0 || search.is_nan() || search < 0.0 || frames.is_empty() {
        return Vec::new();
    }
    // One X track's candidate rows through `f`, under the budget.
    let visit_x = |xt: TrackId, rows: &[PairRow]| -> Vec<T> {
        let mut out = Vec::new();
        // The budget: once passed (here or on another thread) every X stops; the clock is
        // read every BUDGET_STRIDE candidate pairs.
        if q.spent.over() {
            return out;
        }
        for (i, r) in rows.iter().enumerate() {
            if i % BUDGET_STRIDE == BUDGET_STRIDE - 1
                && (q.spent.tick(&q.budget) || q.spent.would_pass(&q.budget, out.len()))
            {
                q.spent.add(&q.budget, out.len());
                return Vec::new();
            }
            if !frames.contains(&r.frame) || !q.allows_track(1, r.y) {
                continue;
            }
            let Some(fb) = ctx.index.frame(ctx.kin, r.frame) else {
                continue;
            };
            let (Some(x), Some(y)) = (fb.boxes.get(r.xi as usize), fb.boxes.get(r.yi as usize))
            else {
                continue;
            };
            debug_assert!(x.track == xt && y.track == r.y);
            // Beyond this the rectangles cannot come within the search radius.
            if r.centres - x.reach - y.reach > search {
                continue;
            }
            let d = PairDistance {
                row: r,
                x,
                y,
                radius,
            };
            f(r.frame, x, y, &d, &mut out);
        }
        if q.spent.add(&q.budget, out.len()) {
            return Vec::new();
        }
        // Already in order when `f` pushes in key order: then this only checks it.
        out.sort_unstable_by_key(|r| packed(key(r)));
        out
    };
    let per_x: Vec<Vec<T>> = match pair_source(ctx, q, &frames, at_frames) {
        PairSource::Cached(list) => list
            .per_x
            .par_iter()
            .filter(|(x, _)| q.allows_track(0, *x))
            .map(|(xt, rows)| visit_x(*xt, rows))
            .collect(),
        PairSource::PerX { xs, direct } => {
            let keep_y = |t: TrackId| q.allows_track(1, t);
            xs.par_iter()
                .map(|&xt| {
                    if q.spent.over() {
                        return Vec::new();
                    }
                    let rows = ctx.index.rows_in(
                        ctx.kin,
                        xt,
                        &keep_y,
                        direct.as_deref(),
                        &frames,
                        search,
                        region,
                    );
                    visit_x(xt, &rows)
                })
                .collect()
        }
        PairSource::Demanded { per_x, at_frames } => per_x
            .par_iter()
            .map(|(xt, at)| {
                if q.spent.over() {
                    return Vec::new();
                }
                let rows = if at_frames {
                    ctx.index.rows_at(ctx.kin, *xt, at, &frames, search)
                } else {
                    let mut ys: Vec<TrackId> = at.iter().map(|a| a.0).collect();
                    ys.dedup();
                    let keep_y = |t: TrackId| ys.binary_search(&t).is_ok();
                    ctx.index
                        .rows_of(ctx.kin, *xt, &keep_y, Some(&ys), &frames, search)
                };
                visit_x(*xt, &rows)
            })
            .collect(),
    };
    per_x.into_iter().flatten().collect()
}

/// For each value of a closed column, its rank among the values in text order.
pub(crate) fn text_ranks(all: &[&str]) -> Vec<u8> {
    all.iter()
        .map(|a| all.iter().filter(|b| *b < a).count() as u8)
        .collect()
}

/// The string values of a closed column the query asks for: the fixed one if a constraint fixes
/// it (and it is one of `all`), else all of them.
pub(crate) fn wanted<'s>(q: &Query, col: usize, all: &[&'s str]) -> Vec<&'s str> {
    match q.fixed_str(col) {
        Some(s) => all.iter().copied().filter(|a| *a == s).collect(),
        None => all.to_vec(),
    }
}

/// The shared string values of a closed column, so each row costs a pointer.
pub(crate) fn str_values(all: &[&str]) -> Vec<Arc<str>> {
    all.iter().map(|s| Arc::from(*s)).collect()
}
