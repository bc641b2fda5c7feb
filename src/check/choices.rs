//! The questions the course leaves open, as data: each of STAFF_NOTES.md's "Still open" list
//! and each "may" of the handouts, with the answers the course allows. raycast renders one
//! answer by default (the first); `raycast -choose NAME` renders another, through the same
//! seams as check's faults. check accepts every allowed answer: a picture that fails against
//! raycast's answer passes when it matches the render of another allowed answer of a question
//! its line depends on, and the report says which answer the tracer took. Which lines depend
//! on which question is found by rendering (an answer whose render of a line is raycast's own
//! changes nothing there), never from a hand-kept list.
//!
//! Where the allowed answers cannot be listed (Wood is free-form, `-visualize_grid` may use any
//! colours), a picture that depends on the question and differs is informational: shown,
//! never counted as failing, with the reason.

use super::faults::{Candidate, LineScene, Planted, SampleFault, TextureFault};
use crate::parse::description::{MaterialSpec, Pattern};
use crate::sample::Filter;

/// One question the course leaves open.
#[derive(Debug)]
pub struct Choice {
    /// Its stable name.
    pub name: &'static str,
    /// The question, as a student would ask it.
    pub question: &'static str,
    /// raycast's answer: what it renders by default.
    pub raycast: &'static str,
    /// What check accepts.
    pub accepted: Accepted,
}

/// What check accepts for a question.
#[derive(Debug)]
pub enum Accepted {
    /// raycast's answer, or any of these (each rendered where a line depends on it).
    Answers(&'static [Answer]),
    /// Anything: pictures that depend on the question are informational where they differ.
    Anything {
        /// Whether a line's shaded picture depends on it.
        depends: fn(&LineScene) -> bool,
        /// Why, for the report.
        why: &'static str,
    },
    /// No line of the course's suites depends on it (said with what was tried).
    NoLineDepends(&'static str),
}

/// An answer the course allows besides raycast's.
#[derive(Debug)]
pub struct Answer {
    /// Its stable name (`-choose NAME`).
    pub name: &'static str,
    /// What the tracer does, said to the student ("your Gaussian is not cut at 2σ").
    pub said: &'static str,
    /// The renders of it for a line: none where it cannot change the line's pictures.
    pub candidates: fn(&LineScene) -> Vec<Candidate>,
}

/// Whether the line filters its samples with a filter of this kind.
fn filters_with(line: &LineScene, kind: fn(&Filter) -> bool) -> bool {
    (line.options.render_filter.is_some() || !line.options.sampling.is_plain())
        && kind(&line.options.sampling.filter)
}

/// Whether the line's shaded picture shows a texture with this pattern.
fn shows_pattern(line: &LineScene, kind: fn(&Pattern) -> bool) -> bool {
    line.has_image()
        && line.description.materials.iter().any(|m| match m {
            MaterialSpec::Texture(t) => kind(&t.pattern),
            MaterialSpec::Phong(_) => false,
        })
}

fn when(applies: bool, planted: Planted) -> Vec<Candidate> {
    if applies {
        vec![Candidate::plain(planted)]
    } else {
        Vec::new()
    }
}

/// Every open question, in STAFF_NOTES.md's order, then the handouts' "may"s.
pub static CHOICES: &[Choice] = &[
    Choice {
        name: "gaussian_cut",
        question: "Is the Gaussian filter cut to 0 beyond 2σ?",
        raycast: "cut at 2σ (the handout: it \"may be\")",
        accepted: Accepted::Answers(&[Answer {
            name: "gaussian_uncut",
            said: "your Gaussian is not cut at 2σ",
            candidates: |line| {
                when(
                    filters_with(line, |f| matches!(f, Filter::Gaussian(_))),
                    Planted::Sample(SampleFault::GaussianUncut),
                )
            },
        }]),
    },
    Choice {
        name: "box_edge",
        question: "Does the box filter take a sample that lies exactly on its edge?",
        raycast: "the near edges in, the far edges out (−r ≤ x < r)",
        accepted: Accepted::Answers(&[
            Answer {
                name: "box_closed",
                said: "your box filter takes samples on both its edges",
                candidates: |line| {
                    when(
                        filters_with(line, |f| matches!(f, Filter::Box(_))),
                        Planted::Sample(SampleFault::BoxClosed),
                    )
                },
            },
            Answer {
                name: "box_open",
                said: "your box filter takes no sample on its edges",
                candidates: |line| {
                    when(
                        filters_with(line, |f| matches!(f, Filter::Box(_))),
                        Planted::Sample(SampleFault::BoxOpen),
                    )
                },
            },
        ]),
    },
    Choice {
        name: "checkerboard_parity",
        question: "Which material has the checkerboard's cube at the origin?",
        raycast: "the first (materialIndex m1)",
        accepted: Accepted::Answers(&[Answer {
            name: "checker_swapped",
            said: "your checkerboard gives the cube at the origin the second material",
            candidates: |line| {
                when(
                    shows_pattern(line, |p| matches!(p, Pattern::Checkerboard)),
                    Planted::Texture(TextureFault::CheckerSwapped),
                )
            },
        }]),
    },
    Choice {
        name: "noise_mapping",
        question: "How is Noise's sum, about −1 to 1, made a weight from 0 to 1?",
        raycast: "(N + 1) / 2, clamped",
        accepted: Accepted::Answers(&[Answer {
            name: "noise_clamped",
            said: "your Noise clamps its sum to [0, 1]",
            candidates: |line| {
                when(
                    shows_pattern(line, |p| matches!(p, Pattern::Noise { .. })),
                    Planted::Texture(TextureFault::NoiseClamped),
                )
            },
        }]),
    },
    Choice {
        name: "marble_mapping",
        question: "How is Marble's sine, −1 to 1, made a weight from 0 to 1?",
        raycast: "(sin + 1) / 2",
        accepted: Accepted::Answers(&[
            Answer {
                name: "marble_clamped",
                said: "your Marble clamps its sine to [0, 1]",
                candidates: |line| {
                    when(
                        shows_pattern(line, |p| matches!(p, Pattern::Marble { .. })),
                        Planted::Texture(TextureFault::MarbleClamped),
                    )
                },
            },
            Answer {
                name: "marble_absolute",
                said: "your Marble takes the sine's absolute value",
                candidates: |line| {
                    when(
                        shows_pattern(line, |p| matches!(p, Pattern::Marble { .. })),
                        Planted::Texture(TextureFault::MarbleAbsolute),
                    )
                },
            },
        ]),
    },
    Choice {
        name: "wood",
        question: "What does Wood look like?",
        raycast: "rings about the y axis, perturbed by the noise",
        accepted: Accepted::Anything {
            depends: |line| shows_pattern(line, |p| matches!(p, Pattern::Wood { .. })),
            why: "the course leaves Wood free-form (extra credit), so a picture with Wood is \
                  shown, not graded",
        },
    },
    Choice {
        name: "visualize_grid_colours",
        question: "Which colours does -visualize_grid draw its cells in?",
        raycast: "a colour for the number of objects a cell holds",
        accepted: Accepted::Anything {
            depends: |line| line.has_image() && line.options.trace.visualize_grid,
            why: "the handout lets -visualize_grid use any colour scheme, so its picture is \
                  shown, not graded",
        },
    },
    Choice {
        name: "uniform_positions",
        question: "Where does the uniform sampler put a pixel's samples?",
        raycast: "at the centres of an s × s grid's cells",
        accepted: Accepted::NoLineDepends(
            "the cells' centres are the only even grid inside a pixel that the handout's \
             pictures show; corners are the fault uniform_corners",
        ),
    },
    Choice {
        name: "default_filter",
        question: "Which filter is used when samples are given without one?",
        raycast: "a box of radius 0.5 (each pixel its own samples)",
        accepted: Accepted::NoLineDepends(
            "no command line of the course gives samples without a filter",
        ),
    },
];

/// How a picture that differs from raycast's answer was accepted.
#[derive(Debug, Clone)]
pub enum Acceptance {
    /// It matches the render of another allowed answer to this question.
    Answer(&'static Choice, &'static Answer),
    /// It depends on a question the course leaves free: shown, not graded, for this reason.
    Informational(&'static str),
}

// Questions and answers are known by their names.
impl PartialEq for Acceptance {
    fn eq(&self, other: &Acceptance) -> bool {
        match (self, other) {
            (Acceptance::Answer(_, a), Acceptance::Answer(_, b)) => a.name == b.name,
            (Acceptance::Informational(a), Acceptance::Informational(b)) => a == b,
            _ => false,
        }
    }
}

impl Acceptance {
    /// What the student reads: which answer the tracer took, or why the picture is not graded.
    pub fn sentence(&self) -> String {
        match self {
            Acceptance::Answer(choice, answer) => format!(
                "Your picture matches another answer the course allows: {} (\"{}\" raycast \
                 answers {}). Accepted.",
                answer.said, choice.question, choice.raycast
            ),
            Acceptance::Informational(why) => {
                let mut why = why.to_string();
                if let Some(first) = why.get(..1) {
                    why.replace_range(..1, &first.to_uppercase());
                }
                format!("Informational: {why}.")
            }
        }
    }

    /// As summary.json writes it.
    pub fn json(&self) -> serde_json::Value {
        match self {
            Acceptance::Answer(choice, answer) => serde_json::json!({
                "choice": choice.name, "answer": answer.name, "said": answer.said,
            }),
            Acceptance::Informational(why) => serde_json::json!({ "informational": why }),
        }
    }

    /// Back from summary.json (a shard's), where it names a question and answer still known.
    pub fn from_json(value: &serde_json::Value) -> Option<Acceptance> {
        if let Some(name) = value["answer"].as_str() {
            let (choice, answer) = answer(name)?;
            return Some(Acceptance::Answer(choice, answer));
        }
        let why = value["informational"].as_str()?;
        CHOICES.iter().find_map(|choice| match choice.accepted {
            Accepted::Anything { why: known, .. } if known == why => {
                Some(Acceptance::Informational(known))
            }
            _ => None,
        })
    }
}

/// The allowed answer named `name`.
pub fn answer(name: &str) -> Option<(&'static Choice, &'static Answer)> {
    CHOICES.iter().find_map(|choice| match &choice.accepted {
        Accepted::Answers(answers) => answers
            .iter()
            .find(|a| a.name == name)
            .map(|answer| (choice, answer)),
        _ => None,
    })
}

/// Every allowed answer besides raycast's, with its question.
pub fn answers() -> impl Iterator<Item = (&'static Choice, &'static Answer)> {
    CHOICES.iter().flat_map(|choice| {
        let answers: &'static [Answer] = match &choice.accepted {
            Accepted::Answers(answers) => answers,
            _ => &[],
        };
        answers.iter().map(move |answer| (choice, answer))
    })
}

/// The answer `-choose NAME` renders for `line`: `None` where it cannot change the line's
/// pictures (the line renders as raycast's default).
pub fn planted_for(name: &str, line: &LineScene) -> Result<Option<Planted>, String> {
    let (_, answer) = answer(name).ok_or_else(|| {
        let names: Vec<&str> = answers().map(|(_, a)| a.name).collect();
        format!(
            "-choose: unknown answer '{name}' (one of {})",
            names.join(", ")
        )
    })?;
    Ok((answer.candidates)(line).first().map(|c| c.planted))
}

/// The question a line's shaded picture depends on that allows any answer, if any: why it is
/// informational where it differs.
pub fn informational(line: &LineScene) -> Option<&'static str> {
    CHOICES.iter().find_map(|choice| match choice.accepted {
        Accepted::Anything { depends, why } if depends(line) => Some(why),
        _ => None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_answer_has_one_name_and_none_is_a_fault() {
        let mut names: Vec<&str> = answers().map(|(_, a)| a.name).collect();
        let count = names.len();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), count, "two answers share a name");
        for name in names {
            assert!(
                super::super::faults::fault(name).is_none(),
                "{name} is both an allowed answer and a fault"
            );
        }
    }
}
