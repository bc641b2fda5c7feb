//! One picture of a line, graded: how the renderer's run ended, what it left in the picture's
//! file, and how that compares with the reference. A picture written whole before a crash is
//! still compared (and, where the suite says so, graded alone).

use std::path::Path;

use super::failure::{failed_run, how_it_ended, missing_output, said};
use super::references::ChanceRule;
use super::{
    CheckOptions, Diagnosis, Ending, Finding, Graded, Image, Line, Ran, Status, finding, judge_by,
    output,
};

/// Grades one image from how its run ended and what it left. `picture_alone`: the suite grades
/// a picture written whole before a crash by the picture alone (its `GRADING` file).
#[allow(clippy::too_many_arguments)]
pub(super) fn grade(
    options: &CheckOptions,
    picture_alone: bool,
    line: &Line,
    index: usize,
    name: &str,
    ran: &Ran,
    path: &Path,
    (reference, chance): (Result<Image, String>, Option<&ChanceRule>),
) -> Graded {
    let graded = |status, findings: Vec<Finding>, explanation: String| Graded {
        status,
        findings,
        explanation,
        stderr: ran.stderr.clone(),
        seconds: ran.seconds,
        ..Graded::blank(line, index, name)
    };
    let reference = match reference {
        Ok(image) => image,
        Err(why) => {
            // check was stopped before the line ran (and perhaps before its reference was
            // rendered): that is what the line says.
            if matches!(ran.ending, Ending::Interrupted | Ending::DeadlineCame)
                && let Some((cause, explanation)) = failed_run(ran, &options.limits)
            {
                return graded(Status::Error, vec![Finding::Diagnosis(cause)], explanation);
            }
            return graded(Status::Error, vec![], format!("No reference image: {why}."));
        }
    };
    if let Some((cause, explanation)) = failed_run(ran, &options.limits) {
        // What a crash left behind, read once: a whole picture, one cut short, or none.
        let left = (cause == Diagnosis::CRASH)
            .then(|| output::read_output(path, (reference.width, reference.height)));
        let explanation = match left {
            // A crash after a whole picture was written: the picture is compared and shown,
            // and the crash blamed on what runs after it. The line still fails: the program
            // did not end well.
            Some(Ok(actual))
                if matches!(ran.ending, Ending::Failed { .. } | Ending::Signaled { .. }) =>
            {
                let judgement = match judge_by(&actual, &reference, chance, options.rule) {
                    Ok(judgement) => judgement,
                    Err(why) => {
                        let blank = graded(Status::Error, vec![], String::new());
                        return not_judged(blank, (actual, reference), chance, &why);
                    }
                };
                let picture = if judgement.pass {
                    "Your picture matches the reference"
                } else {
                    "Your picture was written whole but differs from the reference"
                };
                let off = judgement
                    .bad_fraction
                    .map(|f| format!(" ({:.3}% of pixels off)", 100.0 * f))
                    .unwrap_or_default();
                if picture_alone {
                    // The suite grades the picture: a match passes, a difference fails and is
                    // diagnosed as any other; the crash is still told.
                    let status = if judgement.pass {
                        Status::Pass
                    } else {
                        Status::Fail
                    };
                    return Graded {
                        bad_fraction: judgement.bad_fraction,
                        actual: Some(actual),
                        reference: Some(reference),
                        ..graded(
                            status,
                            judgement
                                .diagnoses
                                .into_iter()
                                .map(Finding::Diagnosis)
                                .collect(),
                            format!(
                                "{picture}{off}; then the renderer {}, which this suite does \
                                 not grade (it grades the picture alone).{} Still, {}",
                                how_it_ended(&ran.ending),
                                said(&ran.stderr),
                                lowercase_first(Diagnosis::CRASH_AT_EXIT.explanation())
                            ),
                        )
                    };
                }
                let mut findings = vec![Finding::Diagnosis(Diagnosis::CRASH_AT_EXIT)];
                findings.extend(judgement.diagnoses.into_iter().map(Finding::Diagnosis));
                return Graded {
                    bad_fraction: judgement.bad_fraction,
                    actual: Some(actual),
                    reference: Some(reference),
                    ..graded(
                        Status::Error,
                        findings,
                        format!(
                            "{picture}{off}; then the renderer {}.{} {}",
                            how_it_ended(&ran.ending),
                            said(&ran.stderr),
                            Diagnosis::CRASH_AT_EXIT.explanation()
                        ),
                    )
                };
            }
            // A picture left cut short or garbled by a crash is said to be, not "never written".
            Some(Err(unread)) if unread.cause != Diagnosis::MISSING_OUTPUT => format!(
                "The renderer {} while its picture was being written: the file it left is cut \
                 short or not a picture ({}).{} Look at what ends the program before the picture \
                 is whole (an exception or a crash while writing it, a file not closed).",
                how_it_ended(&ran.ending),
                unread.message,
                said(&ran.stderr)
            ),
            _ => explanation,
        };
        return Graded {
            reference: Some(reference),
            ..graded(Status::Error, vec![Finding::Diagnosis(cause)], explanation)
        };
    }
    let actual = match output::read_output(path, (reference.width, reference.height)) {
        Ok(image) => image,
        Err(unread) if unread.cause == Diagnosis::MISSING_OUTPUT => {
            let explanation = missing_output(
                line.picture_kind(index),
                &line.outputs[index].1,
                &ran.stderr,
            );
            return Graded {
                reference: Some(reference),
                ..graded(
                    Status::Error,
                    vec![Finding::Diagnosis(unread.cause)],
                    explanation,
                )
            };
        }
        Err(unread) => {
            let explanation = format!(
                "{}. {}{}",
                unread.message,
                unread.cause.explanation(),
                said(&ran.stderr)
            );
            // A picture of the wrong size was made, only wrong: a failure, not an error.
            let status = if unread.cause == Diagnosis::SIZE {
                Status::Fail
            } else {
                Status::Error
            };
            return Graded {
                reference: Some(reference),
                ..graded(status, vec![Finding::Diagnosis(unread.cause)], explanation)
            };
        }
    };
    let judgement = match judge_by(&actual, &reference, chance, options.rule) {
        Ok(judgement) => judgement,
        Err(why) => {
            let blank = graded(Status::Error, vec![], String::new());
            return not_judged(blank, (actual, reference), chance, &why);
        }
    };
    let findings: Vec<Finding> = judgement
        .diagnoses
        .into_iter()
        .map(Finding::Diagnosis)
        .collect();
    Graded {
        status: if judgement.pass {
            Status::Pass
        } else {
            Status::Fail
        },
        bad_fraction: judgement.bad_fraction,
        explanation: finding::explain(&findings, line.picture_kind(index)),
        findings,
        actual: Some(actual),
        reference: Some(reference),
        ..graded(Status::Pass, vec![], String::new())
    }
}

/// `text` with its first letter in lower case, to follow a "Still,".
fn lowercase_first(text: &str) -> String {
    let mut chars = text.chars();
    chars
        .next()
        .map(|first| first.to_lowercase().chain(chars).collect())
        .unwrap_or_default()
}

/// A picture drawn by chance whose rule could not be made (`why`): an error, shown beside its
/// reference; where check was stopped while it rendered the rule's draws, that is the cause.
fn not_judged(
    blank: Graded,
    (actual, reference): (Image, Image),
    chance: Option<&ChanceRule>,
    why: &str,
) -> Graded {
    let drawn = "a picture drawn by chance is graded against raycast's renders of the line \
                 with several seeds, and check stopped while it rendered them";
    let (findings, explanation) = match chance.and_then(ChanceRule::stopped) {
        Some(Ending::DeadlineCame) => (
            vec![Finding::Diagnosis(Diagnosis::OVER_BUDGET)],
            format!("check's --deadline came before this picture was graded: {drawn}."),
        ),
        Some(_) => (
            vec![Finding::Diagnosis(Diagnosis::INTERRUPTED)],
            format!("check was interrupted before this picture was graded: {drawn}."),
        ),
        None => (Vec::new(), format!("Not graded: {why}.")),
    };
    Graded {
        findings,
        explanation,
        actual: Some(actual),
        reference: Some(reference),
        ..blank
    }
}
