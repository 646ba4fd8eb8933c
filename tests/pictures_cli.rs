//! `scenalog explain --picture` and `scenalog mine --report` end to end on the sample logs: the
//! picture files, their errors, and the report page checked in a real headless browser
//! (Debian's `chromium`; the browser part is skipped, with a message, when none is installed).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use scenalog_view::decode_png;

const LOG: &str = "tests/data/av2/logs/3b3570b4-7b0b-3268-a571-b0889dbf40b6";
const RULES: &str = "rules/library/vehicle_with_bicycle_to_its_right.dl";
/// A vehicle this program refers from 7.3 s to 13.7 s, a bicycle on its right.
const TRACK: &str = "2f09a161";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn scenalog(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_scenalog"))
        .current_dir(root())
        .args(args)
        .output()
        .expect("run scenalog")
}

fn explain_picture(out: &Path, extra: &[&str]) -> Output {
    let out = out.to_str().expect("utf-8 path");
    let mut args = vec![
        "explain",
        "--rules",
        RULES,
        "--log",
        LOG,
        "--track",
        TRACK,
        "--picture",
        out,
    ];
    args.extend_from_slice(extra);
    scenalog(&args)
}

#[test]
fn explain_draws_the_match_as_png_svg_and_gif() {
    let dir = tempfile::tempdir().expect("tempdir");
    let png = dir.path().join("m.png");
    let o = explain_picture(&png, &["--at", "8", "--view", "object"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The proof is still printed.
    assert!(String::from_utf8_lossy(&o.stdout).contains("Proof:"));
    let (w, h, rgba) = decode_png(&std::fs::read(&png).expect("png")).expect("decodes");
    assert_eq!((w, h), (800, 800));
    // The referred object is at the centre of the map area in its own frame: the highlight
    // colour is found near the middle of the picture.
    let magenta = rgba
        .chunks(4)
        .filter(|p| p[0] == 0xe6 && p[1] == 0x00 && p[2] == 0x7e)
        .count();
    assert!(magenta > 200, "{magenta} highlight pixels");

    let svg = dir.path().join("m.svg");
    let o = explain_picture(&svg, &["--at", "8"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&svg).expect("svg");
    assert!(text.starts_with("<svg"));
    assert!(text.contains("vehicle with a bicycle to its right"));
    // The `direction` fact of the proof is drawn and labelled.
    assert!(text.contains("right of 2f09a161"), "no direction label");

    let gif = dir.path().join("m.gif");
    let o = explain_picture(&gif, &["--frames", "80..84"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(&gif).expect("gif");
    assert!(bytes.starts_with(b"GIF89a"));
    // One image descriptor (0x2C after a graphic control extension) per frame.
    let frames = bytes.windows(2).filter(|w| w == &[0x00, 0x2C]).count();
    assert!(frames >= 5, "{frames} frames");

    let strip = dir.path().join("path.png");
    let o = explain_picture(&strip, &["--frames", "referred"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(decode_png(&std::fs::read(&strip).expect("png")).is_ok());
}

#[test]
fn explain_picture_errors_are_clear() {
    let dir = tempfile::tempdir().expect("tempdir");
    let o = explain_picture(&dir.path().join("x.png"), &["--frames", "0..100000"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("frame 100000 is outside log"), "{err}");

    // The vehicle is annotated from some frame on; at the log's start it is absent.
    let o = explain_picture(
        &dir.path().join("x.png"),
        &["--at", "0", "--view", "object"],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    if o.status.success() {
        panic!("expected an error for an absent track, got success");
    }
    assert_eq!(o.status.code(), Some(2));
    assert!(err.contains("is not present at frame 0"), "{err}");

    let o = explain_picture(&dir.path().join("no/such/dir/x.png"), &["--at", "8"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("cannot write") && err.contains("no/such/dir/x.png"),
        "{err}"
    );

    let o = explain_picture(&dir.path().join("x.png"), &["--frames", "9..3"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--frames `9..3`"));
    assert!(!dir.path().join("x.png").exists());
}

/// The first browser found on PATH.
fn browser() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |d| d.join(name)))
        .find(|p| p.is_file())
}

fn headless(browser: &Path, extra: &[&str], url: &str) -> Output {
    Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--hide-scrollbars",
            "--virtual-time-budget=3000",
        ])
        .args(extra)
        .arg(url)
        .output()
        .expect("run the browser")
}

#[test]
fn mine_report_opens_from_disk_and_its_scrubber_changes_the_frame() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    let o = scenalog(&[
        "mine",
        "--rules",
        RULES,
        "--logs",
        LOG,
        "--out",
        out.to_str().expect("utf-8"),
        "--report",
        "--report-max-pictures",
        "1",
        "--threads",
        "1",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let page = out.join("report/index.html");
    let html = std::fs::read_to_string(&page).expect("the report page");
    assert!(html.contains("<table class=\"counts\">"));
    assert!(html.contains("vehicle_with_bicycle_to_its_right"));
    assert!(html.contains("type=\"range\""));
    assert!(html.contains("Proof:"));
    // No network: nothing is loaded from another host.
    assert!(!html.contains("http://") && !html.contains("https://"));
    // One pictured match (the cap), the others listed.
    assert_eq!(html.matches("<section class=\"match\"").count(), 1);
    assert!(html.contains("Matches without pictures"));
    let pictures: Vec<PathBuf> = std::fs::read_dir(out.join("report/img"))
        .expect("img dir")
        .map(|e| e.expect("entry").path())
        .collect();
    assert!(pictures.len() >= 2, "{pictures:?}");
    for p in &pictures {
        decode_png(&std::fs::read(p).expect("read")).expect("a PNG");
    }
    let last = pictures.len() - 1;

    let Some(browser) = browser() else {
        eprintln!(
            "skipped the browser check: no chromium on PATH (Debian: apt-get install -y chromium)"
        );
        return;
    };
    let url = format!("file://{}", page.display());
    // The DOM after the page's script ran, with the scrubber moved to the last frame through
    // the page's own handler (the URL fragment calls it as the range input does).
    let dom = headless(&browser, &["--dump-dom"], &format!("{url}#m=0&f={last}"));
    let dom = String::from_utf8_lossy(&dom.stdout);
    assert!(
        dom.contains("<table class=\"counts\">"),
        "no table in the DOM"
    );
    assert!(
        dom.contains(&format!("src=\"img/m0-f{last}.png\"")),
        "the scrubber did not change the picture"
    );
    let shot = |fragment: &str, file: &str| -> Vec<u8> {
        let path = dir.path().join(file);
        let o = headless(
            &browser,
            &[
                &format!("--screenshot={}", path.display()),
                "--window-size=1200,900",
            ],
            &format!("{url}{fragment}"),
        );
        assert!(
            path.is_file(),
            "no screenshot: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let (_, _, rgba) = decode_png(&std::fs::read(&path).expect("shot")).expect("a PNG");
        rgba
    };
    let first_frame = shot("#m=0&f=0", "first.png");
    let last_frame = shot(&format!("#m=0&f={last}"), "last.png");
    // The picture is shown: many pixels of the highlight colour (the referred object) and of
    // the map's grey, in a screenshot that the scrubber's position changes.
    let count = |rgba: &[u8], c: [u8; 3]| {
        rgba.chunks(4)
            .filter(|p| {
                (p[0] as i32 - c[0] as i32).abs() < 8
                    && (p[1] as i32 - c[1] as i32).abs() < 8
                    && (p[2] as i32 - c[2] as i32).abs() < 8
            })
            .count()
    };
    assert!(
        count(&first_frame, [0xe6, 0x00, 0x7e]) > 50,
        "no highlighted object shown"
    );
    assert!(
        count(&first_frame, [0xbc, 0xbc, 0xbc]) > 1000,
        "no lanes shown"
    );
    assert_ne!(
        first_frame, last_frame,
        "the scrubber did not change the frame"
    );
    // The top of the page: the title and the table's text.
    let top = shot("", "top.png");
    let dark = top
        .chunks(4)
        .filter(|p| p[0] < 60 && p[1] < 60 && p[2] < 60)
        .count();
    assert!(dark > 500, "only {dark} text pixels at the top of the page");
}
