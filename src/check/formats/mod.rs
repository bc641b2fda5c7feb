//! The grades of a check in the formats courses' platforms read, written beside `summary.json`:
//! Gradescope's `results.json` ([`gradescope`]), PrairieLearn's external grader results
//! ([`prairielearn`]), JUnit XML ([`junit`], as GitHub, GitLab and Jenkins read it) and GitHub
//! Classroom's autograding result ([`classroom`]). Each picture is one test, worth its points
//! from the suite's `POINTS` file (one by default), all of them for a pass and none otherwise.

pub mod classroom;
pub mod gradescope;
pub mod junit;
pub mod prairielearn;

use std::path::Path;

use super::{Checked, Graded, Group, Status, finding, verdict_lines};

/// The file names, in the report's folder.
pub const FILES: [&str; 4] = [
    "gradescope.json",
    "prairielearn.json",
    "junit.xml",
    "github-classroom.json",
];

/// Writes every format into `dir`, where the report's pictures already are; `groups` is the
/// renderer's verdict.
pub fn write_all(dir: &Path, checked: &Checked, groups: &[Group]) -> Result<(), String> {
    let fail = |name: &str, e: std::io::Error| format!("{}: {e}", dir.join(name).display());
    let pretty =
        |value: &serde_json::Value| serde_json::to_string_pretty(value).unwrap_or_default() + "\n";
    let files = [
        (FILES[0], pretty(&gradescope::results(checked, groups))),
        (
            FILES[1],
            pretty(&prairielearn::results(checked, groups, dir)),
        ),
        (FILES[2], junit::xml(checked, groups)),
        (FILES[3], pretty(&classroom::results(checked))),
    ];
    for (name, text) in files {
        std::fs::write(dir.join(name), text).map_err(|e| fail(name, e))?;
    }
    Ok(())
}

/// A picture's points: all of them for a pass.
pub fn score(g: &Graded) -> f64 {
    if g.status == Status::Pass {
        g.points
    } else {
        0.0
    }
}

/// The points of every picture.
pub fn max_score(checked: &Checked) -> f64 {
    checked.graded.iter().map(|g| g.points).sum()
}

/// The points earned.
pub fn total(checked: &Checked) -> f64 {
    checked.graded.iter().map(score).sum()
}

/// A test's grade in a line: `fail, 6.705% of pixels off: pixel_corner`.
pub fn status_line(g: &Graded) -> String {
    let off = g
        .bad_fraction
        .map(|f| format!(", {:.3}% of pixels off", 100.0 * f))
        .unwrap_or_default();
    match g.status {
        Status::Pass => format!("pass{off}"),
        _ => {
            let codes: Vec<String> = g.findings.iter().map(|f| f.code()).collect();
            format!(
                "{}{off}: {}",
                g.status.code(),
                if codes.is_empty() {
                    "unknown".to_string()
                } else {
                    codes.join(", ")
                },
            )
        }
    }
}

/// A test's message for a student, where a platform has room for one line only: its grade and
/// what to look at.
pub fn message(g: &Graded) -> String {
    match g.status {
        Status::Pass => status_line(g),
        _ => format!(
            "{}: {}",
            status_line(g),
            finding::headline(&g.findings, &g.explanation)
        ),
    }
}

/// What the whole run comes to, first what to read first: the count, a build that failed with
/// its last lines, then the verdict (what to fix first).
pub fn overview(checked: &Checked, groups: &[Group]) -> String {
    let passed = checked
        .graded
        .iter()
        .filter(|g| g.status == Status::Pass)
        .count();
    let mut text = format!(
        "raycast check: {passed} of {} pictures pass ({} of {} points){}\n",
        checked.graded.len(),
        total(checked),
        max_score(checked),
        if checked.partial {
            "; the check was interrupted"
        } else {
            ""
        }
    );
    if let Some(failed) = failed_build(checked) {
        text.push_str(&failed);
    }
    for line in verdict_lines(groups) {
        text.push_str(&line);
        text.push('\n');
    }
    text
}

/// A build that failed, as a student reads it: how it ended, then the last lines it printed.
pub fn failed_build(checked: &Checked) -> Option<String> {
    let build = checked.build.as_ref()?;
    if build["ok"] != false {
        return None;
    }
    let mut text = format!(
        "The submission did not build ({}), so no line was run. The build's last lines:\n",
        build["ending"].as_str().unwrap_or("it failed")
    );
    let output = build["output"].as_str().unwrap_or("");
    text.push_str(if output.trim().is_empty() {
        "(it printed nothing)"
    } else {
        output.trim_end()
    });
    text.push('\n');
    Some(text)
}

/// A test's longer output: the command line, the explanation, the renderer's last words.
pub fn output(g: &Graded) -> String {
    let mut text = format!("$ {}\n", g.command);
    if !g.explanation.is_empty() {
        text.push_str(&g.explanation);
        text.push('\n');
    }
    let said = super::last_lines(&g.stderr, 20);
    if !said.is_empty() {
        text.push_str("The renderer said:\n");
        text.push_str(&said);
        text.push('\n');
    }
    text
}

/// The whole run's seconds, by the clock: its build and its lines (which ran side by side, so
/// not their sum).
pub fn seconds(checked: &Checked) -> f64 {
    let build = checked
        .build
        .as_ref()
        .and_then(|b| b["seconds"].as_f64())
        .unwrap_or(0.0);
    build + checked.seconds
}
