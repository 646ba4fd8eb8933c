//! The `scenalog` command's library half: the subcommands ([`cli`]) and the mining pipeline
//! ([`pipeline`]) that joins the workspace's crates, shared by the binary (`src/main.rs`) and the
//! Python package (`python/`), which calls the same functions instead of duplicating them.

pub mod cli;
pub mod input;
pub mod pipeline;
