//! The course's other allowed answers, tried on a failing picture before any fault: a picture
//! that one of them draws passes, saying which answer the tracer took.

use std::path::Path;

use super::{Renders, Unfinished, on_every_core, prepare, remembered};
use crate::check::cache;
use crate::check::choices::{self, Acceptance, Answer, Choice};
use crate::check::faults::{Plant, Planted};
use crate::check::rule::Rule;
use crate::check::suite::{Line, Pin};
use crate::render::StopFlag;
use crate::shade::Image;

/// For each of `failing` (the index of an image among the line's outputs, whether it is the
/// shaded picture, the student's picture of it, and its reference), how the course's open
/// questions not `pinned` by the suite accept it: the first other allowed answer whose render
/// of the line matches it under `rule`, or, for a shaded picture of a line that shows something
/// the course leaves free, why it is informational. Each allowed answer that can change the
/// line is screened by a few rows, and rendered whole (or read from the cache) where it might
/// match.
pub fn accepted(
    line: &Line,
    scenes: &Path,
    pinned: &[Pin],
    failing: &[(usize, bool, &Image, Option<&Image>)],
    rule: Rule,
    stop: &'static StopFlag,
) -> Result<Vec<Option<Acceptance>>, Unfinished> {
    let pictures: Vec<(usize, &Image, Option<&Image>)> = failing
        .iter()
        .map(|&(image, _, actual, reference)| (image, actual, reference))
        .collect();
    // The pins say which questions are open.
    let kept = cache::LineRenders::of(line, scenes).diagnosis("accepted", pinned, &pictures, rule);
    if let Some(accepted) = kept
        .read()
        .and_then(|text| remembered::accepted_from(&text, failing.len()))
    {
        return Ok(accepted);
    }
    let accepted =
        on_every_core(|| accepted_here(line, scenes, pinned, failing, &pictures, rule, stop))?;
    kept.keep(&remembered::accepted_text(&accepted));
    Ok(accepted)
}

/// [`accepted`], with `pictures` the failing pictures as the renders take them (without
/// whether each is the shaded one).
fn accepted_here(
    line: &Line,
    scenes: &Path,
    pinned: &[Pin],
    failing: &[(usize, bool, &Image, Option<&Image>)],
    pictures: &[(usize, &Image, Option<&Image>)],
    rule: Rule,
    stop: &'static StopFlag,
) -> Result<Vec<Option<Acceptance>>, Unfinished> {
    let prepared = prepare(line, scenes).map_err(Unfinished::Failed)?;
    let mut accepted: Vec<Option<Acceptance>> = vec![None; failing.len()];
    let informational = choices::informational(&prepared.line);
    // A line whose every failing picture is shown, not graded, needs no answer rendered.
    if let Some(why) = informational
        && failing.iter().all(|&(_, shaded, _, _)| shaded)
    {
        return Ok(vec![Some(Acceptance::Informational(why)); failing.len()]);
    }
    let renders = Renders::new(line, scenes, &prepared, pictures, rule, stop)?;
    // A question the suite pins accepts its pinned answer alone, which is the reference.
    let open = choices::answers()
        .filter(|(choice, _)| !pinned.iter().any(|pin| pin.choice.name == choice.name));
    let mut tried = Vec::new();
    for (choice, answer) in open {
        if accepted.iter().all(Option::is_some) {
            break;
        }
        for candidate in (answer.candidates)(&prepared.line) {
            tried.push((choice, answer, candidate.planted));
            let plant = Plant::one(candidate.planted);
            if renders.ruled_out(plant)? {
                continue;
            }
            let rendered = renders.whole(plant)?;
            for (k, &(image, _, actual, _)) in failing.iter().enumerate() {
                let matches = renders.passes(k, rendered.get(image), actual);
                if accepted[k].is_none() && matches {
                    accepted[k] = Some(Acceptance::Answer(choice, answer));
                }
            }
        }
    }
    // Two questions answered otherwise at once (a scene of Noise and Marble, each clamped):
    // the answers that change the line, two of different questions together, for the pictures
    // no one answer draws.
    let questions = |answers: &[(&Choice, &Answer, Planted)]| {
        answers.iter().any(|(c, _, _)| c.name != answers[0].0.name)
    };
    if accepted.iter().any(Option::is_none) && !tried.is_empty() && questions(&tried) {
        // Those whose render (every few rows of it) lies nearer a failing picture than its
        // reference does: each explains a part of it.
        let mut nearer = Vec::new();
        for &(choice, answer, planted) in &tried {
            if renders.nearer_than_references(Plant::one(planted), pictures)? {
                nearer.push((choice, answer, planted));
            }
        }
        for (i, &(first_choice, first, first_planted)) in nearer.iter().enumerate() {
            for &(second_choice, second, second_planted) in &nearer[i + 1..] {
                if first_choice.name == second_choice.name || accepted.iter().all(Option::is_some) {
                    continue;
                }
                let plant = Plant::two(first_planted, second_planted);
                if renders.ruled_out(plant)? {
                    continue;
                }
                let rendered = renders.whole(plant)?;
                for (k, &(image, _, actual, _)) in failing.iter().enumerate() {
                    if accepted[k].is_none() && renders.passes(k, rendered.get(image), actual) {
                        accepted[k] = Some(Acceptance::Answers([
                            (first_choice, first),
                            (second_choice, second),
                        ]));
                    }
                }
            }
        }
    }
    // A picture that differs from raycast's only where a ray's colour turns on its last
    // digits (a picture drawn by chance has its spread, which holds those too).
    if !renders.by_chance() {
        for (choice, answer) in choices::bounded() {
            let waiting: Vec<usize> = (0..failing.len())
                .filter(|&k| accepted[k].is_none())
                .collect();
            let plants: Vec<Plant> = (answer.candidates)(&prepared.line)
                .into_iter()
                .map(|candidate| Plant::one(candidate.planted))
                .collect();
            if waiting.is_empty() || plants.is_empty() {
                continue;
            }
            let references: Vec<Option<&Image>> = failing.iter().map(|f| f.3).collect();
            for k in renders.between(&plants, &waiting, &references)? {
                accepted[k] = Some(Acceptance::Answer(choice, answer));
            }
        }
    }
    if let Some(why) = informational {
        for (k, &(_, shaded, _, _)) in failing.iter().enumerate() {
            if shaded && accepted[k].is_none() {
                accepted[k] = Some(Acceptance::Informational(why));
            }
        }
    }
    Ok(accepted)
}
