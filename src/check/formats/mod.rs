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

use super::{Checked, Graded, Status, finding};

/// The file names, in the report's folder.
pub const FILES: [&str; 4] = [
    "gradescope.json",
    "prairielearn.json",
    "junit.xml",
    "github-classroom.json",
];

/// Writes every format into `dir`, where the report's pictures already are.
pub fn write_all(dir: &Path, checked: &Checked) -> Result<(), String> {
    let fail = |name: &str, e: std::io::Error| format!("{}: {e}", dir.join(name).display());
    let pretty =
        |value: &serde_json::Value| serde_json::to_string_pretty(value).unwrap_or_default() + "\n";
    let files = [
        (FILES[0], pretty(&gradescope::results(checked))),
        (FILES[1], pretty(&prairielearn::results(checked, dir))),
        (FILES[2], junit::xml(checked)),
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

/// A test's message for a student: its grade and what to look at.
pub fn message(g: &Graded) -> String {
    let off = g
        .bad_fraction
        .map(|f| format!(", {:.3}% of pixels off", 100.0 * f))
        .unwrap_or_default();
    match g.status {
        Status::Pass => format!("pass{off}"),
        _ => {
            let codes: Vec<String> = g.findings.iter().map(|f| f.code()).collect();
            format!(
                "{}{off}: {}: {}",
                g.status.code(),
                if codes.is_empty() {
                    "unknown".to_string()
                } else {
                    codes.join(", ")
                },
                finding::headline(&g.findings, &g.explanation)
            )
        }
    }
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

/// The whole run's seconds: the renderer's time over every line.
pub fn seconds(checked: &Checked) -> f64 {
    let mut seen = std::collections::BTreeSet::new();
    // Pictures of one line share its time: counted once.
    checked
        .graded
        .iter()
        .filter(|g| seen.insert(g.command.clone()))
        .map(|g| g.seconds)
        .sum()
}
