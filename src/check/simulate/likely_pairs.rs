//! The likely pairs first. A renderer usually has one or two bugs: where no single fault
//! explains a picture, and faults explained other pictures before in this run (this student's
//! lines, or a class's commonest), those faults together are the likeliest explanation, as a
//! teaching assistant who has seen them elsewhere in the same program would say. They are tried
//! before the fits, whose searches render the line hundreds of times (on a line of many
//! samples a pixel, minutes): a picture a likely pair draws needs none of them.

use super::{Look, Plant, Tried, Unfinished};
use crate::check::faults::{Candidate, Fault};
use crate::check::rule::Rule;
use crate::check::screen::Screen;

/// The faults that explained the most pictures so far, paired among themselves...
const LIKELY_FAULTS: usize = 3;
/// ...each at its renders nearest the picture, this many.
const NEAREST: usize = 2;

/// The run's `likely` faults (commonest first) that can change the line's pictures (have
/// `candidates`), the first [`LIKELY_FAULTS`].
pub(super) fn likely_faults(
    candidates: &[(&'static Fault, Candidate)],
    likely: &[&'static str],
) -> Vec<&'static str> {
    likely
        .iter()
        .copied()
        .filter(|&name| candidates.iter().any(|(fault, _)| fault.name == name))
        .take(LIKELY_FAULTS)
        .collect()
}

/// For each picture no single fault explains (`explained` false), the pairs of the line's
/// `likely` faults (of [`likely_faults`]) but those of two faults both among `tried_before`,
/// each at its renders of the line nearest the picture (`singles`, in the order of
/// `candidates`), tried with `look` until one matches under `rule`; the pictures they match are
/// marked explained. Returns every pair tried.
pub(super) fn likely_pairs(
    candidates: &[(&'static Fault, Candidate)],
    singles: &[Look],
    explained: &mut [bool],
    rule: Rule,
    screen: Option<&Screen>,
    look: &impl Fn(
        Plant,
        &[&'static Fault],
        &[(&'static str, f64)],
        Option<&Screen>,
    ) -> Result<Look, Unfinished>,
    (likely, tried_before): (&[&'static str], &[&'static str]),
) -> Result<Vec<Tried>, Unfinished> {
    let mut tried: Vec<Tried> = Vec::new();
    for k in 0..explained.len() {
        if explained[k] {
            continue;
        }
        // A fault's renders of the line, nearest the picture first.
        let nearest = |name: &str| -> Vec<usize> {
            let mut them: Vec<usize> = (0..candidates.len())
                .filter(|&i| candidates[i].0.name == name)
                .collect();
            them.sort_by(|&a, &b| singles[a].tried.error[k].total_cmp(&singles[b].tried.error[k]));
            them.truncate(NEAREST);
            them
        };
        'pairs: for (rank, &first) in likely.iter().enumerate() {
            for &second in &likely[rank + 1..] {
                if tried_before.contains(&first) && tried_before.contains(&second) {
                    continue;
                }
                for a in nearest(first) {
                    for b in nearest(second) {
                        let (plant, faults, parameters) =
                            singles[a].tried.paired_with(&singles[b].tried);
                        let pair = look(plant, &faults, &parameters, screen)?.tried;
                        let matched: Vec<usize> = (0..explained.len())
                            .filter(|&j| !explained[j] && pair.bad[j] <= rule.max_bad)
                            .collect();
                        tried.push(pair);
                        for j in matched {
                            explained[j] = true;
                        }
                        if explained[k] {
                            break 'pairs;
                        }
                    }
                }
            }
        }
    }
    Ok(tried)
}
