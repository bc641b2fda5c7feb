//! Pictures that depend on chance: a line whose samples fall at random (`-random_samples`,
//! `-jittered_samples`) has no one right picture, and the course publishes none; a correct
//! tracer with another random generator draws another. Such a picture is graded against the
//! spread of raycast's own renders of the line with several seeds: a pixel differs where a
//! channel is further from the renders' mean than the tolerance and [`Z`] standard deviations
//! of one render (the largest of its neighbourhood's: an edge's spread is its whole length's,
//! not what a few seeds happened to show at one pixel). Wrong sampling or filtering moves the
//! mean itself, by far more than chance does.

use super::rule::Comparison;
use super::samples_picture::SamplesRule;
use crate::job::Options;
use crate::sample::Sampler;
use crate::shade::Image;

/// How many seeds measure a line's spread.
pub const SEEDS: u64 = 8;
/// How many standard deviations from the mean chance may put a pixel.
const Z: f32 = 4.0;

/// The seeds of a line's spread: the line's own first, so that raycast's render of the line
/// (its reference) is one of the draws, then 1, 2, 3 ... passing over it.
pub fn seeds(own: u64) -> impl Iterator<Item = u64> {
    std::iter::once(own)
        .chain((1..).filter(move |&seed| seed != own))
        .take(SEEDS as usize)
}

/// How an image of a line drawn by chance is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drawn {
    /// Traced from its samples (the picture, its depth, its normals): graded by a [`Spread`].
    Traced,
    /// The samples picture: graded by its [`SamplesRule`].
    Samples,
}

/// How a picture drawn by chance is graded.
#[derive(Debug, Clone, PartialEq)]
pub enum ByChance {
    /// A picture traced from its samples: against the spread of seeded renders.
    Spread(Spread),
    /// The samples picture: by what must hold wherever the samples fall.
    Samples(SamplesRule),
}

impl ByChance {
    /// `actual` graded: the pixels that chance cannot account for are the differing ones.
    pub fn compare(&self, actual: &Image, tolerance: u8) -> Option<Comparison> {
        match self {
            ByChance::Spread(spread) => spread.compare(actual, tolerance),
            ByChance::Samples(rule) => rule.compare(actual, tolerance),
        }
    }
}

/// Whether the line's samples fall by chance: random or jittered.
pub fn depends_on_chance(options: &Options) -> bool {
    matches!(
        options.sampling.sampler,
        Sampler::Random(_) | Sampler::Jittered(_)
    )
}

/// Per pixel and channel: the mean of the seeded renders, and how far from it a picture of the
/// line may fall by chance.
#[derive(Debug, Clone, PartialEq)]
pub struct Spread {
    width: u32,
    height: u32,
    mean: Vec<[f32; 3]>,
    /// One render's standard deviation, the largest of the pixel's 3×3 neighbourhood.
    deviation: Vec<[f32; 3]>,
}

impl Spread {
    /// The spread of `renders` (of one picture, with different seeds; at least two, of one
    /// size); `None` otherwise.
    pub fn of(renders: &[&Image]) -> Option<Spread> {
        let first = renders.first()?;
        let (width, height) = (first.width, first.height);
        let count = first.pixels.len();
        if renders.len() < 2
            || count != (width * height) as usize
            || renders
                .iter()
                .any(|r| (r.width, r.height, r.pixels.len()) != (width, height, count))
        {
            return None;
        }
        let k = renders.len() as f32;
        let mut mean = vec![[0.0_f32; 3]; count];
        for render in renders {
            for (m, p) in mean.iter_mut().zip(&render.pixels) {
                for c in 0..3 {
                    m[c] += f32::from(p[c]) / k;
                }
            }
        }
        let mut own = vec![[0.0_f32; 3]; count];
        for render in renders {
            for ((d, p), m) in own.iter_mut().zip(&render.pixels).zip(&mean) {
                for c in 0..3 {
                    d[c] += (f32::from(p[c]) - m[c]).powi(2) / (k - 1.0);
                }
            }
        }
        let (w, h) = (width as usize, height as usize);
        let mut deviation = vec![[0.0_f32; 3]; count];
        for y in 0..h {
            for x in 0..w {
                let d = &mut deviation[y * w + x];
                for ny in y.saturating_sub(1)..(y + 2).min(h) {
                    for nx in x.saturating_sub(1)..(x + 2).min(w) {
                        for c in 0..3 {
                            d[c] = d[c].max(own[ny * w + nx][c].sqrt());
                        }
                    }
                }
            }
        }
        Some(Spread {
            width,
            height,
            mean,
            deviation,
        })
    }

    /// `actual` against the seeded renders' mean: a pixel differs where a channel is further
    /// from it than `tolerance` and chance allow (a new render's own deviation and the mean's,
    /// from [`SEEDS`] renders).
    pub fn compare(&self, actual: &Image, tolerance: u8) -> Option<Comparison> {
        let k = SEEDS as f32;
        self.compare_by(actual, tolerance, (1.0 + 1.0 / k).sqrt(), |i, c| {
            self.mean[i][c]
        })
    }

    /// Whether pixel `i` of `actual` lies outside the spread: one pixel of [`Spread::compare`].
    pub fn outside(&self, i: usize, actual: [u8; 3], tolerance: u8) -> bool {
        let widen = (1.0 + 1.0 / SEEDS as f32).sqrt();
        i < self.mean.len()
            && (0..3).any(|c| {
                let off = (f32::from(actual[c]) - self.mean[i][c]).abs();
                off > self.allowed(i, c, tolerance, widen)
            })
    }

    /// Two pictures of the line against each other (a student's, and a fault's render with one
    /// seed): each drawn by chance, so twice the variance of one is allowed.
    pub fn compare_draws(
        &self,
        actual: &Image,
        other: &Image,
        tolerance: u8,
    ) -> Option<Comparison> {
        if (other.width, other.height) != (self.width, self.height)
            || other.pixels.len() != self.mean.len()
        {
            return None;
        }
        self.compare_by(actual, tolerance, std::f32::consts::SQRT_2, |i, c| {
            f32::from(other.pixels[i][c])
        })
    }

    /// Whether pixel `i` of two pictures of the line, each drawn by chance, differs by more than
    /// `tolerance` and chance allow: one pixel of [`Spread::compare_draws`].
    pub fn draws_differ(&self, i: usize, actual: [u8; 3], other: [u8; 3], tolerance: u8) -> bool {
        i < self.deviation.len()
            && (0..3).any(|c| {
                let off = (f32::from(actual[c]) - f32::from(other[c])).abs();
                off > self.allowed(i, c, tolerance, std::f32::consts::SQRT_2)
            })
    }

    /// How far channel `c` of pixel `i` may be from its centre: `tolerance`, and [`Z`]
    /// deviations widened by `widen`.
    fn allowed(&self, i: usize, c: usize, tolerance: u8, widen: f32) -> f32 {
        f32::from(tolerance) + Z * widen * self.deviation[i][c]
    }

    fn compare_by(
        &self,
        actual: &Image,
        tolerance: u8,
        widen: f32,
        centre: impl Fn(usize, usize) -> f32,
    ) -> Option<Comparison> {
        if (actual.width, actual.height) != (self.width, self.height)
            || actual.pixels.len() != self.mean.len()
        {
            return None;
        }
        let mut worst = 0_u8;
        let mask: Vec<bool> = actual
            .pixels
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let mut differs = false;
                for (c, &level) in p.iter().enumerate() {
                    let off = (f32::from(level) - centre(i, c)).abs();
                    let allowed = self.allowed(i, c, tolerance, widen);
                    differs |= off > allowed;
                    worst = worst.max(off.round().min(255.0) as u8);
                }
                differs
            })
            .collect();
        Some(Comparison::of_mask(self.width, self.height, mask, worst))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn picture(levels: &[u8]) -> Image {
        Image {
            width: levels.len() as u32,
            height: 1,
            pixels: levels.iter().map(|&l| [l; 3]).collect(),
        }
    }

    #[test]
    fn a_pixel_that_varies_with_the_seed_may_vary_and_a_steady_one_may_not() {
        // Pixel 0 is steady at 100; pixel 2 (an edge) swings between 40 and 60; pixel 1 sits
        // beside the edge and takes its spread; pixel 3 is far from it.
        let renders = [
            picture(&[100, 100, 40, 100, 100]),
            picture(&[100, 100, 60, 100, 100]),
            picture(&[100, 100, 50, 100, 100]),
            picture(&[100, 100, 50, 100, 100]),
        ];
        let spread = Spread::of(&renders.iter().collect::<Vec<_>>()).unwrap();
        let compare = |levels: &[u8]| spread.compare(&picture(levels), 2).unwrap().mask;
        assert_eq!(compare(&[100, 100, 75, 100, 100]), [false; 5]);
        assert_eq!(compare(&[100, 120, 50, 102, 100]), [false; 5]);
        assert_eq!(
            compare(&[103, 100, 150, 100, 90]),
            [true, false, true, false, true]
        );
    }

    #[test]
    fn the_spread_begins_with_the_lines_own_seed_and_never_draws_a_seed_twice() {
        assert_eq!(seeds(6837).collect::<Vec<_>>(), [6837, 1, 2, 3, 4, 5, 6, 7]);
        assert_eq!(seeds(3).collect::<Vec<_>>(), [3, 1, 2, 4, 5, 6, 7, 8]);
    }

    proptest::proptest! {
        /// What lets check skip a line's seeded renders for a picture that passes against
        /// raycast's own render (references.rs): within the tolerance of one of the draws is
        /// within the spread, however the draws fall.
        #[test]
        fn a_picture_within_the_tolerance_of_a_draw_lies_within_the_spread(
            draws in proptest::collection::vec(
                proptest::collection::vec(proptest::prelude::any::<u8>(), 6),
                SEEDS as usize,
            ),
            nudges in proptest::collection::vec(-2_i16..=2, 6),
            which in 0..SEEDS as usize,
        ) {
            let renders: Vec<Image> = draws.iter().map(|levels| picture(levels)).collect();
            let spread = Spread::of(&renders.iter().collect::<Vec<_>>()).unwrap();
            let near: Vec<u8> = draws[which]
                .iter()
                .zip(&nudges)
                .map(|(&level, &nudge)| (i16::from(level) + nudge).clamp(0, 255) as u8)
                .collect();
            let compared = spread.compare(&picture(&near), 2).unwrap();
            proptest::prop_assert_eq!(compared.differing, 0);
        }
    }

    #[test]
    fn renders_of_other_sizes_make_no_spread() {
        let (a, b) = (picture(&[1, 2]), picture(&[1, 2, 3]));
        assert_eq!(Spread::of(&[&a, &b]), None);
        assert_eq!(Spread::of(&[&a]), None);
    }
}
