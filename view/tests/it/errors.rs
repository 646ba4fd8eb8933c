//! Bad input gives clear errors: a frame outside the log, a track absent at the frame, an
//! unwritable output path, an unknown format, an empty range.

use scenalog_facts::scene::{Scene, EGO_SIZE};
use scenalog_testkit::{straight, SceneBuilder};
use scenalog_view::track_path::animation_frames;
use scenalog_view::{
    path_svg, scene_svg, write_picture, PathPicture, Picture, Reference, ViewError,
};

fn scene() -> Scene {
    SceneBuilder::new(10)
        .track(
            "ego",
            "EGO_VEHICLE",
            EGO_SIZE,
            straight(0, 10, 0.0, 0.0, 0.0, 1.0),
        )
        .track(
            "late-car",
            "REGULAR_VEHICLE",
            [4.5, 2.0, 1.5],
            straight(5, 10, 0.0, 5.0, 0.0, 2.0),
        )
        .build()
}

#[test]
fn a_frame_outside_the_log_is_named() {
    let scene = scene();
    let p = Picture::new(&scene, 10);
    let e = scene_svg(&p).expect_err("frame 10 of 10");
    assert!(matches!(
        e,
        ViewError::FrameOutsideLog {
            frame: 10,
            frames: 10,
            ..
        }
    ));
    assert!(e.to_string().contains("frame 10 is outside log"), "{e}");
}

#[test]
fn a_track_absent_at_the_frame_is_named_with_where_it_is() {
    let scene = scene();
    let car = scene.track_by_uuid("late-car").expect("car").id;
    for reference in [Reference::Ego, Reference::Referred] {
        let mut p = Picture::new(&scene, 2);
        p.referred = Some(car);
        p.reference = reference;
        let e = scene_svg(&p).expect_err("absent at frame 2");
        let text = e.to_string();
        assert!(
            text.contains("late-car is not present at frame 2"),
            "{text}"
        );
        assert!(text.contains("from frame 5 to frame 9"), "{text}");
    }
}

#[test]
fn an_unwritable_path_and_an_unknown_format_are_errors_naming_the_file() {
    let scene = scene();
    let svg = scene_svg(&Picture::new(&scene, 1)).expect("svg");
    let dir = tempfile::tempdir().expect("tempdir");
    let missing = dir.path().join("no/such/dir/out.png");
    let e = write_picture(&missing, &svg).expect_err("no such directory");
    assert!(matches!(e, ViewError::Write { .. }));
    assert!(e.to_string().contains("no/such/dir/out.png"), "{e}");
    let jpg = dir.path().join("out.jpg");
    let e = write_picture(&jpg, &svg).expect_err("jpg");
    assert!(e.to_string().contains("out.jpg"), "{e}");
    assert!(!jpg.exists());
    // A good path works, and leaves no temporary file behind.
    let ok = dir.path().join("out.svg");
    write_picture(&ok, &svg).expect("written");
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .expect("dir")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("out.svg")]);
}

#[test]
fn path_ranges_are_checked() {
    let scene = scene();
    let car = scene.track_by_uuid("late-car").expect("car").id;
    let mut picture = Picture::new(&scene, 6);
    picture.referred = Some(car);
    let mut path = PathPicture {
        picture,
        track: car,
        first: 5,
        last: 12,
        referred_frames: vec![6, 7],
        frames: Vec::new(),
    };
    let e = path_svg(&path).expect_err("frame 12 of 10");
    assert!(e.to_string().contains("frame 12 is outside log"), "{e}");
    path.first = 0;
    path.last = 3;
    let e = path_svg(&path).expect_err("absent over 0..3");
    assert!(e.to_string().contains("not present at frame 0"), "{e}");
    path.first = 5;
    path.last = 9;
    let svg = path_svg(&path).expect("a path");
    // Two referred frames are filled dots in the highlight colour.
    assert_eq!(svg.matches(r##"r="3.20" fill="#e6007e""##).count(), 2);
    // The other three frames are hollow dots.
    assert_eq!(svg.matches(r##"r="2.60" fill="#ffffff""##).count(), 3);
    assert_eq!(animation_frames(&path).expect("frames").len(), 5);
}
