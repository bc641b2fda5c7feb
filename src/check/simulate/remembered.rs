//! A line's diagnoses remembered by the student's pictures. Which faults and which allowed
//! answers match a failing picture depends on raycast's program, the line and the pictures
//! alone: a student who fixes one bug and runs check again is told the kept diagnosis of every
//! line whose pictures did not change, and a student of a class whose pictures of a line are
//! another's to the byte (the same bug in a tracer otherwise exact) is told that student's,
//! with nothing rendered. Kept in the cache beside the renders, trimmed with them.
//!
//! Kept as JSON, every number as its bits (the fitted parameters come back exactly). Text that
//! does not read back as a diagnosis of as many pictures, or names a fault or answer this
//! program lacks, is not used: the line is diagnosed again and the text replaced.

use std::sync::Mutex;

use serde_json::{Value, json};

use super::{FaultMatch, Simulated};
use crate::check::choices::{self, Acceptance};
use crate::check::faults;

/// The faults that match each failing picture, as text to keep.
pub(super) fn simulated_text(simulated: &[Simulated]) -> String {
    let pictures: Vec<Value> = simulated
        .iter()
        .map(|result| {
            let matches: Vec<Value> = result
                .matches
                .iter()
                .map(|m| (m, false))
                .chain(result.near.iter().map(|m| (m, true)))
                .map(|(m, near)| {
                    json!({
                        "near": near,
                        "faults": m.faults.iter().map(|f| f.name).collect::<Vec<_>>(),
                        "parameters": m
                            .parameters
                            .iter()
                            .map(|&(name, value)| json!([name, value.to_bits()]))
                            .collect::<Vec<_>>(),
                        "bad": m.bad_fraction.to_bits(),
                        "accounts_for": m.accounts_for.map(f64::to_bits),
                        "against_spread": m.against_spread,
                    })
                })
                .collect();
            Value::Array(matches)
        })
        .collect();
    Value::Array(pictures).to_string()
}

/// The faults that match each of `pictures` failing pictures, read back from `text`.
pub(super) fn simulated_from(text: &str, pictures: usize) -> Option<Vec<Simulated>> {
    each_picture(text, pictures)?
        .iter()
        .map(|matches| {
            let mut near = None;
            let mut exact = Vec::new();
            for value in matches.as_array()? {
                let m = fault_match(value)?;
                if value["near"].as_bool() == Some(true) {
                    near = Some(m);
                } else {
                    exact.push(m);
                }
            }
            Some(Simulated {
                matches: exact,
                near,
            })
        })
        .collect()
}

fn fault_match(value: &Value) -> Option<FaultMatch> {
    let faults = value["faults"]
        .as_array()?
        .iter()
        .map(|name| faults::fault(name.as_str()?))
        .collect::<Option<Vec<_>>>()?;
    let parameters = value["parameters"]
        .as_array()?
        .iter()
        .map(|pair| Some((interned(pair[0].as_str()?), number(&pair[1])?)))
        .collect::<Option<Vec<_>>>()?;
    let accounts_for = match &value["accounts_for"] {
        Value::Null => None,
        share => Some(number(share)?),
    };
    Some(FaultMatch {
        faults,
        parameters,
        bad_fraction: number(&value["bad"])?,
        accounts_for,
        against_spread: value["against_spread"].as_bool()?,
    })
}

/// How each failing picture was accepted, if it was, as text to keep.
pub(super) fn accepted_text(accepted: &[Option<Acceptance>]) -> String {
    let pictures: Vec<Value> = accepted
        .iter()
        .map(|acceptance| match acceptance {
            None => Value::Null,
            Some(Acceptance::Answer(_, answer)) => json!({ "answer": answer.name }),
            Some(Acceptance::Answers([(_, answer), (_, also)])) => {
                json!({ "answer": answer.name, "also": also.name })
            }
            Some(Acceptance::Informational(why)) => json!({ "informational": why }),
        })
        .collect();
    Value::Array(pictures).to_string()
}

/// How each of `pictures` failing pictures was accepted, read back from `text`.
pub(super) fn accepted_from(text: &str, pictures: usize) -> Option<Vec<Option<Acceptance>>> {
    each_picture(text, pictures)?
        .iter()
        .map(|acceptance| {
            if acceptance.is_null() {
                return Some(None);
            }
            if let Some(name) = acceptance["answer"].as_str() {
                let (choice, answer) = choices::answer_named(name)?;
                return Some(Some(match acceptance["also"].as_str() {
                    Some(also) => {
                        Acceptance::Answers([(choice, answer), choices::answer_named(also)?])
                    }
                    None => Acceptance::Answer(choice, answer),
                }));
            }
            let why = choices::reason_named(acceptance["informational"].as_str()?)?;
            Some(Some(Acceptance::Informational(why)))
        })
        .collect()
}

/// The record of each of `pictures` pictures that `text` keeps: `None` where it is not JSON
/// or keeps another number of pictures.
fn each_picture(text: &str, pictures: usize) -> Option<Vec<Value>> {
    match serde_json::from_str(text).ok()? {
        Value::Array(read) if read.len() == pictures => Some(read),
        _ => None,
    }
}

fn number(value: &Value) -> Option<f64> {
    value.as_u64().map(f64::from_bits)
}

/// A parameter's name read back, as the `'static` name the fits give: each name is kept once
/// for the run (there are a few dozen).
fn interned(name: &str) -> &'static str {
    static NAMES: Mutex<Vec<&'static str>> = Mutex::new(Vec::new());
    let mut names = NAMES.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(&known) = names.iter().find(|&&known| known == name) {
        return known;
    }
    let leaked: &'static str = Box::leak(name.to_owned().into_boxed_str());
    names.push(leaked);
    leaked
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_diagnosis_reads_back_as_it_was_kept() {
        let simulated = vec![
            Simulated {
                matches: vec![FaultMatch {
                    faults: vec![
                        faults::fault("shadow_acne").unwrap(),
                        faults::fault("ambient_missing").unwrap(),
                    ],
                    parameters: vec![("offset", 0.1 + 0.2), ("weight", -1.0 / 3.0)],
                    bad_fraction: 1e-7,
                    accounts_for: Some(0.999_999_999_1),
                    against_spread: true,
                }],
                near: None,
            },
            Simulated::default(),
            // No render passes; the nearest is kept as the guess it is.
            Simulated {
                matches: Vec::new(),
                near: Some(FaultMatch {
                    faults: vec![faults::fault("grid_rays_from_inside").unwrap()],
                    parameters: Vec::new(),
                    bad_fraction: 0.006,
                    accounts_for: Some(0.98),
                    against_spread: false,
                }),
            },
        ];
        let text = simulated_text(&simulated);
        assert_eq!(simulated_from(&text, 3), Some(simulated));
        assert_eq!(simulated_from(&text, 2), None, "kept for three pictures");
        let renamed = text.replace("shadow_acne", "no_such_fault");
        assert_eq!(simulated_from(&renamed, 3), None);
        assert_eq!(simulated_from("[[{\"faults\":", 2), None);
    }

    #[test]
    fn an_acceptance_reads_back_as_it_was_kept() {
        let (choice, answer) = choices::answers().next().unwrap();
        let why = choices::CHOICES
            .iter()
            .find_map(|c| match c.accepted {
                choices::Accepted::Anything { why, .. } => Some(why),
                _ => None,
            })
            .unwrap();
        let other = choices::answers()
            .find(|(c, _)| c.name != choice.name)
            .unwrap();
        let accepted = vec![
            None,
            Some(Acceptance::Answer(choice, answer)),
            Some(Acceptance::Informational(why)),
            Some(Acceptance::Answers([(choice, answer), other])),
        ];
        let text = accepted_text(&accepted);
        assert_eq!(accepted_from(&text, 4), Some(accepted));
        let unknown = text.replace(answer.name, "no_such_answer");
        assert_eq!(accepted_from(&unknown, 4), None);
    }
}
