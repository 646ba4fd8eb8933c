//! Object boxes per frame in `rstar` R-trees, and the ground-rectangle distance between two boxes
//! (with `parry2d`).

use std::ops::Range;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::OnceLock;

use parry2d::math::{Pose, Vector};
use parry2d::query::details::distance_cuboid_cuboid;
use parry2d::shape::Cuboid;
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{RTree, AABB};
use scenalog_facts::{Frame, Scene, TrackId};

use scenalog_facts::VectorMap;

use crate::kinematics::Kinematics;
use crate::lanes::LaneAssignment;
use crate::thresholds::PAIR_MAX_DISTANCE_M;

/// One object's box at one frame, in the ground plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObjBox {
    /// The track.
    pub track: TrackId,
    /// The box's index in the track (`Track::boxes`, `TrackKinematics` entries).
    pub k: usize,
    /// Raw city-frame centre (x, y), metres.
    pub center: [f64; 2],
    /// Box heading in the city frame, radians.
    pub yaw: f64,
    /// Cosine of `yaw`.
    pub cos: f64,
    /// Sine of `yaw`.
    pub sin: f64,
    /// Half the box length (along its heading), metres.
    pub half_len: f64,
    /// Half the box width, metres.
    pub half_wid: f64,
    /// Half the box diagonal: no point of the box is farther from its centre.
    pub reach: f64,
}

impl ObjBox {
    /// A city-frame point in this box's frame: (forward, left) of the centre, metres.
    pub fn to_local(&self, p: [f64; 2]) -> [f64; 2] {
        let (dx, dy) = (p[0] - self.center[0], p[1] - self.center[1]);
        [
            dx * self.cos + dy * self.sin,
            -dx * self.sin + dy * self.cos,
        ]
    }

    /// A city-frame vector (e.g. a velocity) in this box's frame: (forward, left).
    pub fn vec_to_local(&self, v: [f64; 2]) -> [f64; 2] {
        [
            v[0] * self.cos + v[1] * self.sin,
            -v[0] * self.sin + v[1] * self.cos,
        ]
    }

    /// Axis-aligned bounding box of the ground rectangle: (min, max).
    pub fn aabb(&self) -> ([f64; 2], [f64; 2]) {
        let ex = self.half_len * self.cos.abs() + self.half_wid * self.sin.abs();
        let ey = self.half_len * self.sin.abs() + self.half_wid * self.cos.abs();
        (
            [self.center[0] - ex, self.center[1] - ey],
            [self.center[0] + ex, self.center[1] + ey],
        )
    }
}

/// Distance between the ground rectangles of two boxes, metres (0 when they overlap or touch).
///
/// Computed by `parry2d` (single precision) in the frame of the box of the lower track id, so the
/// value does not depend on the argument order and city coordinates never lose precision.
pub fn box_distance(a: &ObjBox, b: &ObjBox) -> f64 {
    let (a, b) = if (a.track, a.k) <= (b.track, b.k) {
        (a, b)
    } else {
        (b, a)
    };
    let rel = a.to_local(b.center);
    let c1 = Cuboid::new(Vector::new(a.half_len as f32, a.half_wid as f32));
    let c2 = Cuboid::new(Vector::new(b.half_len as f32, b.half_wid as f32));
    let pos12 = Pose::new(
        Vector::new(rel[0] as f32, rel[1] as f32),
        (b.yaw - a.yaw) as f32,
    );
    f64::from(distance_cuboid_cuboid(&pos12, &c1, &c2))
}

type Entry = GeomWithData<Rectangle<[f64; 2]>, u32>;

/// The part of X's surroundings (an envelope (min, max) in city coordinates, given X's box) where
/// a relation's Y may be: its bounding box meets the envelope.
pub type Region<'a> = dyn Fn(&ObjBox) -> ([f64; 2], [f64; 2]) + Sync + 'a;

/// The boxes of one frame, sorted by track id, and an R-tree over their bounding boxes.
#[derive(Debug)]
pub struct FrameBoxes {
    /// Boxes present at the frame, ascending track id.
    pub boxes: Vec<ObjBox>,
    tree: RTree<Entry>,
}

impl FrameBoxes {
    /// The box of `track` at this frame, if present.
    pub fn of(&self, track: TrackId) -> Option<&ObjBox> {
        self.position(track).map(|i| &self.boxes[i])
    }

    /// The position of `track`'s box in `boxes`, if present.
    pub fn position(&self, track: TrackId) -> Option<usize> {
        self.boxes.binary_search_by_key(&track, |b| b.track).ok()
    }

    /// Indices (into `boxes`) of the boxes whose bounding box comes within `radius` of `b`'s
    /// bounding box: a superset of the boxes within `radius` of `b` by rectangle distance.
    pub fn candidates(&self, b: &ObjBox, radius: f64) -> impl Iterator<Item = usize> + '_ {
        let (lo, hi) = b.aabb();
        self.candidates_in((
            [lo[0] - radius, lo[1] - radius],
            [hi[0] + radius, hi[1] + radius],
        ))
    }

    /// Indices (into `boxes`) of the boxes whose bounding box meets the envelope (min, max).
    pub fn candidates_in(&self, env: ([f64; 2], [f64; 2])) -> impl Iterator<Item = usize> + '_ {
        self.tree
            .locate_in_envelope_intersecting(AABB::from_corners(env.0, env.1))
            .map(|e| e.data as usize)
    }
}

/// Per-frame boxes of a scene; each frame's R-tree is built on first use. `Sync`.
#[derive(Debug)]
pub struct PairIndex {
    /// Per frame: (track, box index) of every box present, ascending track id.
    present: Vec<Vec<(TrackId, usize)>>,
    /// Half length, half width per track box: `sizes[track][k]`.
    sizes: Vec<Vec<[f64; 2]>>,
    frames: Vec<OnceLock<FrameBoxes>>,
    /// Map lane index of every track box (`lanes[track][k]`), built on first use.
    lanes: OnceLock<Vec<Vec<Option<u32>>>>,
    /// Every pair that may be within [`PAIR_MAX_DISTANCE_M`] at every frame, built on first use;
    /// `None` when it would pass its cap (see [`PairIndex::all_pairs`]).
    all: OnceLock<Option<PairList>>,
}

/// One pair of boxes at one frame whose rectangles may be within the list's radius: Y, the frame,
/// the two boxes' positions in the frame's [`FrameBoxes::boxes`], the distance between their
/// centres, and their rectangle distance once someone needed it (computed at most once per
/// thread race, always to the same value).
#[derive(Debug)]
pub struct PairRow {
    /// The other track.
    pub y: TrackId,
    /// The frame.
    pub frame: Frame,
    /// X's box in the frame's boxes.
    pub xi: u32,
    /// Y's box in the frame's boxes.
    pub yi: u32,
    /// Distance between the two centres, metres (never less than the rectangle distance).
    pub centres: f64,
    dist: AtomicU64,
}

/// `PairRow::dist` before it is computed (a NaN no distance computation returns).
const UNKNOWN: u64 = u64::MAX;

impl PairRow {
    /// The rectangle distance of the pair (`x`, `y` its boxes), computed on first use.
    pub fn distance(&self, x: &ObjBox, y: &ObjBox) -> f64 {
        let bits = self.dist.load(Ordering::Relaxed);
        if bits != UNKNOWN {
            return f64::from_bits(bits);
        }
        let d = box_distance(x, y);
        self.dist.store(d.to_bits(), Ordering::Relaxed);
        d
    }
}

impl Clone for PairRow {
    fn clone(&self) -> Self {
        PairRow {
            dist: AtomicU64::new(self.dist.load(Ordering::Relaxed)),
            ..*self
        }
    }
}

/// The row of boxes `xi` and `yi` of frame `fb`, unless their centres are too far apart for the
/// rectangles to come within `radius`.
fn pair_row(fb: &FrameBoxes, xi: usize, yi: usize, frame: Frame, radius: f64) -> Option<PairRow> {
    let (x, y) = (fb.boxes.get(xi)?, fb.boxes.get(yi)?);
    let (dx, dy) = (y.center[0] - x.center[0], y.center[1] - x.center[1]);
    let d2 = dx * dx + dy * dy;
    // Beyond this the rectangles cannot come within the radius.
    let max = radius + x.reach + y.reach;
    if d2 > max * max {
        return None;
    }
    Some(PairRow {
        y: y.track,
        frame,
        xi: xi as u32,
        yi: yi as u32,
        centres: d2.sqrt(),
        dist: AtomicU64::new(UNKNOWN),
    })
}

/// Pairs of boxes whose rectangles may be at most `radius` apart (their centres are at most
/// `radius` plus both half diagonals apart), grouped by X (ascending), each X's rows sorted by
/// (Y, frame).
#[derive(Debug, Clone, Default)]
pub struct PairList {
    /// The largest distance listed.
    pub radius: f64,
    /// Per X track: its pairs.
    pub per_x: Vec<(TrackId, Vec<PairRow>)>,
}

impl PairIndex {
    /// Prepares the index of `scene` (cheap: the R-trees are built lazily per frame).
    pub fn new(scene: &Scene) -> PairIndex {
        let n = scene.num_frames();
        let mut present: Vec<Vec<(TrackId, usize)>> = vec![Vec::new(); n];
        for t in &scene.tracks {
            for (k, b) in t.boxes.iter().enumerate() {
                if let Some(p) = present.get_mut(b.frame as usize) {
                    p.push((t.id, k));
                }
            }
        }
        for p in &mut present {
            p.sort_unstable();
            p.dedup_by_key(|e| e.0);
        }
        let sizes = scene
            .tracks
            .iter()
            .map(|t| {
                t.boxes
                    .iter()
                    .map(|b| [0.5 * b.size[0].max(0.0), 0.5 * b.size[1].max(0.0)])
                    .collect()
            })
            .collect();
        PairIndex {
            present,
            sizes,
            frames: (0..n).map(|_| OnceLock::new()).collect(),
            lanes: OnceLock::new(),
            all: OnceLock::new(),
        }
    }

    /// Number of frames.
    pub fn num_frames(&self) -> usize {
        self.frames.len()
    }

    /// The boxes of `frame` (empty for a frame outside the log).
    pub fn frame(&self, kin: &Kinematics, frame: Frame) -> Option<&FrameBoxes> {
        let cell = self.frames.get(frame as usize)?;
        Some(cell.get_or_init(|| self.build(kin, frame as usize)))
    }

    /// The map lane index of every track box (`[track][k]`), from the lane assignment's ids
    /// (computed once; later calls return the first answer).
    pub fn lane_indices(&self, lanes: &LaneAssignment, map: &VectorMap) -> &[Vec<Option<u32>>] {
        self.lanes.get_or_init(|| {
            lanes
                .lanes
                .iter()
                .map(|t| {
                    t.iter()
                        .map(|l| l.and_then(|id| map.lane_index(id)).map(|i| i as u32))
                        .collect()
                })
                .collect()
        })
    }

    /// Every pair that may be within [`PAIR_MAX_DISTANCE_M`] at every frame (computed once, in
    /// parallel; rectangle distances are filled in as relations need them), or `None` when the
    /// list would hold more than `max_rows` rows: then it is never kept (the work stops as soon as
    /// the count passes the cap) and callers visit the pairs per X track instead
    /// ([`PairIndex::rows_of`]), so a dense log costs time, not memory. The first caller's cap
    /// decides; later calls return the first answer.
    pub fn all_pairs(&self, kin: &Kinematics, max_rows: usize) -> Option<&PairList> {
        self.all
            .get_or_init(|| {
                use rayon::prelude::*;
                let xs: Vec<TrackId> = (0..kin.tracks.len() as u32).map(TrackId).collect();
                let frames = 0..self.num_frames() as Frame;
                let count = AtomicUsize::new(0);
                let per_x: Vec<(TrackId, Vec<PairRow>)> = xs
                    .par_iter()
                    .map(|&xt| {
                        if count.load(Ordering::Relaxed) > max_rows {
                            return (xt, Vec::new());
                        }
                        let rows =
                            self.rows_of(kin, xt, &|_| true, None, &frames, PAIR_MAX_DISTANCE_M);
                        count.fetch_add(rows.len(), Ordering::Relaxed);
                        (xt, rows)
                    })
                    .collect();
                (count.load(Ordering::Relaxed) <= max_rows).then_some(PairList {
                    radius: PAIR_MAX_DISTANCE_M,
                    per_x,
                })
            })
            .as_ref()
    }

    /// [`PairIndex::all_pairs`] if it has been computed and kept.
    pub fn all_pairs_if_built(&self) -> Option<&PairList> {
        self.all.get().and_then(Option::as_ref)
    }

    /// Whether [`PairIndex::all_pairs`] was tried and found larger than its cap.
    pub fn all_pairs_too_large(&self) -> bool {
        matches!(self.all.get(), Some(None))
    }

    /// The pairs (X in `xs`, Y passing `keep_y`, X ≠ Y) that may be at most `radius` apart at the given
    /// frames: through each frame's R-tree, or by looking up each of `direct_ys` when given (a
    /// small Y set). X tracks in parallel; deterministic.
    pub fn pairs(
        &self,
        kin: &Kinematics,
        xs: &[TrackId],
        keep_y: impl Fn(TrackId) -> bool + Sync,
        direct_ys: Option<&[TrackId]>,
        frames: Range<Frame>,
        radius: f64,
    ) -> PairList {
        use rayon::prelude::*;
        let per_x = xs
            .par_iter()
            .map(|&xt| {
                (
                    xt,
                    self.rows_of(kin, xt, &keep_y, direct_ys, &frames, radius),
                )
            })
            .collect();
        PairList { radius, per_x }
    }

    /// One X track's rows of [`PairIndex::pairs`], sorted by (Y, frame): only boxes whose
    /// bounding boxes come within `radius` of X's at a frame are visited (each frame's R-tree),
    /// and only those whose rectangles may be within `radius` are kept.
    pub fn rows_of(
        &self,
        kin: &Kinematics,
        xt: TrackId,
        keep_y: &(dyn Fn(TrackId) -> bool + Sync),
        direct_ys: Option<&[TrackId]>,
        frames: &Range<Frame>,
        radius: f64,
    ) -> Vec<PairRow> {
        self.rows_in(kin, xt, keep_y, direct_ys, frames, radius, None)
    }

    /// [`PairIndex::rows_of`], the R-tree asked for the boxes meeting `region(x)` (an envelope
    /// (min, max) around X's box `x`) instead of X's bounding box grown by `radius`, when given:
    /// for a relation whose condition puts Y in a known part of X's surroundings (e.g. ahead of
    /// it). The centre-distance test against `radius` still applies.
    #[allow(clippy::too_many_arguments)]
    pub fn rows_in(
        &self,
        kin: &Kinematics,
        xt: TrackId,
        keep_y: &(dyn Fn(TrackId) -> bool + Sync),
        direct_ys: Option<&[TrackId]>,
        frames: &Range<Frame>,
        radius: f64,
        region: Option<&Region<'_>>,
    ) -> Vec<PairRow> {
        let mut rows = Vec::new();
        let Some(kx) = kin.tracks.get(xt.index()) else {
            return rows;
        };
        for &frame in kx.frames.iter().filter(|f| frames.contains(f)) {
            let Some(fb) = self.frame(kin, frame) else {
                continue;
            };
            let Some(xi) = fb.position(xt) else {
                continue;
            };
            let x = &fb.boxes[xi];
            let mut visit = |yi: usize| {
                let y = &fb.boxes[yi];
                if y.track == xt || !keep_y(y.track) {
                    return;
                }
                if let Some(row) = pair_row(fb, xi, yi, frame, radius) {
                    rows.push(row);
                }
            };
            match (direct_ys, region) {
                (Some(ys), _) => ys
                    .iter()
                    .filter_map(|&t| fb.position(t))
                    .for_each(&mut visit),
                (None, Some(region)) => fb.candidates_in(region(x)).for_each(&mut visit),
                (None, None) => fb.candidates(x, radius).for_each(&mut visit),
            }
        }
        rows.sort_unstable_by_key(|r| (u64::from(r.y.0) << 32) | u64::from(r.frame));
        rows
    }

    /// One X track's rows at the given (Y, frame) pairs only (sorted by (Y, frame)), within
    /// `frames`, whose rectangles may be at most `radius` apart: a tuple-level demand
    /// ([`scenalog_facts::relation::Constraint::Triples`]) looked up box by box, without the
    /// R-tree. Sorted by (Y, frame) like [`PairIndex::rows_of`].
    pub fn rows_at(
        &self,
        kin: &Kinematics,
        xt: TrackId,
        at: &[(TrackId, Frame)],
        frames: &Range<Frame>,
        radius: f64,
    ) -> Vec<PairRow> {
        let mut rows = Vec::with_capacity(at.len());
        for &(yt, frame) in at {
            if yt == xt || !frames.contains(&frame) {
                continue;
            }
            let Some(fb) = self.frame(kin, frame) else {
                continue;
            };
            let (Some(xi), Some(yi)) = (fb.position(xt), fb.position(yt)) else {
                continue;
            };
            if let Some(row) = pair_row(fb, xi, yi, frame, radius) {
                rows.push(row);
            }
        }
        rows.sort_unstable_by_key(|r| (u64::from(r.y.0) << 32) | u64::from(r.frame));
        rows
    }

    fn build(&self, kin: &Kinematics, f: usize) -> FrameBoxes {
        let boxes: Vec<ObjBox> = self.present[f]
            .iter()
            .filter_map(|&(track, k)| {
                let tk = kin.tracks.get(track.index())?;
                let center = *tk.center.get(k)?;
                let yaw = *tk.yaw.get(k)?;
                let [half_len, half_wid] = *self.sizes.get(track.index())?.get(k)?;
                if !(center[0].is_finite() && center[1].is_finite() && yaw.is_finite()) {
                    return None;
                }
                let (sin, cos) = yaw.sin_cos();
                Some(ObjBox {
                    track,
                    k,
                    center,
                    yaw,
                    cos,
                    sin,
                    half_len,
                    half_wid,
                    reach: (half_len * half_len + half_wid * half_wid).sqrt(),
                })
            })
            .collect();
        let entries: Vec<Entry> = boxes
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let (lo, hi) = b.aabb();
                GeomWithData::new(Rectangle::from_corners(lo, hi), i as u32)
            })
            .collect();
        FrameBoxes {
            boxes,
            tree: RTree::bulk_load(entries),
        }
    }
}
