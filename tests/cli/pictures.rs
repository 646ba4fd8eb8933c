//! `scenalog explain --picture` and `scenalog mine --report` end to end on the sample logs: the
//! picture files, their errors, and the report page checked in a real headless browser
//! (Debian's `chromium`; the browser part is skipped, with a message, when none is installed).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use scenalog::pipeline::explain::Renderer;
use scenalog::pipeline::picture::frame_pictures;
use scenalog::pipeline::scenario::scenario_from_source;
use scenalog_view::track_path::animation_frames;
use scenalog_view::{decode_png, PathPicture, Picture, Reference};

use crate::util::browser;

const LOG: &str = "tests/data/av2/logs/3b3570b4-7b0b-3268-a571-b0889dbf40b6";
const RULES: &str = "rules/library/vehicle_with_bicycle_to_its_right.dl";
/// A vehicle this program refers from 7.3 s to 13.7 s, a bicycle on its right.
const TRACK: &str = "2f09a161";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn scenalog(args: &[&str]) -> Output {
    crate::util::scenalog()
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
    // An 800 px map, the panel on its right.
    assert_eq!((w, h), (800 + scenalog_view::panel::panel_width(800), 800));
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
    // No network: nothing is loaded from another host; the only addresses are the links that
    // open a match in the studio on this machine.
    let studio_links = html
        .matches("href=\"http://127.0.0.1:7878/#program=")
        .count();
    assert!(studio_links >= 1, "no studio link");
    assert_eq!(html.matches("http://").count(), studio_links);
    assert!(!html.contains("https://"));
    assert!(html.contains("scenalog studio --rules rules/library --logs"));
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
    // The proof shown is the frame's own: only the last frame's is not hidden.
    assert!(
        dom.contains(&format!("<pre class=\"proof\" data-k=\"{last}\">")),
        "the last frame's proof is not shown"
    );
    assert!(
        dom.contains("<pre class=\"proof\" data-k=\"0\" hidden"),
        "the first frame's proof is still shown"
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

/// The frames of a GIF: the global palette (none: empty), and per frame whether it has its own
/// palette and its composited pixels as palette indices.
fn gif_frames(bytes: &[u8]) -> (Vec<u8>, Vec<(bool, Vec<u8>)>) {
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::Indexed);
    let mut d = options.read_info(bytes).expect("a GIF");
    let global = d.global_palette().map(<[u8]>::to_vec).unwrap_or_default();
    let (w, h) = (d.width() as usize, d.height() as usize);
    let mut canvas = vec![0u8; w * h];
    let mut out = Vec::new();
    while let Some(f) = d.read_next_frame().expect("a frame") {
        let fw = f.width as usize;
        for (k, i) in f.buffer.iter().enumerate() {
            if Some(*i) != f.transparent {
                let (x, y) = (f.left as usize + k % fw, f.top as usize + k / fw);
                canvas[y * w + x] = *i;
            }
        }
        out.push((f.palette.is_some(), canvas.clone()));
    }
    (global, out)
}

#[test]
fn the_readme_animation_is_small_with_one_palette() {
    // The README's example: the track's frames 70 to 140 at the default 800 px.
    let dir = tempfile::tempdir().expect("tempdir");
    let gif = dir.path().join("path.gif");
    let o = explain_picture(&gif, &["--frames", "70..140"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(&gif).expect("gif");
    assert!(bytes.starts_with(b"GIF89a"));
    assert!(bytes.len() < 1_000_000, "{} bytes", bytes.len());
    let (global, frames) = gif_frames(&bytes);
    assert_eq!(frames.len(), 71);
    assert_eq!(global.len(), 256 * 3, "one global palette");
    assert!(
        frames.iter().all(|(own, _)| !own),
        "a frame has its own palette"
    );
    // The frames differ (the objects move, the time and the proof change) ...
    let distinct: std::collections::BTreeSet<&Vec<u8>> = frames.iter().map(|(_, f)| f).collect();
    assert!(
        distinct.len() > 60,
        "{} distinct frames of 71",
        distinct.len()
    );
    // ... and the panel's background, the map's off-road colour and the referred object's
    // highlight are each one palette colour, the same in every frame.
    let rgb = |hex: &str| {
        let v = u32::from_str_radix(hex.trim_start_matches('#'), 16).expect("a colour");
        [(v >> 16) as u8, (v >> 8) as u8, v as u8]
    };
    for colour in [
        scenalog_view::style::PANEL,
        scenalog_view::style::BACKGROUND,
        scenalog_view::style::REFERRED,
    ] {
        let c = rgb(colour);
        let n = global.chunks(3).filter(|p| *p == c).count();
        assert_eq!(n, 1, "{colour} is {n} palette entries");
    }
}

#[test]
fn each_animation_frame_carries_its_own_proof() {
    let root = root();
    let rules = root.join(RULES);
    let source = std::fs::read_to_string(&rules).expect("rules");
    let scenario = scenario_from_source(&rules, source).expect("checks");
    let scene = scenalog_facts::load_scene(&root.join(LOG)).expect("log");
    let car = scene
        .tracks
        .iter()
        .find(|t| t.uuid.starts_with(TRACK))
        .expect("the track")
        .id;
    let renderer = Renderer {
        scene: &scene,
        scenario: &scenario,
    };
    let mut like = Picture::new(&scene, 80);
    like.referred = Some(car);
    like.reference = Reference::Referred;
    let limits = scenalog::pipeline::limits::pair_limits(None, None, 1);
    let pictures = frame_pictures(&renderer, &like, 78, 84, &limits).expect("frames");
    assert_eq!(pictures.len(), 7);
    let path = PathPicture {
        picture: like.clone(),
        track: car,
        first: 78,
        last: 84,
        referred_frames: (73..=137).collect(),
        frames: pictures.clone(),
    };
    let svgs = animation_frames(&path).expect("frames");
    assert_eq!(svgs.len(), 7);
    // The panel's text of a frame, whitespace dropped (lines are wrapped).
    let panel_text = |svg: &str| -> String {
        let panel = &svg[svg.find("<g id=\"panel\">").expect("a panel")..];
        panel
            .split("<text")
            .skip(1)
            .filter_map(|t| Some(t.split_once('>')?.1.split_once("</text>")?.0))
            .collect::<String>()
            .replace("&quot;", "\"")
            .split_whitespace()
            .collect()
    };
    for (k, (svg, pic)) in svgs.iter().zip(&pictures).enumerate() {
        let f = 78 + k as u32;
        assert_eq!(pic.frame, f);
        let seconds = scene.timeline.seconds(f).expect("a time");
        assert!(
            svg.contains(&format!("t = {seconds:.1} s (frame {f})")),
            "frame {f}"
        );
        // The frame's own proof: its facts name its own time, and are the ones drawn.
        assert!(!pic.notes.is_empty(), "frame {f}: no proof");
        let direction = pic
            .notes
            .iter()
            .find(|(n, _)| n.starts_with("direction("))
            .expect("the direction fact");
        assert!(
            direction.0.contains(&format!(", {seconds:.1} s,")),
            "{direction:?}"
        );
        let text = panel_text(svg);
        let squashed: String = direction.0.split_whitespace().collect();
        assert!(
            text.contains(&squashed),
            "frame {f}: {squashed} not in {text}"
        );
        for other in pictures.iter().filter(|p| p.frame != f) {
            let s = other.scene.timeline.seconds(other.frame).expect("a time");
            assert!(
                !text.contains(&format!(",{s:.1}s,")),
                "frame {f} shows frame {}'s proof",
                other.frame
            );
        }
    }
}

/// The description line of each library program, by program name.
fn library_descriptions() -> Vec<(String, String)> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(root().join("rules/library")).expect("the library") {
        let p = e.expect("entry").path();
        if p.extension().is_some_and(|x| x == "dl") {
            let text = std::fs::read_to_string(&p).expect("a program");
            let name = p
                .file_stem()
                .expect("a name")
                .to_string_lossy()
                .into_owned();
            let description = text
                .lines()
                .find_map(|l| l.strip_prefix("// description:"))
                .map(|d| d.trim().to_string())
                .unwrap_or_else(|| name.replace('_', " "));
            out.push((name, description));
        }
    }
    out
}

#[test]
fn the_report_pictures_every_matched_program_the_scored_ones_first() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    let gt = "tests/data/av2/eval/combined_gt_dev.pkl";
    let o = scenalog(&[
        "mine",
        "--rules",
        "rules/library",
        "--logs",
        "tests/data/av2/logs",
        "--gt",
        gt,
        "--out",
        out.to_str().expect("utf-8"),
        "--report",
        "--report-max-pictures",
        "0",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let matches: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("matches.json")).expect("matches"))
            .expect("JSON");
    let matched: std::collections::BTreeSet<String> = matches
        .as_array()
        .expect("a list")
        .iter()
        .map(|m| m["program"].as_str().expect("a program").to_string())
        .collect();
    assert!(matched.len() > 40, "{} programs matched", matched.len());
    let html = std::fs::read_to_string(out.join("report/index.html")).expect("the page");
    // The pictured sections' programs, in page order.
    let sections: Vec<&str> = html
        .split("<section class=\"match\"")
        .skip(1)
        .map(|s| {
            let b = s
                .split_once("<div class=\"text\"><b>")
                .expect("a program")
                .1;
            b.split_once("</b>").expect("its end").0
        })
        .collect();
    let pictured: std::collections::BTreeSet<String> =
        sections.iter().map(|s| s.to_string()).collect();
    assert_eq!(pictured, matched, "every matched program has a picture");
    // Every pictured section's images exist.
    for img in html.split("src=\"img/").skip(1) {
        let name = img.split_once('"').expect("quoted").0;
        assert!(out.join("report/img").join(name).is_file(), "{name}");
    }
    // The scored programs: those whose description is a prompt of the ground truth.
    let truth = scenalog_eval::read_any(&root().join(gt)).expect("the ground truth");
    let prompts: std::collections::BTreeSet<&String> =
        truth.sequences.keys().map(|(_, p)| p).collect();
    let scored: Vec<String> = library_descriptions()
        .into_iter()
        .filter(|(n, d)| prompts.contains(d) && matched.contains(n))
        .map(|(n, _)| n)
        .collect();
    assert!(scored.contains(&"stopped_car".to_string()), "{scored:?}");
    assert!(
        scored.contains(&"vehicle_with_bicycle_to_its_right".to_string()),
        "{scored:?}"
    );
    let first: std::collections::BTreeSet<&str> = sections
        .iter()
        .take_while(|s| scored.iter().any(|x| x == *s))
        .copied()
        .collect();
    assert_eq!(
        first.len(),
        scored.len(),
        "the scored programs come first: {sections:?}"
    );
    // Each section shows one proof per frame, the scrubber's.
    let one = html
        .split("<section class=\"match\"")
        .nth(1)
        .expect("a section");
    let one = one.split("</section>").next().expect("its end");
    let positions = one.matches("<pre class=\"proof\"").count();
    assert!(positions >= 2, "{positions} proofs");
    assert_eq!(one.matches(" hidden>").count(), positions - 1);
}

/// A pictured frame of a match where the track is not referred (the frames are spread between
/// its first and last: stopped_car's 0f0d16d4 at 3.6 s on 3b3570b4) says why not, as `explain
/// --at 3.6 --why-not` does, instead of "why not:" followed by nothing.
#[test]
fn a_report_frame_where_the_track_is_not_referred_says_why_not() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    let o = scenalog(&[
        "mine",
        "--rules",
        "rules/library/stopped_car.dl",
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
    let html = std::fs::read_to_string(out.join("report/index.html")).expect("the report page");
    let at = html
        .find("at 3.6 s (frame 36): NOT referred")
        .expect("frame 36 is pictured and not referred");
    let proof = &html[at..];
    let proof = &proof[..proof.find("</pre>").expect("the block ends")];
    assert!(proof.contains("Why not:"), "{proof}");
    assert!(proof.contains("✗ stopped(V, T)"), "{proof}");
}
