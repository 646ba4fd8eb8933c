//! `scenalog mine --report`: the run's browsable report, `OUT/report/index.html`, made from the
//! run's results after the run. Per pictured match, the (log, program) pair is evaluated again
//! with provenance, the proof is rendered as `scenalog explain` prints it, and pictures are
//! drawn at up to [`FRAMES_PER_MATCH`] frames spread over the referred span (the scrubber's
//! frames). Matches past `max_pictures` are listed with the command that pictures them. The
//! page itself is `scenalog-view`'s.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use rayon::prelude::*;
use scenalog_engine::explain;
use scenalog_extractors::cache::Extractor;
use scenalog_facts::relation::Value;
use scenalog_facts::scene::Frame;
use scenalog_facts::{load_scene, Scene};
use scenalog_view::{
    scene_svg, write_picture, Picture, Reference, Report, ReportFrame, ReportMatch,
};

use super::explain::{
    evaluate_for_explain, explanation_text, referred_frames, Explanation, Renderer,
};
use super::output::Match;
use super::picture::{explanation_picture, related_at};
use super::run::{LogInput, PairStatus, RunReport};
use super::scenario::Scenario;

/// The report's directory under the run's output directory.
pub const REPORT_DIR: &str = crate::pipeline::output::REPORT_DIR;
/// How many frames of a match are pictured (the scrubber's positions).
pub const FRAMES_PER_MATCH: usize = 6;
/// The pictures' size in pixels (shown at 480 px).
const PICTURE_PX: u32 = 640;

/// Up to `n` frames spread evenly from the first to the last of `frames` (sorted), both ends
/// included.
fn spread(frames: &[Frame], n: usize) -> Vec<Frame> {
    let (Some(&a), Some(&b)) = (frames.first(), frames.last()) else {
        return Vec::new();
    };
    let n = n.max(1);
    let mut out: Vec<Frame> = (0..n)
        .map(|i| {
            if n == 1 {
                a
            } else {
                a + ((b - a) as u64 * i as u64 / (n as u64 - 1)) as Frame
            }
        })
        .collect();
    out.dedup();
    out
}

/// The matches to picture: one from each pair in turn (table order), then a second from each,
/// and so on, up to `max`; as indices into `all`.
fn choose(all: &[(usize, usize, &Match)], max: usize) -> Vec<usize> {
    let mut per_pair: Vec<Vec<usize>> = Vec::new();
    let mut last: Option<(usize, usize)> = None;
    for (i, (s, l, _)) in all.iter().enumerate() {
        if last != Some((*s, *l)) {
            per_pair.push(Vec::new());
            last = Some((*s, *l));
        }
        if let Some(v) = per_pair.last_mut() {
            v.push(i);
        }
    }
    let mut chosen = Vec::new();
    let mut round = 0;
    while chosen.len() < max {
        let before = chosen.len();
        for v in &per_pair {
            if let Some(i) = v.get(round) {
                if chosen.len() < max {
                    chosen.push(*i);
                }
            }
        }
        if chosen.len() == before {
            break;
        }
        round += 1;
    }
    chosen.sort_unstable();
    chosen
}

/// One picture to draw: the file and what to draw.
struct Job<'a> {
    file: PathBuf,
    picture: Picture<'a>,
}

/// Writes `into/report/index.html` and its pictures (`into`: the run's generation directory,
/// published as `out/report/`); returns the page's path in `out`. Errors name the
/// file that could not be written; a log or program that fails here leaves its matches
/// without pictures (said on the page) rather than failing the report.
pub fn write_run_report(
    into: &Path,
    out: &Path,
    run: &RunReport,
    scenarios: &[Scenario],
    logs: &[LogInput],
    max_pictures: usize,
) -> Result<PathBuf, String> {
    let dir = into.join(REPORT_DIR);
    let img = dir.join("img");
    std::fs::create_dir_all(&img).map_err(|e| format!("cannot create `{}`: {e}", img.display()))?;
    let log_index = |id: &str| logs.iter().position(|l| l.log_id == id);
    let mut counts = vec![vec![Some(0usize); logs.len()]; scenarios.len()];
    let mut all: Vec<(usize, usize, &Match)> = Vec::new();
    for p in &run.pairs {
        let Some(li) = log_index(&p.log_id) else {
            continue;
        };
        if let Some(row) = counts.get_mut(p.scenario) {
            row[li] = match p.status {
                PairStatus::Failed(_) => None,
                _ => Some(p.matches.len()),
            };
        }
        all.extend(p.matches.iter().map(|m| (p.scenario, li, m)));
    }
    all.sort_by_key(|a| (a.0, a.1));
    let chosen = choose(&all, max_pictures);
    let mut notes = vec![format!(
        "{} programs × {} logs, {} matched tracks; {} pictured (at most {max_pictures}, \
         `--report-max-pictures`), each at up to {FRAMES_PER_MATCH} frames over its referred \
         span. Outputs in {}.",
        scenarios.len(),
        logs.len(),
        all.len(),
        chosen.len(),
        out.display()
    )];
    let mut matches: Vec<ReportMatch> = all
        .iter()
        .map(|(s, l, m)| {
            let scenario = &scenarios[*s];
            ReportMatch {
                program: scenario.name.clone(),
                description: scenario.description.clone(),
                log_id: m.log_id.clone(),
                track_uuid: m.track_uuid.clone(),
                category: m.category.clone(),
                span: (m.first_s, m.last_s),
                referred_frames: m.frames,
                proof: String::new(),
                frames: Vec::new(),
                command: format!(
                    "scenalog explain --rules {} --log {} --track {} --at {}",
                    scenario.path.display(),
                    logs[*l].dir.display(),
                    m.track_uuid,
                    m.first_s
                ),
            }
        })
        .collect();

    // Scenes are loaded once per log; a log that cannot be read leaves its matches unpictured.
    let mut scenes: HashMap<usize, Scene> = HashMap::new();
    for &i in &chosen {
        let li = all[i].1;
        if let std::collections::hash_map::Entry::Vacant(e) = scenes.entry(li) {
            match load_scene(&logs[li].dir) {
                Ok(s) => {
                    e.insert(s);
                }
                Err(err) => notes.push(format!("log {}: {err}", logs[li].log_id)),
            }
        }
    }
    let mut jobs: Vec<Job<'_>> = Vec::new();
    let mut by_pair: Vec<((usize, usize), Vec<usize>)> = Vec::new();
    for &i in &chosen {
        let key = (all[i].0, all[i].1);
        match by_pair.last_mut() {
            Some((k, v)) if *k == key => v.push(i),
            _ => by_pair.push((key, vec![i])),
        }
    }
    // `mine`'s default limits for one pair, read once (the default budget reads the machine's
    // memory).
    let limits = super::budget::pair_limits(None, None, 1);
    for ((si, li), members) in by_pair {
        let Some(scene) = scenes.get(&li) else {
            continue;
        };
        let scenario = &scenarios[si];
        let extractor = Extractor::new(scene);
        let ev = match evaluate_for_explain(&extractor, &scenario.program, false, &limits) {
            Ok(ev) => ev,
            Err(e) => {
                notes.push(format!(
                    "{} on log {}: evaluating again for the proofs failed: {e}",
                    scenario.name, logs[li].log_id
                ));
                continue;
            }
        };
        let renderer = Renderer { scene, scenario };
        for i in members {
            let Some(track) = scene.track_by_uuid(&all[i].2.track_uuid) else {
                continue;
            };
            let referred = referred_frames(&ev, track.id);
            let shown = spread(&referred, FRAMES_PER_MATCH);
            for (j, &frame) in shown.iter().enumerate() {
                let tuple = [Value::Track(track.id), Value::Time(frame)];
                let proof = explain(&scenario.program, &ev, "referred", &tuple)
                    .ok()
                    .flatten();
                let explanation = Explanation {
                    track: track.id,
                    frame,
                    referred_frames: referred.clone(),
                    proof,
                    why_not: None,
                };
                if j == 0 {
                    matches[i].proof = explanation_text(&renderer, &explanation);
                }
                let related = related_at(&ev, track.id, frame);
                let mut picture =
                    explanation_picture(&renderer, &explanation, related, Reference::Referred);
                picture.width = PICTURE_PX;
                picture.height = PICTURE_PX;
                let name = format!("m{i}-f{j}.png");
                matches[i].frames.push(ReportFrame {
                    image: format!("img/{name}"),
                    frame,
                    seconds: scene.timeline.seconds(frame).unwrap_or(0.0),
                    referred: explanation.referred(),
                });
                jobs.push(Job {
                    file: img.join(name),
                    picture,
                });
            }
        }
    }
    let failures: Vec<String> = jobs
        .par_iter()
        .filter_map(|job| {
            scene_svg(&job.picture)
                .and_then(|svg| write_picture(&job.file, &svg))
                .err()
                .map(|e| e.to_string())
        })
        .collect();
    if let Some(first) = failures.first() {
        return Err(format!(
            "{} of {} report pictures failed, the first: {first}",
            failures.len(),
            jobs.len()
        ));
    }
    let report = Report {
        title: "Scenalog mining report".to_string(),
        notes,
        programs: scenarios.iter().map(|s| s.name.clone()).collect(),
        logs: logs.iter().map(|l| l.log_id.clone()).collect(),
        counts,
        matches,
    };
    scenalog_view::write_report(&dir, &report).map_err(|e| e.to_string())?;
    Ok(out.join(REPORT_DIR).join("index.html"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_keeps_both_ends_and_order() {
        assert_eq!(spread(&[3, 4, 5, 9, 20], 3), vec![3, 11, 20]);
        assert_eq!(spread(&[7], 6), vec![7]);
        assert_eq!(spread(&[], 6), Vec::<Frame>::new());
        assert_eq!(spread(&[1, 2], 6), vec![1, 2]);
    }
}
