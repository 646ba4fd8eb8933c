//! Resuming a run: a (log, program) pair's fingerprint (the program, the log's files, the
//! options that change its output) and a pair an earlier run wrote read back instead of mined.

use super::*;

/// A pair's earlier record, when `resume` is on and the record matches this run (same program
/// text, description and output timestamps).
pub(crate) fn resumable(
    log: &LogInput,
    scenario: &Scenario,
    options: &RunOptions,
    fingerprint: &str,
) -> Option<PairRecord> {
    if !options.resume {
        return None;
    }
    let path = output::pair_path(&options.out, &log.log_id, &scenario.name);
    let record = output::read_record(&path)?;
    let same = record.log_id == log.log_id
        && record.description == scenario.description
        && record.source == scenario.source
        && record.timestamps.as_ref() == options.timestamps.get(&log.log_id)
        && record.fingerprint == fingerprint;
    same.then_some(record)
}

/// A pair's resume key: SHA-256 over the tool's version, the log's input fingerprint, the
/// program text, its description and the output timestamps.
pub(crate) fn pair_fingerprint(
    log_fingerprint: &str,
    scenario: &Scenario,
    timestamps: Option<&Vec<i64>>,
) -> String {
    use sha2::{Digest, Sha256};
    let mut h = Sha256::new();
    for part in [
        env!("CARGO_PKG_VERSION"),
        log_fingerprint,
        &scenario.source,
        &scenario.description,
        &format!("{timestamps:?}"),
    ] {
        h.update((part.len() as u64).to_le_bytes());
        h.update(part.as_bytes());
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// A fingerprint of what a log's scene is made of: the bytes of its annotations (or the tracker
/// file's fingerprint), ego poses and map files. Unreadable files count as absent (the load
/// itself reports them).
pub(crate) fn log_fingerprint(log: &LogInput) -> String {
    use sha2::{Digest, Sha256};
    let mut h = Sha256::new();
    let mut files: Vec<PathBuf> = Vec::new();
    match &log.tracker {
        Some(t) => {
            h.update(t.fingerprint.as_bytes());
            h.update(log.log_id.as_bytes());
        }
        None => {
            for name in [
                scenalog_facts::read::ANNOTATIONS_WITH_EGO_FILE,
                scenalog_facts::read::ANNOTATIONS_FILE,
            ] {
                files.push(log.dir.join(name));
            }
        }
    }
    files.push(log.dir.join(scenalog_facts::read::EGO_POSES_FILE));
    if let Ok(entries) = std::fs::read_dir(log.dir.join("map")) {
        let mut maps: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        maps.sort();
        files.extend(maps);
    }
    for f in files {
        h.update(f.to_string_lossy().as_bytes());
        match scenalog_input::read_regular_file(&f, scenalog_input::DATA_LIMIT) {
            Ok(bytes) => {
                h.update((bytes.len() as u64).to_le_bytes());
                h.update(&bytes);
            }
            Err(_) => h.update(b"absent"),
        }
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// Rebuilds a finished pair from its record; `None` when the record's tuples do not fit the
/// scene (the log changed), so the pair is mined again.
pub(crate) fn resume_pair(
    ctx: &PairContext<'_>,
    extractor: &Extractor<'_>,
    scenario: &Scenario,
    index: usize,
    record: PairRecord,
) -> Option<PairResult> {
    let scene = ctx.scene;
    let t = Instant::now();
    let n_tracks = scene.tracks.len();
    let n_frames = scene.num_frames();
    let track = |i: u32| ((i as usize) < n_tracks).then_some(TrackId(i));
    let frame = |f: Frame| ((f as usize) < n_frames).then_some(f);
    let referred: Vec<(TrackId, Frame)> = record
        .referred
        .iter()
        .map(|&(v, f)| Some((track(v)?, frame(f)?)))
        .collect::<Option<_>>()?;
    let related: Vec<(TrackId, TrackId, Frame)> = record
        .related
        .iter()
        .map(|&(v, o, f)| Some((track(v)?, track(o)?, frame(f)?)))
        .collect::<Option<_>>()?;
    if record.tracks != n_tracks {
        return None;
    }
    let (out, matches) = build_pair(ctx, extractor, scenario, &referred, &related);
    Some(PairResult {
        log_id: scene.log_id.clone(),
        scenario: index,
        status: PairStatus::Resumed,
        frames: out,
        matches,
        evaluate: Duration::ZERO,
        tracks: t.elapsed(),
        write: Duration::ZERO,
    })
}
