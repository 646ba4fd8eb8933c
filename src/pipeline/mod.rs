//! The mining pipeline: joining extraction, evaluation and scoring for `mine` and `explain`.
//!
//! [`scenario`] reads and checks a program and evaluates it on a log with the extractors as the
//! engine's provider; [`tracks`] turns derived tuples into labelled output frames (dilation, 2 Hz
//! frames, the related-object range); [`predictions`] turns those into the evaluation's data model.

pub mod explain;
pub mod predictions;
pub mod scenario;
pub mod tracks;
