//! The class's table: one row a student, made from the student's `summary.json` (so that a
//! merge of shards makes the same table as one run), for the terminal, CSV and HTML.

use serde_json::{Value, json};

use crate::check::report::escape;

/// One student's row.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
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
    /// The fault that explains most failures (the verdict's first), or "" for none.
    pub verdict: String,
    /// Seconds used: the build and the lines.
    pub seconds: f64,
    /// The build's ending, or "" without `--build`.
    pub build: String,
    /// The last lines a build that failed printed ("" for one that built): the reason the
    /// student's pictures are all missing, shown beside the row.
    pub build_output: String,
}

impl Row {
    /// The row of student `name`, from their `summary.json`.
    pub fn of(name: &str, summary: &Value) -> Row {
        let images = summary["images"].as_array().cloned().unwrap_or_default();
        let mut assignments: Vec<(String, usize, usize)> = Vec::new();
        let mut lines = std::collections::BTreeSet::new();
        let build_seconds = summary["build"]["seconds"].as_f64().unwrap_or(0.0);
        let mut lines_seconds = 0.0;
        let (mut points, mut max_points, mut passed) = (0.0, 0.0, 0);
        for image in &images {
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
            name: name.to_string(),
            passed,
            total: images.len(),
            points,
            max_points,
            assignments,
            verdict: summary["verdict"][0]["fault"]
                .as_str()
                .unwrap_or("")
                .to_string(),
            seconds,
            build: summary["build"]["ending"]
                .as_str()
                .unwrap_or("")
                .to_string(),
            build_output: if summary["build"]["ok"] == false {
                super::super::last_lines(summary["build"]["output"].as_str().unwrap_or(""), 20)
            } else {
                String::new()
            },
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

/// The assignment a picture belongs to, from its name: `output2_01`, `depth3_08` and
/// `normals1_05` are A2, A3 and A1; a name without such a number is "other".
pub fn assignment(name: &str) -> String {
    let digits: String = name
        .trim_start_matches(|c: char| c.is_ascii_alphabetic())
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    let numbered = name.contains('_') && !digits.is_empty();
    if numbered {
        format!("A{digits}")
    } else {
        "other".to_string()
    }
}

/// The table for the terminal: one line a student, aligned.
pub fn terminal(rows: &[Row]) -> String {
    let width = rows
        .iter()
        .map(|r| r.name.chars().count())
        .max()
        .unwrap_or(7)
        .max(7);
    let mut text = format!(
        "{:width$}  {:>9}  {:>11}  {:>8}  verdict / assignments\n",
        "student", "pictures", "points", "seconds"
    );
    for r in rows {
        let verdict = match (r.verdict.as_str(), r.build.as_str()) {
            (_, b) if !b.is_empty() && b != "built" => b.to_string(),
            ("", _) => "all pass".to_string(),
            (v, _) => v.to_string(),
        };
        text.push_str(&format!(
            "{:width$}  {:>9}  {:>11}  {:>8.1}  {verdict} / {}\n",
            r.name,
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
    let field = |text: &str| {
        if text.contains([',', '"', '\n', '\r']) {
            format!("\"{}\"", text.replace('"', "\"\""))
        } else {
            text.to_string()
        }
    };
    let mut text = String::from("student,passed,pictures,points,max_points");
    for label in &labels {
        text.push_str(&format!(",{label} passed,{label} pictures"));
    }
    text.push_str(",verdict,seconds,build,report\r\n");
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
            ",{},{:.3},{},{}\r\n",
            field(&r.verdict),
            r.seconds,
            field(&r.build),
            field(&format!("{}/index.html", r.name))
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
            "<tr class=\"{}\"><td><a href=\"{}/index.html\">{}</a></td><td>{}/{}</td><td>{}/{}</td>{cells}<td>{}</td><td class=\"seconds\">{:.1}</td><td>{}</td></tr>\n",
            if r.passed == r.total { "pass" } else { "fail" },
            escape(&r.name),
            escape(&r.name),
            r.passed,
            r.total,
            r.points,
            r.max_points,
            escape(&r.verdict),
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
         <table><thead><tr><th>student</th><th>pictures</th><th>points</th>{heads}<th>verdict</th><th>seconds</th><th>build</th></tr></thead>\
         <tbody>\n{body}</tbody></table></body></html>\n",
        if partial {
            "<p><strong>The check was interrupted: the table is partial.</strong></p>"
        } else {
            ""
        }
    )
}

/// The class's `summary.json`: each student's row.
pub fn json(rows: &[Row], partial: bool) -> Value {
    json!({
        "raycast": env!("CARGO_PKG_VERSION"),
        "class": true,
        "partial": partial,
        "students": rows.iter().map(|r| json!({
            "name": r.name,
            "passed": r.passed,
            "pictures": r.total,
            "points": r.points,
            "max_points": r.max_points,
            "assignments": r.assignments.iter().map(|(a, p, t)| json!({
                "assignment": a, "passed": p, "pictures": t,
            })).collect::<Vec<_>>(),
            "verdict": r.verdict,
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
    fn csv_quotes_what_needs_quoting() {
        let row = Row {
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
        };
        assert_eq!(
            csv(&[row]),
            "student,passed,pictures,points,max_points,A1 passed,A1 pictures,verdict,seconds,build,report\r\n\
             \"a, \"\"b\"\"\",1,2,1,2,1,2,pixel_corner,1.500,,\"a, \"\"b\"\"/index.html\"\r\n"
        );
    }
}
