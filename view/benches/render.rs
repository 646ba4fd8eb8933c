//! Rendering one picture of a real match: the SVG drawn from the scene (map, every object, the
//! facts), and that SVG rasterised to PNG, on the sample log 3b3570b4 at frame 80.

use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use scenalog_facts::load_scene;
use scenalog_view::{render_png, scene_svg, Annotation, Mark, Picture, Reference, Side};

fn bench(c: &mut Criterion) {
    let log = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/av2/logs/3b3570b4-7b0b-3268-a571-b0889dbf40b6");
    let scene = match load_scene(&log) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("render bench skipped: {e}");
            return;
        }
    };
    let (Some(car), Some(bike)) = (
        scene.tracks.iter().find(|t| t.uuid.starts_with("2f09a161")),
        scene.tracks.iter().find(|t| t.uuid.starts_with("8f1f6bc5")),
    ) else {
        eprintln!("render bench skipped: the match's tracks are not in the log");
        return;
    };
    let mut p = Picture::new(&scene, 80);
    p.reference = Reference::Referred;
    p.referred = Some(car.id);
    p.related = vec![bike.id];
    p.title = "vehicle with a bicycle to its right".into();
    p.status = "referred — why:".into();
    p.notes = vec![("direction(…, \"right\", 1.98 m, 0.00 m)".into(), true)];
    p.annotations = vec![Annotation {
        mark: Mark::Sector {
            from: car.id,
            to: bike.id,
            side: Side::Right,
        },
        label: "right, 2.0 m".into(),
        holds: true,
    }];
    let svg = match scene_svg(&p) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("render bench skipped: {e}");
            return;
        }
    };
    c.bench_function("svg_800px", |b| b.iter(|| scene_svg(&p)));
    c.bench_function("png_800px", |b| b.iter(|| render_png(&svg)));
    c.bench_function("svg_and_png_800px", |b| {
        b.iter(|| scene_svg(&p).and_then(|s| render_png(&s)))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
