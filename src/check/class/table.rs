//! The class's table: one row a student, made from the student's `summary.json` (so that a
//! merge of shards makes the same table as one run), for the terminal, CSV and HTML.

use serde_json::{Value, json};

pub use crate::check::suite::assignment;
use crate::check::untrusted::{html as escape, visible};

/// The verdict column of a student whose biggest group of failing pictures no fault of the
/// library explains.
pub const UNEXPLAINED: &str = "no known fault";

/// One student's row.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The student's report folder, relative to the class's report (their name, unless the name
    /// is one of the class report's own files).
    pub folder: String,
    /// The submission's name.
    pub name: String,
    /// Pictures that pass.
    pub passed: usize,
    /// Pictures in all.
    pub total: usize,
    /// Points earned.
    pub points: f64,
    /// Points to be had.
    pub max_points: f64,
    /// Per assignment (`A2`, from the pictures' names): passes and pictures.
    pub assignments: Vec<(String, usize, usize)>,
    /// The fault that explains most failures (the verdict's first; [`UNEXPLAINED`] where the
    /// biggest group is of pictures no fault explains), or "" where every picture passes.
    pub verdict: String,
    /// Seconds used: the build and the lines.
    pub seconds: f64,
    /// The build's ending, or "" without `--build`.
    pub build: String,
    /// The last lines a build that failed printed ("" for one that built): the reason the
    /// student's pictures are all missing, shown beside the row.
    pub build_output: String,
    /// The answers to the course's open questions the student's pictures took, where not
    /// raycast's (`gaussian_uncut`, ...), each once, in the order first met.
    pub answers: Vec<String>,
}

impl Row {
    /// The row of a student who could not be graded: every picture missing, and why.
    pub fn refused(name: &str, why: &str, pictures: usize, max_points: f64) -> Row {
        Row {
            // No report of their own.
            folder: String::new(),
            name: name.to_string(),
            passed: 0,
            total: pictures,
            points: 0.0,
            max_points,
            assignments: Vec::new(),
            verdict: "not graded".to_string(),
            seconds: 0.0,
            build: why.to_string(),
            build_output: String::new(),
            answers: Vec::new(),
        }
    }

    /// The row of a student as the class's `summary.json` keeps it, for one who has no report
    /// of their own (not graded).
    pub fn of_class_summary(student: &Value) -> Row {
        let name = student["name"].as_str().unwrap_or("");
        Row::refused(
            name,
            student["build"].as_str().unwrap_or(""),
            student["pictures"].as_u64().unwrap_or(0) as usize,
            student["max_points"].as_f64().unwrap_or(0.0),
        )
    }

    /// The row of student `name`, whose report is in `folder`, from their `summary.json`.
    pub fn of(name: &str, folder: &str, summary: &Value) -> Row {
        let images = summary["images"].as_array().cloned().unwrap_or_default();
        let mut assignments: Vec<(String, usize, usize)> = Vec::new();
        let mut lines = std::collections::BTreeSet::new();
        let build_seconds = summary["build"]["seconds"].as_f64().unwrap_or(0.0);
        let mut lines_seconds = 0.0;
        let (mut points, mut max_points, mut passed) = (0.0, 0.0, 0);
        let mut answers: Vec<String> = Vec::new();
        for image in &images {
            if let Some(answer) = image["accepted"]["answer"].as_str()
                && !answers.iter().any(|a| a == answer)
            {
                answers.push(answer.to_string());
            }
            let pass = image["status"] == "pass";
            let worth = image["points"].as_f64().unwrap_or(1.0);
            max_points += worth;
            if pass {
                points += worth;
                passed += 1;
            }
            let label = assignment(image["name"].as_str().unwrap_or(""));
            match assignments.iter_mut().find(|(a, _, _)| *a == label) {
                Some((_, p, t)) => {
                    *p += usize::from(pass);
                    *t += 1;
                }
                None => assignments.push((label, usize::from(pass), 1)),
            }
            // A line's pictures share its time (a report without the run's clock time).
            if lines.insert(image["command"].as_str().unwrap_or("").to_string()) {
                lines_seconds += image["seconds"].as_f64().unwrap_or(0.0);
            }
        }
        assignments.sort();
        // By the clock: the lines ran side by side, so their times overlap.
        let seconds = build_seconds + summary["seconds"].as_f64().unwrap_or(lines_seconds);
        Row {
            folder: folder.to_string(),
            name: name.to_string(),
            passed,
            total: images.len(),
            points,
            max_points,
            assignments,
            verdict: match &summary["verdict"][0] {
                Value::Null => String::new(),
                // The biggest group is of pictures no fault of the library explains.
                first => first["fault"].as_str().unwrap_or(UNEXPLAINED).to_string(),
            },
            seconds,
            build: summary["build"]["ending"]
                .as_str()
                .unwrap_or("")
                .to_string(),
            build_output: if summary["build"]["ok"] == false {
                super::super::untrusted::tail(summary["build"]["output"].as_str().unwrap_or(""))
            } else {
                String::new()
            },
            answers,
        }
    }

    fn assignments_text(&self) -> String {
        self.assignments
            .iter()
            .map(|(a, p, t)| format!("{a} {p}/{t}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The table for the terminal: one line a student, aligned.
pub fn terminal(rows: &[Row]) -> String {
    // A name or a build's words are the submission's: shown, never obeyed, on one line.
    let shown: Vec<String> = rows.iter().map(|r| visible(&r.name)).collect();
    let width = shown
        .iter()
        .map(|name| name.chars().count())
        .max()
        .unwrap_or(7)
        .max(7);
    let mut text = format!(
        "{:width$}  {:>9}  {:>11}  {:>8}  verdict / assignments\n",
        "student", "pictures", "points", "seconds"
    );
    for (r, name) in rows.iter().zip(&shown) {
        let verdict = match (r.verdict.as_str(), r.build.as_str()) {
            (_, b) if !b.is_empty() && b != "built" => visible(b),
            ("", _) => "all pass".to_string(),
            (v, _) => v.to_string(),
        };
        let answers = if r.answers.is_empty() {
            String::new()
        } else {
            format!(" / allowed: {}", r.answers.join(", "))
        };
        text.push_str(&format!(
            "{:width$}  {:>9}  {:>11}  {:>8.1}  {verdict} / {}{answers}\n",
            name,
            format!("{}/{}", r.passed, r.total),
            format!("{}/{}", r.points, r.max_points),
            r.seconds,
            r.assignments_text()
        ));
    }
    text
}

/// The table as CSV (RFC 4180): a header, then one row a student; one column per assignment.
pub fn csv(rows: &[Row]) -> String {
    let labels = labels(rows);
    let field = |text: &str| csv_cell(text);
    let mut text = String::from("student,passed,pictures,points,max_points");
    for label in &labels {
        text.push_str(&format!(",{label} passed,{label} pictures"));
    }
    text.push_str(",verdict,answers,seconds,build,report\r\n");
    for r in rows {
        let mut line = format!(
            "{},{},{},{},{}",
            field(&r.name),
            r.passed,
            r.total,
            r.points,
            r.max_points
        );
        for label in &labels {
            let (p, t) = r
                .assignments
                .iter()
                .find(|(a, _, _)| a == label)
                .map_or((0, 0), |&(_, p, t)| (p, t));
            line.push_str(&format!(",{p},{t}"));
        }
        line.push_str(&format!(
            ",{},{},{:.3},{},{}\r\n",
            field(&r.verdict),
            field(&r.answers.join(" ")),
            r.seconds,
            field(&r.build),
            field(&report_path(&r.folder))
        ));
        text.push_str(&line);
    }
    text
}

/// Every assignment of the class, in order.
fn labels(rows: &[Row]) -> Vec<String> {
    let mut labels: Vec<String> = rows
        .iter()
        .flat_map(|r| r.assignments.iter().map(|(a, _, _)| a.clone()))
        .collect();
    labels.sort();
    labels.dedup();
    labels
}

/// The table as a page: each student's name links to their own report.
pub fn html(rows: &[Row], partial: bool) -> String {
    let labels = labels(rows);
    let mut body = String::new();
    for r in rows {
        let cells: String = labels
            .iter()
            .map(|label| {
                let (p, t) = r
                    .assignments
                    .iter()
                    .find(|(a, _, _)| a == label)
                    .map_or((0, 0), |&(_, p, t)| (p, t));
                format!("<td>{p}/{t}</td>")
            })
            .collect();
        body.push_str(&format!(
            "<tr class=\"{}\"><td>{}</td><td>{}/{}</td><td>{}/{}</td>{cells}<td>{}</td><td>{}</td><td class=\"seconds\">{:.1}</td><td>{}</td></tr>\n",
            if r.passed == r.total { "pass" } else { "fail" },
            name_cell(r),
            r.passed,
            r.total,
            r.points,
            r.max_points,
            escape(&r.verdict),
            escape(&r.answers.join(", ")),
            r.seconds,
            if r.build_output.is_empty() {
                escape(&r.build)
            } else {
                format!(
                    "<details><summary>{}</summary><pre>{}</pre></details>",
                    escape(&r.build),
                    escape(&r.build_output)
                )
            }
        ));
    }
    let heads: String = labels
        .iter()
        .map(|l| format!("<th>{}</th>", escape(l)))
        .collect();
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>raycast check: the class</title>\
         <style>body{{font:14px system-ui,sans-serif;margin:2em}}table{{border-collapse:collapse}}\
         td,th{{padding:.3em .7em;border-bottom:1px solid #ddd;text-align:left}}tr.pass td:nth-child(2){{color:#060}}\
         tr.fail td:nth-child(2){{color:#a00}}</style></head><body><h1>The class</h1>{}\
         <table><thead><tr><th>student</th><th>pictures</th><th>points</th>{heads}<th>verdict</th><th>allowed answers</th><th>seconds</th><th>build</th></tr></thead>\
         <tbody>\n{body}</tbody></table></body></html>\n",
        if partial {
            "<p><strong>The check was interrupted: the table is partial.</strong></p>"
        } else {
            ""
        }
    )
}

/// A cell of class.csv: a text a spreadsheet shows and never runs. Controls are written out
/// (a name cannot add a row), a cell that a spreadsheet would read as a formula (= + - @, a tab
/// or a carriage return first) gets a leading apostrophe (OWASP's rule for CSV injection), and
/// a cell with a comma or a quote is quoted (RFC 4180).
pub fn csv_cell(text: &str) -> String {
    let text = if text.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        format!("'{}", visible(text))
    } else {
        visible(text)
    };
    if text.contains([',', '"']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text
    }
}

/// A student's report, relative to the class's, or "" for one not graded.
fn report_path(folder: &str) -> String {
    if folder.is_empty() {
        String::new()
    } else {
        format!("{folder}/index.html")
    }
}

/// A student's name in class.html: escaped, and a link to their own report where they have one.
fn name_cell(r: &Row) -> String {
    let name = escape(&visible(&r.name));
    if r.folder.is_empty() {
        name
    } else {
        format!("<a href=\"{}\">{name}</a>", report_link(&r.folder))
    }
}

/// The link from class.html to a student's own report: a path relative to the page, each byte
/// of the folder's name outside letters, digits and `-._~` percent-encoded, after `./`, so that
/// no name is read as a scheme (`javascript:`), a query or another folder.
pub fn report_link(folder: &str) -> String {
    let mut link = String::from("./");
    for byte in folder.bytes() {
        if byte.is_ascii_alphanumeric() || b"-._~".contains(&byte) {
            link.push(byte as char);
        } else {
            link.push_str(&format!("%{byte:02X}"));
        }
    }
    link.push_str("/index.html");
    link
}

/// The class's `summary.json`: each student's row.
pub fn json(rows: &[Row], partial: bool) -> Value {
    json!({
        "raycast": env!("CARGO_PKG_VERSION"),
        "class": true,
        "partial": partial,
        "students": rows.iter().map(|r| json!({
            "name": r.name,
            "report": r.folder,
            "passed": r.passed,
            "pictures": r.total,
            "points": r.points,
            "max_points": r.max_points,
            "assignments": r.assignments.iter().map(|(a, p, t)| json!({
                "assignment": a, "passed": p, "pictures": t,
            })).collect::<Vec<_>>(),
            "verdict": r.verdict,
            "answers": r.answers,
            "seconds": r.seconds,
            "build": r.build,
        })).collect::<Vec<_>>(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pictures_belong_to_the_assignment_their_name_numbers() {
        assert_eq!(assignment("output2_01"), "A2");
        assert_eq!(assignment("depth3_08#2"), "A3");
        assert_eq!(assignment("normals1_05"), "A1");
        assert_eq!(assignment("output10_3"), "A10");
        assert_eq!(assignment("teapot"), "other");
    }

    #[test]
    fn a_student_whose_biggest_group_no_fault_explains_is_not_all_pass() {
        let summary = |verdict: Value| {
            serde_json::json!({
                "images": [{"name": "output4_02", "status": "fail", "command": "a"}],
                "verdict": verdict,
            })
        };
        let unexplained = summary(serde_json::json!([
            {"fault": null, "lines": ["output4_02"], "equals": []},
            {"fault": "ambient_missing", "lines": ["output3_01"], "equals": []},
        ]));
        let row = Row::of("eve", "eve", &unexplained);
        assert_eq!(row.verdict, UNEXPLAINED);
        assert!(terminal(&[row]).contains("no known fault / A4 0/1"));
        let explained = summary(serde_json::json!([
            {"fault": "pixel_corner", "lines": ["output4_02"], "equals": []},
        ]));
        assert_eq!(Row::of("eve", "eve", &explained).verdict, "pixel_corner");
        assert_eq!(
            Row::of("eve", "eve", &summary(serde_json::json!([]))).verdict,
            ""
        );
    }

    #[test]
    fn the_answers_a_student_took_to_open_questions_are_in_every_table() {
        let summary = serde_json::json!({
            "images": [
                {"name": "filter7_01c", "status": "pass", "command": "a",
                 "accepted": {"choice": "gaussian_cut", "answer": "gaussian_uncut"}},
                {"name": "output7_02c", "status": "pass", "command": "b",
                 "accepted": {"choice": "gaussian_cut", "answer": "gaussian_uncut"}},
                {"name": "output7_02d", "status": "pass", "command": "c",
                 "accepted": {"choice": "box_edge", "answer": "box_closed"}},
                {"name": "output7_02e", "status": "pass", "command": "d", "accepted": null},
            ],
            "verdict": [],
        });
        let row = Row::of("ada", "ada", &summary);
        assert_eq!(row.answers, ["gaussian_uncut", "box_closed"]);
        assert!(
            terminal(std::slice::from_ref(&row))
                .contains("all pass / A7 4/4 / allowed: gaussian_uncut, box_closed")
        );
        assert!(csv(std::slice::from_ref(&row)).contains(",,gaussian_uncut box_closed,"));
        assert!(
            html(std::slice::from_ref(&row), false).contains("<td>gaussian_uncut, box_closed</td>")
        );
        assert_eq!(
            json(&[row], false)["students"][0]["answers"],
            serde_json::json!(["gaussian_uncut", "box_closed"])
        );
    }

    #[test]
    fn csv_quotes_what_needs_quoting() {
        let row = Row {
            folder: "a, \"b\"".into(),
            name: "a, \"b\"".into(),
            passed: 1,
            total: 2,
            points: 1.0,
            max_points: 2.0,
            assignments: vec![("A1".into(), 1, 2)],
            verdict: "pixel_corner".into(),
            seconds: 1.5,
            build: String::new(),
            build_output: String::new(),
            answers: vec!["gaussian_uncut".into(), "box_closed".into()],
        };
        assert_eq!(
            csv(&[row]),
            "student,passed,pictures,points,max_points,A1 passed,A1 pictures,verdict,answers,seconds,build,report\r\n\
             \"a, \"\"b\"\"\",1,2,1,2,1,2,pixel_corner,gaussian_uncut box_closed,1.500,,\"a, \"\"b\"\"/index.html\"\r\n"
        );
    }

    #[test]
    fn a_name_is_never_a_formula_a_row_or_a_link_elsewhere() {
        for (name, cell) in [
            (
                "=HYPERLINK(\"http://x\",\"y\")",
                "\"'=HYPERLINK(\"\"http://x\"\",\"\"y\"\")\"",
            ),
            ("+1", "'+1"),
            ("-2", "'-2"),
            ("@SUM(A1)", "'@SUM(A1)"),
            ("\tx", "'\\tx"),
            ("eve\nmallory,9,9", "\"eve\\nmallory,9,9\""),
            ("alice", "alice"),
        ] {
            assert_eq!(csv_cell(name), cell, "{name:?}");
        }
        assert_eq!(report_link("bob"), "./bob/index.html");
        assert_eq!(
            report_link("javascript:alert(1)//"),
            "./javascript%3Aalert%281%29%2F%2F/index.html"
        );
        assert_eq!(report_link("é ?#"), "./%C3%A9%20%3F%23/index.html");
    }
}
