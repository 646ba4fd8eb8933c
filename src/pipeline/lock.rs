//! One writer per output folder: a command that writes an output folder (`mine`, `import refav`,
//! `synth --out`) holds `OUT/.lock` for as long as it writes there. The lock is an advisory
//! `flock` on that file, which the system releases when the holder exits however it exits, so a
//! lock of a dead process is stale by construction and the next run takes it over; the file's text
//! names the holder (pid, start time, command line) for the message a second run is refused with.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

/// The symbolic link to the published generation (see `super::output`'s documentation): a
/// run's own link, which [`refuse_foreign_links`] accepts.
pub const CURRENT: &str = ".current";

/// The lock file's name in an output folder.
pub const LOCK_FILE: &str = ".lock";

/// A held output folder; released (and its holder text cleared) when dropped.
#[derive(Debug)]
pub struct OutputLock {
    file: File,
    path: PathBuf,
    /// The holder a stale lock named, when this one took it over.
    pub took_over: Option<String>,
}

/// `OUT/.lock`.
pub fn lock_path(dir: &Path) -> PathBuf {
    dir.join(LOCK_FILE)
}

impl OutputLock {
    /// Holds `dir` (created if missing) for this process. A folder another live process holds is
    /// an error naming that holder; a lock file left by a process no longer running is taken
    /// over (its holder is kept in [`OutputLock::took_over`]).
    ///
    /// # Errors
    /// The folder is held, or the lock file cannot be created, locked or written.
    pub fn acquire(dir: &Path) -> Result<OutputLock, String> {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create output directory `{}`: {e}", dir.display()))?;
        let path = lock_path(dir);
        let cannot = |e: std::io::Error| format!("cannot lock `{}`: {e}", path.display());
        let mut file = scenalog_input::out_dir::open_no_follow(&path).map_err(cannot)?;
        let previous = read_holder(&mut file);
        if let Err(e) = try_lock(&file) {
            if e.kind() != std::io::ErrorKind::WouldBlock {
                return Err(cannot(e));
            }
            let holder =
                previous.unwrap_or_else(|| "a process that has not named itself yet".into());
            return Err(format!(
                "`{}` is in use by another run ({holder}); wait for it to finish or write to \
                 another folder (its lock: `{}`)",
                dir.display(),
                path.display()
            ));
        }
        // Held: nobody else of ours writes here now; a link someone planted is refused before
        // anything is written through it.
        refuse_foreign_links(dir)?;
        let holder = format!(
            "pid {}, started {}, command `{}`",
            std::process::id(),
            utc_now(),
            command_line()
        );
        file.set_len(0).map_err(cannot)?;
        file.seek(SeekFrom::Start(0)).map_err(cannot)?;
        file.write_all(format!("{holder}\n").as_bytes())
            .and_then(|()| file.flush())
            .map_err(cannot)?;
        Ok(OutputLock {
            file,
            path,
            took_over: previous,
        })
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Cleared while still held: a lock file with a holder and no lock is a crashed run's.
        let _ = self.file.set_len(0);
    }
}

/// An error naming every link in the output folder `dir` that no run of ours made
/// ([`scenalog_input::out_dir::refuse_links`]); checked when the folder is created and again
/// once it is held.
///
/// # Errors
/// A link someone else made is in `dir`.
pub fn refuse_foreign_links(dir: &Path) -> Result<(), String> {
    scenalog_input::out_dir::refuse_links(dir, &published_link)
}

/// Whether a link in an output folder is one a run makes when it publishes its outputs
/// (`OUT/<name> -> .current/<name>`, `OUT/.current -> .staging-<pid>-<n>`, and their temporary
/// names left by a killed run): at the folder's top level, pointing at a plain name inside it.
fn published_link(rel: &Path, target: &Path) -> bool {
    use std::path::Component;
    let plain = |c: Option<Component>| matches!(c, Some(Component::Normal(_)));
    let mut top = rel.components();
    if !(plain(top.next()) && top.next().is_none()) {
        return false;
    }
    let parts: Vec<Component> = target.components().collect();
    match parts.as_slice() {
        [Component::Normal(g)] => g.to_string_lossy().starts_with(".staging-"),
        [Component::Normal(c), n] => c.to_str() == Some(CURRENT) && plain(Some(*n)),
        _ => false,
    }
}

/// The holder a lock file names, if it names one.
fn read_holder(file: &mut File) -> Option<String> {
    let mut text = String::new();
    file.take(4096).read_to_string(&mut text).ok()?;
    let text = text.trim();
    (!text.is_empty()).then(|| text.to_string())
}

#[cfg(unix)]
fn try_lock(file: &File) -> std::io::Result<()> {
    use rustix::fs::{flock, FlockOperation};
    flock(file, FlockOperation::NonBlockingLockExclusive).map_err(|e| {
        if e == rustix::io::Errno::WOULDBLOCK {
            std::io::Error::from(std::io::ErrorKind::WouldBlock)
        } else {
            std::io::Error::from_raw_os_error(e.raw_os_error())
        }
    })
}

#[cfg(not(unix))]
fn try_lock(_file: &File) -> std::io::Result<()> {
    Ok(())
}

/// This process's command line, arguments separated by spaces.
fn command_line() -> String {
    std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Now, UTC, as `YYYY-MM-DD HH:MM:SS UTC`.
fn utc_now() -> String {
    let secs = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    utc_text(secs)
}

/// Seconds since 1970 as a UTC date and time (the civil calendar from a day count).
fn utc_text(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let rem = secs % 86_400;
    // Days since 0000-03-01, then 400-year eras (Howard Hinnant's `civil_from_days`).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1_460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02} UTC",
        rem / 3_600,
        rem % 3_600 / 60,
        rem % 60
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utc_text_is_the_calendar_date() {
        assert_eq!(utc_text(0), "1970-01-01 00:00:00 UTC");
        assert_eq!(utc_text(951_782_400), "2000-02-29 00:00:00 UTC");
        assert_eq!(utc_text(1_700_000_000), "2023-11-14 22:13:20 UTC");
    }

    #[test]
    fn a_held_folder_is_refused_and_a_stale_lock_taken_over() {
        let dir = tempfile::tempdir().expect("tempdir");
        std::fs::write(lock_path(dir.path()), "pid 4000000, started long ago\n").expect("write");
        let held = OutputLock::acquire(dir.path()).expect("a stale lock is taken over");
        assert_eq!(
            held.took_over.as_deref(),
            Some("pid 4000000, started long ago")
        );
        let me = format!("pid {}", std::process::id());
        let text = std::fs::read_to_string(held.path()).expect("read");
        assert!(text.starts_with(&me), "{text}");
        // A second holder (another open file description, as another process has) is refused.
        let refused = OutputLock::acquire(dir.path()).expect_err("held");
        assert!(
            refused.contains(&me) && refused.contains("in use"),
            "{refused}"
        );
        drop(held);
        assert_eq!(
            std::fs::read_to_string(lock_path(dir.path())).expect("read"),
            ""
        );
        let again = OutputLock::acquire(dir.path()).expect("released");
        assert_eq!(again.took_over, None);
    }
}
