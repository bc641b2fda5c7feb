//! One verdict per renderer: the failing pictures grouped by the fault that explains them,
//! the biggest group first, then those no fault explains. Where a picture matches several
//! faults equally, the one the most pictures share is named first, so that one fix explains
//! the most.

use serde_json::{Value, json};

use super::finding::Finding;
use super::{Graded, Status};

/// Failing pictures that one cause explains.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// The cause's code; `None` for the pictures no fault of the library explains.
    pub code: Option<String>,
    /// The pictures' names, in the suite's order.
    pub images: Vec<String>,
    /// Other faults whose renders match every one of these pictures too: the pictures cannot
    /// tell them from `code`'s.
    pub equals: Vec<String>,
    /// For the pictures no fault explains: what the pixels suggest (a guess's code, or
    /// `unknown`) and for how many of them, the commonest first.
    pub guesses: Vec<(String, usize)>,
}

/// Groups the failing pictures of `graded` by cause, after putting first, among each picture's
/// equal matches, the fault the most pictures share.
pub fn verdict(graded: &mut [Graded]) -> Vec<Group> {
    let failing = |g: &Graded| g.status != Status::Pass;
    // How many pictures each fault explains, counting each picture once per fault it matches.
    let mut shared: Vec<(String, usize)> = Vec::new();
    for g in graded.iter().filter(|g| failing(g)) {
        for finding in g.findings.iter().filter(|f| matches!(f, Finding::Fault(_))) {
            let code = finding.code();
            match shared.iter_mut().find(|(c, _)| *c == code) {
                Some((_, n)) => *n += 1,
                None => shared.push((code, 1)),
            }
        }
    }
    let share = |code: &str| {
        shared
            .iter()
            .find(|(c, _)| c == code)
            .map_or(0, |&(_, n)| n)
    };
    for g in graded.iter_mut().filter(|g| failing(g)) {
        let best = g
            .findings
            .iter()
            .enumerate()
            .filter(|(_, f)| matches!(f, Finding::Fault(_)))
            .max_by_key(|&(k, f)| (share(&f.code()), std::cmp::Reverse(k)))
            .map(|(k, _)| k);
        if let Some(best) = best.filter(|&k| k > 0) {
            let chosen = g.findings.remove(best);
            g.findings.insert(0, chosen);
            g.moved_from = Some(best);
            g.explanation = super::finding::explain(&g.findings, g.picture);
        }
    }
    let mut groups: Vec<Group> = Vec::new();
    let mut unexplained = Vec::new();
    let mut guesses: Vec<(String, usize)> = Vec::new();
    for g in graded.iter().filter(|g| failing(g)) {
        match g.findings.first().filter(|f| !f.is_guess()) {
            Some(finding) => {
                let code = finding.code();
                let others: Vec<String> = g.findings[1..]
                    .iter()
                    .filter(|f| matches!(f, Finding::Fault(_)))
                    .map(Finding::code)
                    .collect();
                match groups
                    .iter_mut()
                    .find(|group| group.code.as_ref() == Some(&code))
                {
                    Some(group) => {
                        group.images.push(g.name.clone());
                        group.equals.retain(|c| others.contains(c));
                    }
                    None => groups.push(Group {
                        code: Some(code),
                        images: vec![g.name.clone()],
                        equals: others,
                        guesses: Vec::new(),
                    }),
                }
            }
            None => {
                unexplained.push(g.name.clone());
                let guess = g
                    .findings
                    .first()
                    .map_or("unknown".to_string(), Finding::code);
                match guesses.iter_mut().find(|(code, _)| *code == guess) {
                    Some((_, n)) => *n += 1,
                    None => guesses.push((guess, 1)),
                }
            }
        }
    }
    if !unexplained.is_empty() {
        guesses.sort_by_key(|(_, n)| std::cmp::Reverse(*n));
        groups.push(Group {
            code: None,
            images: unexplained,
            equals: Vec::new(),
            guesses,
        });
    }
    // Biggest first, the pictures no fault explains and the time-outs counted like any group:
    // "fix it first" names where most of the failures are. Among equals, one a fault explains
    // (something to fix) before the unexplained, then the order the suite first showed them.
    groups.sort_by_key(|group| (std::cmp::Reverse(group.images.len()), group.code.is_none()));
    groups
}

/// The verdict for the terminal: one line a group, the first saying what to fix first, each
/// fault's sentence and what to look for indented below its group.
pub fn lines(groups: &[Group]) -> Vec<String> {
    let mut out = Vec::new();
    for (headline, details) in entries(groups) {
        out.push(format!("verdict: {headline}"));
        out.extend(details.into_iter().map(|d| format!("         {d}")));
    }
    out
}

/// Each group's headline, and below it each of its faults: name, assignment, sentence and what
/// to look for.
pub fn entries(groups: &[Group]) -> Vec<(String, Vec<String>)> {
    let failing: usize = groups.iter().map(|g| g.images.len()).sum();
    let plural = |n: usize| if n == 1 { "" } else { "s" };
    let mut out = Vec::new();
    for (k, group) in groups.iter().enumerate() {
        let n = group.images.len();
        let equally = if group.equals.is_empty() {
            String::new()
        } else {
            format!(
                " (or, as well, by {}: {} cannot tell them apart)",
                group.equals.join(" or "),
                if n == 1 {
                    "that picture"
                } else {
                    "those pictures"
                }
            )
        };
        // The first group a fault explains, after an unexplained one that is bigger.
        let first_explained = k > 0 && groups[..k].iter().all(|g| g.code.is_none());
        let headline = match (&group.code, k) {
            (Some(code), 0) => format!(
                "{n} of {failing} failing picture{} {} explained by {code}{equally}: fix it \
                 first, then run check again",
                plural(failing),
                if n == 1 { "is" } else { "are" }
            ),
            (Some(code), _) if first_explained => format!(
                "{n} more by {code}{equally}: the biggest group a fault explains, to fix next"
            ),
            (Some(code), _) => format!("{n} more by {code}{equally}"),
            (None, 0) => format!(
                "{n} of {failing} failing picture{} no fault of the library explains, the \
                 biggest group: look at them first, each beside its reference and heat map. \
                 {}: {}",
                plural(failing),
                shared(group),
                group.images.join(", ")
            ),
            (None, _) => format!(
                "{n} failing picture{} no fault explains: {}",
                plural(n),
                group.images.join(", ")
            ),
        };
        // The pictures no fault explains: the fault whose render comes nearest to most of
        // them, where that is the leading guess, says what to look for too.
        let nearest = group
            .code
            .is_none()
            .then(|| group.guesses.first().map(|(code, _)| code))
            .flatten();
        let details = group
            .code
            .iter()
            .chain(&group.equals)
            .chain(nearest)
            .filter_map(|code| faults_of(code))
            .flatten()
            .fold(Vec::new(), |mut seen, fault| {
                if !seen.contains(&fault) {
                    seen.push(fault);
                }
                seen
            })
            .into_iter()
            .map(|fault| {
                format!(
                    "{} (assignment {}): \"{}\" Look for: {}",
                    fault.name, fault.assignment, fault.sentence, fault.look_for
                )
            })
            .collect();
        out.push((headline, details));
    }
    out
}

/// What the pictures no fault explains have in common: their assignments, and what their
/// pixels suggest for most of them.
fn shared(group: &Group) -> String {
    let mut assignments: Vec<String> = group
        .images
        .iter()
        .map(|name| super::suite::assignment(name))
        .collect();
    assignments.sort();
    assignments.dedup();
    let n = group.images.len();
    let mut text = format!(
        "{} of {}",
        if n == 1 { "A picture" } else { "Pictures" },
        assignments.join(", ")
    );
    if let Some((guess, m)) = group.guesses.first().filter(|(code, _)| code != "unknown") {
        if faults_of(guess).is_some() {
            // A near render's guess: a fault of the library, no render of which matched.
            text.push_str(&format!(
                "; {guess}'s render comes nearest to {m} of {n}, a guess: none matches"
            ));
        } else {
            text.push_str(&format!("; the pixels suggest {guess} in {m} of {n}"));
        }
    }
    text
}

/// The library's faults a code names (`a` or `a+b`); `None` for a code of no fault.
fn faults_of(code: &str) -> Option<Vec<&'static super::faults::Fault>> {
    code.split('+').map(super::faults::fault).collect()
}

/// The verdict as `summary.json` carries it: `{fault, lines, equals}` for each group, biggest
/// first, `fault` null for the pictures no fault explains, `equals` the other faults those
/// pictures cannot tell from it.
pub fn json(groups: &[Group]) -> Value {
    Value::Array(
        groups
            .iter()
            .map(|g| json!({ "fault": g.code, "lines": g.images, "equals": g.equals }))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::{Diagnosis, PictureKind, Pictures};

    fn failing(name: &str, cause: Diagnosis) -> Graded {
        Graded {
            name: name.into(),
            command: String::new(),
            status: Status::Fail,
            bad_fraction: Some(0.1),
            findings: vec![Finding::Diagnosis(cause)],
            explanation: String::new(),
            actual: None,
            reference: None,
            stderr: String::new(),
            seconds: 0.0,
            against_raycast: false,
            by_chance: false,
            picture: PictureKind::Image,
            worst_pixel: None,
            pictures: Pictures::default(),
            points: 1.0,
            line: (0, 0),
            moved_from: None,
            located: None,
            accepted: None,
        }
    }

    #[test]
    fn fix_it_first_is_the_biggest_group_even_unexplained() {
        // Two time-outs and five pictures no fault explains (three look too dark or bright).
        let mut graded = vec![
            failing("output4_01", Diagnosis::TIMED_OUT),
            failing("output4_02", Diagnosis::TIMED_OUT),
            failing("output5_01", Diagnosis::COLOUR_SCALE),
            failing("output5_02", Diagnosis::COLOUR_SCALE),
            failing("output6_01", Diagnosis::COLOUR_SCALE),
            failing("output6_02", Diagnosis::UNKNOWN),
            failing("output6_03", Diagnosis::UNKNOWN),
        ];
        let groups = verdict(&mut graded);
        let codes: Vec<Option<&str>> = groups.iter().map(|g| g.code.as_deref()).collect();
        assert_eq!(codes, [None, Some("timed_out")]);
        let lines = lines(&groups);
        assert_eq!(
            lines[0],
            "verdict: 5 of 7 failing pictures no fault of the library explains, the biggest \
             group: look at them first, each beside its reference and heat map. Pictures of A5, \
             A6; the pixels suggest colour_scale in 3 of 5: output5_01, output5_02, output6_01, \
             output6_02, output6_03"
        );
        assert_eq!(
            lines[1],
            "verdict: 2 more by timed_out: the biggest group a fault explains, to fix next"
        );
        // Equal in size, the group a fault explains comes first: something to fix.
        let mut graded = vec![
            failing("output2_01", Diagnosis::UNKNOWN),
            failing("output2_02", Diagnosis::UNKNOWN),
            failing("output2_03", Diagnosis::TIMED_OUT),
            failing("output2_04", Diagnosis::TIMED_OUT),
        ];
        let groups = verdict(&mut graded);
        assert_eq!(groups[0].code.as_deref(), Some("timed_out"));
        assert_eq!(groups[1].code, None);
    }

    #[test]
    fn a_near_render_is_a_guess_among_the_pictures_no_fault_explains() {
        let near = |name: &str| {
            let mut g = failing(name, Diagnosis::UNKNOWN);
            let m = crate::check::simulate::FaultMatch {
                faults: vec![crate::check::faults::fault("grid_rays_from_inside").unwrap()],
                parameters: Vec::new(),
                bad_fraction: 0.01,
                accounts_for: Some(0.99),
                against_spread: false,
            };
            g.findings.insert(0, Finding::Near(m));
            g
        };
        let mut graded = vec![near("output6_02d"), near("output6_11b")];
        let groups = verdict(&mut graded);
        assert_eq!(groups.len(), 1);
        assert_eq!(groups[0].code, None);
        assert_eq!(
            lines(&groups)[0],
            "verdict: 2 of 2 failing pictures no fault of the library explains, the biggest \
             group: look at them first, each beside its reference and heat map. Pictures of A6; \
             grid_rays_from_inside's render comes nearest to 2 of 2, a guess: none matches: \
             output6_02d, output6_11b"
        );
        assert!(
            lines(&groups)[1]
                .starts_with("         grid_rays_from_inside (assignment 5): \"My grid walk"),
            "{:?}",
            lines(&groups)
        );
        // A pixel's guess names no fault to look into.
        let mut graded = vec![failing("output6_01", Diagnosis::COLOUR_SCALE)];
        assert_eq!(lines(&verdict(&mut graded)).len(), 1);
    }
}
