//! Which of a line's renders match a failing picture, and how closely: the faults named for it.

use super::Tried;
use crate::check::faults::{FAULTS, Fault};
use crate::check::rule::{Rule, channel_difference};
use crate::shade::Image;

/// Faults (one, or two planted together) whose render of a line matches a picture.
#[derive(Debug, Clone, PartialEq)]
pub struct FaultMatch {
    /// The fault, or the two faults planted together.
    pub faults: Vec<&'static Fault>,
    /// The fitted parameters, by name.
    pub parameters: Vec<(&'static str, f64)>,
    /// The share of pixels by which the render and the student's picture still differ.
    pub bad_fraction: f64,
    /// The share of the pixels by which the student's picture differs from its reference that
    /// the render accounts for: 1 − [`FaultMatch::bad_fraction`] / the picture's own share off
    /// (none where the picture is graded against no single reference).
    pub accounts_for: Option<f64>,
    /// Whether the picture was measured against the spread of the faults' renders with several
    /// seeds (a line drawn by chance, where the faults place its samples), not one render.
    pub against_spread: bool,
}

impl FaultMatch {
    /// The faults' names, joined by `+` for a pair.
    pub fn code(&self) -> String {
        self.faults
            .iter()
            .map(|f| f.name)
            .collect::<Vec<_>>()
            .join("+")
    }
}

/// The renders that pass against picture `k`, the closest of each fault (or pair, in either
/// order), closest first; among equals, in the library's order.
pub(super) fn matches(tried: &[Tried], k: usize, rule: Rule) -> Vec<FaultMatch> {
    let mut found: Vec<FaultMatch> = Vec::new();
    // A pair is the same two faults whichever was planted first: named in the library's order,
    // on every picture alike.
    let in_library_order = |faults: &[&'static Fault]| {
        let mut faults = faults.to_vec();
        faults.sort_by_key(|fault| FAULTS.iter().position(|f| f.name == fault.name));
        faults
    };
    for t in tried.iter().filter(|t| t.bad[k] <= rule.max_bad) {
        let faults = in_library_order(&t.faults);
        let names: Vec<&str> = faults.iter().map(|f| f.name).collect();
        match found
            .iter_mut()
            .find(|m| m.faults.iter().map(|f| f.name).eq(names.iter().copied()))
        {
            Some(m) if m.bad_fraction <= t.bad[k] => {}
            Some(m) => {
                m.bad_fraction = t.bad[k];
                m.parameters = t.parameters.clone();
                m.against_spread = t.against_spread;
            }
            None => found.push(FaultMatch {
                faults,
                parameters: t.parameters.clone(),
                bad_fraction: t.bad[k],
                accounts_for: None,
                against_spread: t.against_spread,
            }),
        }
    }
    // Fewer mistakes first: a match whose faults hold another match's, and more, is dropped
    // where the other is as close (a fit may name a second fault for numbers that change
    // nothing the picture shows).
    let simpler = |m: &FaultMatch, other: &FaultMatch| {
        other.faults.len() < m.faults.len()
            && other.bad_fraction <= m.bad_fraction
            && other.faults.iter().all(|f| m.faults.contains(f))
    };
    let kept: Vec<bool> = found
        .iter()
        .map(|m| !found.iter().any(|other| simpler(m, other)))
        .collect();
    let mut kept = kept.into_iter();
    found.retain(|_| kept.next().unwrap_or(true));
    // Stable: among equal figures, the library's order stands.
    found.sort_by(|a, b| a.bad_fraction.total_cmp(&b.bad_fraction));
    found
}

/// How many times as many pixels as the student's picture a near render may change: a render
/// that changes far more (a camera turned, every colour scaled) draws the picture's difference
/// among many others, which says little of its cause.
const NEAR_SPREAD: usize = 4;

/// Of the pixels by which `actual` differs from `reference` (beyond `tolerance`), the share at
/// which `render` draws what `actual` does: how much of the student's difference a fault's
/// render accounts for (a mistake that strikes some of the rays a fault strikes is all of its
/// picture's difference and no more). `None` where the pictures' sizes differ, none of the
/// pixels differs, or the render changes more than [`NEAR_SPREAD`] times as many pixels.
pub(super) fn reproduced(
    actual: &Image,
    reference: &Image,
    render: &Image,
    tolerance: u8,
) -> Option<f64> {
    let same_size = |a: &Image, b: &Image| a.width == b.width && a.height == b.height;
    if !same_size(actual, reference) || !same_size(actual, render) {
        return None;
    }
    let (mut differing, mut drawn, mut changed) = (0_usize, 0_usize, 0_usize);
    for ((&got, &want), &planted) in actual
        .pixels
        .iter()
        .zip(&reference.pixels)
        .zip(&render.pixels)
    {
        if channel_difference(planted, want) > tolerance {
            changed += 1;
        }
        if channel_difference(got, want) > tolerance {
            differing += 1;
            if channel_difference(got, planted) <= tolerance {
                drawn += 1;
            }
        }
    }
    (differing > 0 && changed <= NEAR_SPREAD * differing).then(|| drawn as f64 / differing as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A picture of ten pixels, white where `lit` says, black elsewhere.
    fn picture(lit: &[usize]) -> Image {
        Image {
            width: 10,
            height: 1,
            pixels: (0..10)
                .map(|k| if lit.contains(&k) { [255; 3] } else { [0; 3] })
                .collect(),
        }
    }

    #[test]
    fn a_near_render_accounts_for_the_pixels_it_draws_as_the_student_does() {
        let (reference, student) = (picture(&[]), picture(&[1, 2]));
        // Both of the student's pixels, and three more of its own.
        let wider = picture(&[1, 2, 5, 6, 7]);
        assert_eq!(reproduced(&student, &reference, &wider, 2), Some(1.0));
        assert_eq!(
            reproduced(&student, &reference, &picture(&[2]), 2),
            Some(0.5)
        );
        // Nine changed for the student's two: too many to say anything of the cause.
        let everything = picture(&[0, 1, 2, 3, 4, 5, 6, 7, 8]);
        assert_eq!(reproduced(&student, &reference, &everything, 2), None);
        // Nothing to account for.
        assert_eq!(reproduced(&reference, &reference, &wider, 2), None);
    }
}
