//! Screening a fault before rendering it whole: a few rows of its render, those where the
//! student's pictures differ most from the references, can already hold more differing pixels
//! than the rule allows a whole picture. Such a fault cannot match, and the whole render is
//! spared. Only ever a fault that cannot match is ruled out: the rows' count of differing
//! pixels is a part of the whole picture's, so where it is too many, the whole is too.

use super::chance::Spread;
use super::rule::{Rule, channel_difference};
use crate::shade::Image;

/// Rows are added, most differing first, until each picture's chosen rows hold this many times
/// the differing pixels its rule allows (twice was cheaper, but the rows a pair is screened by
/// then left out `pixel_corner` with `ambient_missing` on a sphere of triangles: the zoo's pairs
/// test)...
const ENOUGH: usize = 4;
/// ...or until they are this share of the picture's rows (1 in N).
const MOST_ROWS: usize = 6;

/// The rows to render and what each failing picture allows.
#[derive(Debug, Clone, PartialEq)]
pub struct Screen {
    /// For each row, counted from the top, whether it is rendered.
    wanted: Vec<bool>,
    rule: Rule,
}

/// A failing picture: the student's, and the reference it failed against.
pub struct Failing<'a> {
    /// The student's picture.
    pub actual: &'a Image,
    /// The reference, if there is one of the picture's size.
    pub reference: Option<&'a Image>,
    /// Whether the render makes the picture row for row (the shaded, normals and depth
    /// pictures; the samples picture is zoomed, the filter's is not traced).
    pub traced: bool,
    /// Where the picture is drawn by chance, the spread of raycast's seeded renders: a pixel
    /// then differs as two draws do (the reference being one).
    pub spread: Option<&'a Spread>,
}

/// Whether pixel `i` of `got` and `want` differ, by the rule's tolerance or, for pictures
/// drawn by chance, as two draws of `spread`.
fn differs(spread: Option<&Spread>, tolerance: u8, i: usize, got: [u8; 3], want: [u8; 3]) -> bool {
    match spread {
        Some(spread) => spread.draws_differ(i, got, want, tolerance),
        None => channel_difference(got, want) > tolerance,
    }
}

impl Screen {
    /// The rows that screen every one of `failing`; `None` where one cannot be screened (no
    /// reference of its size, a picture not traced row for row, or pictures of different
    /// sizes) or where the rows would be no cheaper than the whole.
    pub fn of(failing: &[Failing], rule: Rule) -> Option<Screen> {
        let first = failing.first()?.actual;
        let (width, height) = (first.width as usize, first.height as usize);
        let mut by_row = vec![0_usize; height];
        let mut totals = Vec::with_capacity(failing.len());
        for picture in failing {
            let reference = picture.reference?;
            let same_size = |image: &Image| {
                (image.width as usize, image.height as usize) == (width, height)
                    && image.pixels.len() == width * height
            };
            if !picture.traced || !same_size(picture.actual) || !same_size(reference) {
                return None;
            }
            let mut total = vec![0_usize; height];
            for (row, (got, want)) in picture
                .actual
                .pixels
                .chunks(width.max(1))
                .zip(reference.pixels.chunks(width.max(1)))
                .enumerate()
            {
                total[row] = got
                    .iter()
                    .zip(want)
                    .enumerate()
                    .filter(|&(x, (&a, &b))| {
                        differs(picture.spread, rule.tolerance, row * width + x, a, b)
                    })
                    .count();
                by_row[row] += total[row];
            }
            totals.push(total);
        }
        let allowed = (rule.max_bad * (width * height) as f64) as usize;
        let mut order: Vec<usize> = (0..height).collect();
        // Stable: among equal rows, the upper first.
        order.sort_by_key(|&row| std::cmp::Reverse(by_row[row]));
        let mut wanted = vec![false; height];
        let mut chosen = vec![0_usize; failing.len()];
        for (count, &row) in order.iter().enumerate() {
            let enough = chosen.iter().all(|&c| c > ENOUGH * allowed);
            if enough || count >= height.div_ceil(MOST_ROWS) || by_row[row] == 0 {
                break;
            }
            wanted[row] = true;
            for (k, total) in totals.iter().enumerate() {
                chosen[k] += total[row];
            }
        }
        // Rows with no difference in them rule nothing out.
        wanted.contains(&true).then_some(Screen { wanted, rule })
    }

    /// Every `n`th row of a picture `height` rows high, from the `n / 2`th: a sample of the
    /// whole picture (a fit's measure), not of where it differs.
    pub fn every(n: usize, height: usize, rule: Rule) -> Screen {
        let n = n.max(1);
        Screen {
            wanted: (0..height).map(|row| row % n == n / 2).collect(),
            rule,
        }
    }

    /// The rows to render, counted from the top.
    pub fn wanted(&self) -> &[bool] {
        &self.wanted
    }

    /// The mean difference of the channels of `picture` and `actual` over the wanted rows, in
    /// levels; infinite for pictures of other sizes.
    pub fn mean_difference(&self, picture: &Image, actual: &Image) -> f64 {
        if (picture.width, picture.height) != (actual.width, actual.height)
            || picture.pixels.len() != actual.pixels.len()
            || picture.pixels.is_empty()
        {
            return f64::INFINITY;
        }
        let width = actual.width.max(1) as usize;
        let height = actual.height.max(1) as usize;
        // A zoomed picture (the samples' or the filter's) has `zoom` rows for each of the
        // image's: row r shows the image's row r / zoom.
        let wanted = |row: usize| {
            self.wanted
                .get(row * self.wanted.len() / height)
                .is_some_and(|&wanted| wanted)
        };
        let (mut sum, mut count) = (0_u64, 0_usize);
        for (row, (got, want)) in picture
            .pixels
            .chunks(width)
            .zip(actual.pixels.chunks(width))
            .enumerate()
        {
            if !wanted(row) {
                continue;
            }
            for (a, b) in got.iter().zip(want) {
                sum += (0..3).map(|c| u64::from(a[c].abs_diff(b[c]))).sum::<u64>();
            }
            count += got.len();
        }
        sum as f64 / count.max(1) as f64
    }

    /// The wanted rows and the rows next to them: a spread's deviation at a pixel is the
    /// largest of its neighbourhood's, so a spread made from renders of these rows alone is
    /// the whole spread's in the wanted rows.
    pub fn with_neighbours(&self) -> Vec<bool> {
        let near = |row: usize| {
            (row.saturating_sub(1)..(row + 2).min(self.wanted.len())).any(|r| self.wanted[r])
        };
        (0..self.wanted.len()).map(near).collect()
    }

    /// Whether none of the `actual` pictures lies within its spread (a fault's own, made from
    /// renders of [`Screen::with_neighbours`]' rows with several seeds): in the wanted rows
    /// alone, each has more pixels outside it than the rule allows the whole picture. A
    /// picture without a spread is never ruled out.
    pub fn rules_out_spreads(&self, spreads: &[Option<&Spread>], actual: &[&Image]) -> bool {
        actual.iter().enumerate().all(|(k, actual)| {
            let Some(spread) = spreads.get(k).copied().flatten() else {
                return false;
            };
            let width = actual.width.max(1) as usize;
            let outside: usize = actual
                .pixels
                .chunks(width)
                .zip(&self.wanted)
                .enumerate()
                .filter(|(_, (_, wanted))| **wanted)
                .map(|(row, (pixels, _))| {
                    pixels
                        .iter()
                        .enumerate()
                        .filter(|&(x, &p)| spread.outside(row * width + x, p, self.rule.tolerance))
                        .count()
                })
                .sum();
            let pixels = actual.pixels.len();
            pixels > 0 && outside as f64 / pixels as f64 > self.rule.max_bad
        })
    }

    /// Whether a render of the wanted rows (the pictures in the order of the failing ones, each
    /// `None` where the render has no such picture) matches none of the `actual` pictures: in
    /// those rows alone, each differs in more pixels than the rule allows the whole picture
    /// (pixels of a picture drawn by chance differing as two draws of its `spreads`' do).
    pub fn rules_out(
        &self,
        rendered: &[Option<&Image>],
        actual: &[&Image],
        spreads: &[Option<&Spread>],
    ) -> bool {
        let spread = |k: usize| spreads.get(k).copied().flatten();
        rendered
            .iter()
            .zip(actual)
            .enumerate()
            .all(|(k, (rendered, actual))| {
                let Some(rendered) = rendered else {
                    return true;
                };
                if (rendered.width, rendered.height) != (actual.width, actual.height)
                    || rendered.pixels.len() != actual.pixels.len()
                {
                    return true;
                }
                let width = actual.width.max(1) as usize;
                let differing: usize = rendered
                    .pixels
                    .chunks(width)
                    .zip(actual.pixels.chunks(width))
                    .zip(&self.wanted)
                    .enumerate()
                    .filter(|(_, (_, wanted))| **wanted)
                    .map(|(row, ((got, want), _))| {
                        got.iter()
                            .zip(want)
                            .enumerate()
                            .filter(|&(x, (&a, &b))| {
                                differs(spread(k), self.rule.tolerance, row * width + x, a, b)
                            })
                            .count()
                    })
                    .sum();
                let pixels = actual.pixels.len();
                // The whole picture's rule, as `compare` and `Rule::passes` work it out.
                pixels > 0 && differing as f64 / pixels as f64 > self.rule.max_bad
            })
    }
}

/// The mean of every channel's difference over every row, in levels; infinite for pictures of
/// other sizes ([`Screen::mean_difference`] is over a screen's rows).
pub fn mean_difference(picture: Option<&Image>, actual: &Image) -> f64 {
    match picture {
        Some(p) if (p.width, p.height) == (actual.width, actual.height) && !p.pixels.is_empty() => {
            let sum: u64 = p
                .pixels
                .iter()
                .zip(&actual.pixels)
                .map(|(a, b)| (0..3).map(|c| u64::from(a[c].abs_diff(b[c]))).sum::<u64>())
                .sum();
            sum as f64 / p.pixels.len() as f64
        }
        _ => f64::INFINITY,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: u32, height: u32, pixel: impl Fn(u32, u32) -> [u8; 3]) -> Image {
        Image {
            width,
            height,
            pixels: (0..height)
                .flat_map(|y| (0..width).map(move |x| (x, y)))
                .map(|(x, y)| pixel(x, y))
                .collect(),
        }
    }

    #[test]
    fn the_rows_where_the_pictures_differ_most_are_screened() {
        // 6,000 pixels: the rule allows 6 to differ; rows are chosen until they hold more
        // than 24.
        let reference = image(10, 600, |_, _| [0; 3]);
        // Rows 7 and 40 differ entirely, row 20 in one pixel.
        let actual = image(10, 600, |x, y| match y {
            7 | 40 => [200; 3],
            20 if x == 0 => [200; 3],
            _ => [0; 3],
        });
        let failing = [Failing {
            actual: &actual,
            reference: Some(&reference),
            traced: true,
            spread: None,
        }];
        let screen = Screen::of(&failing, Rule::COURSE).unwrap();
        let wanted: Vec<usize> = (0..600).filter(|&r| screen.wanted()[r]).collect();
        assert_eq!(wanted, [7, 20, 40]);
        // The reference itself differs from the student's picture in 21 pixels of those rows:
        // more than 0.1% of 6,000.
        assert!(screen.rules_out(&[Some(&reference)], &[&actual], &[]));
        assert!(!screen.rules_out(&[Some(&actual)], &[&actual], &[]));
        // A render that differs only outside the rows is not ruled out, whatever it does there.
        let elsewhere = image(10, 600, |x, y| match y {
            7 | 40 => [200; 3],
            20 if x == 0 => [200; 3],
            500 => [90; 3],
            _ => [0; 3],
        });
        assert!(!screen.rules_out(&[Some(&elsewhere)], &[&actual], &[]));
    }

    #[test]
    fn a_picture_without_a_reference_or_not_traced_is_not_screened() {
        let actual = image(4, 4, |_, _| [9; 3]);
        let reference = image(4, 4, |_, _| [0; 3]);
        let without = Failing {
            actual: &actual,
            reference: None,
            traced: true,
            spread: None,
        };
        assert_eq!(Screen::of(&[without], Rule::COURSE), None);
        let zoomed = Failing {
            actual: &actual,
            reference: Some(&reference),
            traced: false,
            spread: None,
        };
        assert_eq!(Screen::of(&[zoomed], Rule::COURSE), None);
    }

    #[test]
    fn a_rendered_picture_ruled_out_for_one_picture_but_not_another_is_kept() {
        let reference = image(10, 10, |_, _| [0; 3]);
        let actual = image(10, 10, |_, y| if y == 3 { [99; 3] } else { [0; 3] });
        let failing = [
            Failing {
                actual: &actual,
                reference: Some(&reference),
                traced: true,
                spread: None,
            },
            Failing {
                actual: &actual,
                reference: Some(&reference),
                traced: true,
                spread: None,
            },
        ];
        let screen = Screen::of(&failing, Rule::COURSE).unwrap();
        assert!(!screen.rules_out(&[Some(&reference), Some(&actual)], &[&actual, &actual], &[]));
        assert!(screen.rules_out(&[Some(&reference), None], &[&actual, &actual], &[]));
    }
}

#[cfg(test)]
mod never_rules_out_a_match {
    use super::*;
    use crate::check::rule::compare;
    use proptest::prelude::*;

    fn picture(width: u32, height: u32, bytes: &[u8]) -> Image {
        Image {
            width,
            height,
            pixels: (0..(width * height) as usize)
                .map(|i| {
                    let b = bytes[i % bytes.len()];
                    [b, b / 2, b / 3]
                })
                .collect(),
        }
    }

    proptest! {
        /// Whatever the pictures, a render that passes against the student's picture as a whole
        /// is never ruled out by its rows.
        #[test]
        fn a_render_that_passes_whole_is_never_ruled_out(
            (width, height) in (1_u32..24, 1_u32..24),
            student in proptest::collection::vec(any::<u8>(), 1..64),
            reference in proptest::collection::vec(any::<u8>(), 1..64),
            changed in proptest::collection::vec((0_usize..576, any::<u8>()), 0..12),
            tolerance in 0_u8..8,
            max_bad in 0.0_f64..0.2,
        ) {
            let rule = Rule { tolerance, max_bad };
            let actual = picture(width, height, &student);
            let reference = picture(width, height, &reference);
            // The student's picture, a few pixels changed: sometimes within the rule, sometimes
            // not.
            let mut rendered = actual.clone();
            let pixels = rendered.pixels.len();
            for (at, value) in changed {
                rendered.pixels[at % pixels] = [value; 3];
            }
            let failing = [Failing { actual: &actual, reference: Some(&reference), traced: true, spread: None }];
            let passes = compare(&rendered, &actual, tolerance).is_some_and(|c| rule.passes(&c));
            // The screen of the rows that differ most, and the second, of every third row.
            let screens = Screen::of(&failing, rule)
                .into_iter()
                .chain(std::iter::once(Screen::every(3, height as usize, rule)));
            for screen in screens {
                if passes {
                    prop_assert!(!screen.rules_out(&[Some(&rendered)], &[&actual], &[]));
                }
                prop_assert!(!screen.rules_out(&[Some(&actual)], &[&actual], &[]));
            }
        }

        /// A fault's own spread made from renders of the screen's rows and their neighbours
        /// alone (the other rows black) rules out no picture that lies within the spread of
        /// its whole renders, and rules out one that lies outside it in the rows.
        #[test]
        fn a_spread_of_the_rows_rules_out_only_what_the_whole_spread_does(
            (width, height) in (1_u32..12, 2_u32..24),
            base in proptest::collection::vec(any::<u8>(), 1..32),
            noise in proptest::collection::vec(proptest::collection::vec(0_u8..40, 1..32), 2..5),
            wrong in proptest::collection::vec((0_usize..288, any::<u8>()), 0..40),
            tolerance in 0_u8..8,
            max_bad in 0.0_f64..0.1,
        ) {
            let rule = Rule { tolerance, max_bad };
            let base = picture(width, height, &base);
            let pixels = base.pixels.len();
            let seeded: Vec<Image> = noise
                .iter()
                .map(|noise| {
                    let mut seed = base.clone();
                    for (i, p) in seed.pixels.iter_mut().enumerate() {
                        *p = p.map(|c| c.saturating_add(noise[i % noise.len()]));
                    }
                    seed
                })
                .collect();
            let mut actual = seeded[0].clone();
            for (at, value) in wrong {
                actual.pixels[at % pixels] = [value; 3];
            }
            let failing = [Failing {
                actual: &actual,
                reference: Some(&base),
                traced: true,
                spread: None,
            }];
            let Some(screen) = Screen::of(&failing, rule) else {
                return Ok(());
            };
            let rendered = screen.with_neighbours();
            let rows_only: Vec<Image> = seeded
                .iter()
                .map(|seed| {
                    let mut rows = seed.clone();
                    for (row, pixels) in rows.pixels.chunks_mut(width as usize).enumerate() {
                        if !rendered[row] {
                            pixels.fill([0; 3]);
                        }
                    }
                    rows
                })
                .collect();
            let whole = Spread::of(&seeded.iter().collect::<Vec<_>>()).unwrap();
            let of_rows = Spread::of(&rows_only.iter().collect::<Vec<_>>()).unwrap();
            // Pixel for pixel the same in the wanted rows...
            for (i, &p) in actual.pixels.iter().enumerate() {
                if screen.wanted()[i / width as usize] {
                    prop_assert_eq!(of_rows.outside(i, p, tolerance), whole.outside(i, p, tolerance));
                }
            }
            // ...so what the rows rule out, the whole picture fails.
            let passes_whole = whole.compare(&actual, tolerance).is_some_and(|c| rule.passes(&c));
            if screen.rules_out_spreads(&[Some(&of_rows)], &[&actual]) {
                prop_assert!(!passes_whole);
            }
            prop_assert!(!screen.rules_out_spreads(&[None], &[&actual]));
        }

        /// The same for pictures drawn by chance: a render that passes as a draw of the line's
        /// spread (seeded renders a little apart) is never ruled out by its rows.
        #[test]
        fn a_draw_that_passes_whole_is_never_ruled_out(
            (width, height) in (1_u32..16, 1_u32..16),
            base in proptest::collection::vec(any::<u8>(), 1..32),
            noise in proptest::collection::vec(proptest::collection::vec(0_u8..6, 1..32), 2..5),
            wrong in proptest::collection::vec((0_usize..256, any::<u8>()), 1..40),
            changed in proptest::collection::vec((0_usize..256, any::<u8>()), 0..12),
            tolerance in 0_u8..8,
            max_bad in 0.0_f64..0.1,
        ) {
            let rule = Rule { tolerance, max_bad };
            let base = picture(width, height, &base);
            let pixels = base.pixels.len();
            let seeded: Vec<Image> = noise
                .iter()
                .map(|noise| {
                    let mut seed = base.clone();
                    for (i, p) in seed.pixels.iter_mut().enumerate() {
                        *p = p.map(|c| c.saturating_add(noise[i % noise.len()]));
                    }
                    seed
                })
                .collect();
            let spread = Spread::of(&seeded.iter().collect::<Vec<_>>()).unwrap();
            // The student's draw, wrong in some pixels; a render, one seed with a few changed.
            let mut actual = seeded[1].clone();
            for (at, value) in wrong {
                actual.pixels[at % pixels] = [value; 3];
            }
            let mut rendered = seeded[0].clone();
            for (at, value) in changed {
                rendered.pixels[at % pixels] = [value; 3];
            }
            let failing = [Failing {
                actual: &actual,
                reference: Some(&seeded[1]),
                traced: true,
                spread: Some(&spread),
            }];
            if let Some(screen) = Screen::of(&failing, rule) {
                let passes = spread
                    .compare_draws(&actual, &rendered, tolerance)
                    .is_some_and(|c| rule.passes(&c));
                if passes {
                    prop_assert!(
                        !screen.rules_out(&[Some(&rendered)], &[&actual], &[Some(&spread)])
                    );
                }
                prop_assert!(!screen.rules_out(&[Some(&actual)], &[&actual], &[Some(&spread)]));
            }
        }
    }
}
