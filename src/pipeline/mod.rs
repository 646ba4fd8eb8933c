//! The mining pipeline: joining extraction, evaluation and scoring for `mine` and `explain`.
//!
//! [`scenario`] reads and checks a program and evaluates it on a log with the extractors as the
//! engine's provider; [`tracks`] turns derived tuples into labelled output frames (dilation, 2 Hz
//! frames, the related-object range); [`predictions`] turns those into the evaluation's data model;
//! [`run`] mines every (log, program) pair of a run in parallel and writes what [`output`]
//! describes; [`summary`] renders a run for a person and scores it against ground truth;
//! [`studio_link`] is the address that opens a match in `scenalog studio`; [`limits`] sizes a pair's default tuple budget and time limit; [`lock`] keeps one writer per
//! output folder.

pub mod explain;
pub mod limits;
pub mod lock;
pub mod output;
pub mod picture;
pub mod predictions;
#[cfg(feature = "rerun")]
pub mod recording;
pub mod report;
pub mod run;
pub mod scenario;
pub mod studio_link;
pub mod summary;
pub mod tracks;
