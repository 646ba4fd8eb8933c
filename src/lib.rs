//! The `scenalog` command's library half: the library API ([`api`]: typed requests and results
//! for every subcommand), the mining pipeline ([`pipeline`]) that joins the workspace's crates,
//! and the subcommands ([`cli`]: clap arguments turned into API requests, results printed).
//! The binary (`src/main.rs`) runs [`cli`]; the Python package (`python/`) calls [`api`]
//! directly; neither calls anything else of ours (`tests/tidy.rs`). Calls go `cli` → `api` →
//! `pipeline`, never back; [`input`] (input files read safely) and [`message`] (messages naming
//! a request's fields) serve all three.

pub mod api;
pub mod cli;
pub mod input;
pub mod message;
pub mod pipeline;
