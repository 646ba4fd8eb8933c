//! Prints, per object, the tuples of a relation on a real log:
//! `cargo run -p scenalog-extractors --example inspect LOG_DIR RELATION`.

use std::collections::BTreeMap;

use scenalog_extractors::{relation_json, Extractor};
use scenalog_facts::read::load_scene;
use scenalog_facts::relation::Request;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (Some(dir), Some(rel)) = (args.get(1), args.get(2)) else {
        eprintln!("usage: inspect LOG_DIR RELATION");
        std::process::exit(2);
    };
    let scene = match load_scene(std::path::Path::new(dir)) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    let ex = Extractor::new(&scene);
    if let Ok(prefix) = std::env::var("TRACK") {
        dump(&ex, &prefix);
        return;
    }
    let data = match ex.extract(&Request::all(rel)) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    let json = relation_json(&scene, &data);
    let mut per: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for r in json.as_array().into_iter().flatten() {
        let key = r[0].as_str().map_or(r[0].to_string(), |u| {
            let cat = scene.track_by_uuid(u).map_or("?", |t| t.category.as_str());
            format!("{cat} {}", &u[..u.len().min(8)])
        });
        let rest: Vec<String> = r
            .as_array()
            .into_iter()
            .flatten()
            .skip(1)
            .map(|v| v.to_string())
            .collect();
        per.entry(key).or_default().push(rest.join(" "));
    }
    for (k, v) in per {
        println!(
            "{k}: {} | {}",
            v.len(),
            v.iter().take(40).cloned().collect::<Vec<_>>().join(", ")
        );
    }
    println!(
        "STOP_SIGN tracks: {}",
        scene
            .tracks
            .iter()
            .filter(|t| t.category == "STOP_SIGN")
            .count()
    );
}

/// Per-box lane, position, velocity and yaw rate of the tracks whose uuid starts with `prefix`
/// (set `TRACK=prefix` to print these instead of a relation).
fn dump(ex: &Extractor, prefix: &str) {
    let scene = ex.scene();
    for t in &scene.tracks {
        if !t.uuid.starts_with(prefix) {
            continue;
        }
        let k = &ex.kinematics().tracks[t.id.index()];
        let l = &ex.lanes().lanes[t.id.index()];
        for (i, lane) in l.iter().enumerate() {
            println!(
                "{} lane {:?} pos ({:.2},{:.2}) vel ({:.2},{:.2}) yaw {:.1} w {:.1}",
                k.frames[i],
                lane.map(|x| x.0),
                k.pos[i][0],
                k.pos[i][1],
                k.vel[i][0],
                k.vel[i][1],
                k.yaw[i].to_degrees(),
                k.yaw_rate[i]
            );
        }
    }
}
