//! The library API: typed requests and results for what the command does, called by the
//! command (`src/cli/`, which parses flags into these requests) and the Python package
//! (`python/`, which builds them from keyword arguments); neither parses the other's arguments.
//!
//! [`mine`] (programs on logs), [`split`] (a split's (log, prompt) pairs), [`explain`] (a
//! track's proof or why-not report), [`eval`] (the official metrics), [`check`] (a program's
//! diagnostics). Each is plain structs and functions over [`crate::pipeline`]; errors
//! ([`Error`]) name the request's fields as the caller's user spells them ([`Names`]). The
//! calls go one way: `cli` → `api` → `pipeline`.

pub mod check;
pub mod error;
pub mod eval;
pub mod explain;
pub mod mine;
pub mod split;

pub use error::{Arg, Error, ErrorKind, Names};
