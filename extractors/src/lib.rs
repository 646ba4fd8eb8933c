//! Scenalog's extractors: computing the catalog's relations (the EDB) from a [`Scene`].
//!
//! Owns: kinematics ([`kinematics`]), the map prepared for queries and lane assignment ([`map`],
//! [`lanes`]), events ([`events`]: turning, lane change), RefAV's definitions where they differ
//! ([`refav`], [`refav_lanes`], for imported programs), the pairwise relations ([`pairs`]), the
//! per-scene context that computes each thing once ([`Extractor`]), constraint pushdown
//! ([`Query`]), and every threshold in one place ([`thresholds`]).
//!
//! Does not own: reading logs (the `facts` crate builds the [`Scene`]), the catalog itself (also
//! `facts`), or evaluating rules (the `engine` crate asks for relations through [`extract()`] or an
//! [`Extractor`]).
//!
//! Public API:
//! - [`extract()`]`(scene, &Request) -> Result<RelationData, ExtractError>`: one relation, only the
//!   tuples satisfying the request's constraints, rows sorted.
//! - [`Extractor`]: the same through a per-scene cache (kinematics, lanes, R-trees, answers),
//!   `Sync`, so one run computes each thing once; [`Extractor::extract_within`] computes under a
//!   [`Budget`] (most tuples, a deadline) checked as the pair relations are produced.
//! - [`extract_all`]`(scene)`: every relation; [`extract_logs`]: many logs in parallel (rayon);
//!   deterministic whatever the thread count.
//! - [`pair_relation`]`(&PairContext, &Request)`: a pair relation from an explicit context (for
//!   benchmarks and tests of the pair search).
//! - [`relation_json`]: a relation's tuples as a JSON array of arrays.
//!
//! [`Scene`]: scenalog_facts::Scene

#![warn(missing_docs)]

pub mod budget;
pub mod cache;
pub mod error;
pub mod events;
pub mod extract;
pub mod json;
pub mod kinematics;
pub mod lanes;
pub mod map;
pub mod pairs;
pub mod query;
pub mod refav;
pub mod refav_lanes;
mod relations;
mod rows;
pub mod table;
pub mod thresholds;

pub use budget::Budget;
pub use cache::Extractor;
pub use extract::{extract, extract_all, extract_all_with, extract_logs};
pub use json::relation_json;
pub use query::{ExtractError, Query};
pub use table::{pair_relation, pair_relations};
