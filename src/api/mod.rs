//! The library API: typed requests and results for everything the command does, called by the
//! command (`src/cli/`, which parses flags into these requests) and the Python package
//! (`python/`, which builds them from keyword arguments); neither parses the other's arguments,
//! and neither reaches past this module (a test, `tests/tidy.rs`, reads their sources).
//!
//! One module a request: [`facts`] (a log's summary or one relation), [`catalog`] (the
//! relations a program can use), [`check`] (a program's diagnostics), [`editor`] (what an
//! editor asks while a program is typed: diagnostics placed, hover, completion), [`run`] (a
//! program on its own facts), [`mine`] (programs on logs), [`split`] (a split's (log, prompt) pairs),
//! [`explain`] (a track's proof or why-not report, and its picture), [`eval`] (the official
//! metrics), [`synth`] (programs from descriptions with an LLM), [`import`] (RefAV's programs).
//! Each is plain structs and functions over [`crate::pipeline`] and the workspace's crates;
//! results render themselves (text, JSON) and carry the paths of what they wrote ([`outputs`])
//! and every failure in one list. Every request that evaluates or extracts carries [`Limits`].
//! Errors ([`Error`]) name the request's [`Field`]s, which each front end spells with its own
//! [`Names`] (`--max-tuples`, `max_tuples`). The calls go one way: `cli` → `api` → `pipeline`.

pub mod catalog;
pub mod check;
pub mod editor;
pub mod error;
pub mod eval;
pub mod explain;
pub mod facts;
pub mod import;
pub mod inputs;
pub mod limits;
pub mod mine;
pub mod outputs;
pub mod run;
pub mod split;
pub mod studio;
pub mod synth;
pub mod synth_evidence;
mod synth_fixture;
pub mod synth_search;

pub use error::{Error, ErrorKind, Field, Message, Names};
pub use limits::Limits;
pub use scenalog_eval::join_pickles;
