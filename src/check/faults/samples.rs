//! Faults of assignment 7: where a pixel's samples fall, and how far the filter reaches.

use glam::{Vec2, Vec3A};

use super::{Candidate, Fault, LineScene, Planted};
use crate::sample::{Filter, ONE_BELOW, Sampler};

/// How a student's renderer samples and filters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SampleFault {
    /// Jittered samples anywhere in the pixel, not one in each cell.
    JitterWholePixel,
    /// Uniform samples at the cells' lower-left corners, not their centres.
    UniformCorners,
    /// The uniform grid spread about the pixel's centre by this factor (check's fit: a grid
    /// from edge to edge of the pixel, a / (s − 1), is s / (s − 1)).
    UniformSpread(f32),
    /// The uniform grid moved by this many of its cells along each axis (check's fit: the
    /// cells' lower-left corners are −½, their upper-right ones ½).
    UniformOffset(f32),
    /// The filter's radius (or σ) times this.
    FilterScale(f32),
    /// The weighted samples divided by their number, not by the sum of their weights.
    DividedByCount,
    /// The weighted samples divided by the number of samples a pixel has.
    DividedByPixelSamples(u32),
    /// An allowed answer (check/choices.rs): the Gaussian not cut at 2σ, over the support of
    /// the radius that a reach of this many σ gives (rounded up where `ceil`, else as the
    /// course's support radius is).
    GaussianUncut {
        /// The reach, in σ.
        sigmas: f32,
        /// Whether the radius is the reach rounded up (a student's `ceil`).
        ceil: bool,
    },
    /// An allowed answer: the box's edges in.
    BoxClosed,
    /// An allowed answer: the box's edges out.
    BoxOpen,
    /// The filter another shape: the tent made of two straight ones (form 0) or of another
    /// distance, |x| + |y| (1) or max(|x|, |y|) (2); the box round (0) or of |x| + |y| (1).
    Shape(u8),
    /// The filter gathering the samples of the pixel itself alone, none of its neighbours'.
    OwnPixelOnly,
    /// The filter gathering its neighbours by a loop that stops one short: from −r to r − 1.
    NeighboursShort,
    /// The filter weighing each sample by its distance from a corner of the pixel, not from
    /// its centre: (i, j) with j counted up, as the course's film counts it (form 0), or down,
    /// from the picture's top (form 1).
    FilterFromCorner(u8),
}

impl SampleFault {
    /// Whether it changes where `sampler`'s samples fall.
    pub(super) fn places(&self, sampler: Sampler) -> bool {
        matches!(
            (self, sampler),
            (SampleFault::JitterWholePixel, Sampler::Jittered(_))
                | (
                    SampleFault::UniformCorners
                        | SampleFault::UniformSpread(_)
                        | SampleFault::UniformOffset(_),
                    Sampler::Uniform(_)
                )
        )
    }

    pub(super) fn positions(&self, sampler: Sampler, seed: u64, pixel: u64, out: &mut [Vec2]) {
        match (self, sampler) {
            (SampleFault::JitterWholePixel, Sampler::Jittered(n)) => {
                Sampler::Random(n).positions(seed, pixel, out);
            }
            (SampleFault::UniformCorners, Sampler::Uniform(n)) => {
                let side = n.isqrt().max(1);
                for (k, p) in out.iter_mut().enumerate() {
                    let (i, j) = (k as u32 % side, k as u32 / side);
                    *p = Vec2::new(i as f32, j as f32) / side as f32;
                }
            }
            (SampleFault::UniformSpread(by), Sampler::Uniform(n)) => {
                uniform_grid(n, out, |centre| 0.5 + by * (centre - 0.5));
            }
            (SampleFault::UniformOffset(by), Sampler::Uniform(n)) => {
                uniform_grid(n, out, |centre| centre + by / n.isqrt().max(1) as f32);
            }
            _ => sampler.positions(seed, pixel, out),
        }
    }

    /// The pixels the filter gathers, where the fault changes them (see
    /// [`SampleSeam::neighbours`](crate::sample::SampleSeam::neighbours)).
    pub(super) fn neighbours(&self, reach: i64) -> Option<(i64, i64)> {
        match *self {
            SampleFault::OwnPixelOnly => Some((0, 0)),
            SampleFault::NeighboursShort => Some((-reach, reach - 1)),
            _ => None,
        }
    }

    /// The weight of a sample `(x, y)` from the pixel's centre, where this fault weighs it
    /// otherwise.
    pub(super) fn weight(&self, filter: Filter, x: f32, y: f32) -> Option<f32> {
        match *self {
            // The distance from (i, j): the centre's half pixel left out of the sample's offset.
            SampleFault::FilterFromCorner(form) => {
                let up = if form == 0 { 0.5 } else { -0.5 };
                Some(filter.weight(x + 0.5, y + up))
            }
            _ => None,
        }
    }

    pub(super) fn weighted_mean(&self, sum: Vec3A, count: u32) -> Option<Vec3A> {
        match *self {
            SampleFault::DividedByCount => Some(sum / count as f32),
            SampleFault::DividedByPixelSamples(n) => Some(sum / n as f32),
            _ => None,
        }
    }

    pub(super) fn filter(&self, filter: Filter) -> Filter {
        match *self {
            SampleFault::FilterScale(by) => match filter {
                Filter::Box(r) => Filter::Box(r * by),
                Filter::BoxClosed(r) => Filter::BoxClosed(r * by),
                Filter::BoxOpen(r) => Filter::BoxOpen(r * by),
                Filter::Tent(r) => Filter::Tent(r * by),
                Filter::TentAcross(r) => Filter::TentAcross(r * by),
                Filter::BoxRound(r) => Filter::BoxRound(r * by),
                Filter::TentDiamond(r) => Filter::TentDiamond(r * by),
                Filter::TentSquare(r) => Filter::TentSquare(r * by),
                Filter::BoxDiamond(r) => Filter::BoxDiamond(r * by),
                Filter::Gaussian(s) => Filter::Gaussian(s * by),
                Filter::GaussianNarrow(s) => Filter::GaussianNarrow(s * by),
                Filter::GaussianSigmaUnsquared(s) => Filter::GaussianSigmaUnsquared(s * by),
                Filter::GaussianUncut { sigma, radius } => Filter::GaussianUncut {
                    sigma: sigma * by,
                    radius,
                },
            },
            SampleFault::GaussianUncut { sigmas, ceil } => match filter {
                Filter::Gaussian(sigma) => Filter::GaussianUncut {
                    sigma,
                    radius: gaussian_radius(sigma * sigmas, ceil),
                },
                other => other,
            },
            SampleFault::BoxClosed => match filter {
                Filter::Box(r) => Filter::BoxClosed(r),
                other => other,
            },
            SampleFault::BoxOpen => match filter {
                Filter::Box(r) => Filter::BoxOpen(r),
                other => other,
            },
            SampleFault::Shape(form) => match (filter, form) {
                (Filter::Tent(r), 0) => Filter::TentAcross(r),
                (Filter::Tent(r), 1) => Filter::TentDiamond(r),
                (Filter::Tent(r), _) => Filter::TentSquare(r),
                (Filter::Box(r), 0) => Filter::BoxRound(r),
                (Filter::Box(r), _) => Filter::BoxDiamond(r),
                (Filter::Gaussian(sigma), 0) => Filter::GaussianNarrow(sigma),
                (Filter::Gaussian(sigma), _) => Filter::GaussianSigmaUnsquared(sigma),
                (other, _) => other,
            },
            _ => filter,
        }
    }
}

/// The `n` uniform samples of a pixel, each cell's centre (in [0, 1)²) moved by `place`, kept
/// inside the pixel.
fn uniform_grid(n: u32, out: &mut [Vec2], place: impl Fn(Vec2) -> Vec2) {
    let side = n.isqrt().max(1);
    for (k, p) in out.iter_mut().enumerate() {
        let cell = Vec2::new((k as u32 % side) as f32, (k as u32 / side) as f32);
        let placed = place((cell + 0.5) / side as f32);
        *p = placed.clamp(Vec2::ZERO, Vec2::splat(ONE_BELOW));
    }
}

/// The support radius of a filter reaching `reach` pixels: rounded up (a student's `ceil`), or
/// as the course's (the largest k with k − ½ < reach).
pub fn gaussian_radius(reach: f32, ceil: bool) -> u32 {
    if ceil {
        reach.ceil().max(0.0) as u32
    } else {
        Filter::Box(reach).support_radius()
    }
}

pub(super) const JITTER_WHOLE_PIXEL: Fault = Fault {
    name: "jitter_whole_pixel",
    assignment: 7,
    sentence: "My jittered samples fall anywhere in the pixel, not one in each cell of its grid.",
    look_for: "The jittered sampler: cell (i, j) of the s × s grid gets ((i + r1) / s, (j + r2) / \
               s) with r1, r2 random in [0, 1), not (r1, r2).",
    candidates: |line: &LineScene| {
        if matches!(line.options.sampling.sampler, Sampler::Jittered(n) if n > 1) {
            vec![Candidate::plain(Planted::Sample(
                SampleFault::JitterWholePixel,
            ))]
        } else {
            Vec::new()
        }
    },
};

pub(super) const UNIFORM_CORNERS: Fault = Fault {
    name: "uniform_corners",
    assignment: 7,
    sentence: "My uniform samples are not at the centres of the grid's cells: at their corners \
               (with an offset, the grid moved by that many cells: -0.5 the lower-left corners, \
               0.5 the upper-right; with a spread, a grid spread wider or narrower about the \
               pixel's centre: s / (s - 1) is a grid from edge to edge of the pixel, a / (s - \
               1)).",
    look_for: "The uniform sampler: cell (i, j) of the s × s grid gets ((i + 0.5) / s, (j + 0.5) \
               / s).",
    candidates: |line: &LineScene| {
        if matches!(line.options.sampling.sampler, Sampler::Uniform(_))
            && !line.options.sampling.is_plain()
        {
            vec![Candidate::plain(Planted::Sample(
                SampleFault::UniformCorners,
            ))]
        } else {
            Vec::new()
        }
    },
};

pub(super) const FILTER_RADIUS: Fault = Fault {
    name: "filter_radius",
    assignment: 7,
    sentence: "My filter reaches farther or nearer than the command line says (scale: how many \
               times as far; twice and half as far are the usual slips).",
    look_for: "The filter's support: a box or tent of radius r weighs samples within r of the \
               pixel's centre (in pixels, not in the image's units or as a diameter); a Gaussian \
               of σ reaches to 2σ.",
    candidates: |line: &LineScene| {
        if line.options.sampling.is_plain() {
            return Vec::new();
        }
        [2.0f32, 0.5]
            .into_iter()
            .map(|by| {
                Candidate::with(
                    Planted::Sample(SampleFault::FilterScale(by)),
                    "scale",
                    f64::from(by),
                )
            })
            .collect()
    },
};

pub(super) const FILTER_SHAPE: Fault = Fault {
    name: "filter_shape",
    assignment: 7,
    sentence: "My filter has another shape: a tent made of two straight ones, (1 - |x|/r)(1 - \
               |y|/r) (form 0), or of another distance, |x| + |y| (1) or max(|x|, |y|) (2); a \
               box round, taking the samples nearer than r (0), or of |x| + |y| < r (1); a \
               Gaussian written e^(-d²/σ²), the 2 left out (0), or e^(-d²/2σ), σ not squared \
               (1).",
    look_for: "The filter's weight of a sample at (x, y) from the pixel's centre: the tent is 1 \
               - d/r with d the distance sqrt(x² + y²); the box is 1 where both |x| and |y| are \
               below r (a square), 0 elsewhere; the Gaussian is e^(-d²/(2σ²)).",
    candidates: |line: &LineScene| {
        let sampling = &line.options.sampling;
        let shaped = matches!(
            sampling.filter,
            Filter::Tent(_) | Filter::Box(_) | Filter::Gaussian(_)
        );
        if sampling.is_plain() || !shaped {
            return Vec::new();
        }
        let forms: &[u8] = match sampling.filter {
            Filter::Tent(_) => &[0, 1, 2],
            _ => &[0, 1],
        };
        Candidate::forms(
            forms
                .iter()
                .map(|&form| Planted::Sample(SampleFault::Shape(form))),
        )
    },
};

pub(super) const FILTER_WEIGHTS: Fault = Fault {
    name: "filter_weights",
    assignment: 7,
    sentence: "I divide the filter's weighted sum by a count of samples (form 0: the samples \
               weighed; 1: the samples of one pixel), not by the sum of their weights.",
    look_for: "Film::getColor with a filter: Σ weight × colour over the samples within the \
               support, divided by Σ weight, so that the weights need not add up to 1.",
    candidates: |line: &LineScene| {
        if line.options.sampling.is_plain() {
            return Vec::new();
        }
        let per_pixel = line.options.sampling.sampler.samples();
        Candidate::forms(
            [
                SampleFault::DividedByCount,
                SampleFault::DividedByPixelSamples(per_pixel),
            ]
            .map(Planted::Sample),
        )
    },
};

pub(super) const FILTER_NEIGHBOURS: Fault = Fault {
    name: "filter_neighbours",
    assignment: 7,
    sentence: "My filter gathers the samples of the wrong pixels: the pixel's own alone (form 0), \
               or its neighbours by a loop that stops one short, from −r to r − 1 (form 1).",
    look_for: "Film::getColor(i, j) with a filter: the samples of every pixel from i − r to i + r \
               and from j − r to j + r, both ends included, r the filter's support radius in \
               pixels, each weighed by the filter at its distance from the pixel's centre.",
    candidates: |line: &LineScene| {
        let sampling = &line.options.sampling;
        if sampling.is_plain() || sampling.filter.support_radius() == 0 {
            return Vec::new();
        }
        Candidate::forms(
            [SampleFault::OwnPixelOnly, SampleFault::NeighboursShort].map(Planted::Sample),
        )
    },
};

pub(super) const FILTER_CENTRE: Fault = Fault {
    name: "filter_centre",
    assignment: 7,
    sentence: "My filter weighs each sample by its distance from a corner of the pixel, (i, j), \
               not from its centre, (i + ½, j + ½): the corner below (form 0) or above (form 1, \
               rows counted from the top).",
    look_for: "Film::getColor(i, j): a sample at p within pixel (pi, pj) lies at (pi + p.x − (i + \
               0.5), pj + p.y − (j + 0.5)) from the pixel's centre, and the filter weighs it at \
               that offset; without the ½ the whole picture shifts by half a pixel and blurs to \
               one side.",
    candidates: |line: &LineScene| {
        if line.options.sampling.is_plain() {
            return Vec::new();
        }
        Candidate::forms([0, 1].map(|form| Planted::Sample(SampleFault::FilterFromCorner(form))))
    },
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weighted_sums_divided_by_a_count() {
        let sum = Vec3A::splat(3.0);
        assert_eq!(
            SampleFault::DividedByCount.weighted_mean(sum, 4),
            Some(Vec3A::splat(0.75))
        );
        assert_eq!(
            SampleFault::DividedByPixelSamples(9).weighted_mean(sum, 4),
            Some(Vec3A::splat(1.0 / 3.0))
        );
        assert_eq!(SampleFault::UniformCorners.weighted_mean(sum, 4), None);
    }
}
