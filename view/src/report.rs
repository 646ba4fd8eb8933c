//! The static HTML report of a mining run: one self-contained page (inline style and script,
//! pictures as files beside it, no server and no network) with the table of programs × logs
//! and, per pictured match, its pictures over the referred span with a frame scrubber, its time
//! span and the proof of the frame the scrubber shows.

use std::fmt::Write;
use std::path::Path;

use crate::error::ViewError;
use crate::output::write_file;
use crate::svg::escape;

/// One picture of a match: an image file relative to the page, and its time.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportFrame {
    /// Path of the image relative to the page (e.g. `img/m3-f2.png`).
    pub image: String,
    /// The frame index.
    pub frame: u32,
    /// Seconds from the log's start.
    pub seconds: f64,
    /// Whether the track is referred at this frame.
    pub referred: bool,
    /// The proof at this frame (as `scenalog explain` prints it).
    pub proof: String,
}

/// One matched track of one (log, program) pair.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportMatch {
    /// The program's name.
    pub program: String,
    /// The scenario's description.
    pub description: String,
    /// The log id.
    pub log_id: String,
    /// The track's uuid.
    pub track_uuid: String,
    /// The track's category.
    pub category: String,
    /// First and last second the track is referred at.
    pub span: (f64, f64),
    /// How many frames it is referred at.
    pub referred_frames: usize,
    /// Its pictures with their proofs, in time order (empty past the picture cap).
    pub frames: Vec<ReportFrame>,
    /// The `scenalog explain` command that explains it.
    pub command: String,
    /// The address that opens it in `scenalog studio` (started on the run's rules and logs).
    pub studio: String,
}

/// Everything the page shows.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Report {
    /// The page's title.
    pub title: String,
    /// Lines under the title (where the run's outputs are, the picture cap, …).
    pub notes: Vec<String>,
    /// The table's rows: program names.
    pub programs: Vec<String>,
    /// Per row, whether the run is scored on that program's prompt (marked in the table).
    pub scored: Vec<bool>,
    /// The table's columns: log ids.
    pub logs: Vec<String>,
    /// Matched tracks per program (row) and log (column); `None` where the pair failed.
    pub counts: Vec<Vec<Option<usize>>>,
    /// The matches, in table order.
    pub matches: Vec<ReportMatch>,
    /// The pictures' size in pixels, width and height (shown 480 px high); `(0, 0)`: square.
    pub image_size: (u32, u32),
}

const STYLE: &str = r#"
body{font-family:system-ui,sans-serif;margin:1.5em;color:#111;background:#fafafa}
h1{font-size:1.4em;margin:0 0 .3em}
table.counts{border-collapse:collapse;font-size:.85em;margin:1em 0}
table.counts td,table.counts th{border:1px solid #ccc;padding:2px 8px;text-align:right}
table.counts td:first-child,table.counts th:first-child{text-align:left}
table.counts td.zero{color:#bbb}
table.counts td.failed{color:#d50000}
section.match{background:#fff;border:1px solid #ddd;border-radius:6px;padding:.8em;margin:1em 0;display:flex;gap:1em;flex-wrap:wrap}
section.match .pic{max-width:100%}
section.match img{height:480px;width:auto;max-width:100%;display:block;background:#eee}
section.match .text{flex:1;min-width:320px}
pre{font-size:.78em;background:#f4f4f4;padding:.6em;overflow:auto;max-height:28em}
input.scrub{width:100%}
.scored{font-size:.75em;background:#1565c0;color:#fff;border-radius:3px;padding:0 4px;margin-left:4px}
.label{font-size:.9em}
details.rest summary h2{display:inline}
.referred{color:#e6007e;font-weight:bold}
"#;

const SCRIPT: &str = r#"
function show(sec, k) {
  var frames = JSON.parse(sec.getAttribute('data-frames'));
  if (!frames.length) return;
  k = Math.max(0, Math.min(frames.length - 1, k|0));
  var f = frames[k];
  sec.querySelector('img').src = f[0];
  sec.querySelector('input.scrub').value = k;
  var l = sec.querySelector('.label');
  l.textContent = 't = ' + f[2].toFixed(1) + ' s (frame ' + f[1] + ')' + (f[3] ? ' · referred' : ' · not referred');
  l.className = 'label' + (f[3] ? ' referred' : '');
  sec.querySelectorAll('pre.proof').forEach(function (p) { p.hidden = p.getAttribute('data-k') != k; });
}
document.addEventListener('input', function (e) {
  if (e.target.classList.contains('scrub')) show(e.target.closest('section'), e.target.value);
});
function fromHash() {
  var m = /m=(\d+)(?:&f=(\d+))?/.exec(location.hash);
  if (!m) return;
  var sec = document.getElementById('m-' + m[1]);
  if (!sec) return;
  if (m[2] !== undefined) show(sec, +m[2]);
  sec.scrollIntoView();
}
window.addEventListener('hashchange', fromHash);
window.addEventListener('load', fromHash);
fromHash();
"#;

fn frames_json(frames: &[ReportFrame]) -> String {
    let items: Vec<String> = frames
        .iter()
        .map(|f| {
            format!(
                "[\"{}\",{},{:.3},{}]",
                f.image.replace('\\', "/").replace('"', ""),
                f.frame,
                f.seconds,
                f.referred
            )
        })
        .collect();
    format!("[{}]", items.join(","))
}

/// The page as HTML text.
pub fn report_html(r: &Report) -> String {
    let mut h = String::with_capacity(64 * 1024 + r.matches.len() * 4096);
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>{}</title><style>{STYLE}</style></head><body>\n<h1>{}</h1>\n",
        escape(&r.title),
        escape(&r.title)
    );
    for n in &r.notes {
        let _ = writeln!(h, "<p>{}</p>", escape(n));
    }
    // The table: first match of each pair linked from its cell.
    let _ = write!(h, "<table class=\"counts\"><tr><th>program</th>");
    for l in &r.logs {
        let short: String = l.chars().take(8).collect();
        let _ = write!(h, "<th title=\"{}\">{}</th>", escape(l), escape(&short));
    }
    h.push_str("<th>total</th></tr>\n");
    for (i, p) in r.programs.iter().enumerate() {
        let tag = if r.scored.get(i).copied().unwrap_or(false) {
            "<span class=\"scored\" title=\"the run is scored on this program's prompt\">scored</span>"
        } else {
            ""
        };
        let _ = write!(h, "<tr><td>{}{tag}</td>", escape(p));
        let mut total = 0;
        for (j, l) in r.logs.iter().enumerate() {
            match r
                .counts
                .get(i)
                .and_then(|row| row.get(j))
                .copied()
                .flatten()
            {
                None => h.push_str("<td class=\"failed\">failed</td>"),
                Some(0) => h.push_str("<td class=\"zero\">0</td>"),
                Some(n) => {
                    total += n;
                    let first = r
                        .matches
                        .iter()
                        .position(|m| &m.program == p && &m.log_id == l && !m.frames.is_empty());
                    match first {
                        Some(k) => {
                            let _ = write!(h, "<td><a href=\"#m={k}\">{n}</a></td>");
                        }
                        None => {
                            let _ = write!(h, "<td>{n}</td>");
                        }
                    }
                }
            }
        }
        let _ = writeln!(h, "<td>{total}</td></tr>");
    }
    h.push_str("</table>\n");
    let pictured: Vec<(usize, &ReportMatch)> = r
        .matches
        .iter()
        .enumerate()
        .filter(|(_, m)| !m.frames.is_empty())
        .collect();
    let _ = writeln!(h, "<h2>Matches with pictures ({})</h2>", pictured.len());
    let (iw, ih) = match r.image_size {
        (w, h) if w > 0 && h > 0 => (480 * w / h, 480),
        _ => (480, 480),
    };
    for (k, m) in &pictured {
        let referred_at = m.frames.iter().position(|f| f.referred).unwrap_or_default();
        let f0 = &m.frames[referred_at];
        let _ = write!(
            h,
            "<section class=\"match\" id=\"m-{k}\" data-frames='{}'>\
             <div class=\"pic\"><img loading=\"lazy\" alt=\"{} at {:.1} s\" src=\"{}\" width=\"{iw}\" height=\"{ih}\">\
             <input class=\"scrub\" type=\"range\" min=\"0\" max=\"{}\" value=\"{referred_at}\" aria-label=\"frame\">\
             <div class=\"label{}\">t = {:.1} s (frame {}){}</div></div>\
             <div class=\"text\"><b>{}</b> · {} <br>log {} · track {} ({})<br>\
             referred in {} frames, from {:.1} s to {:.1} s\
             <pre class=\"cmd\">{}</pre><a class=\"studio\" href=\"{}\">open in the studio</a><details open><summary>proof at the frame shown</summary>",
            frames_json(&m.frames),
            escape(&m.track_uuid),
            f0.seconds,
            escape(&f0.image),
            m.frames.len().saturating_sub(1),
            if f0.referred { " referred" } else { "" },
            f0.seconds,
            f0.frame,
            if f0.referred { " · referred" } else { " · not referred" },
            escape(&m.program),
            escape(&m.description),
            escape(&m.log_id),
            escape(&m.track_uuid),
            escape(&m.category),
            m.referred_frames,
            m.span.0,
            m.span.1,
            escape(&m.command),
            escape(&m.studio),
        );
        for (j, f) in m.frames.iter().enumerate() {
            let _ = write!(
                h,
                "<pre class=\"proof\" data-k=\"{j}\"{}>{}</pre>",
                if j == referred_at { "" } else { " hidden" },
                escape(&f.proof)
            );
        }
        h.push_str("</details></div></section>\n");
    }
    let rest: Vec<&ReportMatch> = r.matches.iter().filter(|m| m.frames.is_empty()).collect();
    if !rest.is_empty() {
        let _ = writeln!(
            h,
            "<details class=\"rest\"><summary><h2>Matches without pictures ({}): past --report-max-pictures</h2></summary>\
             <table class=\"counts\"><tr><th>program</th><th>log</th><th>track</th><th>span</th><th>picture</th><th>studio</th></tr>",
            rest.len()
        );
        for m in rest {
            let short: String = m.log_id.chars().take(8).collect();
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{} ({})</td><td>{:.1}–{:.1} s</td><td><code>{} --picture out.png</code></td><td><a href=\"{}\">open</a></td></tr>",
                escape(&m.program),
                escape(&short),
                escape(&m.track_uuid),
                escape(&m.category),
                m.span.0,
                m.span.1,
                escape(&m.command),
                escape(&m.studio)
            );
        }
        h.push_str("</table></details>\n");
    }
    let _ = write!(h, "<script>{SCRIPT}</script>\n</body></html>\n");
    h
}

/// Writes `dir/index.html` (the pictures the report names must be written by the caller,
/// relative to `dir`).
pub fn write_report(dir: &Path, report: &Report) -> Result<(), ViewError> {
    std::fs::create_dir_all(dir).map_err(|source| ViewError::Write {
        path: dir.to_path_buf(),
        source,
    })?;
    write_file(&dir.join("index.html"), report_html(report).as_bytes())
}
