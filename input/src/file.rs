//! Is a path a regular file? Reading one without blocking on a FIFO or misreporting a symlink
//! loop or a permission problem as "not found", and never past a size limit.
//!
//! [`read_regular_file`] is the one way every command reads an input file: it opens the path
//! without blocking (a FIFO's open would otherwise wait for a writer), checks what the opened
//! descriptor is (so a path swapped between a check and the open is still caught), and reads at
//! most the given limit, so `/dev/zero`, a FIFO or a file growing under the reader is an error
//! naming what it is rather than a read that never ends or exhausts memory.

use std::io::{ErrorKind, Read};
use std::path::Path;

/// The largest text input read (rules, prompt lists, descriptions, JSON maps and timestamps).
pub const TEXT_LIMIT: u64 = 256 << 20;
/// The largest binary input read (Arrow tables, pickles of predictions, ground truth, tracks).
pub const DATA_LIMIT: u64 = 32 << 30;
/// The largest table of one log read (its annotations, a tracker's per-log boxes, its ego
/// poses): an AV2 log's annotations are tens of megabytes.
pub const LOG_TABLE_LIMIT: u64 = 2 << 30;
/// The largest vector map read (JSON; an AV2 log's map is a few megabytes).
pub const MAP_LIMIT: u64 = TEXT_LIMIT;

/// A check of a file's first and last bytes (see [`read_file_checking_ends`]): `Err` says what is
/// wrong with them.
pub type EndsCheck<'a> = &'a dyn Fn(&[u8], &[u8]) -> Result<(), String>;

/// How many bytes of each end of a file [`read_file_checking_ends`] shows its check.
pub const END_BYTES: usize = 64;

/// Why a path cannot be read as a regular file.
#[derive(Debug)]
pub enum FileProblem {
    /// Nothing is at the path (a dangling symlink included).
    NotFound,
    /// Something of another kind is at the path.
    WrongKind {
        /// What is there: "a directory", "a FIFO (named pipe)", "a regular file", ….
        found: &'static str,
        /// What was wanted: "a regular file" or "a directory".
        expected: &'static str,
    },
    /// The file is larger than the reader accepts.
    TooLarge {
        /// Its size in bytes (at least this many: reading stops one byte past the limit).
        size: u64,
        /// The limit in bytes.
        limit: u64,
    },
    /// A text file is not UTF-8; the byte offset of the first invalid byte.
    NotUtf8(usize),
    /// The file's first or last bytes are not those of its format (checked before the whole
    /// file is read); what is wrong.
    NotFormat(String),
    /// The path could not be examined or read: permission denied, a symlink loop, an I/O error.
    Io(std::io::Error),
}

impl std::fmt::Display for FileProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FileProblem::NotFound => write!(f, "not found"),
            FileProblem::WrongKind { found, expected } => write!(f, "is {found}, not {expected}"),
            FileProblem::TooLarge { size, limit } => write!(
                f,
                "is too large ({size} bytes or more; the limit for this input is {limit} bytes)"
            ),
            FileProblem::NotFormat(what) => write!(f, "{what}"),
            FileProblem::NotUtf8(at) => {
                write!(f, "is not UTF-8 text (invalid byte at offset {at})")
            }
            FileProblem::Io(e) => write!(f, "cannot read: {}", describe_io(e)),
        }
    }
}

/// The operating system's message, with what it means for the common cases spelt out
/// ("a symlink loop (…)", "permission denied (…)").
pub fn describe_io(e: &std::io::Error) -> String {
    // ELOOP has no stable `ErrorKind` yet; its raw code is 40 on Linux, 62 on the BSDs and macOS.
    let loop_code = if cfg!(target_os = "linux") { 40 } else { 62 };
    if e.raw_os_error() == Some(loop_code) {
        format!("a symlink loop ({e})")
    } else if e.kind() == ErrorKind::PermissionDenied {
        format!("permission denied ({e})")
    } else {
        e.to_string()
    }
}

/// What a file type is, in words, when it is not a regular file.
fn kind_of(ty: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if ty.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if ty.is_socket() {
            return "a socket";
        }
        if ty.is_block_device() {
            return "a block device";
        }
        if ty.is_char_device() {
            return "a character device";
        }
    }
    if ty.is_dir() {
        "a directory"
    } else if ty.is_file() {
        "a regular file"
    } else {
        "an unknown kind of file"
    }
}

/// Checks that `path` (following symlinks) is a regular file and returns its length in bytes.
pub fn regular_file(path: &Path) -> Result<u64, FileProblem> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() => Ok(m.len()),
        Ok(m) => Err(FileProblem::WrongKind {
            found: kind_of(m.file_type()),
            expected: "a regular file",
        }),
        Err(e) if e.kind() == ErrorKind::NotFound => Err(FileProblem::NotFound),
        Err(e) => Err(FileProblem::Io(e)),
    }
}

/// Checks that `path` (following symlinks) is a directory.
pub fn directory(path: &Path) -> Result<(), FileProblem> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Ok(()),
        Ok(m) => Err(FileProblem::WrongKind {
            found: kind_of(m.file_type()),
            expected: "a directory",
        }),
        Err(e) if e.kind() == ErrorKind::NotFound => Err(FileProblem::NotFound),
        Err(e) => Err(FileProblem::Io(e)),
    }
}

/// Opens `path` for reading without blocking, whatever is there (a FIFO's open returns at once).
fn open_nonblocking(path: &Path) -> std::io::Result<std::fs::File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    options.open(path)
}

/// Reads the whole of `path`, at most `limit` bytes, after checking that what was opened is a
/// regular file: a FIFO, a device (`/dev/zero`), a directory or a symlink loop is an error
/// saying what it is, never a read that waits forever or runs out of memory. Every input file of
/// every command is read through this function (or [`read_text_file`]).
pub fn read_regular_file(path: &Path, limit: u64) -> Result<Vec<u8>, FileProblem> {
    read_file_checking_ends(path, limit, &|_, _| Ok(()))
}

/// [`read_regular_file`], with the file's first and last [`END_BYTES`] bytes (fewer in a
/// shorter file) shown to `ends` before the rest is read: a file of the wrong format, or one
/// padded to gigabytes, is an error at once ([`FileProblem::NotFormat`] with `ends`'s message)
/// instead of after reading and decoding all of it. Memory is what the file holds, reserved
/// fallibly: a size that cannot be allocated is an error, not an abort.
pub fn read_file_checking_ends(
    path: &Path,
    limit: u64,
    ends: EndsCheck,
) -> Result<Vec<u8>, FileProblem> {
    // The kind first by path, so a directory or FIFO is named without being opened at all.
    regular_file(path)?;
    let file = open_nonblocking(path).map_err(|e| match e.kind() {
        ErrorKind::NotFound => FileProblem::NotFound,
        _ => FileProblem::Io(e),
    })?;
    // Then the kind of what was opened, in case the path changed in between.
    let meta = file.metadata().map_err(FileProblem::Io)?;
    if !meta.is_file() {
        return Err(FileProblem::WrongKind {
            found: kind_of(meta.file_type()),
            expected: "a regular file",
        });
    }
    if meta.len() > limit {
        return Err(FileProblem::TooLarge {
            size: meta.len(),
            limit,
        });
    }
    let mut file = file;
    let (head, tail) = read_ends(&mut file, meta.len()).map_err(FileProblem::Io)?;
    ends(&head, &tail).map_err(FileProblem::NotFormat)?;
    let mut data = Vec::new();
    data.try_reserve_exact(usize::try_from(meta.len()).unwrap_or(usize::MAX))
        .map_err(|_| {
            FileProblem::Io(std::io::Error::new(
                ErrorKind::OutOfMemory,
                format!("{} bytes cannot be allocated", meta.len()),
            ))
        })?;
    file.take(limit.saturating_add(1))
        .read_to_end(&mut data)
        .map_err(FileProblem::Io)?;
    if data.len() as u64 > limit {
        return Err(FileProblem::TooLarge {
            size: data.len() as u64,
            limit,
        });
    }
    Ok(data)
}

/// The first and last [`END_BYTES`] bytes of a file of `len` bytes, then back at its start.
fn read_ends(file: &mut std::fs::File, len: u64) -> std::io::Result<(Vec<u8>, Vec<u8>)> {
    use std::io::{Seek, SeekFrom};
    let n = len.min(END_BYTES as u64);
    let mut head = vec![0; n as usize];
    file.read_exact(&mut head)?;
    let mut tail = vec![0; n as usize];
    file.seek(SeekFrom::Start(len - n))?;
    file.read_exact(&mut tail)?;
    file.seek(SeekFrom::Start(0))?;
    Ok((head, tail))
}

/// [`read_regular_file`] for a UTF-8 text file.
pub fn read_text_file(path: &Path, limit: u64) -> Result<String, FileProblem> {
    let data = read_regular_file(path, limit)?;
    String::from_utf8(data).map_err(|e| FileProblem::NotUtf8(e.utf8_error().valid_up_to()))
}

/// Reads standard input as UTF-8 text, at most `limit` bytes (`check -`, `run -`).
pub fn read_stdin_text(limit: u64) -> Result<String, FileProblem> {
    let mut data = Vec::new();
    std::io::stdin()
        .lock()
        .take(limit.saturating_add(1))
        .read_to_end(&mut data)
        .map_err(FileProblem::Io)?;
    if data.len() as u64 > limit {
        return Err(FileProblem::TooLarge {
            size: data.len() as u64,
            limit,
        });
    }
    String::from_utf8(data).map_err(|e| FileProblem::NotUtf8(e.utf8_error().valid_up_to()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_missing_directory_and_loop() {
        let dir = tempfile::tempdir().expect("tempdir");
        let file = dir.path().join("a.feather");
        std::fs::write(&file, b"abc").expect("write");
        assert_eq!(regular_file(&file).expect("regular"), 3);
        assert_eq!(read_regular_file(&file, 3).expect("read"), b"abc");
        let problem = read_regular_file(&file, 2).expect_err("over the limit");
        assert_eq!(
            problem.to_string(),
            "is too large (3 bytes or more; the limit for this input is 2 bytes)"
        );
        std::fs::write(&file, [b'a', 0xff]).expect("write");
        let problem = read_text_file(&file, 10).expect_err("not UTF-8");
        assert_eq!(
            problem.to_string(),
            "is not UTF-8 text (invalid byte at offset 1)"
        );

        assert!(directory(dir.path()).is_ok());
        let problem = directory(&file).expect_err("a file");
        assert_eq!(problem.to_string(), "is a regular file, not a directory");
        let missing = dir.path().join("missing");
        assert!(matches!(regular_file(&missing), Err(FileProblem::NotFound)));
        let problem = regular_file(dir.path()).expect_err("a directory");
        assert_eq!(problem.to_string(), "is a directory, not a regular file");

        #[cfg(unix)]
        {
            let a = dir.path().join("loop_a");
            let b = dir.path().join("loop_b");
            std::os::unix::fs::symlink(&b, &a).expect("symlink");
            std::os::unix::fs::symlink(&a, &b).expect("symlink");
            let problem = read_regular_file(&a, 10).expect_err("a loop");
            assert!(problem.to_string().contains("symlink loop"), "{problem}");
            let dangling = dir.path().join("dangling");
            std::os::unix::fs::symlink(&missing, &dangling).expect("symlink");
            assert!(matches!(
                regular_file(&dangling),
                Err(FileProblem::NotFound)
            ));

            let fifo = dir.path().join("fifo");
            let made = std::process::Command::new("mkfifo")
                .arg(&fifo)
                .status()
                .expect("run mkfifo");
            assert!(made.success(), "mkfifo failed");
            // Would block forever if it were opened for reading.
            let problem = read_regular_file(&fifo, 10).expect_err("a FIFO");
            assert_eq!(
                problem.to_string(),
                "is a FIFO (named pipe), not a regular file"
            );
            // Opening it does not wait for a writer either.
            let opened = open_nonblocking(&fifo).expect("open a FIFO without blocking");
            assert!(!opened.metadata().expect("fstat").is_file());
            if Path::new("/dev/zero").exists() {
                let problem = read_regular_file(Path::new("/dev/zero"), 10).expect_err("a device");
                assert_eq!(
                    problem.to_string(),
                    "is a character device, not a regular file"
                );
            }
        }
    }
}
