//! Scoring predictions against ground truth (`scenalog eval`, `scenalog.evaluate`) with the
//! official scenario-mining metrics: each side a file or bytes, optionally resampled and
//! filtered by range and drivable area. The result renders itself as `scenalog eval` prints
//! it ([`Evaluated::text`], [`Report::to_json`]) and writes the official metric files
//! ([`Evaluated::write_metrics`]).

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;
use std::sync::Arc;

use scenalog_eval::{EvalOptions, RoiMaps, Sampling, Submission};

use crate::api::error::{Error, ErrorKind, Field, Message};

pub use scenalog_eval::{ClassHota, Report};

/// One side of an evaluation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SubmissionSource {
    /// An official pickle or a long Arrow table, by path.
    File(PathBuf),
    /// An official pickle's bytes.
    Pickle(Vec<u8>),
    /// An Arrow IPC file's bytes (the long table).
    Arrow(Vec<u8>),
}

impl SubmissionSource {
    /// The submission; `what` names bytes in errors ("predictions", "ground truth").
    fn read(&self, what: &str) -> Result<Submission, Error> {
        match self {
            SubmissionSource::File(p) => scenalog_eval::read_any(p),
            SubmissionSource::Pickle(b) => scenalog_eval::read_pickle_bytes(b, what),
            SubmissionSource::Arrow(b) => scenalog_eval::table_from_bytes(b, what),
        }
        .map_err(Error::plain)
    }
}

/// Which frames are evaluated.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Frames {
    /// Every frame of the sequences as they are.
    All,
    /// Resampled at this rate (Hz, at least 1).
    Rate(u32),
    /// The timestamps of a JSON file `{log_id: [timestamp_ns, …]}`.
    TimestampsFile(PathBuf),
    /// These timestamps (ns) per log id.
    Timestamps(BTreeMap<String, BTreeSet<i64>>),
}

/// An evaluation.
#[derive(Clone, Debug, PartialEq)]
pub struct EvalRequest {
    /// The predictions.
    pub pred: SubmissionSource,
    /// The ground truth.
    pub gt: SubmissionSource,
    /// Objects farther than this from the ego (x-y, metres, finite, above 0) are not evaluated.
    pub max_range_m: f64,
    /// A dataset directory (`<log_id>/map/…`): objects outside the drivable area grown by 5 m
    /// are not evaluated (the official `dataset_dir`).
    pub dataset_dir: Option<PathBuf>,
    /// Which frames.
    pub frames: Frames,
    /// Score only the ground truth's sequences the predictions hold (as `mine --gt` scores a
    /// run); without it a ground-truth sequence missing from the predictions is an error, as in
    /// the official evaluation.
    pub only_predicted: bool,
}

/// An evaluation's report, and how many ground-truth sequences `only_predicted` left out.
#[derive(Clone, Debug)]
pub struct Evaluated {
    /// The metrics.
    pub report: Report,
    /// Ground-truth sequences not scored because the predictions do not hold them (0 unless
    /// [`EvalRequest::only_predicted`]).
    pub left_out: usize,
    /// Ground-truth sequences before any was left out.
    pub gt_sequences: usize,
}

impl EvalRequest {
    /// `pred` against `gt` with the official defaults (50 m, no drivable-area filter, every
    /// frame).
    pub fn new(pred: SubmissionSource, gt: SubmissionSource) -> EvalRequest {
        EvalRequest {
            pred,
            gt,
            max_range_m: 50.0,
            dataset_dir: None,
            frames: Frames::All,
            only_predicted: false,
        }
    }
}

/// The metrics of the request's predictions against its ground truth.
pub fn evaluate(request: &EvalRequest) -> Result<Report, Error> {
    evaluate_counted(request).map(|e| e.report)
}

/// [`evaluate`], saying how many ground-truth sequences were left out.
pub fn evaluate_counted(request: &EvalRequest) -> Result<Evaluated, Error> {
    let m = request.max_range_m;
    if !(m.is_finite() && m > 0.0) {
        return Err(Error::about(
            Field::MaxRangeM,
            format!("expected a finite number greater than 0, got {m}"),
        )
        .of_kind(ErrorKind::Invalid));
    }
    if request.frames == Frames::Rate(0) {
        return Err(
            Error::about(Field::Rate, "expected at least 1 (Hz)").of_kind(ErrorKind::Invalid)
        );
    }
    let mut pred = request.pred.read("predictions")?;
    let mut gt = request.gt.read("ground truth")?;
    let gt_sequences = gt.sequences.len();
    if request.only_predicted {
        gt.sequences.retain(|k, _| pred.sequences.contains_key(k));
    }
    let left_out = gt_sequences - gt.sequences.len();
    let sampling = match &request.frames {
        Frames::All => None,
        Frames::Rate(hz) => Some(Sampling::Rate(*hz)),
        Frames::TimestampsFile(path) => Some(Sampling::Timestamps(
            scenalog_eval::read_timestamps(path).map_err(|e| Error::about(Field::Timestamps, e))?,
        )),
        Frames::Timestamps(t) => Some(Sampling::Timestamps(t.clone())),
    };
    if let Some(s) = &sampling {
        scenalog_eval::resample(&mut pred, &mut gt, s).map_err(Error::plain)?;
    }
    let roi = match &request.dataset_dir {
        None => None,
        Some(dir) => {
            let ids = gt.sequences.keys().chain(pred.sequences.keys());
            let maps = RoiMaps::load(dir, ids.map(|k| k.0.as_str()))
                .map_err(|e| Error::about(Field::DatasetDir, e))?;
            Some(Arc::new(maps))
        }
    };
    let opts = EvalOptions {
        max_range_m: request.max_range_m,
        roi,
    };
    let missing = gt.sequences.keys().any(|k| !pred.sequences.contains_key(k));
    let report = scenalog_eval::evaluate(&pred, &gt, &opts).map_err(|e| {
        let error = Error::plain(e);
        if missing && !request.only_predicted {
            error.with_hint(
                Message::text(
                    "(to score only the sequences the predictions hold, as `scenalog mine --gt` \
                     does, add ",
                )
                .mention(Field::OnlyPredicted)
                .then(")"),
            )
        } else {
            error
        }
    })?;
    Ok(Evaluated {
        report,
        left_out,
        gt_sequences,
    })
}

/// Timestamps per log id from JSON text `{log_id: [timestamp_ns, …]}` (as RefAV's
/// `eval_timestamps.json`), for [`Frames::Timestamps`].
pub fn timestamps_from_json(text: &str) -> Result<BTreeMap<String, BTreeSet<i64>>, Error> {
    scenalog_eval::parse_timestamps(text, "timestamps").map_err(Error::plain)
}

impl Evaluated {
    /// The text `scenalog eval` prints: the headline metrics, the paper's further columns (`-`
    /// and why where the ground truth has no such object), and with `per_prompt` a table of
    /// every prompt's values.
    pub fn text(&self, per_prompt: bool) -> String {
        let report = &self.report;
        let f = &report.further;
        let mut out = format!(
            "HOTA-Temporal: {}\nHOTA-Track: {}\nTimestamp-level Balanced Accuracy: {}\n\
             Log-level Balanced Accuracy: {}\n",
            report.hota_temporal, report.hota_track, report.timestamp_ba, report.log_ba
        );
        out.push_str(&format!(
            "HOTA-Temporal (related objects): {}\n",
            shown(f.related.value(), "no related object in the ground truth")
        ));
        out.push_str(&format!(
            "HOTA-Temporal (other objects): {}\n",
            shown(f.other.value(), "no other object in the ground truth")
        ));
        out.push_str(&format!(
            "HOTA (tracker, every object): {}\n",
            shown(f.tracker.value(), "no object in the ground truth")
        ));
        if !per_prompt {
            return out;
        }
        out.push_str(
            "\nprompt\tHOTA-Temporal\tHOTA-Track\ttimestamp BA\tlog BA\tHOTA-Temporal related\t\
             HOTA-Temporal other\tHOTA\n",
        );
        let by = |c: &ClassHota, prompt: &str| {
            let v = c
                .by_prompt
                .get(prompt)
                .and_then(|h| h.as_ref().map(|h| h.value));
            v.map_or_else(|| "-".to_string(), |v| v.to_string())
        };
        for (prompt, ts) in &report.timestamp_ba_by_prompt {
            let ht = report
                .hota_temporal_by_prompt
                .get(prompt)
                .map_or(0.0, |h| h.value);
            let hk = report
                .hota_track_by_prompt
                .get(prompt)
                .map_or(0.0, |h| h.value);
            let lb = report
                .log_ba_by_prompt
                .get(prompt)
                .copied()
                .unwrap_or(f64::NAN);
            let (rel, oth, trk) = (
                by(&f.related, prompt),
                by(&f.other, prompt),
                by(&f.tracker, prompt),
            );
            out.push_str(&format!(
                "{prompt}\t{ht}\t{hk}\t{ts}\t{lb}\t{rel}\t{oth}\t{trk}\n"
            ));
        }
        out
    }

    /// Writes `temporal_metrics.json` and `spatiotemporal_metrics.json` (as the official code)
    /// and `paper_metrics.json` (HOTA-Temporal of related and other objects, the tracker's HOTA)
    /// into `dir` (created), each atomically.
    pub fn write_metrics(&self, dir: &std::path::Path) -> Result<(), Error> {
        let (temporal, spatio) = self.report.official_json();
        let mut files = vec![("temporal_metrics.json", temporal)];
        if let Some(s) = spatio {
            files.push(("spatiotemporal_metrics.json", s));
        }
        files.push(("paper_metrics.json", self.report.paper_json()));
        std::fs::create_dir_all(dir)
            .map_err(|e| Error::plain(format!("{}: {e}", dir.display())))?;
        for (name, v) in &files {
            crate::pipeline::output::write_atomic(
                &dir.join(name),
                format!("{v:#}\n").as_bytes(),
                true,
            )
            .map_err(Error::plain)?;
        }
        Ok(())
    }
}

/// A value, or `-` and why there is none.
fn shown(v: Option<f64>, why_none: &str) -> String {
    v.map_or_else(|| format!("- ({why_none})"), |v| v.to_string())
}
