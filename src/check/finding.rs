//! What check found a picture's fault to be, for the terminal, the report and `summary.json`.

use serde_json::{Value, json};

use super::diagnose::Diagnosis;
use super::simulate::FaultMatch;

/// One cause named for a picture.
#[derive(Debug, Clone, PartialEq)]
pub enum Finding {
    /// raycast's render of the line with these faults planted matches the picture: the cause.
    Fault(FaultMatch),
    /// Decided from the run (a crash, no picture, the wrong size) or, where no fault of the
    /// library reproduces the picture, guessed from the pixels.
    Diagnosis(Diagnosis),
}

impl Finding {
    /// The fault's name (two joined by `+`), or the diagnosis's code.
    pub fn code(&self) -> String {
        match self {
            Finding::Fault(m) => m.code(),
            Finding::Diagnosis(d) => d.code().to_string(),
        }
    }

    /// Whether it is a guess from the pixels rather than a fault reproduced or a fact of the run.
    pub fn is_guess(&self) -> bool {
        matches!(self, Finding::Diagnosis(d) if !d.is_fact())
    }

    /// As `summary.json` carries it: `code`, `kind` (`fault`, `run` or `guess`), and for a
    /// fault the faults' names, fitted parameters, the match figure (the share of pixels off
    /// between the student's picture and the fault's render), assignment, sentence and what to
    /// look for; for the others the explanation.
    pub fn json(&self) -> Value {
        match self {
            Finding::Fault(m) => json!({
                "code": m.code(),
                "kind": "fault",
                "faults": m.faults.iter().map(|f| f.name).collect::<Vec<_>>(),
                "parameters": m
                    .parameters
                    .iter()
                    .map(|&(name, value)| (name.to_string(), json!(value)))
                    .collect::<serde_json::Map<_, _>>(),
                "match": m.bad_fraction,
                "assignment": m.faults.iter().map(|f| f.assignment).collect::<Vec<_>>(),
                "sentence": m.faults.iter().map(|f| f.sentence).collect::<Vec<_>>().join(" "),
                "look_for": m.faults.iter().map(|f| f.look_for).collect::<Vec<_>>().join(" "),
            }),
            Finding::Diagnosis(d) => json!({
                "code": d.code(),
                "kind": if d.is_fact() { "run" } else { "guess" },
                "explanation": d.explanation(),
            }),
        }
    }
}

/// What a student reads about a failing picture: the faults whose render matches it (all of
/// them, where the line cannot tell them apart), or the guesses from the pixels.
pub fn explain(findings: &[Finding]) -> String {
    let faults: Vec<&FaultMatch> = findings
        .iter()
        .filter_map(|f| match f {
            Finding::Fault(m) => Some(m),
            Finding::Diagnosis(_) => None,
        })
        .collect();
    let Some(first) = faults.first() else {
        let guesses: Vec<&Finding> = findings.iter().filter(|f| f.is_guess()).collect();
        let text = findings
            .iter()
            .filter_map(|f| match f {
                Finding::Diagnosis(d) => Some(d.explanation()),
                Finding::Fault(_) => None,
            })
            .collect::<Vec<_>>()
            .join(" ");
        return if guesses.is_empty() {
            text
        } else {
            format!(
                "No fault in raycast's library reproduces this picture; a guess from the \
                 pixels: {text}"
            )
        };
    };
    let planted = if first.faults.len() == 1 {
        "this fault"
    } else {
        "these two faults"
    };
    let parameters = if first.parameters.is_empty() {
        String::new()
    } else {
        let shown: Vec<String> = first
            .parameters
            .iter()
            .map(|(name, value)| format!("{name} {}", show(*value)))
            .collect();
        format!(", {}", shown.join(", "))
    };
    let mut text = format!(
        "Your picture equals raycast's render of this line with {planted} planted ({:.3}% of \
         pixels off{parameters}). {} Look for: {}",
        100.0 * first.bad_fraction,
        first
            .faults
            .iter()
            .map(|f| format!("\"{}\"", f.sentence))
            .collect::<Vec<_>>()
            .join(" and "),
        first
            .faults
            .iter()
            .map(|f| f.look_for)
            .collect::<Vec<_>>()
            .join(" ")
    );
    if faults.len() > 1 {
        let others: Vec<String> = faults[1..].iter().map(|m| m.code()).collect();
        text.push_str(&format!(
            " {} match{} as well: this line alone cannot tell them apart.",
            others.join(", "),
            if others.len() == 1 { "es" } else { "" }
        ));
    }
    text
}

/// The terminal's short account of a failing picture: the faults that match it (the figure and
/// fitted parameters), their sentences and what to look for being in the verdict above; or the
/// full explanation where no fault matches.
pub fn headline(findings: &[Finding], explanation: &str) -> String {
    let faults: Vec<&FaultMatch> = findings
        .iter()
        .filter_map(|f| match f {
            Finding::Fault(m) => Some(m),
            Finding::Diagnosis(_) => None,
        })
        .collect();
    let Some(first) = faults.first() else {
        return explanation.to_string();
    };
    let parameters: Vec<String> = first
        .parameters
        .iter()
        .map(|(name, value)| format!(", {name} {}", show(*value)))
        .collect();
    let mut text = format!(
        "raycast's render with {} planted matches ({:.3}% of pixels off{})",
        if first.faults.len() == 1 {
            "this fault"
        } else {
            "these faults"
        },
        100.0 * first.bad_fraction,
        parameters.concat()
    );
    if faults.len() > 1 {
        text.push_str("; this line alone cannot tell the faults named apart");
    }
    text
}

/// A parameter as a person reads it: whole numbers without a fraction, others to four places.
fn show(value: f64) -> String {
    if value.fract() == 0.0 && value.abs() < 1e9 {
        format!("{value:.0}")
    } else if value.is_infinite() {
        if value > 0.0 { "infinity" } else { "-infinity" }.to_string()
    } else {
        format!("{value:.4}")
    }
}
