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

/// A binary input (a pickle), at most [`scenalog_input::DATA_LIMIT`] bytes.
pub fn read_data(path: &Path) -> Result<Vec<u8>, String> {
    scenalog_input::read_regular_file(path, scenalog_input::DATA_LIMIT)
        .map_err(|problem| format!("cannot read `{}`: {problem}", path.display()))
}
