//! Standard output for every subcommand. `println!` panics when the reader has gone
//! (`scenalog facts LOG | head`); writing through [`write_with`] (or the `out!` and `outln!`
//! macros) instead ends the output quietly on a closed pipe and lets the command finish. Any other
//! write error (a full disk under `> file`) is reported once on standard error, and [`exit_code`]
//! turns the command's exit code into 2.

use std::io::{ErrorKind, StdoutLock, Write};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

/// The reader closed the pipe: nothing more is written.
static CLOSED: AtomicBool = AtomicBool::new(false);
/// A write failed for another reason (already reported on standard error).
static FAILED: AtomicBool = AtomicBool::new(false);

/// Writes to standard output with `f` (locked, flushed at the end), unless the output is
/// already closed. A closed pipe ends the output quietly; another error is reported once.
pub fn write_with(f: impl FnOnce(&mut StdoutLock<'static>) -> std::io::Result<()>) {
    if CLOSED.load(Ordering::Relaxed) {
        return;
    }
    let mut out = std::io::stdout().lock();
    if let Err(e) = f(&mut out).and_then(|()| out.flush()) {
        CLOSED.store(true, Ordering::Relaxed);
        if e.kind() != ErrorKind::BrokenPipe {
            FAILED.store(true, Ordering::Relaxed);
            eprintln!("scenalog: cannot write standard output: {e}");
        }
    }
}

/// Writes `text` to standard output (see [`write_with`]).
pub fn write_str(text: &str) {
    write_with(|out| out.write_all(text.as_bytes()));
}

/// The exit code of a command that returned `code`: 2 if writing its output failed for a
/// reason other than a closed pipe, else `code`.
pub fn exit_code(code: ExitCode) -> ExitCode {
    if FAILED.load(Ordering::Relaxed) {
        ExitCode::from(2)
    } else {
        code
    }
}

/// `print!` that ends quietly on a closed pipe.
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::cli::stdout::write_with(|o| ::std::io::Write::write_fmt(o, format_args!($($arg)*)))
    };
}

/// `println!` that ends quietly on a closed pipe.
macro_rules! outln {
    () => {
        $crate::cli::stdout::write_str("\n")
    };
    ($($arg:tt)*) => {
        $crate::cli::stdout::write_with(|o| {
            ::std::io::Write::write_fmt(o, format_args!($($arg)*))?;
            ::std::io::Write::write_all(o, b"\n")
        })
    };
}
