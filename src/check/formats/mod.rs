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
    // Made whole first; made again with each test's text cut where the whole is too big.
    let fitted = |make: &dyn Fn(Room) -> serde_json::Value| {
        let whole = pretty(&make(Room::Whole));
        match Room::to_fit(whole.len(), FILE_BUDGET, checked.graded.len()) {
            Room::Whole => whole,
            room => pretty(&make(room)),
        }
    };
    let files = [
        (
            FILES[0],
            fitted(&|room| gradescope::results(checked, groups, room)),
        ),
        (
            FILES[1],
            fitted(&|room| prairielearn::results(checked, groups, dir, room)),
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
    if checked.no_cage {
        text.push_str(
            "graded with --no-cage: nothing was known to keep the renderer from the references\n",
        );
    }
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

/// The most bytes a platform's file may take: PrairieLearn refuses results over 1 MB, and
/// Gradescope is held to the same (it documents no size, and pages of megabytes are no use to a
/// student). Texts are cut to fit, and pictures dropped, before anything is left out.
pub const FILE_BUDGET: usize = 1_000_000;

/// How much of each test's text a file has room for: all of it, or its first `n` characters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Room {
    /// Every test's whole text.
    Whole,
    /// Each test's text cut to this many characters, with a note.
    Cut(usize),
}

impl Room {
    /// The room each of `tests` tests has when the whole file must fit `budget` bytes and took
    /// `used` bytes with nothing cut.
    pub fn to_fit(used: usize, budget: usize, tests: usize) -> Room {
        if used <= budget {
            Room::Whole
        } else {
            // Most of the budget for the texts; the rest for names, numbers and the overview.
            Room::Cut((budget * 3 / 5 / tests.max(1)).max(80))
        }
    }

    /// `text` cut to the room, saying so.
    pub fn fit(self, text: String) -> String {
        match self {
            Room::Cut(n) if text.chars().count() > n => {
                let kept: String = text.chars().take(n).collect();
                format!(
                    "{kept}\n[cut to {n} characters to fit the platform's size limit: the \
                     report's summary.json and index.html hold the rest]"
                )
            }
            _ => text,
        }
    }
}

/// A test's longer output: the command line, the explanation, and the renderer's last words,
/// once a line: a line's other pictures point to its first.
pub fn output(checked: &Checked, g: &Graded) -> String {
    let mut text = format!("$ {}\n", g.command);
    if !g.explanation.is_empty() {
        text.push_str(&g.explanation);
        text.push('\n');
    }
    let said = super::untrusted::tail(&g.stderr);
    if said.is_empty() {
        return text;
    }
    let first = checked
        .graded
        .iter()
        .find(|other| other.line.0 == g.line.0 && other.line.1 == 0)
        .filter(|first| first.name != g.name);
    match first {
        Some(first) => text.push_str(&format!(
            "The renderer's output for this line is under {}.\n",
            first.name
        )),
        None => text.push_str(&renderer_said(&said)),
    }
    text
}

/// What the renderer said, its tail as the report keeps it (`untrusted::tail`), under its
/// heading; "" when it said nothing.
pub fn renderer_said(tail: &str) -> String {
    if tail.is_empty() {
        String::new()
    } else {
        format!("The renderer said:\n{tail}\n")
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texts_are_cut_only_when_the_file_would_not_fit() {
        assert_eq!(Room::to_fit(999_999, FILE_BUDGET, 44), Room::Whole);
        // 168 pictures in 3 MB: each text gets its share of three fifths of the budget.
        let room = Room::to_fit(3_000_000, FILE_BUDGET, 168);
        assert_eq!(room, Room::Cut(3571));
        let long = "x".repeat(10_000);
        let cut = room.fit(long);
        assert!(cut.starts_with(&"x".repeat(3571)));
        assert!(cut.ends_with(
            "[cut to 3571 characters to fit the platform's size limit: the report's \
             summary.json and index.html hold the rest]"
        ));
        assert_eq!(room.fit("short".into()), "short");
        // However many pictures, a text keeps a line or so.
        assert_eq!(
            Room::to_fit(50_000_000, FILE_BUDGET, 100_000),
            Room::Cut(80)
        );
    }
}
