//! Where a run's results are: the files a mining run (or a split's) published in its output
//! directory, each by its name there and its path, so a caller reads the results it was handed
//! instead of knowing the layout (`crate::pipeline::output` describes it).

use std::path::{Path, PathBuf};

use crate::pipeline::output::{OutputNames, MATCHES_JSON, PAIRS_DIR, SCORED_PICKLE, SUMMARY_JSON};

/// One file a run published.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutputFile {
    /// Its name in the output directory (`predictions.feather`).
    pub name: &'static str,
    /// Its path (`OUT/predictions.feather`).
    pub path: PathBuf,
}

impl OutputFile {
    fn new(dir: &Path, name: &'static str) -> OutputFile {
        OutputFile {
            name,
            path: dir.join(name),
        }
    }
}

/// The files a run published in its output directory.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Outputs {
    /// The output directory.
    pub dir: PathBuf,
    /// The predictions as the long Arrow table (`predictions.feather`, a split's
    /// `submission.feather`).
    pub table: OutputFile,
    /// The official pickle (`predictions.pkl` when asked for, a split's `submission.pkl`).
    pub pickle: Option<OutputFile>,
    /// One entry per matched track (`matches.json`).
    pub matches: OutputFile,
    /// Every pair's status and the stage times (`summary.json`).
    pub summary: OutputFile,
    /// With ground truth: the scored sequences' predictions (`scored.pkl`), which `scenalog eval`
    /// scores as the run did.
    pub scored: Option<OutputFile>,
    /// With a report: its page (`report/index.html`).
    pub report: Option<PathBuf>,
    /// The per-pair records `resume` reads (`pairs/`).
    pub pairs: PathBuf,
    /// With `mine --rerun`: the Rerun recording (`matches.rrd`).
    pub rerun: Option<PathBuf>,
}

impl Outputs {
    /// The files of a run into `dir` named by `names`; `scored` says whether `scored.pkl` was
    /// written, `report` is the report's page when one was.
    pub(crate) fn of(
        dir: &Path,
        names: &OutputNames,
        scored: bool,
        report: Option<PathBuf>,
    ) -> Outputs {
        Outputs {
            dir: dir.to_path_buf(),
            table: OutputFile::new(dir, names.table),
            pickle: names
                .write_pickle
                .then(|| OutputFile::new(dir, names.pickle)),
            matches: OutputFile::new(dir, MATCHES_JSON),
            summary: OutputFile::new(dir, SUMMARY_JSON),
            scored: scored.then(|| OutputFile::new(dir, SCORED_PICKLE)),
            report,
            pairs: dir.join(PAIRS_DIR),
            rerun: None,
        }
    }
}
