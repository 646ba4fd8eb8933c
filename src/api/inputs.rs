//! What the requests read before they run, shared by [`crate::api::mine`],
//! [`crate::api::split`] and [`crate::api::synth`]: the bundled scenario library and sample logs,
//! the default output directory, rule files and log directories found as `--rules` and `--logs`
//! find them, output timestamps, programs checked and named uniquely, and the checks of the
//! fields every run has (threads).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use crate::api::error::{invalid, Error, ErrorKind, Field};
use crate::pipeline::run::LogInput;
use crate::pipeline::scenario::Scenario;

/// Where the workspace was built: the bundled library and sample logs are found from here.
pub(crate) const MANIFEST_DIR: &str = env!("CARGO_MANIFEST_DIR");
/// The scenario library, relative to the workspace.
pub const LIBRARY: &str = "rules/library";
/// The bundled sample logs, relative to the workspace.
pub const SAMPLE_LOGS: &str = "tests/data/av2/logs";
/// The bundled ground truth of the sample logs, relative to the workspace.
pub const SAMPLE_GT: &str = "tests/data/av2/eval/combined_gt_dev.pkl";

/// A bundled path: under the workspace the binary was built from, else under the current
/// directory; `None` when neither exists.
pub fn bundled(rel: &str) -> Option<PathBuf> {
    [Path::new(MANIFEST_DIR).join(rel), PathBuf::from(rel)]
        .into_iter()
        .find(|p| p.exists())
}

/// `target/scenalog-mine` in the workspace the binary was built from (ignored by git, even when
/// the build itself went to another `CARGO_TARGET_DIR`), else `./scenalog-out` when the binary
/// runs away from its sources.
pub fn default_out() -> PathBuf {
    let workspace = Path::new(MANIFEST_DIR);
    if workspace.join("Cargo.toml").is_file() {
        workspace.join("target").join("scenalog-mine")
    } else {
        PathBuf::from("scenalog-out")
    }
}

/// Worker threads checked: 1 to 1024.
pub(crate) fn check_threads(threads: Option<usize>) -> Result<(), Error> {
    match threads {
        Some(n) if !(1..=1024).contains(&n) => Err(invalid(
            Field::Threads,
            format!("expected 1 to 1024, got {n}"),
        )),
        _ => Ok(()),
    }
}

/// Creates the output directory; one holding a link no run of ours made is an error naming it
/// (nothing is written through a link planted there).
pub(crate) fn create_out(out: &Path) -> Result<(), Error> {
    std::fs::create_dir_all(out).map_err(|e| {
        Error::plain(format!(
            "cannot create output directory `{}`: {e}",
            out.display()
        ))
    })?;
    crate::pipeline::lock::refuse_foreign_links(out).map_err(Error::plain)
}

/// Reads the output timestamps: `{"<log_id>": [timestamp_ns, …], …}`.
pub fn read_timestamps(path: &Path) -> Result<BTreeMap<String, Vec<i64>>, Error> {
    let text = crate::input::read_text(path).map_err(|e| Error::about(Field::EvalTimestamps, e))?;
    let timestamps: BTreeMap<String, Vec<i64>> = serde_json::from_str(&text).map_err(|e| {
        Error::about(
            Field::EvalTimestamps,
            format!(
                "`{}`: expected a JSON object mapping log ids to lists of integer timestamps \
                 (ns): {e}",
                path.display()
            ),
        )
    })?;
    for log in timestamps.keys() {
        scenalog_input::check_log_id(log).map_err(|e| {
            Error::about(Field::EvalTimestamps, format!("`{}`: {e}", path.display()))
        })?;
    }
    Ok(timestamps)
}

/// The `.dl` files of rule paths: files as given, directories' `.dl` files sorted by name.
pub fn rule_files(paths: &[PathBuf]) -> Result<Vec<PathBuf>, Error> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut files: Vec<PathBuf> = std::fs::read_dir(p)
                .map_err(|e| {
                    Error::about(
                        Field::Rules,
                        format!("cannot read directory `{}`: {e}", p.display()),
                    )
                })?
                .filter_map(|e| e.ok().map(|e| e.path()))
                // Anything named *.dl but a directory is kept, so a FIFO or a dangling link
                // is reported when read rather than skipped in silence.
                .filter(|f| !f.is_dir() && f.extension().is_some_and(|x| x == "dl"))
                .collect();
            files.sort();
            if files.is_empty() {
                return Err(Error::about(
                    Field::Rules,
                    format!("no .dl file in `{}`", p.display()),
                ));
            }
            out.extend(files);
        } else {
            match scenalog_input::regular_file(p) {
                Ok(_) => out.push(p.clone()),
                Err(problem) => {
                    let kind = match problem {
                        scenalog_input::FileProblem::NotFound => ErrorKind::NotFound,
                        _ => ErrorKind::Failed,
                    };
                    return Err(
                        Error::about(Field::Rules, format!("`{}` {problem}", p.display()))
                            .of_kind(kind),
                    );
                }
            }
        }
    }
    Ok(out)
}

/// Whether a directory looks like one AV2 log (rather than a directory of logs).
fn is_log_dir(p: &Path) -> bool {
    p.join("city_SE3_egovehicle.feather").exists()
        || p.join("annotations.feather").exists()
        || p.join("annotations_with_ego.feather").exists()
        || p.join("map").is_dir()
}

/// The logs of log paths (a log directory, or a directory whose subdirectories are logs,
/// sorted by name), and the duplicates left out (same log id twice).
pub fn log_dirs(paths: &[PathBuf]) -> Result<(Vec<LogInput>, Vec<String>), Error> {
    let mut dirs = Vec::new();
    for p in paths {
        if !p.is_dir() {
            let kind = if p.exists() {
                ErrorKind::Failed
            } else {
                ErrorKind::NotFound
            };
            return Err(
                Error::about(Field::Logs, format!("`{}` is not a directory", p.display()))
                    .of_kind(kind),
            );
        }
        if is_log_dir(p) {
            dirs.push(p.clone());
            continue;
        }
        let mut subs: Vec<PathBuf> = std::fs::read_dir(p)
            .map_err(|e| {
                Error::about(
                    Field::Logs,
                    format!("cannot read directory `{}`: {e}", p.display()),
                )
            })?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|d| {
                d.is_dir()
                    && !d
                        .file_name()
                        .is_some_and(|n| n.to_string_lossy().starts_with('.'))
            })
            .collect();
        subs.sort();
        if subs.is_empty() {
            return Err(Error::about(
                Field::Logs,
                format!(
                    "`{}` is neither a log directory nor a directory of logs",
                    p.display()
                ),
            ));
        }
        dirs.extend(subs);
    }
    let mut seen = BTreeSet::new();
    let mut logs = Vec::new();
    let mut problems = Vec::new();
    for d in dirs {
        let log = LogInput::new(d).map_err(|e| Error::about(Field::Logs, e))?;
        if seen.insert(log.log_id.clone()) {
            logs.push(log);
        } else {
            problems.push(format!(
                "log `{}`: a log with id {} is already in the run; left out",
                log.dir.display(),
                log.log_id
            ));
        }
    }
    Ok((logs, problems))
}

/// The logs of `logs` as [`log_dirs`] finds them, or the bundled sample logs when none are
/// given (`missing` is the error's text when they are not bundled either); duplicates left out.
pub fn logs_or_samples(logs: &[PathBuf], missing: &str) -> Result<Vec<LogInput>, Error> {
    let paths: Vec<PathBuf> = if logs.is_empty() {
        vec![bundled(SAMPLE_LOGS).ok_or_else(|| Error::about(Field::Logs, missing))?]
    } else {
        logs.to_vec()
    };
    Ok(log_dirs(&paths)?.0)
}

/// Checks every program; those that do not check, and those whose description another program
/// already has (predictions are keyed by it), are failures. Names are made unique (`name-2`…)
/// so every pair has its own files.
pub fn scenarios_of(
    loaded: Vec<(PathBuf, Result<Scenario, String>)>,
    failures: &mut Vec<String>,
) -> Vec<Scenario> {
    let mut out: Vec<Scenario> = Vec::new();
    let mut names = BTreeSet::new();
    let mut descriptions: BTreeMap<String, String> = BTreeMap::new();
    for (path, scenario) in loaded {
        let mut s = match scenario {
            Ok(s) => s,
            Err(e) => {
                failures.push(e);
                continue;
            }
        };
        if let Some(other) = descriptions.get(&s.description) {
            failures.push(format!(
                "`{}`: its description {:?} is already that of `{other}`; left out",
                path.display(),
                s.description
            ));
            continue;
        }
        descriptions.insert(s.description.clone(), path.display().to_string());
        let base = s.name.clone();
        let mut n = 1;
        while !names.insert(s.name.clone()) {
            n += 1;
            s.name = format!("{base}-{n}");
        }
        out.push(s);
    }
    out
}
