//! The integration tests of scenalog-extractors in one binary (one link instead of one per file): a module
//! per concern, each saying what it tests. Run one with `cargo test -p scenalog-extractors --test it MODULE::`.

mod budget;
mod concepts;
mod kinematics;
mod map;
mod map_scale;
mod pairs;
mod pairs_real_logs;
mod real_logs;
mod refav;
mod relations;
mod road;
