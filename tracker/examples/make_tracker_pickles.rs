//! Writes the tracker-format test pickles of the bundled sample logs, from their annotations:
//!
//! - `exact.pkl`: every annotated box, no noise, score 1.0, `float64` arrays; track ids are the
//!   indices of the log's non-ego tracks sorted by uuid. Mining it must give what mining the
//!   annotations gives.
//! - `noisy.pkl`: the same boxes as a tracker might report them (`float32` arrays, as trackers
//!   write), with deterministic noise from a seeded generator (seed: the log's index):
//!   - centre jitter: x and y each moved by a uniform amount in ±0.25 m;
//!   - dropped detections: each box is left out with probability 0.08;
//!   - scores: `0.35 + 0.65·√u` (u uniform in [0, 1)), so most true boxes score high;
//!   - an id switch: the longest-lived REGULAR_VEHICLE track takes a new id from the middle
//!     of its life on;
//!   - false positives: in each frame, with probability 0.3, a REGULAR_VEHICLE or PEDESTRIAN
//!     box 5–40 m from the ego, alone in its track, with a score uniform in [0, 0.3) (so some
//!     fall to the confidence filter), and one 12-frame false track per log scoring 0.2–0.3.
//!
//! Run from the workspace: `cargo run -p scenalog-tracker --example make_tracker_pickles --
//! tests/data/av2/logs tests/data/av2/tracker`.
//!
//! `… -- LOGS OUT --scaled N LIBRARY` writes instead a simulated split for the scale benchmark:
//! `OUT/split/<id>/` for N log ids (the sample logs in turn, their files linked), `OUT/tracks.pkl`
//! (each log's noisy detections, seeded by its position) and `OUT/log_prompt_pairs.json` (the
//! first 30 library descriptions for every log).

use std::path::{Path, PathBuf};

use scenalog_eval::PyValue as P;
use scenalog_facts::scene::{yaw_of, EGO_CATEGORY};
use scenalog_facts::Scene;

/// One box as written.
struct Row {
    t: [f64; 3],
    size: [f64; 3],
    yaw: f64,
    name: String,
    score: f32,
    id: i64,
}

fn frame_value(ts: i64, rows: &[Row], f64s: bool) -> P {
    let s = |x: &str| P::Str(x.to_string());
    let n = rows.len();
    let flat3 = |g: &dyn Fn(&Row) -> [f64; 3]| rows.iter().flat_map(g).collect::<Vec<f64>>();
    let arr = |shape: Vec<usize>, v: Vec<f64>| {
        if f64s {
            P::F64Array(shape, v)
        } else {
            P::F32Array(shape, v.into_iter().map(|x| x as f32).collect())
        }
    };
    P::Dict(vec![
        (s("timestamp_ns"), P::I64(ts)),
        (s("translation_m"), arr(vec![n, 3], flat3(&|r| r.t))),
        (s("size"), arr(vec![n, 3], flat3(&|r| r.size))),
        (s("yaw"), arr(vec![n], rows.iter().map(|r| r.yaw).collect())),
        (
            s("velocity_m_per_s"),
            P::F32Array(vec![n, 3], vec![0.0; n * 3]),
        ),
        (s("label"), P::I64Array(vec![0; n])),
        (
            s("name"),
            P::StrArray(rows.iter().map(|r| r.name.clone()).collect()),
        ),
        (
            s("score"),
            P::F32Array(vec![n], rows.iter().map(|r| r.score).collect()),
        ),
        (
            s("track_id"),
            P::I64Array(rows.iter().map(|r| r.id).collect()),
        ),
    ])
}

/// Every annotated non-ego box per frame, track ids as documented.
fn exact_rows(scene: &Scene) -> Vec<Vec<Row>> {
    let mut frames: Vec<Vec<Row>> = (0..scene.num_frames()).map(|_| Vec::new()).collect();
    let others = scene.tracks.iter().filter(|t| t.category != EGO_CATEGORY);
    for (id, t) in others.enumerate() {
        for b in &t.boxes {
            let c = b.city_center();
            frames[b.frame as usize].push(Row {
                t: [c.x, c.y, c.z],
                size: b.size,
                yaw: yaw_of(&b.city.rotation),
                name: t.category.clone(),
                score: 1.0,
                id: id as i64,
            });
        }
    }
    frames
}

fn noisy_rows(scene: &Scene, seed: u64) -> Vec<Vec<Row>> {
    let mut rng = fastrand::Rng::with_seed(seed);
    let mut frames = exact_rows(scene);
    let n_ids = frames.iter().flatten().map(|r| r.id + 1).max().unwrap_or(0);
    // The id switch: the longest-lived REGULAR_VEHICLE.
    let longest = scene
        .tracks
        .iter()
        .filter(|t| t.category != EGO_CATEGORY)
        .enumerate()
        .filter(|(_, t)| t.category == "REGULAR_VEHICLE")
        .max_by_key(|(_, t)| t.boxes.len())
        .map(|(i, t)| (i as i64, t.boxes[t.boxes.len() / 2].frame as usize));
    let mut next_id = n_ids + 1;
    for (f, rows) in frames.iter_mut().enumerate() {
        rows.retain(|_| rng.f64() >= 0.08);
        for r in rows.iter_mut() {
            r.t[0] += (rng.f64() - 0.5) * 0.5;
            r.t[1] += (rng.f64() - 0.5) * 0.5;
            r.score = (0.35 + 0.65 * rng.f64().sqrt()) as f32;
            if let Some((id, from)) = longest {
                if r.id == id && f >= from {
                    r.id = n_ids;
                }
            }
        }
        let ego = scene.ego_poses[f];
        let near = |rng: &mut fastrand::Rng| {
            let d = 5.0 + 35.0 * rng.f64();
            let a = rng.f64() * std::f64::consts::TAU;
            let p = ego * nalgebra::Point3::new(d * a.cos(), d * a.sin(), 0.5);
            [p.x, p.y, p.z]
        };
        if rng.f64() < 0.3 {
            let ped = rng.bool();
            rows.push(Row {
                t: near(&mut rng),
                size: if ped {
                    [0.6, 0.6, 1.7]
                } else {
                    [4.5, 1.9, 1.5]
                },
                yaw: rng.f64() * 6.0 - 3.0,
                name: if ped { "PEDESTRIAN" } else { "REGULAR_VEHICLE" }.into(),
                score: (0.3 * rng.f64()) as f32,
                id: next_id,
            });
            next_id += 1;
        }
    }
    // One false track of 12 frames from frame 40, parked 15 m to the ego's left.
    let start = 40.min(frames.len().saturating_sub(12));
    let anchor = scene.ego_poses[start] * nalgebra::Point3::new(3.0, 15.0, 0.5);
    for (k, rows) in frames.iter_mut().skip(start).take(12).enumerate() {
        rows.push(Row {
            t: [anchor.x, anchor.y, anchor.z],
            size: [4.5, 1.9, 1.5],
            yaw: 0.3,
            name: "REGULAR_VEHICLE".into(),
            score: 0.2 + 0.1 * (k as f32 / 12.0),
            id: next_id,
        });
    }
    frames
}

/// The scaled split (see the module documentation).
fn scaled(
    dirs: &[PathBuf],
    out: &Path,
    n: usize,
    library: &Path,
) -> Result<(), Box<dyn std::error::Error>> {
    let scenes: Vec<Scene> = dirs
        .iter()
        .map(|d| scenalog_facts::load_scene(d))
        .collect::<Result<_, _>>()?;
    let mut prompts: Vec<String> = std::fs::read_dir(library)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "dl"))
        .filter_map(|p| std::fs::read_to_string(p).ok())
        .filter_map(|t| {
            t.lines().find_map(|l| {
                l.strip_prefix("// description:")
                    .map(|d| d.trim().to_string())
            })
        })
        .collect();
    prompts.sort();
    prompts.dedup();
    prompts.truncate(30);
    let split = out.join("split");
    let mut logs = Vec::new();
    let mut pairs: Vec<(String, Vec<String>)> = Vec::new();
    for i in 0..n {
        let k = i % scenes.len();
        let id = format!("{i:08x}-5ca1-4000-8000-{:012x}", k);
        let dir = split.join(&id);
        std::fs::create_dir_all(dir.join("map"))?;
        link(
            &dirs[k].join("city_SE3_egovehicle.feather"),
            &dir.join("city_SE3_egovehicle.feather"),
        )?;
        for e in std::fs::read_dir(dirs[k].join("map"))?.flatten() {
            link(&e.path(), &dir.join("map").join(e.file_name()))?;
        }
        let stamps = scenes[k].timeline.timestamps_ns().to_vec();
        let rows = noisy_rows(&scenes[k], i as u64 + 100);
        let frames = P::List(
            rows.iter()
                .zip(&stamps)
                .map(|(r, &ts)| frame_value(ts, r, false))
                .collect(),
        );
        logs.push((P::Str(id.clone()), frames));
        pairs.push((id, prompts.clone()));
    }
    std::fs::write(
        out.join("tracks.pkl"),
        scenalog_eval::encode_value(&P::Dict(logs)),
    )?;
    let json: Vec<String> = pairs
        .iter()
        .map(|(id, ps)| {
            let list: Vec<String> = ps.iter().map(|p| format!("{p:?}")).collect();
            format!("  {id:?}: [{}]", list.join(", "))
        })
        .collect();
    std::fs::write(
        out.join("log_prompt_pairs.json"),
        format!("{{\n{}\n}}\n", json.join(",\n")),
    )?;
    println!(
        "{n} logs x {} prompts under {}",
        prompts.len(),
        out.display()
    );
    Ok(())
}

/// A symbolic link (a copy where links are not available).
fn link(from: &Path, to: &Path) -> std::io::Result<()> {
    let from = from.canonicalize()?;
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(&from, to)
    }
    #[cfg(not(unix))]
    {
        std::fs::copy(&from, to).map(|_| ())
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    if let [logs, out, flag, n, library] = args.as_slice() {
        if flag.as_os_str() == "--scaled" {
            let n: usize = n.to_string_lossy().parse()?;
            let mut dirs: Vec<PathBuf> = std::fs::read_dir(logs)?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_dir())
                .collect();
            dirs.sort();
            return scaled(&dirs, out, n, library);
        }
    }
    let [logs, out] = args.as_slice() else {
        return Err("usage: make_tracker_pickles LOGS_DIR OUT_DIR [--scaled N LIBRARY_DIR]".into());
    };
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(logs)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    let mut exact = Vec::new();
    let mut noisy = Vec::new();
    for (i, d) in dirs.iter().enumerate() {
        let scene = scenalog_facts::load_scene(d)?;
        let stamps = scene.timeline.timestamps_ns().to_vec();
        let key = P::Str(scene.log_id.clone());
        let write = |rows: Vec<Vec<Row>>, f64s: bool| {
            P::List(
                rows.iter()
                    .zip(&stamps)
                    .map(|(r, &ts)| frame_value(ts, r, f64s))
                    .collect(),
            )
        };
        exact.push((key.clone(), write(exact_rows(&scene), true)));
        noisy.push((key, write(noisy_rows(&scene, i as u64 + 1), false)));
    }
    std::fs::create_dir_all(out)?;
    for (name, v) in [("exact.pkl", exact), ("noisy.pkl", noisy)] {
        let bytes = scenalog_eval::encode_value(&P::Dict(v));
        std::fs::write(Path::new(out).join(name), &bytes)?;
        println!("{name}: {} bytes", bytes.len());
    }
    Ok(())
}
