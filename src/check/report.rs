//! The report of a check: `summary.json`, and `index.html`, one page with the images beside it
//! (no network): per image the renderer's picture, the reference and a difference heat map, a
//! slider to wipe between the first two, zoom with visible pixels, the diagnosis and the command
//! line; failures first, with filters.
//!
//! The page is written with `format!` rather than a template crate: it is one small page with
//! one repeated block, and every value put into it goes through `escape`
//! ([`super::untrusted::html`]).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::untrusted::html as escape;
use super::{
    Checked, Finding, Graded, Group, Rule, Status, diagnose, summary_json, verdict_entries,
};
use crate::image_io::{self, ImageFormat};

/// A report being built: a folder beside its place, which each line's pictures go into as soon
/// as the line is graded (so that check keeps no pixels), and which is renamed into place once
/// `summary.json` and `index.html` are written beside them.
#[derive(Debug)]
pub struct Staging {
    folder: tempfile::TempDir,
    place: PathBuf,
    /// The first picture that could not be written, reported when the report is placed.
    failed: std::sync::Mutex<Option<String>>,
}

impl Staging {
    /// A new report for `place`: refused if `place` holds files and is not a report of
    /// raycast's (it would be replaced).
    pub fn new(place: &Path) -> Result<Staging, String> {
        let parent = match place.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        if let Ok(entries) = std::fs::read_dir(place) {
            if entries.count() > 0 && !place.join("summary.json").is_file() {
                return Err(format!(
                    "{} holds files and is not a report of raycast's (it has no \
                     summary.json): give a new or empty folder",
                    place.display()
                ));
            }
        } else if place.exists() {
            return Err(format!("{} is not a folder", place.display()));
        }
        std::fs::create_dir_all(&parent).map_err(|e| format!("{}: {e}", parent.display()))?;
        let folder = tempfile::Builder::new()
            .prefix(".raycast-report-")
            .tempdir_in(&parent)
            .map_err(|e| format!("{}: {e}", parent.display()))?;
        Ok(Staging {
            folder,
            place: place.to_path_buf(),
            failed: std::sync::Mutex::new(None),
        })
    }

    /// The folder being built.
    pub fn path(&self) -> &Path {
        self.folder.path()
    }

    /// Puts the report in its place: renamed over the old one (a reader, or a second check
    /// writing the same report, sees the old report or the new one whole, never a mixture).
    pub fn place(self) -> Result<(), String> {
        if let Some(failed) = self.failed.lock().ok().and_then(|f| f.clone()) {
            return Err(failed);
        }
        let fail = |path: &Path, e: std::io::Error| format!("{}: {e}", path.display());
        {
            super::modes::set_mode(self.path(), 0o755).map_err(|e| fail(self.path(), e))?;
        }
        let dir = self.place.clone();
        let parent = self
            .path()
            .parent()
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        let built = self.folder.keep();
        for _ in 0..10 {
            let old = parent.join(format!(
                ".raycast-old-report-{}-{}",
                std::process::id(),
                std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_nanos())
            ));
            let moved_old = std::fs::rename(&dir, &old).is_ok();
            let placed = std::fs::rename(&built, &dir);
            if moved_old {
                let _ = std::fs::remove_dir_all(&old);
            }
            if placed.is_ok() {
                return Ok(());
            }
        }
        let _ = std::fs::remove_dir_all(&built);
        Err(format!(
            "{}: another program keeps writing there",
            dir.display()
        ))
    }

    /// Writes the pictures of one line (its own, the references and the heat maps) and names
    /// them in each `Graded`; their pixels are dropped either way.
    pub fn keep_pictures(&self, graded: &mut [Graded], tolerance: u8) {
        for g in graded.iter_mut() {
            // Named by the suite's line, which a shard keeps: shards' pictures never collide.
            let name =
                |kind: &str| format!("{:03}-{}-{}-{kind}.png", g.line.0, g.line.1, safe(&g.name));
            let write = |kind: &str, image: &crate::shade::Image| -> Option<String> {
                let file = name(kind);
                let bytes = image_io::encode(image, ImageFormat::Png);
                match std::fs::write(self.folder.path().join(&file), bytes) {
                    Ok(()) => Some(file),
                    Err(e) => {
                        if let Ok(mut failed) = self.failed.lock() {
                            failed.get_or_insert_with(|| format!("{file}: {e}"));
                        }
                        None
                    }
                }
            };
            let actual = g.actual.take();
            let reference = g.reference.take();
            g.pictures = Pictures {
                actual: actual.as_ref().and_then(|i| write("actual", i)),
                reference: reference.as_ref().and_then(|i| write("reference", i)),
                diff: match (&actual, &reference) {
                    (Some(a), Some(r)) if (a.width, a.height) == (r.width, r.height) => {
                        write("diff", &diagnose::heat_map(a, r, tolerance))
                    }
                    _ => None,
                },
            };
        }
    }
}

/// The files of one picture's report: the renderer's, the reference, the heat map.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Pictures {
    /// The renderer's picture.
    pub actual: Option<String>,
    /// The reference.
    pub reference: Option<String>,
    /// Where they differ.
    pub diff: Option<String>,
}

/// Writes `summary.json` and `index.html` beside the pictures `checked` kept in the report it
/// began (its staging, taken), and puts the report in its place.
pub fn write_report(checked: &mut Checked, groups: &[Group], rule: Rule) -> Result<(), String> {
    let staging = checked
        .staging
        .take()
        .ok_or("no report was begun (check was run without --report)")?;
    write_into(staging.path(), checked, groups, rule)?;
    staging.place()
}

/// Writes the report's files into `dir`, an empty folder.
fn write_into(dir: &Path, checked: &Checked, groups: &[Group], rule: Rule) -> Result<(), String> {
    let graded = &checked.graded[..];
    let fail = |e: std::io::Error| format!("{}: {e}", dir.display());
    let json = serde_json::to_string_pretty(&summary_json(checked, groups, rule))
        .map_err(|e| e.to_string())?;
    std::fs::write(dir.join("summary.json"), json + "\n").map_err(fail)?;
    super::formats::write_all(dir, checked, groups)?;
    let mut order: Vec<&Graded> = graded.iter().collect();
    // Failures and errors first, then passes, each in the suite's order.
    order.sort_by_key(|g| g.status == Status::Pass);
    let mut blocks = String::new();
    for g in order {
        let Pictures {
            actual,
            reference,
            diff,
        } = g.pictures.clone();
        blocks.push_str(&block(g, actual, reference, diff));
    }
    let passed = graded.iter().filter(|g| g.status == Status::Pass).count();
    let page = PAGE
        .replace(
            "{{SUMMARY}}",
            &format!("{passed} passed, {} failed", graded.len() - passed),
        )
        .replace(
            "{{VERDICT}}",
            &(build_html(checked) + &variation_html(checked) + &verdict_html(groups)),
        )
        .replace("{{BLOCKS}}", &blocks);
    std::fs::write(dir.join("index.html"), page).map_err(fail)
}

/// A file name made of an image's name: letters, digits, `-`, `_` and `.` only.
fn safe(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// A build that failed, above the verdict: how it ended and its last lines, the one reason
/// every picture below is missing.
fn build_html(checked: &Checked) -> String {
    match super::formats::failed_build(checked) {
        Some(text) => format!(
            "<section class=\"build\"><h2>The build failed</h2><pre>{}</pre></section>",
            escape(&text)
        ),
        None => String::new(),
    }
}

/// The scenes' variation (`--vary`), above the verdict: its seed and a link to each varied
/// scene, so that a teacher can read and render what the student was graded on.
fn variation_html(checked: &Checked) -> String {
    let Some(variation) = &checked.variation else {
        return String::new();
    };
    let scenes: String = variation
        .scenes
        .iter()
        .map(|scene| {
            let path = format!("{}/{}", super::vary::VARIED_FOLDER, scene.display());
            format!(
                "<li><a href=\"{}\">{}</a></li>",
                escape(&path),
                escape(&scene.display().to_string())
            )
        })
        .collect();
    format!(
        "<section class=\"varied\"><p>{}.</p><ul>{scenes}</ul></section>",
        escape(&upper_first(&variation.sentence()))
    )
}

fn upper_first(text: &str) -> String {
    let mut chars = text.chars();
    chars
        .next()
        .map_or_else(String::new, |c| c.to_uppercase().chain(chars).collect())
}

/// The renderer's verdict, at the top of the page: one line a group of failing pictures.
fn verdict_html(groups: &[Group]) -> String {
    if groups.is_empty() {
        return String::new();
    }
    let items: String = verdict_entries(groups)
        .iter()
        .map(|(headline, details)| {
            let details: String = details
                .iter()
                .map(|d| format!("<li>{}</li>", escape(d)))
                .collect();
            let details = if details.is_empty() {
                String::new()
            } else {
                format!("<ul>{details}</ul>")
            };
            format!("<li><strong>{}</strong>{details}</li>", escape(headline))
        })
        .collect();
    format!("<section class=\"verdict\"><h2>Verdict</h2><ol>{items}</ol></section>")
}

fn block(
    g: &Graded,
    actual: Option<String>,
    reference: Option<String>,
    diff: Option<String>,
) -> String {
    let status = g.status.code();
    let codes: Vec<String> = g.findings.iter().map(Finding::code).collect();
    let off = g
        .bad_fraction
        .map(|f| format!("{:.3}% of pixels off", 100.0 * f))
        .unwrap_or_else(|| "not compared".into());
    let picture = |file: &Option<String>, what: &str, caption: &str| match file {
        Some(f) => format!(
            "<figure><img class=\"px\" src=\"{}\" alt=\"{what}\"><figcaption>{caption}</figcaption></figure>",
            escape(f)
        ),
        None => format!(
            "<figure class=\"none\"><div>no image</div><figcaption>{caption}</figcaption></figure>"
        ),
    };
    // The course published no picture for the line: say whose the reference is, on the page
    // as the terminal does.
    let (reference_caption, against) = if g.by_chance {
        (
            "reference: raycast's render (one seed)",
            "<p class=\"against\">The course published no picture for this line, and its samples \
             fall by chance: it is graded against the spread of raycast's renders with several \
             seeds (a samples picture by where its dots may fall); the reference shown is one \
             of them.</p>",
        )
    } else if g.against_raycast {
        (
            "reference: raycast's render",
            "<p class=\"against\">The course published no picture for this line: the \
             reference is raycast's own render of it.</p>",
        )
    } else {
        ("reference", "")
    };
    let wipe = match (&actual, &reference) {
        (Some(a), Some(r)) => format!(
            "<figure class=\"wipe\"><div class=\"stack\"><img class=\"px under\" src=\"{}\" \
             alt=\"reference\"><img class=\"px over\" src=\"{}\" alt=\"yours\"></div>\
             <input type=\"range\" min=\"0\" max=\"100\" value=\"50\" aria-label=\"wipe between \
             yours (left) and the reference (right)\"><figcaption>yours ◀ wipe ▶ reference \
             <button type=\"button\" class=\"flip\">flip</button></figcaption></figure>",
            escape(r),
            escape(a)
        ),
        _ => String::new(),
    };
    let mut html = String::new();
    let _ = writeln!(
        html,
        "<section class=\"image {status}\" data-status=\"{status}\">\
         <h2><span class=\"badge\">{status}</span> {name} <small>{off}</small></h2>\
         <p class=\"codes\">{codes}</p><p class=\"why\">{why}</p>\
         {against}<pre class=\"command\">{command}</pre>{stderr}\
         <div class=\"pictures\">{a}{r}{d}{wipe}</div>{tree}</section>",
        name = escape(&g.name),
        codes = escape(&codes.join(", ")),
        why = escape(&g.explanation),
        command = escape(&g.command),
        stderr = if g.status == super::Status::Error && !g.stderr.trim().is_empty() {
            format!(
                "<details open><summary>the renderer's stderr (last lines)</summary>\
                 <pre class=\"stderr\">{}</pre></details>",
                escape(&super::untrusted::tail(&g.stderr))
            )
        } else {
            String::new()
        },
        a = picture(&actual, "yours", "yours"),
        r = picture(&reference, "reference", reference_caption),
        d = picture(&diff, "difference", "difference"),
        tree = match &g.worst_pixel {
            Some(w) => format!(
                "<details class=\"ray-tree\"><summary>what raycast traced at pixel ({x}, {y}), \
                 where yours differs most ({d} levels; x from the left, y from the bottom, as \
                 <code>raycast ... -inspect {x} {y}</code> counts)</summary>\
                 <pre>{tree}</pre></details>",
                x = w.x,
                y = w.y,
                d = w.difference,
                tree = escape(&w.ray_tree)
            ),
            None => String::new(),
        },
    );
    html
}

/// The page; `{{SUMMARY}}` and `{{BLOCKS}}` are filled in. Its script also checks itself when
/// opened with `?selftest` (every picture loads, the wipe moves, no script error), for the
/// tests to run it in a real browser.
const PAGE: &str = r#"<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>raycast check: {{SUMMARY}}</title>
<style>
body { font-family: system-ui, sans-serif; margin: 1.5em; background: #fafafa; color: #222; }
header { display: flex; gap: 1.5em; align-items: center; flex-wrap: wrap; }
.image { background: white; border: 1px solid #ddd; border-left: 6px solid #2a2; margin: 1em 0; padding: 0.5em 1em; }
.image.fail, .image.error { border-left-color: #c22; }
.badge { text-transform: uppercase; font-size: 0.8em; padding: 0.1em 0.4em; border-radius: 3px; background: #2a2; color: white; }
.fail .badge, .error .badge { background: #c22; }
.codes { font-family: monospace; font-weight: bold; }
.command { background: #f3f3f3; padding: 0.4em; overflow-x: auto; }
.pictures { display: flex; gap: 1em; flex-wrap: wrap; align-items: flex-start; }
figure { margin: 0; text-align: center; }
figure.none div { width: calc(var(--zoom) * var(--ref-w, 128px)); height: calc(var(--zoom) * var(--ref-h, 128px)); display: flex; align-items: center; justify-content: center; background: #eee; }
img.px { image-rendering: pixelated; image-rendering: crisp-edges; width: calc(var(--zoom) * var(--w, 200px)); }
.stack { position: relative; display: inline-block; }
.stack .over { position: absolute; left: 0; top: 0; clip-path: inset(0 50% 0 0); }
.wipe input { width: 100%; }
.hidden { display: none; }
</style>
</head>
<body style="--zoom: 1">
<header>
<h1>raycast check: {{SUMMARY}}</h1>
<label><input type="checkbox" id="show-pass" checked> passes</label>
<label><input type="checkbox" id="show-fail" checked> failures</label>
<label>zoom <select id="zoom"><option>1</option><option>2</option><option>4</option><option>8</option></select></label>
</header>
<main>
{{VERDICT}}
{{BLOCKS}}
</main>
<pre id="selftest" class="hidden"></pre>
<script>
"use strict";
const errors = [];
window.addEventListener("error", e => errors.push(String(e.message)));
function wipe(section, value) {
  const over = section.querySelector(".over");
  if (over) over.style.clipPath = "inset(0 " + (100 - value) + "% 0 0)";
}
for (const section of document.querySelectorAll(".image")) {
  const range = section.querySelector(".wipe input");
  if (range) {
    range.addEventListener("input", () => wipe(section, Number(range.value)));
    section.querySelector(".flip").addEventListener("click", () => {
      range.value = Number(range.value) > 50 ? 0 : 100;
      wipe(section, Number(range.value));
    });
    wipe(section, Number(range.value));
  }
}
for (const img of document.querySelectorAll("img.px")) {
  const size = () => {
    img.style.setProperty("--w", img.naturalWidth + "px");
    // A picture that is missing stands in a box of the reference's size, in line with it.
    if (img.alt === "reference" && !img.classList.contains("under")) {
      const section = img.closest(".image");
      section.style.setProperty("--ref-w", img.naturalWidth + "px");
      section.style.setProperty("--ref-h", img.naturalHeight + "px");
    }
  };
  if (img.complete) size(); else img.addEventListener("load", size);
}
function filter() {
  const pass = document.getElementById("show-pass").checked;
  const fail = document.getElementById("show-fail").checked;
  for (const section of document.querySelectorAll(".image")) {
    const shown = section.dataset.status === "pass" ? pass : fail;
    section.classList.toggle("hidden", !shown);
  }
}
document.getElementById("show-pass").addEventListener("change", filter);
document.getElementById("show-fail").addEventListener("change", filter);
document.getElementById("zoom").addEventListener("change", e => {
  document.body.style.setProperty("--zoom", e.target.value);
});
if (location.search.includes("selftest")) {
  window.addEventListener("load", () => {
    const problems = errors.slice();
    const images = [...document.querySelectorAll("img")];
    for (const img of images) {
      if (!img.complete || img.naturalWidth === 0) problems.push("not loaded: " + img.getAttribute("src"));
    }
    let wipes = 0;
    for (const section of document.querySelectorAll(".image")) {
      const range = section.querySelector(".wipe input");
      if (!range) continue;
      const over = section.querySelector(".over");
      range.value = 10; range.dispatchEvent(new Event("input"));
      const at10 = over.style.clipPath;
      range.value = 90; range.dispatchEvent(new Event("input"));
      const at90 = over.style.clipPath;
      if (at10 === at90) problems.push("the wipe does not move: " + section.querySelector("h2").textContent);
      wipes += 1;
    }
    for (const none of document.querySelectorAll("figure.none div")) {
      const reference = none.closest(".image").querySelector("img.px[alt=reference]");
      if (!reference) continue;
      const a = none.getBoundingClientRect(), b = reference.getBoundingClientRect();
      if (Math.abs(a.width - b.width) > 0.5 || Math.abs(a.height - b.height) > 0.5 || Math.abs(a.top - b.top) > 0.5) {
        problems.push("a missing picture's box is not the reference's size and height: " + none.closest(".image").querySelector("h2").textContent);
      }
    }
    document.getElementById("show-pass").click();
    const hidden = document.querySelectorAll(".image.pass.hidden").length;
    const passes = document.querySelectorAll(".image.pass").length;
    if (hidden !== passes) problems.push("the pass filter hides " + hidden + " of " + passes);
    const out = document.getElementById("selftest");
    out.textContent = (problems.length ? "FAILED: " + problems.join("; ") : "ok") +
      " (" + images.length + " images, " + wipes + " wipes)";
    out.classList.remove("hidden");
  });
}
</script>
</body>
</html>
"#;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escaping() {
        assert_eq!(safe("out/put 3.tga"), "out_put_3.tga");
    }
}
