//! Where things go in a picture of a real scene (the sample logs under `tests/data`): the proof
//! is beside the map and never changes a pixel of it; map labels never cover each other, the
//! referred object or the ego, stay inside the map, and the referred and related objects'
//! labels are always there; where the rasteriser really draws each label lies inside the
//! rectangle it was placed in; the legend lists what the map shows.

use scenalog_facts::scene::{Scene, TrackId, EGO_SIZE};
use scenalog_facts::{load_scene, LaneType};
use scenalog_testkit::{straight, SceneBuilder};
use scenalog_view::label::{overlaps, Rect};
use scenalog_view::usvg::{Node, Tree};
use scenalog_view::{
    draw_scene, layout, raster, render_rgba, style, Annotation, Mark, Picture, Reference, Side,
};

fn log(id: &str) -> Scene {
    let dir = scenalog_testkit::sample_logs_dir();
    let dir = std::fs::read_dir(&dir)
        .expect("the sample logs")
        .map(|e| e.expect("entry").path())
        .find(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with(id))
        })
        .expect("the log");
    load_scene(&dir).expect("loads")
}

fn track(scene: &Scene, prefix: &str) -> TrackId {
    scene
        .tracks
        .iter()
        .find(|t| t.uuid.starts_with(prefix))
        .expect("the track")
        .id
}

/// The halo around label text (half its stroke), pixels.
const HALO: f64 = 1.5;

/// Every text of the tree under the group `group` whose id starts with `prefix`, with the box
/// the rasteriser lays it out in (the font's ascent to its descent, the advance widths), grown
/// by `grow`.
fn texts(tree: &Tree, group: &str, prefix: &str, grow: f64) -> Vec<(String, Rect)> {
    fn walk(nodes: &[Node], prefix: &str, grow: f64, out: &mut Vec<(String, Rect)>) {
        for n in nodes {
            match n {
                Node::Text(t) if t.id().starts_with(prefix) => {
                    let b = t.abs_bounding_box();
                    out.push((
                        t.id().to_string(),
                        [
                            b.left() as f64 - grow,
                            b.top() as f64 - grow,
                            b.right() as f64 + grow,
                            b.bottom() as f64 + grow,
                        ],
                    ));
                }
                Node::Group(g) => walk(g.children(), prefix, grow, out),
                _ => {}
            }
        }
    }
    let mut out = Vec::new();
    match tree.node_by_id(group) {
        Some(Node::Group(g)) => walk(g.children(), prefix, grow, &mut out),
        _ => panic!("no group {group}"),
    }
    out
}

fn inside(inner: &Rect, outer: &Rect, tolerance: f64) -> bool {
    inner[0] >= outer[0] - tolerance
        && inner[1] >= outer[1] - tolerance
        && inner[2] <= outer[2] + tolerance
        && inner[3] <= outer[3] + tolerance
}

/// The vehicle with a bicycle to its right (3b3570b4, frame 80), its proof's sector drawn.
fn bicycle_match(scene: &Scene) -> Picture<'_> {
    let car = track(scene, "2f09a161");
    let bike = track(scene, "8f1f6bc5");
    let mut p = Picture::new(scene, 80);
    p.reference = Reference::Referred;
    p.referred = Some(car);
    p.related = vec![bike];
    p.width = 560;
    p.height = 560;
    p.half_extent = 18.0;
    p.annotations = vec![Annotation {
        mark: Mark::Sector {
            from: car,
            to: bike,
            side: Side::Right,
        },
        label: "8f1f6bc5 right of 2f09a161, 2.0 m".into(),
        holds: true,
    }];
    p
}

#[test]
fn the_proof_is_beside_the_map_and_changes_none_of_its_pixels() {
    let scene = log("3b3570b4");
    let bare = bicycle_match(&scene);
    let mut told = bare.clone();
    told.title = "vehicle with a bicycle to its right".into();
    told.status = "2f09a161 (REGULAR_VEHICLE): referred — why:".into();
    // Many long lines: more than the panel holds.
    told.notes = (0..30)
        .map(|i| {
            (
                format!(
                    "direction(2f09a161 (REGULAR_VEHICLE), 8f1f6bc5 (BICYCLE), 8.0 s, \"right\", \
                     1.98 m, 0.00 m) number {i}"
                ),
                i % 3 != 0,
            )
        })
        .collect();
    let l = layout(&told);
    assert_eq!(l.map, [0.0, 0.0, 560.0, 560.0]);
    assert!(!overlaps(&l.map, &l.panel), "{l:?}");
    assert_eq!(l.panel[0], l.map[2]);
    assert_eq!((l.width, l.height), (l.panel[2] as u32, 560));

    let a = draw_scene(&bare).expect("draws");
    let b = draw_scene(&told).expect("draws");
    let (w, h, pa) = render_rgba(&a.svg).expect("raster");
    let (_, _, pb) = render_rgba(&b.svg).expect("raster");
    assert_eq!((w, h), (l.width, l.height));
    let map_w = l.map[2] as usize;
    for y in 0..h as usize {
        let row = y * w as usize * 4;
        assert!(
            pa[row..row + map_w * 4] == pb[row..row + map_w * 4],
            "the text changed the map's row {y}"
        );
    }
    // Every text of the panel (the proof, the legend, the scale) is laid out inside it.
    let tree = raster::parse(&b.svg).expect("parses");
    let panel = texts(&tree, "panel", "", 0.0);
    assert!(panel.len() > 20, "{panel:?}");
    for (_, r) in &panel {
        assert!(
            inside(r, &l.panel, 0.0),
            "{r:?} outside the panel {:?}",
            l.panel
        );
    }
    // And the panel says so when the proof does not fit.
    assert!(b.svg.contains("more lines of the proof"));
}

/// Checks the labels of a drawn picture; returns how many there are.
fn check_labels(p: &Picture<'_>, related: &[&str]) -> usize {
    let d = draw_scene(p).expect("draws");
    let map = d.layout.map;
    let referred = d.referred.expect("the referred object is drawn");
    let ids: Vec<&str> = d.labels.iter().map(|l| l.id.as_str()).collect();
    assert!(
        ids.contains(&"label-referred"),
        "frame {}: {ids:?}",
        p.frame
    );
    for r in related {
        assert!(
            ids.iter()
                .any(|i| i.starts_with(&format!("label-related-{r}"))),
            "frame {}: no label for related {r}: {ids:?}",
            p.frame
        );
    }
    for (i, a) in d.labels.iter().enumerate() {
        assert!(inside(&a.rect, &map, 0.0), "{} leaves the map", a.id);
        assert!(
            !overlaps(&a.rect, &referred),
            "frame {}: {} covers the referred object",
            p.frame,
            a.id
        );
        for b in &d.labels[i + 1..] {
            assert!(
                !overlaps(&a.rect, &b.rect),
                "frame {}: {} and {} overlap",
                p.frame,
                a.id,
                b.id
            );
        }
    }
    // What the rasteriser draws for each label is inside the rectangle it was placed in.
    let tree = raster::parse(&d.svg).expect("parses");
    let texts = texts(&tree, "map", "label-", HALO);
    assert_eq!(texts.len(), d.labels.len());
    for (id, r) in &texts {
        let placed = d.labels.iter().find(|l| &l.id == id).expect("placed");
        assert!(
            inside(r, &placed.rect, 0.01),
            "{id}: drawn at {r:?}, placed at {:?}",
            placed.rect
        );
    }
    d.labels.len()
}

#[test]
fn a_group_keeps_its_referred_and_related_labels_and_no_label_collides() {
    // A group of pedestrians in adcf7d18, close together from 3.6 s to 15.5 s.
    let scene = log("adcf7d18");
    let group = ["63601b36", "f80e6db9", "5f033846", "6c5a91c4"];
    let mut labels = 0;
    for frame in (40..150).step_by(10) {
        for reference in [Reference::Referred, Reference::Ego] {
            let mut p = Picture::new(&scene, frame);
            p.reference = reference;
            p.referred = Some(track(&scene, "1c385d62"));
            p.related = group
                .iter()
                .map(|g| track(&scene, g))
                .filter(|t| scene.tracks[t.index()].box_at(frame).is_some())
                .collect();
            let present: Vec<&str> = group
                .iter()
                .copied()
                .filter(|g| {
                    scene.tracks[track(&scene, g).index()]
                        .box_at(frame)
                        .is_some()
                })
                .collect();
            p.width = 640;
            p.height = 640;
            labels += check_labels(&p, &present);
        }
    }
    assert!(labels > 200, "only {labels} labels in 22 pictures");
}

#[test]
fn labels_of_a_match_never_collide_over_its_span() {
    let scene = log("3b3570b4");
    for frame in (73..=137).step_by(8) {
        let mut p = bicycle_match(&scene);
        p.frame = frame;
        if scene.tracks[p.related[0].index()].box_at(frame).is_none() {
            p.related.clear();
            p.annotations.clear();
        }
        check_labels(&p, &[]);
    }
}

#[test]
fn the_legend_lists_the_lanes_the_map_shows_in_their_colours() {
    let build = |ty: LaneType| {
        SceneBuilder::new(3)
            .track(
                "ego",
                "EGO_VEHICLE",
                EGO_SIZE,
                straight(0, 3, 0.0, 0.0, 0.0, 0.0),
            )
            .straight_lane(7, -40.0, 40.0, -9.0, -5.0)
            .lane_type(ty)
            .build()
    };
    for (ty, colour, name, other) in [
        (LaneType::Bus, style::BUS_LANE, "bus lane", "bike lane"),
        (LaneType::Bike, style::BIKE_LANE, "bike lane", "bus lane"),
    ] {
        let scene = build(ty);
        let mut p = Picture::new(&scene, 1);
        p.width = 400;
        p.height = 400;
        let d = draw_scene(&p).expect("draws");
        assert!(d.svg.contains(&format!(">{name}</text>")), "{name}");
        assert!(!d.svg.contains(&format!(">{other}</text>")), "{other}");
        // The lane is filled with the legend's colour.
        let view = scenalog_view::picture::picture_view(&p).expect("view");
        let (w, _, rgba) = render_rgba(&d.svg).expect("raster");
        let at = view.px([10.0, -7.0]);
        let i = (at[1].round() as usize * w as usize + at[0].round() as usize) * 4;
        let hex = u32::from_str_radix(colour.trim_start_matches('#'), 16).expect("colour");
        assert_eq!(
            &rgba[i..i + 3],
            &[(hex >> 16) as u8, (hex >> 8) as u8, hex as u8],
            "{name}"
        );
    }
}
