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
                    }),
                }
            }
            None => unexplained.push(g.name.clone()),
        }
    }
    // Biggest first; among equals, the order in which the suite first showed them.
    groups.sort_by_key(|group| std::cmp::Reverse(group.images.len()));
    if !unexplained.is_empty() {
        groups.push(Group {
            code: None,
            images: unexplained,
            equals: Vec::new(),
        });
    }
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
        let headline = match (&group.code, k) {
            (Some(code), 0) => format!(
                "{n} of {failing} failing picture{} {} explained by {code}{equally}: fix it \
                 first, then run check again",
                plural(failing),
                if n == 1 { "is" } else { "are" }
            ),
            (Some(code), _) => format!("{n} more by {code}{equally}"),
            (None, _) => format!(
                "{n} failing picture{} no fault explains: {}",
                plural(n),
                group.images.join(", ")
            ),
        };
        let details = group
            .code
            .iter()
            .chain(&group.equals)
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
