//! Scenalog's input guard: reading files that come from outside without crashing on them.
//!
//! Owns: deciding whether a path is a regular file that can be read (and saying what it is when
//! it is not: missing, a directory, a FIFO, a symlink loop, permission denied), and the checks an
//! Arrow IPC file (feather v2) must pass before the Arrow decoder may trust it: the framing
//! (magic bytes, footer), every block and buffer inside the file, and no declared row count or
//! uncompressed length larger than the bytes could hold. A corrupt length otherwise makes the
//! decoder panic or allocate petabytes and abort the process.
//!
//! Also owns the one check of a log id read from an input file ([`log_id::check_log_id`]), since
//! every reader joins ids to a dataset directory, and the other side of the same guard: an output
//! folder is input too (someone who can write there can plant a link), so every writer replaces
//! files through [`out_dir::write_atomic`] and checks a folder with [`out_dir::refuse_links`]
//! before writing into it.
//!
//! Does not own: what the columns mean. The log reader (`scenalog-facts`) and the evaluation
//! (`scenalog-eval`) both read their tables through [`arrow::read_batches`] and wrap
//! [`arrow::Corrupt`] and [`file::FileProblem`] into their own errors, naming the file.
//!
//! Depends on no other crate of ours.

#![warn(missing_docs)]

pub mod arrow;
pub mod ends;
pub mod file;
pub mod log_id;
pub mod out_dir;

pub use arrow::{read_batches, read_schema, Corrupt};
pub use file::{
    directory, read_file_checking_ends, read_regular_file, read_stdin_text, read_text_file,
    regular_file, FileProblem, DATA_LIMIT, LOG_TABLE_LIMIT, MAP_LIMIT, TEXT_LIMIT,
};
pub use log_id::check_log_id;
