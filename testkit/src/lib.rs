//! What Scenalog's tests share, so no test file types it out again: where the bundled sample logs
//! and the scenario library are, the sample scenes loaded once per test binary ([`data`]), small
//! scenes built in code whose answers are known by construction ([`scene`]), and a relation's
//! tuples as rows ([`rows`]).
//!
//! A dev-dependency only: nothing of the product depends on it.

#![warn(missing_docs)]

pub mod data;
pub mod rows;
pub mod scene;

pub use data::{
    copy_sample_log, library_files, repo_root, sample_log, sample_log_dirs, sample_logs_dir,
    sample_scenes, SAMPLE_LOGS,
};
pub use rows::rows;
pub use scene::{straight, SceneBuilder, Waypoint};
