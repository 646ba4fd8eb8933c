//! The mining pipeline: joining extraction, evaluation and scoring for `mine` and `explain`.
//!
//! Only the output stage exists so far ([`tracks`]: dilation, 2 Hz frames, the related-object
//! range); `mine` wires it once the engine and the evaluation crates land (issue 7).

pub mod tracks;
