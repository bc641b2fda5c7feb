//! The grading rule: how two pictures are compared pixel by pixel, and when a picture passes.
//! The one place where pass and fail are decided, for `check` and `diff` alike.

use crate::shade::Image;

/// When a picture passes: at most `max_bad` of its pixels have a channel off by more than
/// `tolerance` levels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rule {
    /// A pixel differs when a channel is off by more than this many levels.
    pub tolerance: u8,
    /// A picture passes when at most this fraction of its pixels differ.
    pub max_bad: f64,
}

impl Rule {
    /// The course's conformance rule: 2 levels, 0.1 % of pixels.
    pub const COURSE: Rule = Rule {
        tolerance: 2,
        max_bad: 0.001,
    };

    /// Whether the compared picture passes.
    pub fn passes(self, comparison: &Comparison) -> bool {
        comparison.bad_fraction <= self.max_bad
    }
}

impl Default for Rule {
    fn default() -> Rule {
        Rule::COURSE
    }
}

/// How two pictures of the same size differ.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// In pixels.
    pub width: u32,
    /// In pixels.
    pub height: u32,
    /// How many pixels have a channel off by more than the tolerance.
    pub differing: usize,
    /// `differing` over the number of pixels (0 for an empty picture).
    pub bad_fraction: f64,
    /// The largest difference of any channel of any pixel, in levels.
    pub worst: u8,
    /// Per pixel, in the pictures' order (rows top first): whether it differs.
    pub mask: Vec<bool>,
}

impl Comparison {
    /// The comparison a per-pixel `mask` of differing pixels makes (rows top first), with the
    /// largest difference seen.
    pub fn of_mask(width: u32, height: u32, mask: Vec<bool>, worst: u8) -> Comparison {
        let differing = mask.iter().filter(|&&differs| differs).count();
        let bad_fraction = if mask.is_empty() {
            0.0
        } else {
            differing as f64 / mask.len() as f64
        };
        Comparison {
            width,
            height,
            differing,
            bad_fraction,
            worst,
            mask,
        }
    }
}

/// Compares `actual` with `reference` pixel by pixel: a pixel differs when any channel is off by
/// more than `tolerance` levels. `None` when the sizes differ (or a picture's pixels do not fill
/// its size).
pub fn compare(actual: &Image, reference: &Image, tolerance: u8) -> Option<Comparison> {
    if !same_shape(actual, reference) {
        return None;
    }
    let mut worst = 0_u8;
    let mask: Vec<bool> = actual
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(&got, &want)| {
            let difference = channel_difference(got, want);
            worst = worst.max(difference);
            difference > tolerance
        })
        .collect();
    Some(Comparison::of_mask(
        reference.width,
        reference.height,
        mask,
        worst,
    ))
}

/// The largest difference of any channel.
pub(crate) fn channel_difference(a: [u8; 3], b: [u8; 3]) -> u8 {
    a[0].abs_diff(b[0])
        .max(a[1].abs_diff(b[1]))
        .max(a[2].abs_diff(b[2]))
}

fn same_shape(actual: &Image, reference: &Image) -> bool {
    let pixel_count = reference.width as usize * reference.height as usize;
    actual.width == reference.width
        && actual.height == reference.height
        && actual.pixels.len() == pixel_count
        && reference.pixels.len() == pixel_count
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compare_counts_channels_beyond_the_tolerance() {
        let reference = Image {
            width: 3,
            height: 2,
            pixels: vec![
                [10, 10, 10],
                [10, 10, 10],
                [10, 10, 10],
                [0, 0, 0],
                [0, 0, 0],
                [9; 3],
            ],
        };
        let actual = Image {
            width: 3,
            height: 2,
            // Equal; off by exactly the tolerance; off by one more in blue; off by 200 in red;
            // equal; off by the tolerance in every channel.
            pixels: vec![
                [10, 10, 10],
                [12, 8, 10],
                [10, 10, 13],
                [200, 0, 0],
                [0, 0, 0],
                [7; 3],
            ],
        };
        let comparison = compare(&actual, &reference, 2).expect("same size");
        assert_eq!((comparison.width, comparison.height), (3, 2));
        assert_eq!(comparison.differing, 2);
        assert_eq!(comparison.worst, 200);
        assert_eq!(comparison.mask, [false, false, true, true, false, false]);
        assert!((comparison.bad_fraction - 2.0 / 6.0).abs() < 1e-12);
        let rule = |max_bad| Rule {
            tolerance: 2,
            max_bad,
        };
        assert!(rule(0.34).passes(&comparison));
        assert!(!rule(0.3).passes(&comparison));
        let strict = compare(&actual, &reference, 0).expect("same size");
        assert_eq!(strict.differing, 4);

        let narrower = Image {
            width: 2,
            height: 3,
            pixels: reference.pixels.clone(),
        };
        assert!(compare(&narrower, &reference, 2).is_none());
    }

    #[test]
    fn the_course_rule_allows_two_levels_on_every_pixel_and_one_pixel_in_a_thousand() {
        let grey = |level: u8| Image {
            width: 1000,
            height: 1,
            pixels: vec![[level; 3]; 1000],
        };
        let reference = grey(100);
        let compared = |actual: &Image| compare(actual, &reference, 2).expect("same size");
        assert!(Rule::COURSE.passes(&compared(&grey(102))));
        let mut one_off = grey(100);
        one_off.pixels[7] = [0; 3];
        assert!(Rule::COURSE.passes(&compared(&one_off)));
        one_off.pixels[8] = [0; 3];
        assert!(!Rule::COURSE.passes(&compared(&one_off)));
    }
}
