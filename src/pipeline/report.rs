//! `scenalog mine --report`: the run's browsable report, `OUT/report/index.html`, made from the
//! run's results after the run. Every program that matched has its first match pictured (the
//! programs the ground truth scores first, in the table too), then one match per (program, log)
//! pair and more, up to `max_pictures` in all. Per pictured match, its (log, program) pair is
//! evaluated again with provenance (the pairs in parallel), and pictures are drawn (in
//! parallel) at up to [`FRAMES_PER_MATCH`] frames spread over the referred span, each with its
//! own proof, which the page shows as the scrubber moves. The other matches are listed with the
//! command that pictures them. The page itself is `scenalog-view`'s.

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};

use rayon::prelude::*;
use scenalog_engine::{explain, why_not};
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
use super::studio_link::{studio_command, studio_url};
use crate::message::Names;

/// The report's directory under the run's output directory.
pub const REPORT_DIR: &str = crate::pipeline::output::REPORT_DIR;
/// How many frames of a match are pictured (the scrubber's positions).
pub const FRAMES_PER_MATCH: usize = 6;
/// The pictures' map size in pixels (the panel beside it adds half; shown at 480 px high).
const PICTURE_PX: u32 = 640;

/// The prompts a ground truth scores (its sequences' descriptions), for the report to put
/// first.
pub fn scored_prompts(gt: Option<&scenalog_eval::Submission>) -> Vec<String> {
    let Some(gt) = gt else {
        return Vec::new();
    };
    let prompts: BTreeSet<&String> = gt.sequences.keys().map(|(_, p)| p).collect();
    prompts.into_iter().cloned().collect()
}

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

/// The matches to picture, as indices into `all` (grouped by program, programs in report
/// order): the first match of every program, then one from each (program, log) pair in turn,
/// then a second from each, and so on, until `max` are chosen (never fewer than one per
/// program); in `all`'s order.
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
    let mut chosen: BTreeSet<usize> = BTreeSet::new();
    let mut program: Option<usize> = None;
    for v in &per_pair {
        let Some(&first) = v.first() else { continue };
        if program != Some(all[first].0) {
            program = Some(all[first].0);
            chosen.insert(first);
        }
    }
    let mut round = 0;
    while chosen.len() < max {
        let mut any = false;
        for v in &per_pair {
            if let Some(i) = v.get(round) {
                any = true;
                if chosen.len() < max {
                    chosen.insert(*i);
                }
            }
        }
        if !any {
            break;
        }
        round += 1;
    }
    chosen.into_iter().collect()
}

/// One picture to draw: the file and what to draw.
struct Job<'a> {
    file: PathBuf,
    picture: Picture<'a>,
}

/// What one (program, log) pair gives its pictured matches: per match its frames (with their
/// proofs) and pictures to draw, or a note saying why it has none.
type PairOut<'a> = Result<Vec<(usize, Vec<ReportFrame>, Vec<Job<'a>>)>, String>;

/// Evaluates one pair again with provenance and makes its matches' frames and pictures.
fn pair_pictures<'a>(
    scene: &'a Scene,
    scenario: &'a Scenario,
    log_id: &str,
    members: &[usize],
    all: &[(usize, usize, &Match)],
    img: &Path,
    limits: &scenalog_engine::Options,
) -> PairOut<'a> {
    let extractor = Extractor::new(scene);
    let ev = evaluate_for_explain(&extractor, &scenario.program, false, limits).map_err(|e| {
        let context = format!(
            "{} on log {log_id}: evaluating again for the proofs failed: ",
            scenario.name
        );
        // The page is the command's (it quotes `scenalog explain` commands): its flags.
        e.message(&context).render(Names::Flags)
    })?;
    let renderer = Renderer { scene, scenario };
    // The evaluation a why-not report needs (every tuple kept), made once, only if a pictured
    // frame turns out not to be referred (the frames are spread between a match's first and last).
    let mut whole: Option<Result<scenalog_engine::Evaluation, String>> = None;
    let mut out = Vec::new();
    for &i in members {
        let Some(track) = scene.track_by_uuid(&all[i].2.track_uuid) else {
            continue;
        };
        let referred = referred_frames(&ev, track.id);
        let mut frames = Vec::new();
        let mut jobs = Vec::new();
        for (j, &frame) in spread(&referred, FRAMES_PER_MATCH).iter().enumerate() {
            let tuple = [Value::Track(track.id), Value::Time(frame)];
            let proof = explain(&scenario.program, &ev, "referred", &tuple)
                .ok()
                .flatten();
            let why_not = if proof.is_none() {
                let w = whole.get_or_insert_with(|| {
                    evaluate_for_explain(&extractor, &scenario.program, true, limits)
                        .map_err(|e| e.to_string())
                });
                w.as_ref()
                    .ok()
                    .and_then(|w| why_not(&scenario.program, w, "referred", &tuple).ok())
            } else {
                None
            };
            let explanation = Explanation {
                track: track.id,
                frame,
                referred_frames: referred.clone(),
                proof,
                why_not,
            };
            let related = related_at(&ev, track.id, frame);
            let mut picture =
                explanation_picture(&renderer, &explanation, related, Reference::Referred);
            picture.width = PICTURE_PX;
            picture.height = PICTURE_PX;
            let name = format!("m{i}-f{j}.png");
            frames.push(ReportFrame {
                image: format!("img/{name}"),
                frame,
                seconds: scene.timeline.seconds(frame).unwrap_or(0.0),
                referred: explanation.referred(),
                proof: explanation_text(&renderer, &explanation),
            });
            jobs.push(Job {
                file: img.join(name),
                picture,
            });
        }
        out.push((i, frames, jobs));
    }
    Ok(out)
}

/// Writes `into/report/index.html` and its pictures (`into`: the run's generation directory,
/// published as `out/report/`); returns the page's path in `out`. `scored` are the prompts the
/// run is scored on (their programs come first). Errors name the file that could not be
/// written; a log or program that fails here leaves its matches without pictures (said on the
/// page) rather than failing the report.
pub fn write_run_report(
    into: &Path,
    out: &Path,
    run: &RunReport,
    scenarios: &[Scenario],
    logs: &[LogInput],
    max_pictures: usize,
    scored: &[String],
) -> Result<PathBuf, String> {
    let dir = into.join(REPORT_DIR);
    let img = dir.join("img");
    std::fs::create_dir_all(&img).map_err(|e| format!("cannot create `{}`: {e}", img.display()))?;
    // The programs in report order: the scored ones first, each group in the run's order.
    let is_scored = |s: &Scenario| scored.contains(&s.description);
    let mut order: Vec<usize> = (0..scenarios.len()).collect();
    order.sort_by_key(|&s| !is_scored(&scenarios[s]));
    let mut rank = vec![0usize; scenarios.len()];
    for (r, &s) in order.iter().enumerate() {
        rank[s] = r;
    }
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
    all.sort_by_key(|a| (rank[a.0], a.1));
    let chosen = choose(&all, max_pictures);
    let programs_matched: BTreeSet<usize> = all.iter().map(|a| a.0).collect();
    let mut notes = vec![format!(
        "{} programs × {} logs, {} matched tracks of {} programs; {} pictured: the first match \
         of every program that matched, then one per (program, log) pair and more up to \
         `--report-max-pictures` ({max_pictures}), each at up to {FRAMES_PER_MATCH} frames over \
         its referred span. {}Outputs in {}.",
        scenarios.len(),
        logs.len(),
        all.len(),
        programs_matched.len(),
        chosen.len(),
        if scored.is_empty() {
            String::new()
        } else {
            "The programs the ground truth scores come first. ".to_string()
        },
        out.display()
    )];
    notes.push(format!(
        "Each match's \"open in the studio\" link opens it in `{}` (rule, map and proof as you \
         edit).",
        studio_command(
            scenarios.iter().map(|s| s.path.as_path()),
            logs.iter().map(|l| l.dir.as_path())
        )
    ));
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
                frames: Vec::new(),
                command: format!(
                    "scenalog explain --rules {} --log {} --track {} --at {}",
                    scenario.path.display(),
                    logs[*l].dir.display(),
                    m.track_uuid,
                    m.first_s
                ),
                studio: studio_url(&scenario.name, &m.log_id, &m.track_uuid, m.first_s),
            }
        })
        .collect();

    // Scenes are loaded once per log; a log that cannot be read leaves its matches unpictured.
    let needed: BTreeSet<usize> = chosen.iter().map(|&i| all[i].1).collect();
    let loaded: Vec<(usize, Result<Scene, String>)> = needed
        .into_par_iter()
        .map(|li| (li, load_scene(&logs[li].dir).map_err(|e| e.to_string())))
        .collect();
    let mut scenes: HashMap<usize, Scene> = HashMap::new();
    for (li, s) in loaded {
        match s {
            Ok(s) => {
                scenes.insert(li, s);
            }
            Err(err) => notes.push(format!("log {}: {err}", logs[li].log_id)),
        }
    }
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
    let limits = super::limits::pair_limits(None, None, 1);
    let made: Vec<PairOut<'_>> = by_pair
        .par_iter()
        .filter_map(|((si, li), members)| {
            let scene = scenes.get(li)?;
            Some(pair_pictures(
                scene,
                &scenarios[*si],
                &logs[*li].log_id,
                members,
                &all,
                &img,
                &limits,
            ))
        })
        .collect();
    let mut jobs: Vec<Job<'_>> = Vec::new();
    for pair in made {
        match pair {
            Ok(pictured) => {
                for (i, frames, js) in pictured {
                    matches[i].frames = frames;
                    jobs.extend(js);
                }
            }
            Err(note) => notes.push(note),
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
        programs: order.iter().map(|&s| scenarios[s].name.clone()).collect(),
        scored: order.iter().map(|&s| is_scored(&scenarios[s])).collect(),
        logs: logs.iter().map(|l| l.log_id.clone()).collect(),
        counts: order.iter().map(|&s| counts[s].clone()).collect(),
        matches,
        image_size: (
            PICTURE_PX + scenalog_view::panel::panel_width(PICTURE_PX),
            PICTURE_PX,
        ),
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

    fn m(track: &str) -> Match {
        Match {
            log_id: "log".into(),
            description: "d".into(),
            program: "p".into(),
            track_uuid: track.into(),
            category: "REGULAR_VEHICLE".into(),
            first_s: 0.0,
            last_s: 1.0,
            frames: 10,
            related: Vec::new(),
        }
    }

    #[test]
    fn every_program_gets_its_first_match_whatever_the_cap() {
        let ms: Vec<Match> = (0..8).map(|i| m(&format!("t{i}"))).collect();
        // Program 0: 3 matches on log 0, 1 on log 1; program 1: 2 on log 1; program 2: 2 on log 0.
        let all: Vec<(usize, usize, &Match)> = vec![
            (0, 0, &ms[0]),
            (0, 0, &ms[1]),
            (0, 0, &ms[2]),
            (0, 1, &ms[3]),
            (1, 1, &ms[4]),
            (1, 1, &ms[5]),
            (2, 0, &ms[6]),
            (2, 0, &ms[7]),
        ];
        assert_eq!(choose(&all, 0), vec![0, 4, 6]);
        assert_eq!(choose(&all, 1), vec![0, 4, 6]);
        // Then the first of each pair (program 0 on log 1), then seconds.
        assert_eq!(choose(&all, 4), vec![0, 3, 4, 6]);
        assert_eq!(choose(&all, 6), vec![0, 1, 3, 4, 5, 6]);
        assert_eq!(choose(&all, 100), (0..8).collect::<Vec<_>>());
    }
}
