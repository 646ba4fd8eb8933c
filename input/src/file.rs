//! Is a path a regular file? Reading one without blocking on a FIFO or misreporting a symlink
//! loop or a permission problem as "not found".

use std::io::ErrorKind;
use std::path::Path;

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
    /// The path could not be examined or read: permission denied, a symlink loop, an I/O error.
    Io(std::io::Error),
}

impl std::fmt::Display for FileProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FileProblem::NotFound => write!(f, "not found"),
            FileProblem::WrongKind { found, expected } => write!(f, "is {found}, not {expected}"),
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

/// Reads the whole of `path` after checking it is a regular file (so a FIFO is an error, not a
/// read that waits forever for a writer).
pub fn read_regular_file(path: &Path) -> Result<Vec<u8>, FileProblem> {
    regular_file(path)?;
    std::fs::read(path).map_err(|e| match e.kind() {
        ErrorKind::NotFound => FileProblem::NotFound,
        _ => FileProblem::Io(e),
    })
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
        assert_eq!(read_regular_file(&file).expect("read"), b"abc");

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
            let problem = read_regular_file(&a).expect_err("a loop");
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
            let problem = read_regular_file(&fifo).expect_err("a FIFO");
            assert_eq!(
                problem.to_string(),
                "is a FIFO (named pipe), not a regular file"
            );
        }
    }
}
