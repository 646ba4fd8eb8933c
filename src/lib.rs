//! The `scenalog` command's library half: the library API ([`api`]: typed requests and results
//! for mine, explain, eval and check), the mining pipeline ([`pipeline`]) that joins the
//! workspace's crates, and the subcommands ([`cli`]: clap arguments turned into API requests,
//! results printed). The binary (`src/main.rs`) runs [`cli`]; the Python package (`python/`)
//! calls [`api`] directly. Calls go `cli` → `api` → `pipeline`, never back.

pub mod api;
pub mod cli;
pub mod input;
pub mod pipeline;
