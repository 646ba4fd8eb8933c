//! Pixel tests on small synthetic scenes: colours where the geometry says they must be, and
//! identical output across runs.

use scenalog_facts::scene::{Scene, TrackId, EGO_SIZE};
use scenalog_facts::LaneType;
use scenalog_testkit::{straight, SceneBuilder};
use scenalog_view::picture::picture_view;
use scenalog_view::{layout, render_png, render_rgba, scene_svg, style, Picture};

/// The ego at the origin heading +x, a car 5 m to its left (+y), a pedestrian and a bus ahead, a bike lane
/// on the ego's right, all still for 10 frames.
fn scene() -> Scene {
    SceneBuilder::new(10)
        .track(
            "ego",
            "EGO_VEHICLE",
            EGO_SIZE,
            straight(0, 10, 0.0, 0.0, 0.0, 0.0),
        )
        .track(
            "car-left",
            "REGULAR_VEHICLE",
            [4.5, 2.0, 1.5],
            straight(0, 10, 0.0, 5.0, 0.0, 0.0),
        )
        .track(
            "ped-ahead",
            "PEDESTRIAN",
            [0.6, 0.6, 1.7],
            straight(0, 5, 12.0, 0.0, 0.0, 0.0),
        )
        .track(
            "bus-ahead",
            "BUS",
            [12.0, 2.6, 3.2],
            straight(0, 10, 20.0, 0.0, 0.0, 0.0),
        )
        .straight_lane(7, -40.0, 40.0, -9.0, -5.0)
        .lane_type(LaneType::Bike)
        .build()
}

fn hex(c: &str) -> [u8; 3] {
    let v = u32::from_str_radix(c.trim_start_matches('#'), 16).expect("a colour constant");
    [(v >> 16) as u8, (v >> 8) as u8, v as u8]
}

fn pixel(rgba: &[u8], width: u32, at: [f64; 2]) -> [u8; 3] {
    let (x, y) = (at[0].round() as usize, at[1].round() as usize);
    let i = (y * width as usize + x) * 4;
    [rgba[i], rgba[i + 1], rgba[i + 2]]
}

fn track(scene: &Scene, uuid: &str) -> TrackId {
    scene.track_by_uuid(uuid).expect("the track").id
}

#[test]
fn the_referred_car_left_of_the_ego_is_drawn_left_in_the_highlight_colour() {
    let scene = scene();
    let mut p = Picture::new(&scene, 3);
    p.referred = Some(track(&scene, "car-left"));
    p.width = 400;
    p.height = 400;
    let view = picture_view(&p).expect("a view");
    let (w, h, rgba) = render_rgba(&scene_svg(&p).expect("svg")).expect("raster");
    // The map is 400 px square; the panel beside it adds its width.
    assert_eq!((w, h), (layout(&p).width, 400));
    assert!(w > 400);
    // The ego heads up, so its left is the picture's left: the car's centre is left of the ego's.
    let car = view.px([0.0, 5.0]);
    let ego = view.px([0.0, 0.0]);
    assert!(car[0] < ego[0] - 30.0, "car at {car:?}, ego at {ego:?}");
    assert!((car[1] - ego[1]).abs() < 1.0);
    // Inside the car's box, away from the heading tick (which runs forward from the centre):
    // the highlight colour, at the back half of the box, on both sides of the tick.
    for at in [[-1.2, 5.5], [-1.2, 4.5], [-1.8, 5.0]] {
        assert_eq!(
            pixel(&rgba, w, view.px(at)),
            hex(style::REFERRED),
            "at {at:?}"
        );
    }
    // Inside the ego's box: the ego's colour, not the highlight.
    assert_eq!(pixel(&rgba, w, view.px([-1.5, 0.5])), hex(style::EGO));
    // The bus ahead: the bus colour, above the ego in the picture.
    assert_eq!(
        pixel(&rgba, w, view.px([18.0, 0.7])),
        hex(style::category_colour("BUS"))
    );
    assert!(view.px([20.0, 0.0])[1] < ego[1] - 100.0);
}

#[test]
fn a_bike_lane_fills_its_polygon_and_nothing_else() {
    let scene = scene();
    let mut p = Picture::new(&scene, 3);
    p.width = 400;
    p.height = 400;
    let view = picture_view(&p).expect("a view");
    let (w, _, rgba) = render_rgba(&scene_svg(&p).expect("svg")).expect("raster");
    // The lane lies 5-9 m to the ego's right: the picture's right of the ego.
    for x in [-15.0, 0.0, 15.0] {
        assert_eq!(pixel(&rgba, w, view.px([x, -7.0])), hex(style::BIKE_LANE));
    }
    // Outside it (no drivable area in this scene): the background.
    for at in [[0.0, -11.0], [10.0, -3.0], [-10.0, 10.0]] {
        assert_eq!(
            pixel(&rgba, w, view.px(at)),
            hex(style::BACKGROUND),
            "at {at:?}"
        );
    }
}

#[test]
fn the_picture_is_identical_across_runs() {
    let scene = scene();
    let mut p = Picture::new(&scene, 2);
    p.referred = Some(track(&scene, "car-left"));
    p.related = vec![track(&scene, "ped-ahead")];
    p.title = "car left of the ego".into();
    p.notes = vec![("a note".into(), true), ("a failing literal".into(), false)];
    let svg1 = scene_svg(&p).expect("svg");
    let svg2 = scene_svg(&p).expect("svg");
    assert_eq!(svg1, svg2);
    let png1 = render_png(&svg1).expect("png");
    let png2 = render_png(&svg2).expect("png");
    assert_eq!(png1, png2);
    assert!(png1.starts_with(b"\x89PNG"));
}

#[test]
fn text_renders_with_the_embedded_font() {
    // With no system fonts, text would draw nothing: the title's pixels in the panel would all
    // be the panel's own colour.
    let scene = scene();
    let mut p = Picture::new(&scene, 2);
    p.title = "WWWWWWWWWWWWWWWWWWWW".into();
    p.width = 400;
    p.height = 400;
    let (w, _, rgba) = render_rgba(&scene_svg(&p).expect("svg")).expect("raster");
    let left = layout(&p).panel[0] as usize;
    let dark = (10..30)
        .flat_map(|y| (left + 10..left + 200).map(move |x| [x as f64, y as f64]))
        .filter(|at| pixel(&rgba, w, *at).iter().all(|c| *c < 80))
        .count();
    assert!(dark > 100, "only {dark} dark pixels where the title is");
}

/// A why-not picture (the track not referred at the frame) draws the track in its category's
/// colour with a dashed outline, not filled in the referred colour with its halo.
#[test]
fn a_track_not_referred_here_is_not_drawn_in_the_referred_colour() {
    let scene = scene();
    let car = scene.track_by_uuid["car-left"];
    let mut p = Picture::new(&scene, 3);
    p.referred = Some(car);
    let referred = scene_svg(&p).expect("svg");
    let fill = format!("id=\"referred-box\" fill=\"{}\"", style::REFERRED);
    assert!(referred.contains(&fill), "{referred}");
    p.referred_here = false;
    let not = scene_svg(&p).expect("svg");
    assert!(!not.contains(&fill));
    assert!(not.contains("id=\"referred-box\""));
    assert!(not.contains("stroke-dasharray=\"5 3\""));
    assert!(!not.contains("stroke-opacity=\"0.35\" stroke-width=\"10\""));
}
