//! GitHub Classroom's autograding result, as its grading reporter reads a runner's `result`
//! (base64 of this JSON): `version` 1, `status` (`pass`, `fail` or `error`), `max_score`, and
//! one entry of `tests` a picture with `name`, `status`, `score`, `message`, `test_code` (the
//! command line) and `duration` in milliseconds. The check's exit status says the same: 0 when
//! every picture passes.

use serde_json::{Value, json};

use super::{max_score, message, score};
use crate::check::{Checked, Status};

/// The result of `checked`.
pub fn results(checked: &Checked) -> Value {
    let status = |s: Status| match s {
        Status::Pass => "pass",
        Status::Fail => "fail",
        Status::Error => "error",
    };
    let overall = if checked.graded.iter().all(|g| g.status == Status::Pass) && !checked.partial {
        "pass"
    } else if checked.graded.iter().any(|g| g.status == Status::Error) {
        "error"
    } else {
        "fail"
    };
    json!({
        "version": 1,
        "status": overall,
        "max_score": max_score(checked),
        "tests": checked.graded.iter().map(|g| json!({
            "name": g.name,
            "status": status(g.status),
            "score": score(g),
            "message": message(g),
            "test_code": g.command,
            "filename": "",
            "line_no": 0,
            "duration": (g.seconds * 1000.0).round() as u64,
        })).collect::<Vec<_>>(),
    })
}
