//! Which objects an evaluation keeps: the official range and drivable-area filters
//! ([`Filter`]) and the objects a metric looks at ([`Pick`]: referred, related, other, the
//! referred tracks whole), copied out of a submission.

use std::collections::{BTreeMap, BTreeSet};

use rayon::prelude::*;

use crate::model::{FrameData, SeqKey, Submission};
use crate::roi::{RoiMaps, RoiRaster};

/// Copies of the frames holding only the objects `keep(frame, object)` selects.
fn select(frames: &[FrameData], keep: impl Fn(usize, &FrameData, usize) -> bool) -> Vec<FrameData> {
    frames
        .iter()
        .enumerate()
        .map(|(j, f)| {
            let idx: Vec<usize> = (0..f.len()).filter(|&i| keep(j, f, i)).collect();
            FrameData {
                timestamp_ns: f.timestamp_ns,
                ego_translation_m: f.ego_translation_m,
                description: None,
                translation_m: idx.iter().map(|&i| f.translation_m[i]).collect(),
                size: idx.iter().filter_map(|&i| f.size.get(i).copied()).collect(),
                yaw: idx.iter().filter_map(|&i| f.yaw.get(i).copied()).collect(),
                velocity_m_per_s: Vec::new(),
                label: idx.iter().map(|&i| f.label[i]).collect(),
                name: Vec::new(),
                track_id: idx.iter().map(|&i| f.track_id[i]).collect(),
                score: f
                    .score
                    .as_ref()
                    .map(|s| idx.iter().map(|&i| s[i]).collect()),
                is_positive: f.is_positive,
            }
        })
        .collect()
}

/// Whether object `i` survives the range filter and, when given, the ROI filter.
fn kept(f: &FrameData, i: usize, max_range_m: f64, roi: Option<&RoiRaster>) -> bool {
    let e = f.ego_translation_m;
    let t = f.translation_m[i];
    let dx = t[0] - e[0];
    let dy = t[1] - e[1];
    if (dx * dx + dy * dy).sqrt() > max_range_m {
        return false;
    }
    match roi {
        // sizes and yaws were checked to be present when the ROI is on
        Some(r) => r.box_in_roi(t, f.size[i], f.yaw[i]),
        None => true,
    }
}

/// Which objects the filters keep.
pub(crate) enum Filter<'a> {
    /// The range filter alone, tested inline.
    Range(f64),
    /// Range and ROI, per sequence, frame and object: computed once, as the box test is the costly part.
    Masks(BTreeMap<&'a SeqKey, Vec<Vec<bool>>>),
}

impl<'a> Filter<'a> {
    pub(crate) fn new(sub: &'a Submission, max_range_m: f64, roi: Option<&RoiMaps>) -> Filter<'a> {
        let Some(maps) = roi else {
            return Filter::Range(max_range_m);
        };
        let masks = sub
            .sequences
            .par_iter()
            .map(|(k, frames)| {
                let r = maps.get(&k.0);
                let m = frames
                    .iter()
                    .map(|f| (0..f.len()).map(|i| kept(f, i, max_range_m, r)).collect())
                    .collect();
                (k, m)
            })
            .collect();
        Filter::Masks(masks)
    }
}

/// Which objects of a frame [`pick`] keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Pick {
    /// The objects carrying this label (0 referred, 1 related, 2 other).
    Label(i32),
    /// Every object of a track referred in any kept object (`referred_full_tracks`).
    ReferredTracks,
    /// Every object, labels ignored.
    Every,
}

/// The referred objects kept by the filters (`filter_max_dist`, `filter_drivable_area`, then
/// `classify_referred_objects`); with `full_tracks`, every kept object of a track referred in any kept
/// object (`referred_full_tracks`).
pub(crate) fn referred(sub: &Submission, filter: &Filter, full_tracks: bool) -> Submission {
    let which = if full_tracks {
        Pick::ReferredTracks
    } else {
        Pick::Label(0)
    };
    pick(sub, filter, which)
}

/// The objects kept by the filters that `which` selects, in copies of every sequence.
pub(crate) fn pick(sub: &Submission, filter: &Filter, which: Pick) -> Submission {
    let sequences = sub
        .sequences
        .iter()
        .map(|(k, frames)| {
            let masks = match filter {
                Filter::Masks(m) => m.get(k),
                Filter::Range(_) => None,
            };
            let keep = |j: usize, f: &FrameData, i: usize| match (filter, masks) {
                (Filter::Range(r), _) => kept(f, i, *r, None),
                (Filter::Masks(_), m) => m.is_some_and(|m| m[j][i]),
            };
            let out = match which {
                Pick::ReferredTracks => {
                    let ids: BTreeSet<i32> = frames
                        .iter()
                        .enumerate()
                        .flat_map(|(j, f)| {
                            (0..f.len())
                                .filter(move |&i| f.label[i] == 0 && keep(j, f, i))
                                .map(move |i| f.track_id[i])
                        })
                        .collect();
                    select(frames, |j, f, i| {
                        ids.contains(&f.track_id[i]) && keep(j, f, i)
                    })
                }
                Pick::Label(l) => select(frames, |j, f, i| f.label[i] == l && keep(j, f, i)),
                Pick::Every => select(frames, keep),
            };
            (k.clone(), out)
        })
        .collect();
    Submission { sequences }
}
