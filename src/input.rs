//! The command's input files, read in one place: every file a flag names (rules, programs,
//! log-prompts, descriptions, timestamps, tracks, predictions, ground truth) goes through
//! `scenalog-input`, so a FIFO, a device, a directory or a symlink loop is an error naming the
//! path and what it is, and nothing is read past its size limit.

use std::path::Path;

/// A UTF-8 text input (a program, a JSON or text list), at most [`scenalog_input::TEXT_LIMIT`]
/// bytes; `-` is standard input. The error reads "cannot read `PATH`: is a FIFO …".
pub fn read_text(path: &Path) -> Result<String, String> {
    let read = if path.as_os_str() == "-" {
        scenalog_input::read_stdin_text(scenalog_input::TEXT_LIMIT)
    } else {
        scenalog_input::read_text_file(path, scenalog_input::TEXT_LIMIT)
    };
    read.map_err(|problem| format!("cannot read `{}`: {problem}", path.display()))
}

/// A pickle, at most [`scenalog_input::DATA_LIMIT`] bytes; one that does not end as a pickle
/// does (cut short, padded) is an error before it is read whole.
pub fn read_pickle(path: &Path) -> Result<Vec<u8>, String> {
    scenalog_input::read_file_checking_ends(
        path,
        scenalog_input::DATA_LIMIT,
        &scenalog_eval::dict_pickle_ends,
    )
    .map_err(|problem| format!("cannot read `{}`: {problem}", path.display()))
}
