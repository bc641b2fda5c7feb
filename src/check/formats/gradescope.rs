//! Gradescope's autograder `results.json`: `score` and `execution_time` at the top, and one
//! entry of `tests` a picture, with `name`, `number`, `score`, `max_score`, `status`
//! (`passed` or `failed`), `output` and `visibility`.

use serde_json::{Value, json};

use super::{Room, output, overview, score, seconds, status_line, total};
use crate::check::{Checked, Group, Status};

/// The results of `checked`; the top-level output is the run's overview, the verdict in it.
pub fn results(checked: &Checked, groups: &[Group], room: Room) -> Value {
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
                // The explanation once: in the output, after the grade's line.
                "output": room.fit(format!("{}\n{}", status_line(g), output(checked, g))),
                "visibility": "visible",
            })
        })
        .collect();
    json!({
        "score": total(checked),
        "execution_time": seconds(checked).round() as u64,
        "output": overview(checked, groups),
        "visibility": "visible",
        "stdout_visibility": "hidden",
        "tests": tests,
    })
}
