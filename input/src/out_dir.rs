//! Writing into an output folder without following a link someone else planted there: a folder
//! is shared with whoever can write to it, and a link at a path a writer opens (`OUT/.lock`,
//! `OUT/pairs`, a temporary file's predictable name) would send the write to the link's target.
//!
//! Three rules, used by every writer of the workspace:
//! - a file is replaced through a temporary file created new (`O_EXCL`, and `O_NOFOLLOW` on
//!   Unix: a link planted at the temporary name is an error, never followed) and renamed over
//!   the destination (a rename replaces a link, it does not write through it): [`write_atomic`];
//! - a file written in place is opened with [`open_no_follow`];
//! - a folder a command writes into is first checked for links it did not make:
//!   [`refuse_links`] names each one, so the command stops before writing anything.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

static TMP_COUNTER: AtomicUsize = AtomicUsize::new(0);

/// Options that never follow a link at the path's last component (Unix; elsewhere as given).
fn no_follow(options: &mut OpenOptions) -> &mut OpenOptions {
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NOFOLLOW);
    }
    options
}

/// Opens `path` for reading and writing, creating it when missing, never through a link at
/// `path` (an error, `ELOOP` on Unix) and never truncating it; a path that is not a regular file
/// (a FIFO, a device) is an error too.
///
/// # Errors
/// The file cannot be opened or created, is a link, or is not a regular file.
pub fn open_no_follow(path: &Path) -> std::io::Result<File> {
    let file = no_follow(
        OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false),
    )
    .open(path)
    .map_err(|e| explain_link(path, e))?;
    if !file.metadata()?.is_file() {
        return Err(std::io::Error::other("not a regular file"));
    }
    Ok(file)
}

/// Creates `path` as a new file (an existing file or a link there is an error), for writing.
///
/// # Errors
/// Something is already at `path`, or it cannot be created.
pub fn create_new(path: &Path) -> std::io::Result<File> {
    no_follow(OpenOptions::new().write(true).create_new(true))
        .open(path)
        .map_err(|e| explain_link(path, e))
}

/// A clearer error when `path` is a link that was not followed.
fn explain_link(path: &Path, e: std::io::Error) -> std::io::Error {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => std::io::Error::other(format!(
            "it is a symbolic link{}, which is not followed in an output folder",
            target_text(path)
        )),
        _ => e,
    }
}

/// ` (to `TARGET`)` for a link whose target can be read.
fn target_text(path: &Path) -> String {
    std::fs::read_link(path)
        .map(|t| format!(" (to `{}`)", t.display()))
        .unwrap_or_default()
}

/// Replaces `path` with `bytes`: a temporary file `.<name>.<pid>-<n>.tmp` beside it, created new
/// and never through a link, synced when `sync`, then renamed over `path` (a link at `path` is
/// replaced, not written through). The parent directory must exist. On failure the temporary
/// file is removed and `path` is unchanged.
///
/// # Errors
/// The temporary file cannot be created or written, or the rename fails.
pub fn write_atomic(path: &Path, bytes: &[u8], sync: bool) -> std::io::Result<()> {
    let parent = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".to_string());
    let n = TMP_COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp = parent.join(format!(".{name}.{}-{n}.tmp", std::process::id()));
    let mut f = create_new(&tmp)?;
    let written = (|| {
        f.write_all(bytes)?;
        if sync {
            f.sync_all()?;
        }
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written
}

/// The links under `dir` (recursively, never through a link), each with its target, but those
/// `ours(relative path, target)` accepts: a command's own links (a published output pointing
/// into its generation folder).
pub fn links_under(dir: &Path, ours: &dyn Fn(&Path, &Path) -> bool) -> Vec<(PathBuf, PathBuf)> {
    let mut found = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let Ok(kind) = e.file_type() else { continue };
            let path = e.path();
            if kind.is_symlink() {
                let target = std::fs::read_link(&path).unwrap_or_default();
                let rel = path.strip_prefix(dir).unwrap_or(&path);
                if !ours(rel, &target) {
                    found.push((path, target));
                }
            } else if kind.is_dir() {
                todo.push(path);
            }
        }
    }
    found.sort();
    found
}

/// An error naming the links under `dir` that `ours` does not accept ([`links_under`]); `Ok`
/// when there are none. The message names up to five and says what to do.
///
/// # Errors
/// A link not accepted is in `dir`.
pub fn refuse_links(dir: &Path, ours: &dyn Fn(&Path, &Path) -> bool) -> Result<(), String> {
    let links = links_under(dir, ours);
    if links.is_empty() {
        return Ok(());
    }
    let shown: Vec<String> = links
        .iter()
        .take(5)
        .map(|(p, t)| format!("`{}` -> `{}`", p.display(), t.display()))
        .collect();
    let more = match links.len() {
        n if n > 5 => format!(" and {} more", n - 5),
        _ => String::new(),
    };
    Err(format!(
        "the output folder `{}` holds symbolic links Scenalog did not make: {}{more}; links in \
         an output folder are never followed: remove them or write to another folder",
        dir.display(),
        shown.join(", ")
    ))
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::os::unix::fs::symlink;

    #[test]
    fn a_link_at_the_temporary_or_final_name_is_never_written_through() {
        let t = tempfile::tempdir().expect("tempdir");
        let victim = t.path().join("victim");
        std::fs::write(&victim, "keep").expect("write");
        let out = t.path().join("out");
        std::fs::create_dir(&out).expect("mkdir");
        // A link at the final name is replaced.
        symlink(&victim, out.join("a.json")).expect("link");
        write_atomic(&out.join("a.json"), b"new", true).expect("write");
        assert_eq!(std::fs::read_to_string(&victim).expect("read"), "keep");
        assert_eq!(
            std::fs::read_to_string(out.join("a.json")).expect("read"),
            "new"
        );
        // A link at the next temporary name is an error, not followed.
        let n = TMP_COUNTER.load(Ordering::Relaxed);
        let tmp = out.join(format!(".b.json.{}-{n}.tmp", std::process::id()));
        symlink(&victim, &tmp).expect("link");
        let e = write_atomic(&out.join("b.json"), b"new", false).expect_err("planted");
        assert!(e.to_string().contains("symbolic link"), "{e}");
        assert_eq!(std::fs::read_to_string(&victim).expect("read"), "keep");
        assert!(!out.join("b.json").exists());
    }

    #[test]
    fn open_no_follow_refuses_a_link_and_a_fifo_and_keeps_the_content() {
        let t = tempfile::tempdir().expect("tempdir");
        let victim = t.path().join("victim");
        std::fs::write(&victim, "keep").expect("write");
        let lock = t.path().join(".lock");
        symlink(&victim, &lock).expect("link");
        let e = open_no_follow(&lock).expect_err("a link");
        assert!(e.to_string().contains("symbolic link"), "{e}");
        assert_eq!(std::fs::read_to_string(&victim).expect("read"), "keep");
        std::fs::write(t.path().join("plain"), "text").expect("write");
        open_no_follow(&t.path().join("plain")).expect("a file");
        assert_eq!(
            std::fs::read_to_string(t.path().join("plain")).expect("read"),
            "text",
            "not truncated"
        );
    }

    #[test]
    fn links_are_found_at_any_depth_and_named_but_ours_pass() {
        let t = tempfile::tempdir().expect("tempdir");
        let out = t.path();
        std::fs::create_dir_all(out.join("pairs/log")).expect("mkdir");
        symlink("/tmp", out.join("pairs/elsewhere")).expect("link");
        symlink("/etc/passwd", out.join("pairs/log/p.json")).expect("link");
        symlink(".current/x", out.join("x")).expect("link");
        let ours =
            |rel: &Path, target: &Path| rel == Path::new("x") && target.starts_with(".current");
        let found = links_under(out, &ours);
        assert_eq!(found.len(), 2, "{found:?}");
        let e = refuse_links(out, &ours).expect_err("links");
        assert!(
            e.contains("pairs/elsewhere") && e.contains("/etc/passwd"),
            "{e}"
        );
        std::fs::remove_file(out.join("pairs/elsewhere")).expect("rm");
        std::fs::remove_file(out.join("pairs/log/p.json")).expect("rm");
        refuse_links(out, &ours).expect("only ours left");
    }
}
