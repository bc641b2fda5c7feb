//! The second pass over a renderer's lines, once every line is graded: the causes of each
//! failing picture (an answer the course allows, the faults whose render matches, raycast's
//! account of the pixel that differs most), the lines of the biggest group first, and what a
//! diagnosis cut short says.

use std::time::Duration;

use super::diagnose::Diagnosis;
use super::suite::{Line, Suite};
use super::vary::Variation;
use super::{
    CheckOptions, Finding, Graded, PictureKind, Status, WorstPixel, finding, simulate, worst_pixel,
};
use crate::render::StopFlag;
use crate::shade::Image;

/// Names the causes of a graded line's failing pictures: an answer the course allows, the
/// faults whose render matches, and raycast's account of the pixel that differs most. Once
/// `stop` is set, or `spent` says the renderer's budget is, the pictures not yet diagnosed say
/// so and keep their guesses from the pixels.
/// Returns whether the faults were read from the cache's record of an earlier run (whose
/// search tried that run's likely faults, not `likely`).
pub(super) fn diagnose_line(
    options: &CheckOptions,
    suite: &Suite,
    line: &Line,
    graded: &mut [Graded],
    stop: &'static StopFlag,
    spent: Option<Duration>,
    likely: &[&'static str],
) -> bool {
    if let Some(budget) = spent {
        let why = format!("the --budget of {} s was spent", budget.as_secs_f64());
        not_finished(graded.iter_mut().filter(|g| g.status == Status::Fail), &why);
        return false;
    }
    if let Some(variation) = &options.varied {
        find_original_pictures(variation, options, line, graded, stop);
    }
    accept_allowed_answers(options, suite, line, graded, stop);
    let search = simulate::Search::Whole { likely };
    let remembered = explain_by_simulation(options, suite, line, graded, stop, search);
    for g in graded.iter_mut().filter(|g| open_failure(g)) {
        let (Some(actual), Some(reference)) = (&g.actual, &g.reference) else {
            continue;
        };
        let Some((x, y, difference)) = worst_pixel(actual, reference) else {
            continue;
        };
        if let Ok(ray_tree) = simulate::ray_tree(line, &suite.scenes, (x, y)) {
            g.worst_pixel = Some(WorstPixel {
                x,
                y,
                difference,
                ray_tree,
            });
        }
    }
    remembered
}

/// Looks again at a diagnosed line's pictures that no fault explained, with the run's likely
/// faults as they are once every line is diagnosed (`now`; the line's diagnosis had `before`):
/// the pairs among them it did not try. See [`simulate::Search::LikelyPairs`].
pub(super) fn pair_again(
    options: &CheckOptions,
    suite: &Suite,
    line: &Line,
    graded: &mut [Graded],
    stop: &'static StopFlag,
    (before, now): (&[&'static str], &[&'static str]),
) {
    if before != now && graded.iter().any(|g| open_failure(g) && unexplained(g)) {
        let search = simulate::Search::LikelyPairs { before, now };
        explain_by_simulation(options, suite, line, graded, stop, search);
    }
}

/// Whether a failing picture's diagnosis names no fault and no fact of the run: what it says
/// are guesses.
pub(super) fn unexplained(g: &Graded) -> bool {
    g.actual.is_some() && g.findings.first().is_none_or(Finding::is_guess)
}

/// Whether a picture fails for a cause still to be found: not one found to be the original
/// scene's under `--vary` (a fact: there is nothing of the varied scene to diagnose).
fn open_failure(g: &Graded) -> bool {
    g.status == Status::Fail && g.findings.first() != Some(&Finding::Diagnosis(Diagnosis::UNVARIED))
}

/// Graded on varied scenes: a failing picture that matches the original scene's (the suite's
/// reference, or raycast's render of the line on the original scene, kept as any reference
/// is) is `unvaried`. The original suite unreadable or its render failing, nothing is said.
fn find_original_pictures(
    variation: &Variation,
    options: &CheckOptions,
    line: &Line,
    graded: &mut [Graded],
    stop: &'static StopFlag,
) {
    if !graded.iter().any(|g| g.status == Status::Fail) {
        return;
    }
    let Ok(original) = Suite::read(&variation.from) else {
        return;
    };
    let renders = std::sync::OnceLock::new();
    for g in graded.iter_mut().filter(|g| g.status == Status::Fail) {
        let Some(actual) = &g.actual else {
            continue;
        };
        let output = g.line.1;
        let Some((_, file)) = line.outputs.get(output) else {
            continue;
        };
        let reference = match original.reference(&super::suite::image_name(file)) {
            Some(path) => super::read_image(&path).ok(),
            None => renders
                .get_or_init(|| super::references::raycasts_pictures(&original, line, stop).ok())
                .as_ref()
                .and_then(|pictures| pictures.get(output).cloned()),
        };
        let matches = reference
            .and_then(|reference| super::rule::compare(actual, &reference, options.rule.tolerance))
            .is_some_and(|comparison| options.rule.passes(&comparison));
        if matches {
            g.findings = vec![Finding::Diagnosis(Diagnosis::UNVARIED)];
            g.explanation = Diagnosis::UNVARIED.explanation().to_string();
        }
    }
}

/// Says of each of `graded` that its diagnosis was not finished, and why: its causes are the
/// pixels' guesses, no more.
pub(super) fn not_finished<'g>(graded: impl Iterator<Item = &'g mut Graded>, why: &str) {
    for g in graded {
        g.explanation = format!(
            "Diagnosis not finished: {why}; from the pixels alone: {}",
            g.explanation
        );
    }
}

/// The lines with a failing picture, in the order their diagnoses are run: the lines of the
/// biggest group of the pixels' guesses first (what the verdict will most likely tell the
/// student to fix first), then by the suite's order.
pub(super) fn diagnosis_order(lines: &[Vec<Graded>]) -> Vec<usize> {
    let guess = |g: &Graded| g.findings.first().map(Finding::code);
    let failing = |g: &&Graded| g.status == Status::Fail;
    let mut groups: std::collections::HashMap<Option<String>, usize> = Default::default();
    for g in lines.iter().flatten().filter(failing) {
        *groups.entry(guess(g)).or_default() += 1;
    }
    let mut order: Vec<(usize, usize)> = lines
        .iter()
        .enumerate()
        .filter_map(|(number, graded)| {
            let biggest = graded
                .iter()
                .filter(failing)
                .map(|g| groups[&guess(g)])
                .max()?;
            Some((number, biggest))
        })
        .collect();
    // Stable: among equal groups, the suite's order.
    order.sort_by_key(|&(_, biggest)| std::cmp::Reverse(biggest));
    order.into_iter().map(|(number, _)| number).collect()
}

/// A failing picture that matches another answer the course allows to one of its open
/// questions passes, saying which; one that depends on a question the course leaves free is
/// informational. Asked to stop, the pictures stay as they are (the diagnosis says so).
fn accept_allowed_answers(
    options: &CheckOptions,
    suite: &Suite,
    line: &Line,
    graded: &mut [Graded],
    stop: &'static StopFlag,
) {
    let failing: Vec<(usize, bool, &Image, Option<&Image>)> = graded
        .iter()
        .enumerate()
        .filter(|(_, g)| open_failure(g))
        .filter_map(|(k, g)| {
            let shaded = g.picture == PictureKind::Image;
            let reference = g.reference.as_ref();
            g.actual
                .as_ref()
                .map(|actual| (k, shaded, actual, reference))
        })
        .collect();
    if failing.is_empty() {
        return;
    }
    let Ok(accepted) = simulate::accepted(
        line,
        &suite.scenes,
        &suite.pinned,
        &failing,
        options.rule,
        stop,
    ) else {
        return;
    };
    let indices: Vec<usize> = failing.iter().map(|&(k, _, _, _)| k).collect();
    for (k, acceptance) in indices.into_iter().zip(accepted) {
        let Some(acceptance) = acceptance else {
            continue;
        };
        let g = &mut graded[k];
        g.status = Status::Pass;
        g.findings.clear();
        g.explanation = acceptance.sentence();
        g.accepted = Some(acceptance);
    }
}

/// Names the faults whose render of the line matches each failing picture; where none does,
/// the pixels' guesses stay, said to be guesses.
fn explain_by_simulation(
    options: &CheckOptions,
    suite: &Suite,
    line: &Line,
    graded: &mut [Graded],
    stop: &'static StopFlag,
    search: simulate::Search<'_>,
) -> bool {
    let again = matches!(search, simulate::Search::LikelyPairs { .. });
    let failing: Vec<(usize, &Image, Option<&Image>)> = graded
        .iter()
        .enumerate()
        .filter(|(_, g)| open_failure(g) && (!again || unexplained(g)))
        .filter_map(|(k, g)| {
            g.actual
                .as_ref()
                .map(|actual| (k, actual, g.reference.as_ref()))
        })
        .collect();
    if failing.is_empty() {
        return false;
    }
    let indices: Vec<usize> = failing.iter().map(|&(k, _, _)| k).collect();
    let rule = options.rule;
    let (simulated, remembered) =
        match simulate::simulate(line, &suite.scenes, &failing, rule, stop, search) {
            Ok(simulated) => simulated,
            // A line raycast cannot render itself leaves the guesses as they are; so does a
            // stop during the pairs' second look, which only adds to a finished diagnosis.
            Err(simulate::Unfinished::Failed(_)) => return false,
            Err(simulate::Unfinished::Stopped) if again => return false,
            // Asked to stop: the pixels' guesses stand, said to be no more than that.
            Err(simulate::Unfinished::Stopped) => {
                let why = if stop.is_out_of_time() {
                    "check's --deadline came"
                } else {
                    "check was interrupted"
                };
                let cut_short = graded
                    .iter_mut()
                    .enumerate()
                    .filter(|(k, _)| indices.contains(k))
                    .map(|(_, g)| g);
                not_finished(cut_short, why);
                return false;
            }
        };
    for (k, result) in indices.into_iter().zip(simulated) {
        if result.matches.is_empty() {
            let g = &mut graded[k];
            // The nearest fault leads the pixels' guesses, itself a guess.
            if let Some(near) = result.near {
                g.findings.insert(0, Finding::Near(near));
                g.explanation = finding::explain(&g.findings, g.picture);
            }
            // Where the difference lies, when one material or light holds it. (Said once: by
            // the whole search, not by the pairs' second look; not once asked to stop.)
            let shaded = g.picture == PictureKind::Image && !again && !stop.is_set();
            if let (true, Some(actual), Some(reference)) = (shaded, &g.actual, &g.reference) {
                let tolerance = options.rule.tolerance;
                g.located = simulate::locate(line, &suite.scenes, actual, reference, tolerance);
                if let Some(located) = &g.located {
                    g.explanation = format!("{} {}", g.explanation, located.sentence());
                }
            }
            continue;
        }
        let g = &mut graded[k];
        // Explained (by the pairs' second look, where the first said where it differs).
        g.located = None;
        g.findings = result.matches.into_iter().map(Finding::Fault).collect();
        g.explanation = finding::explain(&g.findings, g.picture);
    }
    remembered
}
