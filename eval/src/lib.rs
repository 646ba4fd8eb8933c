//! The official Argoverse 2 scenario-mining evaluation (av2 0.3.6 on TrackEval 1.3.0), in Rust.
//!
//! Owns: reading (and writing) the official pickle format into a plain [`Submission`], HOTA as TrackEval
//! computes it, and the scenario-mining metrics (HOTA-Temporal, HOTA-Track, timestamp- and log-level
//! balanced accuracy), the paper's further columns (HOTA-Temporal of related and other objects, the
//! tracker's HOTA: [`classes`]), sampling at a chosen rate ([`sampling`]), and the optional drivable-area ROI filter ([`roi`], rasters built from each log's vector
//! map). Does not own: mining itself, or any other use of the map.
#![warn(missing_docs)]

pub mod arrow_table;
pub mod classes;
pub mod error;
mod filters;
pub mod hota;
pub mod mining;
pub mod model;
mod numpy_data;
pub mod pickle;
mod pickle_text;

pub mod roi;
pub mod sampling;
mod tuning;

pub use arrow_table::{read_any, read_table, table_from_bytes, write_table};
pub use classes::{ClassHota, Further};
pub use error::EvalError;
pub use mining::{evaluate, EvalOptions, PromptHota, Report};
pub use model::{FrameData, SeqKey, Submission};
pub use pickle::join::{encode_part, join_pickles, PartKeys, PickleJoin};
pub use pickle::write::{
    encode_value, pickle_bytes, sequences_bytes, write_pickle, PyValue, SUBMISSION_HEAD,
    SUBMISSION_TAIL,
};
pub use pickle::{
    dict_pickle_ends, parse_pickle, parse_pickle_dict, read_pickle, read_pickle_bytes,
    submission_ends, Node, NumArray, Pickle,
};
pub use roi::{RoiMaps, RoiRaster};
pub use sampling::{parse_timestamps, read_timestamps, resample, Sampling};
