//! PrairieLearn's external grader results: `gradable`, `score` from 0 to 1, `message`, and
//! one entry of `tests` a picture with `name`, `description`, `points`, `max_points`,
//! `message`, `output` and, for a failing picture, its `images` (the renderer's, the reference
//! and the heat map) as data URLs, as long as the whole stays within PrairieLearn's 1 MB.

use std::path::Path;

use serde_json::{Value, json};

use super::{FILE_BUDGET, Room, max_score, output, overview, score, status_line, total};
use crate::check::{Checked, Group, Status};

/// Room kept beside the pictures for what pretty-printing adds around them.
const MARGIN: usize = 16 * 1024;

/// The results of `checked`, each test's text within `room`; the pictures are read from
/// `dir`, the report's folder, and added, failures in the suite's order, while the whole stays
/// within the platform's budget: the texts first, then the pictures in the room they leave.
pub fn results(checked: &Checked, groups: &[Group], dir: &Path, room: Room) -> Value {
    let mut results = without_pictures(checked, groups, room);
    let used = serde_json::to_string_pretty(&results).map_or(FILE_BUDGET, |t| t.len());
    let mut budget = FILE_BUDGET.saturating_sub(used + MARGIN);
    for (g, test) in checked
        .graded
        .iter()
        .zip(results["tests"].as_array_mut().into_iter().flatten())
    {
        if g.status == Status::Pass {
            continue;
        }
        let mut images = Vec::new();
        for (label, file) in [
            ("yours", &g.pictures.actual),
            ("reference", &g.pictures.reference),
            ("difference", &g.pictures.diff),
        ] {
            let Some(bytes) = file.as_ref().and_then(|f| std::fs::read(dir.join(f)).ok()) else {
                continue;
            };
            let url = format!("data:image/png;base64,{}", base64(&bytes));
            // Its label and the JSON around it count too.
            let cost = url.len() + g.name.len() + 64;
            if cost > budget {
                continue;
            }
            budget -= cost;
            images.push(json!({ "label": format!("{}: {label}", g.name), "url": url }));
        }
        test["images"] = json!(images);
    }
    results
}

/// The results with each test's text and no pictures.
fn without_pictures(checked: &Checked, groups: &[Group], room: Room) -> Value {
    let tests: Vec<Value> = checked
        .graded
        .iter()
        .map(|g| {
            json!({
                "name": g.name,
                "description": g.command,
                "points": score(g),
                "max_points": g.points,
                // The explanation once: in the output.
                "message": status_line(g),
                "output": room.fit(output(checked, g)),
                "images": [],
            })
        })
        .collect();
    let most = max_score(checked);
    json!({
        "gradable": true,
        "score": if most > 0.0 { total(checked) / most } else { 0.0 },
        "message": room.fit(overview(checked, groups)),
        "tests": tests,
    })
}

/// Standard base64 with padding (RFC 4648).
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, &b)| n | u32::from(b) << (16 - 8 * i));
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn base64_is_rfc_4648s() {
        // The RFC's own test vectors.
        for (text, encoded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(super::base64(text.as_bytes()), encoded);
        }
    }
}
