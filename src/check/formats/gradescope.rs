//! Gradescope's autograder `results.json`: `score` and `execution_time` at the top, and one
//! entry of `tests` a picture, with `name`, `number`, `score`, `max_score`, `status`
//! (`passed` or `failed`), `output` and `visibility`.

use serde_json::{Value, json};

use super::{max_score, message, output, score, seconds, total};
use crate::check::{Checked, Status};

/// The results of `checked`.
pub fn results(checked: &Checked) -> Value {
    let tests: Vec<Value> = checked
        .graded
        .iter()
        .enumerate()
        .map(|(k, g)| {
            json!({
                "name": g.name,
                "number": format!("{}", k + 1),
                "score": score(g),
                "max_score": g.points,
                "status": if g.status == Status::Pass { "passed" } else { "failed" },
                "output": format!("{}\n{}", message(g), output(g)),
                "visibility": "visible",
            })
        })
        .collect();
    let passed = checked
        .graded
        .iter()
        .filter(|g| g.status == Status::Pass)
        .count();
    json!({
        "score": total(checked),
        "execution_time": seconds(checked).round() as u64,
        "output": format!(
            "raycast check: {passed} of {} pictures pass ({} of {} points){}",
            checked.graded.len(),
            total(checked),
            max_score(checked),
            if checked.partial { "; the check was interrupted" } else { "" }
        ),
        "visibility": "visible",
        "stdout_visibility": "hidden",
        "tests": tests,
    })
}
